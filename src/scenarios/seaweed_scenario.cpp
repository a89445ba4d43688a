#include "scenarios/seaweed_scenario.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iterator>
#include <numeric>
#include <tuple>
#include <unordered_map>
#include <utility>

#include "core/error.hpp"
#include "coupling/particle_transfer.hpp"
#include "grid/plane_weights.hpp"
#include "grid/two_phase_cut.hpp"
#include "io/checkpoint.hpp"
#include "io/output_step.hpp"
#include "io/particle_output.hpp"
#include "models/plants/ulva_growth.hpp"
#include "scenarios/lbm_output.hpp"
#include "solvers/lbm/rank_speed.hpp"

namespace biota::scenarios {

namespace mp = models::plants;
using core::Vec3;

void SeaweedScenario::declare_config(core::ConfigSchema& s) {
  solvers::lbm::LbmSolver::declare_config(s);
  mp::GrowthParams::declare_config(s);
  mp::MechanicsParams::declare_config(s);
  s.add_real("growth.env_radius", 0.3, 0.0, std::nullopt, "m",
             "outer radius of the concentric environment regions (centred on the tank axis)", true);
  s.add_int("seaweed.plants", 50, 1, 10000000, "number of individuals");
  s.add_real_list("seaweed.placement.lo", std::vector<double>{0.2, 0.2, 0.25}, 3, "m",
                  "lower corner of the seed placement box");
  s.add_real_list("seaweed.placement.hi", std::vector<double>{0.8, 0.8, 0.75}, 3, "m",
                  "upper corner of the seed placement box");
  s.add_real("seaweed.placement.min_spacing", 0.12, 0.0, std::nullopt, "m",
             "minimum distance between seeds");
  s.add_bool("seaweed.two_way", true, "plants act back on the water (false: the paper's one-way)");
  s.add_real("seaweed.physics_dt", 1.0 / 60, 0.0, std::nullopt, "s", "physics step", true);
  s.add_real("seaweed.balance.sphere_cost", 25.0, 0.0, 1e6, "LBM cells",
             "work of one sphere's physics step as the number of fluid cells whose physics step "
             "costs the same; the cut between the ranks minimises the most cells on a rank plus "
             "this times the most spheres on a rank (0: equal cells)");
  s.add_bool("seaweed.balance.rank_speed", false,
             "time every rank at the LBM sweep at start-up (~0.3 s) and give slower cores fewer "
             "cells: for lasting differences (hybrid cores, mixed nodes), not for a shared VM "
             "whose contention comes and goes within a stage");
  s.add_int("seaweed.metrics_interval", 6, 1, 1'000'000'000, "physics steps between metric rows");
}

SeaweedScenario::SeaweedScenario(const RunContext& ctx) : ctx_(ctx) {
  const auto& cfg = ctx.config;
  auto params = solvers::lbm::LbmParams::from_config(cfg);
  const grid::GridKeys keys{cfg.source(), {"lbm.nx", "lbm.ny", "lbm.nz"}};
  // The plants are grown first (the same on every rank, from the deck alone): their spheres
  // weight the cut between the ranks' blocks.
  auto gp = mp::GrowthParams::from_config(cfg);
  const Vec3 L{params.cells.x * params.dx, params.cells.y * params.dx, params.cells.z * params.dx};
  gp.env_centre = L * 0.5;
  gp.env_radius = cfg.get_real("growth.env_radius");
  n_plants_ = static_cast<int>(cfg.get_int("seaweed.plants"));
  const auto& lo = cfg.get_real_list("seaweed.placement.lo");
  const auto& hi = cfg.get_real_list("seaweed.placement.hi");
  for (int d = 0; d < 3; ++d)
    if (!(lo[d] >= 0 && lo[d] <= hi[d] && hi[d] <= L[d]))  // lo == hi: plant at a point
      cfg.fail("seaweed.placement.lo",
               fmt::format("and seaweed.placement.hi = [{}, {}, {}] do not give a box inside the "
                           "tank [0, {}] x [0, {}] x [0, {}] m (lbm.nx, lbm.ny, lbm.nz x lbm.dx) "
                           "with lo <= hi on every axis",
                           hi[0], hi[1], hi[2], L[0], L[1], L[2]));
  // A metamer is shorter than the tank (metamers of 1e300 m grew non-finite positions, whose
  // plane index in the rank cut wrote past its array).
  const double env = std::max(gp.env_min, gp.env_max), longest = gp.length_max * env,
               side = std::min({L.x, L.y, L.z});
  if (!(longest <= side))
    cfg.fail("growth.length_max",
             fmt::format("m times the largest environment factor {} (growth.env_min, "
                         "growth.env_max) gives metamers of {:.3g} m, longer than the tank's "
                         "shortest side {} m; allowed: at most {:.6g} m with these factors",
                         env, longest, side, side / env));
  auto seeds = mp::place_seeds(gp.seed, n_plants_, {lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]},
                               cfg.get_real("seaweed.placement.min_spacing"));
  auto mpar = mp::MechanicsParams::from_config(cfg);
  mp::Population pop;
  {
    auto scope = ctx_.timers.scope("growth");
    pop = mp::grow_population(gp, seeds);
  }
  if (cfg.get_bool("seaweed.balance.rank_speed"))
    rank_speed_ = solvers::lbm::measure_rank_speeds(ctx.comm, params);
  {
    // The rank grid the decomposition will pick (its errors are the ones the user gets). The LBM
    // sub-cycle and the particle sub-steps each wait for the slowest rank, so the cut minimises
    // the most cells on a rank plus sphere_cost times the most spheres on a rank. Blocks at least
    // the particle ghost layer thick (and half an even block): a deck that runs with even blocks
    // passes the halo and ghost-width checks with these too.
    int size = 0;
    MPI_Comm_size(ctx.comm, &size);
    const core::Index3 dims = grid::Decomposition::rank_grid(size, params.cells, {0, 0, 0}, keys);
    const double sphere_cost = cfg.get_real("seaweed.balance.sphere_cost");
    std::array<std::vector<int>, 3> starts;
    if (sphere_cost > 0 || !rank_speed_.empty())
      starts = grid::two_phase_block_starts(
          dims, params.cells, spheres_per_plane(dims, params, pop, mpar.spacing), sphere_cost,
          rank_speed_,
          // At most a cell count (a huge cutoff is rejected below; its cast would be undefined).
          static_cast<int>(std::min(1 + std::ceil(mpar.ghost_cutoff() / params.dx), 1e9)));
    decomp_ = std::make_unique<grid::Decomposition>(ctx.comm, params.cells, params.periodic(), dims,
                                                    keys, starts);
    // Every block holds the particle ghost layer, named after the cutoff's largest term.
    const double cutoff = mpar.ghost_cutoff();
    if (const auto t = particles::thinnest_split_block(*decomp_, params.dx); cutoff > t.width) {
      const std::pair<double, const char*> terms[] = {
          {2 * mpar.radius, "seaweed.radius"},
          {mpar.cluster_margin, "seaweed.cluster_margin"},
          {2 * mpar.spacing, "seaweed.spacing"},
          {mpar.skin, "seaweed.skin"}};
      cfg.fail(std::max_element(std::begin(terms), std::end(terms))->second,
               fmt::format("m gives a particle ghost cutoff of {:.3g} m (max(2 seaweed.radius + "
                           "seaweed.cluster_margin, 2 seaweed.spacing) + seaweed.skin), wider "
                           "than the thinnest rank block ({:.3g} m along axis {} with {} ranks "
                           "along it); allowed: a cutoff of at most {:.3g} m, or fewer ranks",
                           cutoff, t.width, t.axis, dims[t.axis], t.width));
    }
  }
  out_layout_ = grid_output_layout(cfg, *decomp_, params.dx, {0, 0, 0});
  core::check_memory(ctx.comm, cfg, solvers::lbm::LbmSolver::memory_estimate(*decomp_, params),
                     "lbm.nx x lbm.ny x lbm.nz = " + std::to_string(params.cells.x) + " x " +
                         std::to_string(params.cells.y) + " x " + std::to_string(params.cells.z) +
                         " cells (" + params.lattice + ")");
  lbm_ = std::make_unique<solvers::lbm::LbmSolver>(*decomp_, params);
  lbm_->enable_force_field();
  const double dx = lbm_->units().dx();
  dt_ = cfg.get_real("seaweed.physics_dt");
  lbm_substeps_ = std::max(1, static_cast<int>(std::lround(dt_ / lbm_->units().dt())));
  if (std::abs(lbm_substeps_ * lbm_->units().dt() - dt_) > 1e-9 * dt_)
    cfg.fail("seaweed.physics_dt",
             fmt::format("must be a multiple of lbm.dt = {}", lbm_->units().dt()));
  two_way_ = cfg.get_bool("seaweed.two_way");
  metrics_every_ = static_cast<int>(cfg.get_int("seaweed.metrics_interval"));
  pcomm_ = std::make_unique<particles::ParticleComm>(*decomp_, dx);
  coupling_ = std::make_unique<coupling::TrilinearCoupling>(*decomp_, dx);

  const double wdt = mpar.omega_max() * dt_ / mpar.substeps;
  if (wdt > 1.8)
    cfg.fail("seaweed.substeps",
             fmt::format("omega_max dt_sub = {:.2f} > 1.8: explicit sub-steps unstable", wdt));
  bodies_ = std::make_unique<mp::SeaweedBodies>(*pcomm_, mpar);
  {
    auto scope = ctx_.timers.scope("growth");
    bodies_->build(pop, n_plants_);
  }
  const long long n = bodies_->global_count();
  {  // Plants grown beyond the tank start inside the wall springs: warn (they are pushed back
     // hard).
    const auto& st = bodies_->set();
    long long outside = 0;
    for (std::size_t i = 0; i < st.n_owned(); ++i)
      for (int d = 0; d < 3; ++d)
        outside += st.pos(i)[d] < mpar.radius || st.pos(i)[d] > L[d] - mpar.radius ? 1 : 0;
    MPI_Allreduce(MPI_IN_PLACE, &outside, 1, MPI_LONG_LONG, MPI_SUM, ctx.comm);
    if (outside > 0 && decomp_->rank() == 0)
      fmt::print(
          "seaweed: WARNING: {} sphere coordinates start outside the tank (less than one "
          "radius from a wall); move the placement box or use a larger tank\n",
          outside);
  }
  check_particle_halo(mpar, dx);
  if (decomp_->rank() == 0) {
    std::string cuts;
    for (int a = 0; a < 3; ++a)
      if (decomp_->dims()[a] > 1) {
        cuts += fmt::format("{}{} blocks", cuts.empty() ? ", " : "; ", "xyz"[a]);
        for (int i = 0; i < decomp_->dims()[a]; ++i)
          cuts +=
              fmt::format(" {}", decomp_->block_start_of(a, i + 1) - decomp_->block_start_of(a, i));
      }
    if (!rank_speed_.empty()) {
      cuts += "; rank speeds";
      for (double v : rank_speed_) cuts += fmt::format(" {:.2f}", v);
    }
    fmt::print("{}\ndecomposition: {} x {} x {} ranks{}\n", lbm_->units().summary(),
               decomp_->dims().x, decomp_->dims().y, decomp_->dims().z, cuts);
    fmt::print(
        "seaweed: {} plants, {} spheres, growth cycles {}, {} LBM steps per physics step, "
        "omega_max*dt_sub = {:.2f}, coupling {}\n",
        n_plants_, n, gp.cycles, lbm_substeps_, wdt, two_way_ ? "two-way" : "one-way");
  }
  bodies_->begin_step();
  last_ = bodies_->clusters();
  {  // The spheres exist only after growth: their memory (owned + ghosts, every attribute, id) is
     // printed here, beside the LBM estimate printed before allocation.
    const auto& st = bodies_->set();
    long long bytes = static_cast<long long>(st.n_total()) * (st.pack_width(false) + 1) * 8,
              most = 0;
    MPI_Allreduce(&bytes, &most, 1, MPI_LONG_LONG, MPI_MAX, ctx.comm);
    if (decomp_->rank() == 0)
      fmt::print("memory: seaweed spheres {:.3g} kB on the fullest rank (owned + ghosts)\n",
                 most / 1e3);
  }
}

std::array<std::vector<double>, 3> SeaweedScenario::spheres_per_plane(
    const core::Index3& dims, const solvers::lbm::LbmParams& params,
    const models::plants::Population& pop, double spacing) {
  grid::PlaneWeights count(dims, params.cells, params.dx);
  if (ctx_.restart_path.empty()) {  // the grown plants, the same on every rank
    mp::for_each_sphere(
        pop, spacing,
        [&](std::uint64_t, const Vec3& x, int, std::uint64_t, const Vec3&) { count.add(x); });
    return count.planes();
  }
  // A restart: where the spheres are now (they drift), each rank its share of the rows, summed.
  // The share is kept for read_checkpoint (it does not depend on the cut), so it is read once.
  const grid::Decomposition even(ctx_.comm, params.cells, params.periodic(), dims);
  io::CheckpointReader reader(even, ctx_.restart_path);
  restart_rows_ = reader.read_rows_share("seaweed_particles", restart_width_);
  mp::to_current_seaweed_rows(restart_rows_, restart_width_, ctx_.restart_path, ctx_.comm);
  restart_rows_read_ = true;
  particles::ParticleSet set(mp::seaweed_layout());
  const std::size_t n = restart_rows_.size() / restart_width_;
  set.resize(n, n);
  for (std::size_t k = 0; k < n; ++k) {
    set.unpack(k, false, restart_rows_.data() + k * restart_width_);
    count.add(set.pos(k));
  }
  count.sum_over(ctx_.comm);
  return count.planes();
}

void SeaweedScenario::check_particle_halo(const mp::MechanicsParams& mpar, double dx) {
  const auto& cfg = ctx_.config;
  // Interpolation: an owned sphere drifts up to skin/2 out of its rank's box before the list
  // rebuild migrates it; its 2x2x2 stencil must stay within the velocity's ghost layers.
  const int g = lbm_->velocity().ghosts();
  if (mpar.skin > (2 * g - 1) * dx)
    cfg.fail("seaweed.skin",
             fmt::format("m exceeds {} x lbm.dx = {} m (allowed: 0 to {} m): a sphere may drift "
                         "half the skin out of its rank's box before migrating, past the "
                         "{}-cell ghost layer of the velocity it samples",
                         2 * g - 1, (2 * g - 1) * dx, (2 * g - 1) * dx, g));
  // Spreading: every sphere whose stencil reaches an owned cell must be a ghost, also after
  // moving skin/2 since the ghosts were built.
  const double need = coupling_->reach() + 0.5 * mpar.skin;
  if (bodies_->ghost_cutoff() < std::max(need, dx))
    cfg.fail("seaweed.skin",
             fmt::format("m: particle ghost cutoff {} m is below max(lbm.dx, lbm.dx/2 + "
                         "seaweed.skin/2) = {} m needed for spreading (raise seaweed.skin or "
                         "seaweed.spacing)",
                         bodies_->ghost_cutoff(), std::max(need, dx)));
  // Joints: the cutoff covers bonds up to 2 x seaweed.spacing; the grown plants must start
  // within that (they do by construction: stems are cut into pieces of at most the spacing).
  const double bond = bodies_->longest_bond();
  if (bond > 2 * mpar.spacing)
    throw core::InputError(fmt::format(
        "seaweed: longest joint at set-up {} m exceeds 2 x seaweed.spacing = {} m covered by "
        "the particle ghost cutoff",
        bond, 2 * mpar.spacing));
}

void SeaweedScenario::open_csv() {
  // Fresh run: new file with the t = 0 row. Restart: keep the rows up to the restart time and
  // append (no spurious t = 0 row; rows of the abandoned future are dropped).
  csv_started_ = true;
  if (decomp_->rank() != 0) {
    if (step_ == 0) record_metrics();
    return;
  }
  const std::string path = ctx_.output_dir + "/seaweed_clusters.csv";
  const std::string header = "time,clusters,largest,largest_share,contacts,broken_joints,joints";
  if (step_ > 0)
    csv_.resume(path, header, time() + 0.5 * dt_);
  else
    csv_.start(path, header);
  if (step_ == 0) record_metrics();
}

void SeaweedScenario::record_metrics() {
  last_ = bodies_->clusters();
  if (decomp_->rank() == 0)
    csv_.row(fmt::format("{:.9f},{},{},{:.6f},{},{},{}", time(), last_.clusters, last_.largest,
                         last_.largest_share, last_.contacts, last_.broken_joints, last_.joints));
}

void SeaweedScenario::step() {
  if (!csv_started_) open_csv();
  auto& set = bodies_->set();
  const auto& units = lbm_->units();
  check_spheres_finite();  // before migrate, which cannot place a NaN
  {
    auto scope = ctx_.timers.scope("particles");
    bodies_->begin_step();  // migrate + ghosts + lists when the skin is used up, else refresh
  }
  {
    auto scope = ctx_.timers.scope("coupling");
    // Sample at the step's start position, kept in x_sample for the reaction's spreading.
    for (std::size_t i = 0; i < set.n_owned(); ++i) set.set_vec3(bodies_->a_xs, i, set.pos(i));
    coupling::interpolate_to_particles(*coupling_, lbm_->velocity(), set, bodies_->a_xs,
                                       bodies_->a_uf, units.velocity_to_si(1.0));
  }
  {
    auto scope = ctx_.timers.scope("particles");
    bodies_->advance(dt_);
  }
  {
    auto scope = ctx_.timers.scope("coupling");
    auto& f = lbm_->force();
    f.fill(0.0);
    if (two_way_) {
      // Reaction of the drag, averaged over the step: -impulse/dt [N] per sphere, spread with the
      // interpolation weights (at the sampling position) as a lattice force density. Every rank
      // spreads its owned and ghost spheres in global-id order into its owned cells only, so
      // each cell sums the same terms in the same order on any rank count (no reverse halo sum).
      coupling::spread_from_particles(*coupling_, f, set, bodies_->a_xs, bodies_->a_imp,
                                      -units.force_to_lattice(1.0) / dt_);
    }
  }
  // The LBM velocity used for sampling is always the one update_macroscopic() computes from the
  // populations and this step's force field, so output steps and restarts (which call it too)
  // cannot change the trajectory.
  lbm_->advance(lbm_substeps_);
  {
    auto scope = ctx_.timers.scope("lbm_macroscopic");  // listed apart from the LBM's own timers
    const std::vector<grid::Box> sampled = sampled_velocity_cells();
    lbm_->update_macroscopic(sampled);
  }
  ctx_.timers.add("lbm", lbm_->time_collide() + lbm_->time_halo() + lbm_->time_boundary() -
                             t_lbm_[0] - t_lbm_[1] - t_lbm_[2]);
  t_lbm_[0] = lbm_->time_collide(), t_lbm_[1] = lbm_->time_halo(),
  t_lbm_[2] = lbm_->time_boundary();
  ++step_;
  if (step_ % metrics_every_ == 0) {
    auto scope = ctx_.timers.scope("clusters");
    record_metrics();
  }
}

std::vector<grid::Box> SeaweedScenario::sampled_velocity_cells() const {
  // The next step samples the velocity only at its owned spheres, which are where this step left
  // them: the owned ones (their stencils' cells, row by row) and those migrating in from a
  // neighbour, whose stencils read this rank's cells only through that neighbour's ghost layer,
  // i.e. the face layers kept below (a migration moves no sphere). Every other cell may keep an
  // older value; output and restarts recompute all cells.
  const core::Index3 n = decomp_->local_cells();
  std::vector<grid::Box> cells =
      coupling::sampled_cell_rows(*coupling_, bodies_->set(), particles::ParticleSet::kPos, n);
  const int g = lbm_->velocity().ghosts();
  for (int d = 0; d < 3; ++d)
    for (int side = 0; side < 2; ++side) {
      if (decomp_->neighbor(d, side) == MPI_PROC_NULL) continue;
      grid::Box layer{{0, 0, 0}, n};
      if (side == 0)
        layer.hi[d] = g;
      else
        layer.lo[d] = n[d] - g;
      cells.push_back(layer);
    }
  return cells;
}

void SeaweedScenario::write_output() {
  auto scope = ctx_.timers.scope("output");
  lbm_->update_macroscopic();
  io::OutputStep out(*decomp_, ctx_.output_dir, "seaweed", step_, time(), lbm_->units().dx(),
                     {0, 0, 0}, ctx_.config.effective_toml(), "SI: m, s, kg/m^3, m/s, Pa",
                     out_layout_);
  add_lbm_fields(out, *lbm_);
  out.write();
  write_particles();
}

void SeaweedScenario::write_particles() {
  // Owned spheres as points (radius, plant, joint force/torque, velocity); each intact joint as a
  // line from the child to its parent (a ghost parent is appended as an extra point).
  auto& s = bodies_->set();
  const std::size_t no = s.n_owned();
  io::ParticleData d;
  std::vector<std::size_t> src;
  for (std::size_t i = 0; i < no; ++i) src.push_back(i);
  std::unordered_map<core::GlobalId, std::size_t> local;
  for (std::size_t i = 0; i < s.n_total(); ++i) local.emplace(s.id(i), i);
  std::vector<double> line_force, line_torque;
  for (std::size_t i = 0; i < no; ++i) {
    const auto pid = s.u64(bodies_->u_parent)[i];
    if (pid == particles::kNoId) continue;
    auto it = local.find(pid);
    if (it == local.end()) continue;
    std::size_t j = it->second;
    if (j >= no) {
      src.push_back(j);
      j = src.size() - 1;
    }
    d.lines.push_back({static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j)});
    line_force.push_back(s.real(bodies_->a_jforce)[i]);
    line_torque.push_back(s.real(bodies_->a_jtorque)[i]);
  }
  d.owned = no;
  std::vector<double> radius, plant, jf, jt, vel;
  for (std::size_t k : src) {
    const Vec3 p = s.pos(k), v = s.vec3(bodies_->a_vel, k);
    d.positions.insert(d.positions.end(), {p.x, p.y, p.z});
    d.ids.push_back(s.id(k));
    radius.push_back(s.real(bodies_->a_radius)[k]);
    plant.push_back(static_cast<double>(s.u64(bodies_->u_plant)[k]));
    jf.push_back(s.real(bodies_->a_jforce)[k]);
    jt.push_back(s.real(bodies_->a_jtorque)[k]);
    vel.insert(vel.end(), {v.x, v.y, v.z});
  }
  d.scalars = {{"radius", std::move(radius)},
               {"plant", std::move(plant)},
               {"joint_force", std::move(jf)},
               {"joint_torque", std::move(jt)}};
  d.vectors = {{"velocity", std::move(vel)}};
  d.line_scalars = {{"joint_force", std::move(line_force)},
                    {"joint_torque", std::move(line_torque)}};
  io::ParticleOutput out(ctx_.comm, ctx_.output_dir, "seaweed_particles", step_, time(),
                         ctx_.config.effective_toml(), out_layout_.compression);
  out.write(d);
}

