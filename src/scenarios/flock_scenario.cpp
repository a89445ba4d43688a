#include "scenarios/flock_scenario.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>

#include "core/allgather.hpp"
#include "core/error.hpp"
#include "core/memory.hpp"
#include "core/reproducible_sum.hpp"
#include "core/rng.hpp"
#include "io/checkpoint.hpp"
#include "io/output_step.hpp"
#include "io/particle_output.hpp"

namespace biota::scenarios {

namespace mf = models::flock;
using core::Vec3;

FlockScenario::OwnedComm::~OwnedComm() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (comm != MPI_COMM_NULL && !finalized) MPI_Comm_free(&comm);
}

FlockScenario::FlockScenario(const RunContext& ctx) : ctx_(ctx) {
  const auto& c = ctx.config;
  out_layout_ = io::output_layout_whole(
      c,
      "applies to grid fields (tank, seaweed, wind); the flock's only grid output, the "
      "sandpile lattice, is written whole");
  seed_ = static_cast<std::uint64_t>(c.get_int("seed"));
  dt_ = c.get_real("flock.dt");
  stats_every_ = static_cast<int>(c.get_int("flock.stats_interval"));
  periodic_ = c.get_string("flock.domain.boundary") == "periodic";
  const double dx = c.get_real("flock.domain.dx");
  const auto& size = c.get_real_list("flock.domain.size");
  core::Index3 cells;
  for (int d = 0; d < 3; ++d) {
    cells[d] = static_cast<int>(std::lround(size[d] / dx));
    if (cells[d] < 1 || std::abs(cells[d] * dx - size[d]) > 1e-9 * size[d])
      c.fail("flock.domain.size",
             fmt::format("must be a positive multiple of flock.domain.dx = {}", dx));
  }
  radius_ = c.get_real("flock.boids.perception_radius");
  if (periodic_)
    for (int d = 0; d < 3; ++d)
      if (size[d] < 3 * radius_)
        c.fail("flock.domain.size",
               "must be >= 3 perception radii on a periodic box (no double images)");
  grid_keys_ = grid::GridKeys{
      c.source(),
      {"flock.domain.size[0] / flock.domain.dx", "flock.domain.size[1] / flock.domain.dx",
       "flock.domain.size[2] / flock.domain.dx"}};
  decomp_ = std::make_unique<grid::Decomposition>(
      ctx.comm, cells, std::array<bool, 3>{periodic_, periodic_, periodic_}, core::Index3{0, 0, 0},
      grid_keys_);
  check_scales(c, *decomp_, dx);
  pcomm_ = std::make_unique<particles::ParticleComm>(*decomp_, dx);
  balance_interval_ = static_cast<int>(c.get_int("flock.balance.interval"));
  balance_tolerance_ = c.get_real("flock.balance.tolerance");
  lo_ = pcomm_->domain_lo();
  hi_ = pcomm_->domain_hi();
  wall_margin_ = c.get_real("flock.domain.wall_margin");
  bin_reach_ = static_cast<int>(c.get_int("flock.domain.bin_reach"));
  wall_weight_ = periodic_ ? 0.0 : c.get_real("flock.domain.wall_weight");

  fov_cos_ = std::cos(c.get_real("flock.boids.fov_degrees") / 2 * std::numbers::pi / 180);
  if (c.get_real("flock.boids.fov_degrees") >= 360) fov_cos_ = -1;
  w_sep_ = c.get_real("flock.boids.separation_weight");
  w_ali_ = c.get_real("flock.boids.alignment_weight");
  w_coh_ = c.get_real("flock.boids.cohesion_weight");
  align_mode_ = c.get_string("flock.boids.alignment") == "nearest" ? mf::AlignmentMode::kNearest
                                                                   : mf::AlignmentMode::kAverage;
  a_max_ = c.get_real("flock.boids.max_accel");
  v_min_ = c.get_real("flock.boids.min_speed");
  if (v_min_ > c.get_real("flock.boids.max_speed"))
    c.fail("flock.boids.min_speed", "must not exceed flock.boids.max_speed");
  flee_radius_ = c.get_real("flock.prey.flee_radius");
  w_flee_ = c.get_real("flock.prey.flee_weight");
  w_flee_boost_ = c.get_real("flock.prey.flee_boost_weight");
  flee_frames_ = c.get_int("flock.prey.flee_frames");
  n_pred_ = c.get_int("flock.predator.count");
  if (n_pred_ > 0) {  // without a predator its keys are not read (reported as unused)
    pred_vmax_ = c.get_real("flock.predator.max_speed");
    pred_amax_ = c.get_real("flock.predator.max_accel");
    w_chase_ = c.get_real("flock.predator.chase_weight");
    pred_start_step_ = std::llround(c.get_real("flock.predator.start_time") / dt_);
    const auto& ps = c.get_real_list("flock.predator.start");
    pred_start_ = {ps[0], ps[1], ps[2]};
  }
  // Points of the deck must lie in the box (a point outside selects no rank's cell); a point
  // the deck does not use (no predator, the uniform take-off) is not checked.
  for (const char* key : {"flock.predator.start", "flock.takeoff.origin"}) {
    if (key == std::string_view("flock.predator.start")
            ? n_pred_ == 0
            : c.get_string("flock.takeoff.ifs") == "uniform")
      continue;
    const auto& q = c.get_real_list(key);
    for (int d = 0; d < 3; ++d)
      if (!(q[d] >= 0 && q[d] <= size[d]))
        c.fail(key, fmt::format("lies outside the box [0, {}] x [0, {}] x [0, {}] m "
                                "(flock.domain.size)",
                                size[0], size[1], size[2]));
  }

  const int L = static_cast<int>(c.get_int("flock.sandpile.size"));
  n_prey_ = c.get_int("flock.prey.count");
  if (n_prey_ == 0) n_prey_ = 1LL * L * L * L;
  {
    // Replicated on every rank: the take-off points (orbit and positions, 48 B per prey), the
    // sandpile (heights, flee timers, toppling lists: ~40 B per site) and two 2D fBm fields over
    // the take-off grid; per rank: its share of the boids (~200 B each with ghosts and bins).
    int ranks = 1;
    MPI_Comm_size(ctx.comm, &ranks);
    const double prey = double(n_prey_), sites = double(L) * L * L;
    const double grid_side = std::ceil(std::sqrt(prey)) * 2 + 1;
    core::check_memory(ctx.comm, c,
                       {{"take-off points", 48 * prey},
                        {"sandpile", 40 * sites},
                        {"fBm fields", 2 * 8 * grid_side * grid_side},
                        {"boids", 200 * (prey + double(n_pred_)) / ranks}},
                       fmt::format("flock.prey.count = {} prey and flock.sandpile.size = {} ({}^3 "
                                   "sites)",
                                   n_prey_, L, L));
  }
  sandpile_ = std::make_unique<mf::Sandpile>(L, L, L, seed_);
  {
    int rank = 0, size = 1;
    MPI_Comm_rank(ctx.comm, &rank);
    MPI_Comm_size(ctx.comm, &size);
    const bool writes = rank < std::min(size, L);
    MPI_Comm_split(ctx.comm, writes ? 0 : MPI_UNDEFINED, rank, &lattice_comm_.comm);
    if (writes)
      lattice_ = std::make_unique<grid::Decomposition>(lattice_comm_.comm, core::Index3{L, L, L},
                                                       std::array<bool, 3>{false, false, false});
  }
  {
    auto scope = ctx_.timers.scope("setup");
    const long long warm = c.get_int("flock.sandpile.warmup");
    for (long long k = 0; k < warm; ++k)
      sandpile_->add_grain(sandpile_->random_site(static_cast<std::uint64_t>(k)),
                           mf::ToppleOrder::kStack);
  }
  flee_until_.assign(static_cast<std::size_t>(sandpile_->num_sites()), 0);
  trigger_radius_ = c.get_real("flock.sandpile.trigger_radius");
  grains_per_frame_ = static_cast<int>(c.get_int("flock.sandpile.grains_per_frame"));
  topple_order_ = c.get_string("flock.sandpile.order") == "stack" ? mf::ToppleOrder::kStack
                                                                  : mf::ToppleOrder::kWaves;

  noise_hurst_ = c.get_real("flock.noise.hurst");
  noise_signal_ = c.get_string("flock.noise.signal") == "increments" ? mf::FbmSignal::kIncrements
                                                                     : mf::FbmSignal::kPath;
  noise_levels_ = static_cast<int>(c.get_int("flock.noise.levels"));
  noise_heading_ = c.get_real("flock.noise.heading");

  takeoff_interval_ = c.get_real("flock.takeoff.interval");
  takeoff_speed_ = c.get_real("flock.takeoff.speed");
  const auto& td = c.get_real_list("flock.takeoff.direction");
  takeoff_dir_ = {td[0], td[1], td[2]};
  if (core::norm(takeoff_dir_) == 0) c.fail("flock.takeoff.direction", "must not be zero");
  takeoff_dir_ = takeoff_dir_ / core::norm(takeoff_dir_);

  particles::ParticleLayout layout;
  a_vel_ = layout.add_real("velocity", 3, true, true);
  a_dstar_ = layout.add_real("cruising_distance", 1, true, false);
  a_vmax_ = layout.add_real("max_speed", 1, true, false);
  set_ = std::make_unique<particles::ParticleSet>(layout);
  {
    auto scope = ctx_.timers.scope("setup");
    place_boids();
    pcomm_->redistribute(*set_);
    begin_step();
  }
  if (decomp_->rank() == 0) {
    fmt::print(
        "flock: {} prey, {} predators, sandpile {}^3, box {} x {} x {} m ({}), ranks {} x {} x "
        "{}\n",
        n_prey_, n_pred_, L, size[0], size[1], size[2], periodic_ ? "periodic" : "soft walls",
        decomp_->dims()[0], decomp_->dims()[1], decomp_->dims()[2]);
  }
}

