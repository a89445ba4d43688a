#include "scenarios/wind_scenario.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/memory.hpp"
#include "grid/halo_exchange.hpp"
#include "io/checkpoint.hpp"
#include "io/output_step.hpp"
#include "linalg/petsc_environment.hpp"
#include "scenarios/lbm_output.hpp"

namespace biota::scenarios {

using solvers::mac::BoundaryType;

void WindScenario::declare_config(core::ConfigSchema& s) {
  s.add_int("wind.nx", 80, 1, 100000, "cells along x (the wind direction)");
  s.add_int("wind.ny", 40, 1, 100000, "cells along y (crosswind)");
  s.add_int("wind.nz", 40, 1, 100000, "cells along z (vertical)");
  s.add_real("wind.dx", 0.4, 0.0, std::nullopt, "m", "cubic cell size", true);
  s.add_real("wind.viscosity", 1.5e-5, 0.0, std::nullopt, "m^2/s",
             "kinematic viscosity nu (air: 1.5e-5)");
  s.add_real("wind.reynolds_number", 0.0, 0.0, std::nullopt, "-",
             "if > 0: viscosity = U L / Re replaces wind.viscosity, with U the largest noslip wall "
             "speed (else the inflow speed) and L = wind.nx * wind.dx (the lid-driven cavity)",
             true);
  s.add_real("wind.air_density", 1.2, 0.0, std::nullopt, "kg/m^3",
             "air density (turns phi = p/rho into Pa for output)", true);
  s.add_real("wind.cfl", 0.5, 0.0, 1.0, "-", "advective CFL number of the adaptive dt", true);
  s.add_real("wind.diffusion_number", 1.0 / 6, 0.0, 0.25, "-",
             "nu dt / dx^2 limit of the adaptive dt (1/6: 3D explicit limit)", true);
  s.add_real("wind.dt_max", 1e30, 0.0, std::nullopt, "s", "largest solver time step", true);
  s.add_real("wind.step_time", 0.05, 0.0, std::nullopt, "s",
             "scenario step (coupling/output unit); made of adaptive solver steps", true);
  s.add_string("wind.time_scheme", "rk2", {"rk2", "euler"},
               "rk2: SSP-RK2 with a projection per stage (2nd order); euler: the paper's eq. 17");
  const char* faces[6] = {"x_lo", "x_hi", "y_lo", "y_hi", "z_lo", "z_hi"};
  const char* defaults[6] = {"inflow",  "convective_outflow", "periodic", "periodic", "ground",
                             "freeslip"};
  for (int f = 0; f < 6; ++f) {
    s.add_string(std::string("wind.boundary.") + faces[f], defaults[f],
                 solvers::mac::boundary_type_names(),
                 std::string("boundary condition of the ") + faces[f] + " face");
    s.add_real_list(std::string("wind.boundary.") + faces[f] + "_velocity",
                    std::vector<double>{0, 0, 0}, 3, "m/s",
                    std::string("wall velocity of a noslip ") + faces[f] + " face (moving lid)");
  }
  s.add_string("wind.inflow.profile", "log", {"uniform", "log"},
               "inflow profile: uniform speed, or the neutral log law U_ref ln(z/z0)/ln(z_ref/z0)");
  s.add_real("wind.inflow.speed", 5.0, 0.0, std::nullopt, "m/s",
             "inflow speed (uniform) or speed at the reference height (log)");
  s.add_real("wind.inflow.reference_height", 10.0, 0.0, std::nullopt, "m",
             "reference height z_ref of the log profile", true);
  s.add_real("wind.inflow.roughness_length", 0.03, 0.0, std::nullopt, "m",
             "roughness length z0 of the log profile (0.03: open flat terrain)", true);
  s.add_real("wind.ground.roughness_length", 0.03, 0.0, std::nullopt, "m",
             "roughness length of 'ground' faces (log-law wall stress)", true);
  s.add_real_list("wind.initial_velocity", std::vector<double>{0, 0, 0}, 3, "m/s",
                  "initial velocity where there is no inflow profile to start from");
  s.add_bool("wind.initial_from_inflow", true,
             "start from the inflow profile extended through the box (then projected)");
  s.add_real_list("wind.body_force", std::vector<double>{0, 0, 0}, 3, "m/s^2",
                  "uniform body force per unit mass");
  s.add_string(
      "wind.poisson_options", "", {},
      "PETSc options of the pressure solve, all under -poisson_ (default: -poisson_ksp_type "
      "cg -poisson_pc_type gmg (matrix-free geometric multigrid), stopping when the divergence "
      "after projection is <= 1e-10 relative or at rtol 1e-10; an explicit "
      "-poisson_ksp_rtol/_atol keeps KSP's test alone; also pfmg (hypre), gamg, hypre "
      "(BoomerAMG), mg (cell-centred Galerkin PCMG)); the command line after -- wins");
}

solvers::mac::MacParams wind_params_from_config(const core::Config& cfg) {
  solvers::mac::MacParams p;
  p.cells = {static_cast<int>(cfg.get_int("wind.nx")), static_cast<int>(cfg.get_int("wind.ny")),
             static_cast<int>(cfg.get_int("wind.nz"))};
  p.dx = cfg.get_real("wind.dx");
  p.viscosity = cfg.get_real("wind.viscosity");
  p.cfl = cfg.get_real("wind.cfl");
  p.diffusion_number = cfg.get_real("wind.diffusion_number");
  p.dt_max = cfg.get_real("wind.dt_max");
  p.scheme = cfg.get_string("wind.time_scheme") == "euler" ? solvers::mac::TimeScheme::kEuler
                                                           : solvers::mac::TimeScheme::kRK2;
  for (int a = 0; a < 3; ++a)
    for (int side = 0; side < 2; ++side) {
      const std::string key = "wind.boundary." + solvers::mac::face_name(a, side);
      p.boundaries[a][side].type = solvers::mac::parse_boundary_type(cfg.get_string(key), key);
      // Only a noslip wall moves; read the velocity there alone, so that one given for another
      // kind of face is reported as unused (Config::unused_given_keys) instead of ignored.
      if (p.boundaries[a][side].type != solvers::mac::BoundaryType::kNoSlip) continue;
      const auto& w = cfg.get_real_list(key + "_velocity");
      p.boundaries[a][side].wall_velocity = {w[0], w[1], w[2]};
    }
  solvers::mac::validate(p.boundaries, "wind.boundary.");
  p.inflow.kind = cfg.get_string("wind.inflow.profile") == "log"
                      ? solvers::mac::InflowProfile::kLog
                      : solvers::mac::InflowProfile::kUniform;
  p.inflow.speed = cfg.get_real("wind.inflow.speed");
  p.inflow.reference_height = cfg.get_real("wind.inflow.reference_height");
  p.inflow.roughness_length = cfg.get_real("wind.inflow.roughness_length");
  p.ground_roughness = cfg.get_real("wind.ground.roughness_length");
  bool any_ground = false;
  for (const auto& axis : p.boundaries)
    for (const auto& face : axis) any_ground |= face.type == BoundaryType::kGround;
  if (any_ground && p.ground_roughness >= 0.5 * p.dx)
    cfg.fail("wind.ground.roughness_length",
             fmt::format("must be below half a cell (dx/2 = {} m) for the log-law wall stress",
                         0.5 * p.dx));
  const auto& iv = cfg.get_real_list("wind.initial_velocity");
  p.initial_velocity = {iv[0], iv[1], iv[2]};
  p.initial_from_inflow = cfg.get_bool("wind.initial_from_inflow");
  const auto& bf = cfg.get_real_list("wind.body_force");
  p.body_force = {bf[0], bf[1], bf[2]};
  if (const double re = cfg.get_real("wind.reynolds_number"); re > 0) {
    double u = 0;
    bool any_inflow = false;
    for (const auto& axis : p.boundaries)
      for (const auto& face : axis) {
        if (face.type == BoundaryType::kNoSlip)
          u = std::max(u, std::sqrt(core::dot(face.wall_velocity, face.wall_velocity)));
        any_inflow |= face.type == BoundaryType::kInflow;
      }
    if (u == 0 && any_inflow) u = p.inflow.speed;
    if (u == 0)
      cfg.fail("wind.reynolds_number",
               "needs a velocity scale: a moving noslip wall (<face>_velocity) or an inflow");
    p.viscosity = u * p.cells.x * p.dx / re;
  }
  p.poisson_options = cfg.get_string("wind.poisson_options");
  p.poisson_options_key = "wind.poisson_options";
  return p;
}

WindScenario::WindScenario(const RunContext& ctx) : ctx_(ctx) {
  auto p = wind_params_from_config(ctx.config);
  step_time_ = ctx.config.get_real("wind.step_time");
  air_density_ = ctx.config.get_real("wind.air_density");
  owns_petsc_ = !linalg::initialized();  // whoever starts PETSc ends it
  linalg::initialize(ctx.solver_options);
  std::array<bool, 3> periodic;
  for (int a = 0; a < 3; ++a) periodic[a] = p.boundaries[a][0].type == BoundaryType::kPeriodic;
  const grid::GridKeys keys{ctx.config.source(), {"wind.nx", "wind.ny", "wind.nz"}};
  decomp_ = std::make_unique<grid::Decomposition>(ctx.comm, p.cells, periodic,
                                                  core::Index3{0, 0, 0}, keys);
  grid::check_halo_width(*decomp_, solvers::mac::MacSolver::kGhosts, keys);
  out_layout_ = grid_output_layout(ctx.config, *decomp_, p.dx, {0, 0, 0});
  core::check_memory(ctx.comm, ctx.config, solvers::mac::MacSolver::memory_estimate(*decomp_),
                     "wind.nx x wind.ny x wind.nz = " + std::to_string(p.cells.x) + " x " +
                         std::to_string(p.cells.y) + " x " + std::to_string(p.cells.z) + " cells");
  mac_ = std::make_unique<solvers::mac::MacSolver>(*decomp_, p, ctx.timers);
  try {
    mac_->project_initial();
  } catch (const core::UnstableError& e) {
    throw core::UnstableError(
        fmt::format("wind: the initial projection: {}; check wind.dx and the "
                    "initial and inflow velocities",
                    e.what()));
  }
  const auto st = mac_->next_dt();
  check_solver_steps(ctx.config, p, st);
  int rank = 0;
  MPI_Comm_rank(ctx.comm, &rank);
  if (rank == 0)
    fmt::print(
        "wind: {}x{}x{} cells of {} m on {}x{}x{} ranks, viscosity {:.6g} m^2/s, Poisson: {}\n"
        "wind: time step limits at start: CFL {:.4g} s, viscous {:.4g} s -> dt {:.4g} s "
        "(scenario step {} s)\n",
        p.cells.x, p.cells.y, p.cells.z, p.dx, decomp_->dims().x, decomp_->dims().y,
        decomp_->dims().z, p.viscosity, mac_->poisson_description(), st.dt_cfl, st.dt_viscous,
        st.dt, step_time_);
}

void WindScenario::check_solver_steps(const core::Config& cfg, const solvers::mac::MacParams& p,
                                      const solvers::mac::StepStats& st) const {
  // A deck whose limits give millions of solver steps per scenario step does not hang: it stops
  // here, naming the limit that binds (the same on every rank: the limits are global minima).
  // Each limit is proportional to its key, so the key times `factor` would do.
  const double steps = step_time_ / st.dt;
  if (!(steps > kMaxSolverSteps) || p.fixed_dt > 0) return;
  const double factor = steps / kMaxSolverSteps;
  const auto fail = [&](const std::string& key, const std::string& limit, const std::string& fix) {
    cfg.fail(key, fmt::format("gives solver steps of {:.3g} s at the start ({}), {:.3g} per "
                              "wind.step_time = {:.6g} s; allowed: at most {:.0f} per scenario "
                              "step: {}",
                              st.dt, limit, steps, step_time_, kMaxSolverSteps, fix));
  };
  if (st.dt == p.dt_max)
    fail("wind.dt_max", "its cap", fmt::format("wind.dt_max >= {:.3g} s", p.dt_max * factor));
  if (st.dt_cfl <= st.dt_viscous)
    fail("wind.cfl", "the advective limit",
         p.cfl * factor <= 1 ? fmt::format("wind.cfl >= {:.3g}", p.cfl * factor)
                             : "no CFL number in (0, 1] gives so few for the flow at the start "
                               "on these cells (wind.dx, the inflow or initial velocity)");
  // The viscous limit: diffusion_number dx^2 / viscosity, with diffusion_number at most 0.25.
  const double re = cfg.get_real("wind.reynolds_number"),
               nu_max = p.viscosity * 0.25 / (p.diffusion_number * factor);
  fail(re > 0 ? "wind.reynolds_number" : "wind.viscosity",
       fmt::format("the viscous limit of viscosity {:.3g} m^2/s with wind.diffusion_number = {}",
                   p.viscosity, p.diffusion_number),
       re > 0 ? fmt::format("wind.reynolds_number >= {:.3g} (with wind.diffusion_number = 0.25)",
                            re * p.viscosity / nu_max)
              : fmt::format("wind.viscosity <= {:.3g} m^2/s (with wind.diffusion_number = 0.25)",
                            nu_max));
}

WindScenario::~WindScenario() {
  mac_.reset();  // PETSc objects go before PETSc itself
  if (owns_petsc_) linalg::finalize();
}

void WindScenario::step() {
  const double target = (step_ + 1) * step_time_;
  // Solver steps until the scenario time is reached; the last one is shortened to land on it.
  // Steps that shrink without bound (a flow speeding up, e.g. under a forcing the air cannot
  // carry) stop the run instead of hanging it; dt is global, so every rank stops alike.
  const auto unstable = [&](const std::string& what) {
    return core::UnstableError(
        fmt::format("wind: at step {} (t = {:.6g} s): {}; reduce wind.cfl "
                    "or wind.dt_max, or the forcing",
                    step_, mac_->time(), what));
  };
  long long steps = 0;
  while (target - mac_->time() > 1e-12 * step_time_) {
    if (++steps > kMaxSolverSteps)
      throw unstable(fmt::format("more than {:.0f} solver steps in one scenario step (dt {:.3g} s)",
                                 kMaxSolverSteps, mac_->last_stats().dt));
    try {
      mac_->step(target - mac_->time());
    } catch (const core::UnstableError& e) {
      throw unstable(e.what());
    }
    ++substeps_;
    poisson_its_ += mac_->last_stats().poisson_iterations;
  }
  mac_->set_clock(target, mac_->step_index());
  ++step_;
}

void WindScenario::write_output() {
  auto scope = ctx_.timers.scope("output");
  io::OutputStep out(*decomp_, ctx_.output_dir, "wind", step_, mac_->time(), mac_->params().dx,
                     {0, 0, 0}, ctx_.config.effective_toml(), "SI: m, s, m/s, Pa, 1/s",
                     out_layout_);
  out.add_vector("velocity", mac_->cell_velocity(), "m/s");
  auto p = mac_->cell_pressure();
  for (auto& v : p) v *= air_density_;
  out.add_scalar("pressure", std::move(p), "Pa");
  out.add_scalar("vorticity_magnitude", mac_->vorticity_magnitude(), "1/s");
  out.add_scalar("divergence", mac_->divergence(), "1/s");
  out.write();
}

void WindScenario::write_checkpoint(const std::string& path) {
  auto scope = ctx_.timers.scope("checkpoint");
  io::CheckpointWriter w(*decomp_, path);
  w.write_attribute("scenario", checkpoint_name());
  w.write_attribute("config", ctx_.config.effective_toml());
  w.write_attribute("time", mac_->time());
  w.write_attribute("step", static_cast<std::int64_t>(step_));
  w.write_attribute("solver_step", static_cast<std::int64_t>(mac_->step_index()));
  w.write_field("wind_velocity", mac_->velocity(), 0, 3);
  w.write_field("wind_pressure", mac_->pressure(), 0, 1);
  w.write_rows("wind_boundary_faces", mac_->boundary_face_rows(), 5);
  write_extra(w);
  w.commit();
}

void WindScenario::read_checkpoint(const std::string& path) {
  io::CheckpointReader r(*decomp_, path);
  if (r.read_attribute_string("scenario") != checkpoint_name())
    throw core::InputError(path + ": not a " + checkpoint_name() + " checkpoint");
  r.read_field("wind_velocity", mac_->velocity(), 0, 3);
  r.read_field("wind_pressure", mac_->pressure(), 0, 1);
  int ncols = 0;
  mac_->set_boundary_face_rows(r.read_all_rows("wind_boundary_faces", ncols));
  step_ = r.read_attribute_int("step");
  mac_->set_clock(r.read_attribute_real("time"), r.read_attribute_int("solver_step"));
  mac_->refresh();
  read_extra(r);
}

void WindScenario::check_health() {
  if (!mac_->finite())
    throw core::UnstableError(fmt::format(
        "wind: non-finite velocity at step {} (t = {:.6g} s); reduce wind.cfl or wind.dt_max",
        step_, mac_->time()));
}

std::string WindScenario::progress() {
  const auto& s = mac_->last_stats();
  const auto m = mac_->max_speed();
  const long long sub = substeps_ - last_substeps_, its = poisson_its_ - last_poisson_its_;
  last_substeps_ = substeps_;
  last_poisson_its_ = poisson_its_;
  return fmt::format(
      "dt {:.3g} s (CFL limit {:.3g}, viscous limit {:.3g}) substeps {} Poisson its/solve {:.1f} "
      "|u|max {:.3g} m/s div {:.1e}",
      s.dt, s.dt_cfl, s.dt_viscous, sub,
      sub ? double(its) /
                double(sub * (mac_->params().scheme == solvers::mac::TimeScheme::kRK2 ? 2 : 1))
          : 0.0,
      std::max({m.x, m.y, m.z}), s.max_divergence);
}

std::vector<std::string> WindScenario::timer_sections() const {
  return {"wind.advection", "wind.diffusion", "wind.poisson", "wind.correction",
          "wind.halo",      "wind.boundary",  "output",       "checkpoint"};
}

}  // namespace biota::scenarios