void SeaweedScenario::write_checkpoint(const std::string& path) {
  auto scope = ctx_.timers.scope("checkpoint");
  io::CheckpointWriter w(*decomp_, path);
  w.write_attribute("scenario", std::string("seaweed"));
  w.write_attribute("config", ctx_.config.effective_toml());
  w.write_attribute("seaweed_step", static_cast<std::int64_t>(step_));
  w.write_attribute("seaweed_broken_joints", static_cast<std::int64_t>(last_broken_total()));
  // The force field of the last step enters the velocity the next step samples.
  w.write_field("seaweed_lbm_force", lbm_->force(), 0, 3);
  lbm_->write_checkpoint(w);
  // Particles: every migrating column, one row per owned sphere (ids travel bit-exactly).
  auto& s = bodies_->set();
  const int width = s.pack_width(false);
  std::vector<double> rows;
  for (std::size_t i = 0; i < s.n_owned(); ++i) s.pack(i, false, rows);
  w.write_rows("seaweed_particles", rows, width);
  w.commit();
}

void SeaweedScenario::read_checkpoint(const std::string& path) {
  io::CheckpointReader r(*decomp_, path);
  r.read_field("seaweed_lbm_force", lbm_->force(), 0, 3);  // before the LBM's macroscopic update
  lbm_->read_checkpoint(r);
  step_ = r.read_attribute_int("seaweed_step");
  const long long broken = r.read_attribute_int("seaweed_broken_joints");
  bodies_->broken_local() = decomp_->rank() == 0 ? broken : 0;  // summed over ranks in metrics
  // Each rank reads its share of the rows (the constructor already did for the restart it cut
  // the grid for); the redistribution sends them to their owners.
  int width = restart_width_;
  std::vector<double> rows;
  if (path == ctx_.restart_path && restart_rows_read_) {  // the same on every rank
    rows.swap(restart_rows_);
    restart_rows_read_ = false;
  } else {
    rows = r.read_rows_share("seaweed_particles", width);
    mp::to_current_seaweed_rows(rows, width, path, decomp_->comm());
  }
  auto& s = bodies_->set();
  const std::size_t n = rows.size() / width;
  s.resize(n, n);
  for (std::size_t k = 0; k < n; ++k) s.unpack(k, false, rows.data() + k * width);
  pcomm_->redistribute(s);
  bodies_->begin_step();
  last_ = bodies_->clusters();
}