Vec3 FlockScenario::min_image(Vec3 d) const {
  if (!periodic_) return d;
  for (int k = 0; k < 3; ++k) {
    const double L = hi_[k] - lo_[k];
    d[k] -= L * std::round(d[k] / L);
  }
  return d;
}

std::vector<FlockScenario::Predator> FlockScenario::gather_predators() const {
  return gather_records(/*predators_only=*/true);
}

std::vector<BoidRecord> FlockScenario::gather_records(bool predators_only) const {
  std::vector<double> mine;
  for (std::size_t i = 0; i < set_->n_owned(); ++i) {
    if (predators_only && is_prey(set_->id(i))) continue;
    const Vec3 x = set_->pos(i), v = set_->vec3(a_vel_, i);
    mine.insert(mine.end(), {std::bit_cast<double>(set_->id(i)), x.x, x.y, x.z, v.x, v.y, v.z});
  }
  const std::vector<double> all = core::allgather_concat(ctx_.comm, mine);
  const int total = static_cast<int>(all.size());
  std::vector<BoidRecord> out;
  for (int k = 0; k + 7 <= total; k += 7)
    out.push_back({std::bit_cast<core::GlobalId>(all[k]),
                   {all[k + 1], all[k + 2], all[k + 3]},
                   {all[k + 4], all[k + 5], all[k + 6]}});
  std::sort(out.begin(), out.end(), [](auto& a, auto& b) { return a.id < b.id; });
  return out;
}

