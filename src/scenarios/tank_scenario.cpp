#include "scenarios/tank_scenario.hpp"

#include <fmt/format.h>

#include "io/checkpoint.hpp"
#include "io/output_step.hpp"
#include "scenarios/lbm_output.hpp"

namespace biota::scenarios {

void TankScenario::declare_config(core::ConfigSchema& schema) {
  solvers::lbm::LbmSolver::declare_config(schema);
}

TankScenario::TankScenario(const RunContext& ctx) : ctx_(ctx) {
  auto params = solvers::lbm::LbmParams::from_config(ctx.config);
  decomp_ = std::make_unique<grid::Decomposition>(
      ctx.comm, params.cells, params.periodic(), core::Index3{0, 0, 0},
      grid::GridKeys{ctx.config.source(), {"lbm.nx", "lbm.ny", "lbm.nz"}});
  out_layout_ = grid_output_layout(ctx.config, *decomp_, params.dx, {0, 0, 0});
  core::check_memory(ctx.comm, ctx.config,
                     solvers::lbm::LbmSolver::memory_estimate(*decomp_, params),
                     "lbm.nx x lbm.ny x lbm.nz = " + std::to_string(params.cells.x) + " x " +
                         std::to_string(params.cells.y) + " x " + std::to_string(params.cells.z) +
                         " cells (" + params.lattice + ")");
  lbm_ = std::make_unique<solvers::lbm::LbmSolver>(*decomp_, params);
  if (decomp_->rank() == 0)
    fmt::print("{}\ndecomposition: {} x {} x {} ranks\n", lbm_->units().summary(),
               decomp_->dims().x, decomp_->dims().y, decomp_->dims().z);
  last_wall_ = MPI_Wtime();
}

void TankScenario::step() {
  lbm_->step(false);
  // Move the solver's cumulative section times into the run's timing table.
  ctx_.timers.add("lbm collide+stream", lbm_->time_collide() - t_collide_);
  ctx_.timers.add("lbm halo exchange", lbm_->time_halo() - t_halo_);
  ctx_.timers.add("lbm boundaries", lbm_->time_boundary() - t_boundary_);
  t_collide_ = lbm_->time_collide();
  t_halo_ = lbm_->time_halo();
  t_boundary_ = lbm_->time_boundary();
}

void TankScenario::write_output() {
  auto scope = ctx_.timers.scope("output");
  lbm_->update_macroscopic();
  io::OutputStep out(*decomp_, ctx_.output_dir, "tank", lbm_->step_index(), lbm_->time(),
                     lbm_->units().dx(), {0, 0, 0}, ctx_.config.effective_toml(),
                     "SI: m, s, kg/m^3, m/s, Pa", out_layout_);
  add_lbm_fields(out, *lbm_);
  out.write();
}

void TankScenario::write_checkpoint(const std::string& path) {
  auto scope = ctx_.timers.scope("checkpoint");
  io::CheckpointWriter w(*decomp_, path);
  w.write_attribute("scenario", std::string("tank"));
  w.write_attribute("config", ctx_.config.effective_toml());
  lbm_->write_checkpoint(w);
  w.commit();
}

void TankScenario::read_checkpoint(const std::string& path) {
  io::CheckpointReader r(*decomp_, path);
  lbm_->read_checkpoint(r);
}

std::string TankScenario::progress() {
  double updates = lbm_->cell_updates(), total = 0;
  MPI_Allreduce(&updates, &total, 1, MPI_DOUBLE, MPI_SUM, ctx_.comm);
  double now = MPI_Wtime();
  double mlups = (total - last_updates_) / (now - last_wall_) / 1e6;
  last_updates_ = total;
  last_wall_ = now;
  return fmt::format("MLUPS {:7.1f}", mlups);
}

std::vector<std::string> TankScenario::timer_sections() const {
  return {"lbm collide+stream", "lbm halo exchange", "lbm boundaries", "output", "checkpoint"};
}

}  // namespace biota::scenarios
