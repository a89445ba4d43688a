#pragma once
/// \file tank_scenario.hpp
/// \brief The seaweed paper's water tank: 100^3 LBM with an upward fountain jet from the bottom
/// that drives a vertical recirculation (docs/lbm.md gives the chosen geometry and speeds).
#include <memory>

#include "grid/decomposition.hpp"
#include "io/output_layout.hpp"
#include "scenarios/scenario.hpp"
#include "solvers/lbm/lbm_solver.hpp"

namespace biota::scenarios {

/// \brief LBM-only tank scenario.
class TankScenario : public Scenario {
 public:
  static void declare_config(core::ConfigSchema& schema);
  explicit TankScenario(const RunContext& ctx);

  void step() override;
  long long step_index() const override { return lbm_->step_index(); }
  double time() const override { return lbm_->time(); }
  double dt() const override { return lbm_->units().dt(); }
  void write_output() override;
  void write_checkpoint(const std::string& path) override;
  void read_checkpoint(const std::string& path) override;
  void check_health() override { lbm_->check_health(); }
  void poison_for_test() override { lbm_->poison_for_test(); }
  core::CommCounter comm_sent() const override { return lbm_->halo_sent(); }
  std::string progress() override;
  std::vector<std::string> timer_sections() const override;

 private:
  RunContext ctx_;
  io::OutputLayout out_layout_;  ///< output.region/stride/chunk/compression of the LBM fields
  std::unique_ptr<grid::Decomposition> decomp_;
  std::unique_ptr<solvers::lbm::LbmSolver> lbm_;
  double last_updates_ = 0, last_wall_ = 0;
  double t_collide_ = 0, t_halo_ = 0, t_boundary_ = 0;
};

}  // namespace biota::scenarios