std::vector<FlockScenario::NearestPrey> FlockScenario::nearest_prey(
    const std::vector<Predator>& preds) const {
  // Local candidates, then an all-gather and the same (distance, id) choice on every rank.
  const std::size_t np = preds.size();
  std::vector<double> mine(np * 5);
  for (std::size_t p = 0; p < np; ++p) {
    NearestPrey best{std::numeric_limits<double>::infinity(), kNone, {}};
    for (std::size_t i = 0; i < set_->n_owned(); ++i) {
      const core::GlobalId id = set_->id(i);
      if (!is_prey(id) || !flying(id)) continue;
      const Vec3 d = min_image(set_->pos(i) - preds[p].x);
      const double d2 = core::dot(d, d);
      if (d2 < best.d2 || (d2 == best.d2 && id < best.id)) best = {d2, id, set_->pos(i)};
    }
    double* m = mine.data() + 5 * p;
    m[0] = best.d2, m[1] = std::bit_cast<double>(best.id), m[2] = best.x.x, m[3] = best.x.y,
    m[4] = best.x.z;
  }
  const int P = decomp_->size();
  std::vector<double> all(mine.size() * P);
  MPI_Allgather(mine.data(), static_cast<int>(mine.size()), MPI_DOUBLE, all.data(),
                static_cast<int>(mine.size()), MPI_DOUBLE, ctx_.comm);
  std::vector<NearestPrey> out(np, {std::numeric_limits<double>::infinity(), kNone, {}});
  for (int r = 0; r < P; ++r)
    for (std::size_t p = 0; p < np; ++p) {
      const double* m = all.data() + (static_cast<std::size_t>(r) * np + p) * 5;
      const core::GlobalId id = std::bit_cast<core::GlobalId>(m[1]);
      if (id == kNone) continue;
      if (m[0] < out[p].d2 || (m[0] == out[p].d2 && id < out[p].id))
        out[p] = {m[0], id, {m[2], m[3], m[4]}};
    }
  return out;
}