long long SeaweedScenario::last_broken_total() {
  long long b = bodies_->broken_local();
  MPI_Allreduce(MPI_IN_PLACE, &b, 1, MPI_LONG_LONG, MPI_SUM, ctx_.comm);
  return b;
}

void SeaweedScenario::check_spheres_finite() {
  // Collective, so every rank throws together (a throw on one rank alone would leave the others
  // waiting in the next collective).
  const auto& s = bodies_->set();
  std::uint64_t bad = ~std::uint64_t{0};
  for (std::size_t i = 0; i < s.n_owned(); ++i) {
    const Vec3 p = s.pos(i);
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      bad = std::min(bad, s.id(i));
  }
  MPI_Allreduce(MPI_IN_PLACE, &bad, 1, MPI_UINT64_T, MPI_MIN, ctx_.comm);
  if (bad != ~std::uint64_t{0})
    throw core::UnstableError(fmt::format(
        "seaweed: sphere {} non-finite at step {} (typical causes: plants grown through the tank "
        "walls, see the start-up warning; two-way coupling of a dense lump; docs/seaweed.md)",
        bad, step_));
}

void SeaweedScenario::check_health() {
  lbm_->check_health();
  check_spheres_finite();
}

std::string SeaweedScenario::progress() {
  std::string s =
      fmt::format("clusters {} largest {:.2f} contacts {} broken {} lists {} filters {}",
                  last_.clusters, last_.largest_share, last_.contacts, last_.broken_joints,
                  bodies_->rebuilds(), bodies_->filters());
  // Joints whose partner was beyond the ghost cutoff at the last list build (normally none).
  if (last_.skipped_joints > 0) s += fmt::format(" SKIPPED-JOINTS {}", last_.skipped_joints);
  return s;
}

std::vector<std::string> SeaweedScenario::timer_sections() const {
  return {"growth",   "lbm",      "lbm_macroscopic", "particles",
          "coupling", "clusters", "output",          "checkpoint"};
}

}  // namespace biota::scenarios
