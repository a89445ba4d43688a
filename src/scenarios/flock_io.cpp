// Flock output (boids as particles, the sandpile lattice), CSV series and checkpoints.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "io/checkpoint.hpp"
#include "io/output_step.hpp"
#include "io/particle_output.hpp"
#include "scenarios/flock_scenario.hpp"

namespace biota::scenarios {

namespace mf = models::flock;
using core::Vec3;

void FlockScenario::open_csv(bool resume) {
  const std::string order = ctx_.output_dir + "/flock_order.csv";
  const std::string aval = ctx_.output_dir + "/flock_avalanches.csv";
  const std::string order_header =
      "step,time,flying,fleeing,polarisation,predator_distance,grains_added,topplings,avalanches";
  const std::string aval_header = "step,time,predator,prey,site,size,area,duration,lost";
  if (!resume) {
    order_csv_.start(order, order_header);
    aval_csv_.start(aval, aval_header);
    return;
  }
  // Rows carry the step they were made in (before it advanced): a checkpoint at step S holds
  // steps 0 .. S-1, so rows with step >= S are the abandoned future.
  const double keep = static_cast<double>(step_) - 0.5;
  order_csv_.resume(order, order_header, keep);
  aval_csv_.resume(aval, aval_header, keep);
}

std::vector<BoidRecord> FlockScenario::gather_boids() const {
  return gather_records(/*predators_only=*/false);
}

void FlockScenario::write_output() {
  auto scope = ctx_.timers.scope("output");
  io::ParticleData d;
  const std::size_t no = set_->n_owned();
  d.owned = no;
  std::vector<double> state, flee, kind, speed, vel;
  for (std::size_t i = 0; i < no; ++i) {
    const core::GlobalId id = set_->id(i);
    const Vec3 x = set_->pos(i), v = set_->vec3(a_vel_, i);
    d.positions.insert(d.positions.end(), {x.x, x.y, x.z});
    d.ids.push_back(id);
    // state: 0 grounded, 1 flying, 2 fleeing (site toppled), 3 predator.
    state.push_back(!is_prey(id) ? 3.0 : !flying(id) ? 0.0 : fleeing(id) ? 2.0 : 1.0);
    flee.push_back(fleeing(id) ? 1.0 : 0.0);
    kind.push_back(is_prey(id) ? 0.0 : 1.0);
    speed.push_back(core::norm(v));
    vel.insert(vel.end(), {v.x, v.y, v.z});
  }
  d.scalars = {{"state", std::move(state)},
               {"fleeing", std::move(flee)},
               {"predator", std::move(kind)},
               {"speed", std::move(speed)}};
  d.vectors = {{"velocity", std::move(vel)}};
  io::ParticleOutput out(ctx_.comm, ctx_.output_dir, "flock_boids", step_, time(),
                         ctx_.config.effective_toml(), out_layout_.compression);
  out.write(d);
  // Sandpile lattice (replicated) written through its own L^3 decomposition, one unit per site,
  // by the ranks of lattice_comm_ only.
  if (!lattice_) return;
  const auto& b = lattice_->local_box();
  std::vector<double> h, left;
  for (int z = b.lo.z; z < b.hi.z; ++z)
    for (int y = b.lo.y; y < b.hi.y; ++y)
      for (int x = b.lo.x; x < b.hi.x; ++x) {
        const std::int64_t s = sandpile_->site(x, y, z);
        h.push_back(sandpile_->height(s));
        left.push_back(static_cast<double>(std::max(0LL, flee_until_[s] - step_)));
      }
  io::OutputStep lat(*lattice_, ctx_.output_dir, "flock_sandpile", step_, time(), 1.0, {0, 0, 0},
                     ctx_.config.effective_toml(), "lattice units: one site per prey", out_layout_);
  lat.add_scalar("height", std::move(h), "grains");
  lat.add_scalar("flee_frames_left", std::move(left), "frames");
  lat.write();
}

void FlockScenario::write_checkpoint(const std::string& path) {
  auto scope = ctx_.timers.scope("checkpoint");
  io::CheckpointWriter w(*decomp_, path);
  w.write_attribute("scenario", std::string("flock"));
  w.write_attribute("config", ctx_.config.effective_toml());
  w.write_attribute("flock_step", static_cast<std::int64_t>(step_));
  w.write_attribute("flock_avalanches", static_cast<std::int64_t>(avalanches_));
  const int width = set_->pack_width(false);
  std::vector<double> rows;
  for (std::size_t i = 0; i < set_->n_owned(); ++i) set_->pack(i, false, rows);
  w.write_rows("flock_boids", rows, width);
  // Replicated sandpile: heights, counters and flee timers (exact in doubles: all < 2^53).
  const auto st = sandpile_->state();
  w.write_replicated("sandpile_heights", std::vector<double>(st.heights.begin(), st.heights.end()));
  w.write_replicated("sandpile_counters",
                     {double(st.initial_grains), double(st.grains_added), double(st.grains_lost),
                      double(st.topplings), double(st.relaxations)});
  w.write_replicated("flee_until", std::vector<double>(flee_until_.begin(), flee_until_.end()));
  w.commit();
}

void FlockScenario::read_checkpoint(const std::string& path) {
  io::CheckpointReader r(*decomp_, path);
  step_ = r.read_attribute_int("flock_step");
  avalanches_ = r.read_attribute_int("flock_avalanches");
  int width = 0;
  // Each rank reads its share of the rows; the redistribution sends them to their owners.
  auto rows = r.read_rows_share("flock_boids", width);
  if (width != set_->pack_width(false))
    throw core::InputError(path + ": checkpoint boid layout differs");
  const std::size_t n = rows.size() / width;
  unsigned long long total = n;
  MPI_Allreduce(MPI_IN_PLACE, &total, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, ctx_.comm);
  if (static_cast<long long>(total) != n_prey_ + n_pred_)
    throw core::InputError(path + ": checkpoint has a different number of boids than the deck");
  set_->resize(n, n);
  for (std::size_t k = 0; k < n; ++k) set_->unpack(k, false, rows.data() + k * width);
  pcomm_->redistribute(*set_);
  mf::SandpileState st;
  const auto h = r.read_replicated("sandpile_heights");
  st.heights.assign(h.begin(), h.end());
  const auto cnt = r.read_replicated("sandpile_counters");
  st.initial_grains = std::llround(cnt.at(0)), st.grains_added = std::llround(cnt.at(1));
  st.grains_lost = std::llround(cnt.at(2)), st.topplings = std::llround(cnt.at(3));
  st.relaxations = std::llround(cnt.at(4));
  sandpile_->restore(st);
  const auto fu = r.read_replicated("flee_until");
  if (fu.size() != flee_until_.size()) throw core::InputError(path + ": sandpile size differs");
  for (std::size_t s = 0; s < fu.size(); ++s) flee_until_[s] = std::llround(fu[s]);
  noise_cache_.clear();
  begin_step();
  if (decomp_->rank() == 0) open_csv(true);
}

}  // namespace biota::scenarios