void FlockScenario::drive_sandpile(const std::vector<Predator>& preds,
                                   const std::vector<NearestPrey>& near) {
  // Replicated: every rank runs exactly this, in predator-id order, so every lattice is identical.
  const bool root = decomp_->rank() == 0;
  for (std::size_t p = 0; p < preds.size(); ++p) {
    if (step_ < pred_start_step_ || near[p].id == kNone) continue;
    if (near[p].d2 >= trigger_radius_ * trigger_radius_) continue;
    const std::int64_t site =
        static_cast<std::int64_t>(near[p].id % static_cast<core::GlobalId>(flee_until_.size()));
    for (int g = 0; g < grains_per_frame_; ++g) {
      const mf::Avalanche a = sandpile_->add_grain(site, topple_order_);
      for (std::int64_t s : sandpile_->last_toppled_sites()) flee_until_[s] = step_ + flee_frames_;
      ++avalanches_;
      if (root && aval_csv_.is_open())
        aval_csv_.row(fmt::format("{},{:.6f},{},{},{},{},{},{},{}", step_, time(), preds[p].id,
                                  near[p].id, site, a.size, a.area, a.duration, a.lost));
    }
  }
}

double FlockScenario::heading_angle(core::GlobalId id) {
  if (noise_heading_ == 0) return 0;
  const std::uint64_t n = std::uint64_t{1} << noise_levels_;
  const std::uint64_t block = static_cast<std::uint64_t>(step_) / n;
  auto& e = noise_cache_[id];
  if (e.second.empty() || e.first != block) {
    e.first = block;
    e.second =
        mf::heading_noise_block(noise_levels_, noise_hurst_, noise_signal_, seed_, id, block);
  }
  return noise_heading_ * e.second[static_cast<std::uint64_t>(step_) % n];
}

void FlockScenario::step() {
  if (!order_csv_.is_open() && decomp_->rank() == 0) open_csv(false);
  std::vector<Predator> preds;
  std::vector<NearestPrey> near;
  {
    auto scope = ctx_.timers.scope("predators");
    if (n_pred_ > 0) {  // two collectives per step, skipped when there is nothing to find
      preds = gather_predators();
      near = nearest_prey(preds);
    }
  }
  {
    auto scope = ctx_.timers.scope("sandpile");
    drive_sandpile(preds, near);
  }
  if (step_ % stats_every_ == 0) {
    auto scope = ctx_.timers.scope("stats");
    record_order(near);
  }
  {
    auto scope = ctx_.timers.scope("rules");
    const std::size_t no = set_->n_owned();
    // Work estimates for the load balance, only where it runs: 1 per boid, plus the candidates
    // tested and the neighbours perceived per prey (flock_decomposition.cpp).
    const bool track_cost = balancing();
    if (track_cost) boid_cost_.assign(no, 1.0f);
    double work = static_cast<double>(no);
    // Reused across steps: every flying boid that is not launched gets acc[i] below before it
    // is read, so only the launch flags need clearing.
    acc_.resize(no);
    launch_.assign(no, 0);
    Vec3* acc = acc_.data();
    char* launch = launch_.data();
    // fleeing() (a 64-bit modulo per prey) can only be true while some site's flee window is open.
    const bool any_fleeing =
        !flee_until_.empty() && *std::max_element(flee_until_.begin(), flee_until_.end()) > step_;
    const double R2 = radius_ * radius_;
    const double* X = cells_.x();
    const double* Y = cells_.y();
    const double* Z = cells_.z();
    const core::GlobalId* ids = cells_.ids();
    const double *VX = cells_.carried(0), *VY = cells_.carried(1), *VZ = cells_.carried(2);
    // Bin by bin (the slot order, no per-slot bin lookup); gathered_end: end slot of the bin whose
    // candidates bin_ holds.
    std::size_t gathered_end = 0;
    const double* dstar_of = set_->real(a_dstar_);
    // Bins in slabs of rows sized to the L2 (flock_neighbours.hpp). The visiting order changes no
    // result: a boid's sums depend only on its own candidates, in their fixed order.
    cells_.for_each_bin_in_slabs(slab_rows(cells_, bin_reach_), [&](std::size_t b) {
      const std::size_t bin_first = cells_.bin_begin(b), bin_last = cells_.bin_begin(b + 1);
      for (std::size_t k = bin_first; k < bin_last; ++k) {
        const std::size_t i = cells_.index(k);
        if (i >= no) continue;
        const core::GlobalId id = ids[k];
        if (!flying(id)) continue;
        const Vec3 x{X[k], Y[k], Z[k]}, v{VX[k], VY[k], VZ[k]};
        if (core::dot(v, v) == 0) {  // first flying frame: launch (chaos-game order, spec 2.7)
          launch[i] = 1;
          continue;
        }
        if (!is_prey(id)) {  // predator: chase the nearest prey, stay inside
          Vec3 chase{};
          for (std::size_t p = 0; p < preds.size(); ++p)
            if (preds[p].id == id && near[p].id != kNone)
              chase = mf::chase(min_image(near[p].x - x), w_chase_);
          const Vec3 rules[2] = {mf::soft_wall(x, lo_, hi_, wall_margin_, wall_weight_), chase};
          acc[i] = mf::prioritized_sum(rules, pred_amax_);
          continue;
        }
        const double dstar = dstar_of[i];
        // Initialised once, by the path taken (a default NeighbourSums overwritten by the
        // result cost a 120-byte clear per boid).
        std::size_t candidates = 0;
        const mf::NeighbourSums s = [&] {
          if (align_mode_ == mf::AlignmentMode::kAverage) {
            if (gathered_end != bin_last) {  // first boid of its bin that needs the candidates
              bin_.gather(cells_, bin_first, bin_last, VX, VY, VZ, eligible_.data(), R2);
              gathered_end = bin_last;
            }
            candidates = bin_.size();
            return bin_.sums(x, v, R2, fov_cos_, dstar);
          }
          mf::NeighbourSums near_sums;
          cells_.for_each_near(x, [&](std::size_t j) {
            ++candidates;
            const Vec3 d{X[j] - x.x, Y[j] - x.y, Z[j] - x.z};
            const double r2 = core::dot(d, d);
            if (r2 >= R2 || !eligible_[j]) return;
            if (!mf::perceives(v, d, r2, R2, fov_cos_)) return;
            mf::accumulate_neighbour(near_sums, d, r2, {VX[j], VY[j], VZ[j]}, ids[j], dstar);
          });
          return near_sums;
        }();
        neighbour_sum_ += s.count;
        if (track_cost) {
          const double extra = static_cast<double>(candidates + s.count);
          boid_cost_[i] += static_cast<float>(extra);
          work += extra;
        }
        ++prey_updates_;
        // Flee the nearest active predator (tie: lower id); boosted, at any range, while fleeing.
        Vec3 flee{};
        const bool is_fleeing = any_fleeing && fleeing(id);
        if (step_ >= pred_start_step_ && !preds.empty()) {
          double best = std::numeric_limits<double>::infinity();
          Vec3 dp{};
          for (const auto& p : preds) {
            const Vec3 d = min_image(p.x - x);
            if (core::dot(d, d) < best) best = core::dot(d, d), dp = d;
          }
          flee = is_fleeing ? mf::flee(dp, std::numeric_limits<double>::infinity(), w_flee_boost_)
                            : mf::flee(dp, flee_radius_, w_flee_);
        }
        const Vec3 rules[5] = {flee, mf::separation(s, w_sep_),
                               mf::soft_wall(x, lo_, hi_, wall_margin_, wall_weight_),
                               mf::alignment(s, v, w_ali_, align_mode_), mf::cohesion(s, w_coh_)};
        const double amax = is_fleeing ? std::max(a_max_, w_flee_boost_) : a_max_;
        // heading_angle() is an out-of-line call; without noise it is 0 (and rotate_z skips it).
        const double turn = noise_heading_ != 0 ? heading_angle(id) : 0.0;
        acc[i] = mf::rotate_z(mf::prioritized_sum(rules, amax), turn);
      }
    });
    if (track_cost) work_since_balance_ += work;
    // Column pointers hoisted: the stores below would otherwise make the compiler reload them
    // through set_ for every boid.
    const core::GlobalId* own_ids = set_->u64(particles::ParticleSet::kId);
    double* const pos[3] = {set_->real(particles::ParticleSet::kPos, 0),
                            set_->real(particles::ParticleSet::kPos, 1),
                            set_->real(particles::ParticleSet::kPos, 2)};
    double* const vel[3] = {set_->real(a_vel_, 0), set_->real(a_vel_, 1), set_->real(a_vel_, 2)};
    const double* vmax_of = set_->real(a_vmax_);
    for (std::size_t i = 0; i < no; ++i) {
      const core::GlobalId id = own_ids[i];
      if (!flying(id)) continue;
      Vec3 x{pos[0][i], pos[1][i], pos[2][i]}, v{vel[0][i], vel[1][i], vel[2][i]};
      const double vmax = vmax_of[i];
      if (launch[i]) {
        core::Rng r(seed_, id, 2, core::RngPurpose::kBoidInit);
        const Vec3 side{r.uniform(-0.3, 0.3), r.uniform(-0.3, 0.3), r.uniform(-0.3, 0.3)};
        if (is_prey(id)) {
          v = (takeoff_dir_ + side) * takeoff_speed_;
        } else {  // a predator sets off towards the centre of the box
          const Vec3 to = (lo_ + hi_) * 0.5 - x;
          v = core::norm(to) > 0 ? to * (0.5 * vmax / core::norm(to)) : Vec3{0.5 * vmax, 0, 0};
        }
        x += v * dt_;
      } else {
        mf::integrate(x, v, acc[i], dt_, is_prey(id) ? v_min_ : 0.0, vmax);
      }
      pos[0][i] = x.x, pos[1][i] = x.y, pos[2][i] = x.z;
      vel[0][i] = v.x, vel[1][i] = v.y, vel[2][i] = v.z;
    }
  }
  ++step_;
  {
    auto scope = ctx_.timers.scope("comm");
    begin_step();
  }
  // Drop noise blocks of boids that left this rank (bounded memory).
  if (noise_heading_ > 0 && step_ % (1LL << noise_levels_) == 0) {
    std::unordered_map<core::GlobalId, std::pair<std::uint64_t, std::vector<double>>> keep;
    for (std::size_t i = 0; i < set_->n_owned(); ++i) {
      auto it = noise_cache_.find(set_->id(i));
      if (it != noise_cache_.end()) keep.emplace(it->first, std::move(it->second));
    }
    noise_cache_.swap(keep);
  }
}

void FlockScenario::record_order(const std::vector<NearestPrey>& near) {
  // Sum of unit velocities of flying prey, summed reproducibly: the CSV is the same on any rank
  // count (it does not feed back; a plain Allreduce differed in the last bits).
  for (auto& c : unit_) c.clear();
  long long count[2] = {0, 0};
  for (std::size_t i = 0; i < set_->n_owned(); ++i) {
    const core::GlobalId id = set_->id(i);
    if (!is_prey(id) || !flying(id)) continue;
    const Vec3 v = set_->vec3(a_vel_, i);
    const double s = core::norm(v);
    if (s > 0)
      unit_[0].push_back(v.x / s), unit_[1].push_back(v.y / s), unit_[2].push_back(v.z / s);
    count[0] += 1;
    count[1] += fleeing(id) ? 1 : 0;
  }
  double sum[3];
  for (int c = 0; c < 3; ++c)
    sum[c] = core::reproducible_sum(unit_[c].data(), unit_[c].size(), ctx_.comm);
  MPI_Allreduce(MPI_IN_PLACE, count, 2, MPI_LONG_LONG, MPI_SUM, ctx_.comm);
  last_flying_ = count[0];
  last_fleeing_ = count[1];
  last_phi_ = last_flying_ > 0 ? std::sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]) /
                                     static_cast<double>(last_flying_)
                               : 0.0;
  if (decomp_->rank() == 0 && order_csv_.is_open()) {
    const double dnear = near.empty() || near[0].id == kNone ? -1.0 : std::sqrt(near[0].d2);
    order_csv_.row(fmt::format("{},{:.6f},{},{},{:.8f},{:.6f},{},{},{}", step_, time(),
                               last_flying_, last_fleeing_, last_phi_, dnear,
                               sandpile_->grains_added(), sandpile_->topplings(), avalanches_));
  }
}

void FlockScenario::check_health() {
  for (std::size_t i = 0; i < set_->n_owned(); ++i) {
    const Vec3 p = set_->pos(i), v = set_->vec3(a_vel_, i);
    if (!std::isfinite(p.x + p.y + p.z + v.x + v.y + v.z))
      throw core::UnstableError(
          fmt::format("flock: boid {} non-finite at step {}", set_->id(i), step_));
  }
}

void FlockScenario::poison_for_test() {
  if (set_->n_owned() == 0) return Scenario::poison_for_test();
  Vec3 v = set_->vec3(a_vel_, 0);
  v.x = std::numeric_limits<double>::quiet_NaN();
  set_->set_vec3(a_vel_, 0, v);
}

std::string FlockScenario::progress() {
  std::string line =
      fmt::format("flying {} fleeing {} phi {:.3f} avalanches {} topplings {}", last_flying_,
                  last_fleeing_, last_phi_, avalanches_, sandpile_->topplings());
  // How often the load balance moved the cut between ranks (flock.balance.*).
  if (balancing()) line += fmt::format(" cut moves {}", balance_moves_);
  return line;
}

std::vector<std::string> FlockScenario::timer_sections() const {
  return {"setup", "predators", "sandpile", "rules", "comm", "stats", "output", "checkpoint"};
}

}  // namespace biota::scenarios
