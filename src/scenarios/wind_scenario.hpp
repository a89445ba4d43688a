#pragma once
/// \file wind_scenario.hpp
/// \brief Wind over open ground (tree paper section 4, tree.md 2.3): the staggered MAC solver in a
/// box sized for the 6.67 m tree, log-law inflow, convective outflow, rough ground. The tree
/// itself arrives in a later issue and will push on the wind through MacSolver::force().
#include <memory>

#include "grid/decomposition.hpp"
#include "io/checkpoint.hpp"
#include "io/output_layout.hpp"
#include "scenarios/scenario.hpp"
#include "solvers/mac/mac_solver.hpp"

namespace biota::scenarios {

/// \brief Read the wind.* keys into solver parameters (throws core::InputError naming the key).
solvers::mac::MacParams wind_params_from_config(const core::Config& cfg);

/// \brief MAC-only wind scenario. One scenario step is `wind.step_time` seconds, made of as many
/// adaptive solver steps as the CFL and viscous limits require (the last one shortened).
class WindScenario : public Scenario {
 public:
  static void declare_config(core::ConfigSchema& schema);
  explicit WindScenario(const RunContext& ctx);
  ~WindScenario() override;

  void step() override;
  long long step_index() const override { return step_; }
  double time() const override { return mac_->time(); }
  double dt() const override { return step_time_; }
  void write_output() override;
  void write_checkpoint(const std::string& path) override;
  void read_checkpoint(const std::string& path) override;
  void check_health() override;
  std::string progress() override;
  std::vector<std::string> timer_sections() const override;

  solvers::mac::MacSolver& solver() { return *mac_; }
  core::CommCounter comm_sent() const override { return mac_->halo_sent(); }

 protected:
  /// \brief Name stored in (and required of) checkpoints: "wind" here.
  virtual std::string checkpoint_name() const { return "wind"; }
  /// \brief Extra state a derived scenario stores in / restores from the wind's checkpoint.
  virtual void write_extra(io::CheckpointWriter&) {}
  virtual void read_extra(io::CheckpointReader&) {}

  /// \brief Solver steps allowed in one scenario step: more at the start is an input error
  /// (check_solver_steps), later an instability.
  static constexpr double kMaxSolverSteps = 1e5;
  /// \brief Fails (the binding limit's key, value, least allowed value) when the solver steps
  /// at the start would exceed kMaxSolverSteps per scenario step.
  void check_solver_steps(const core::Config& cfg, const solvers::mac::MacParams& p,
                          const solvers::mac::StepStats& st) const;

  RunContext ctx_;
  io::OutputLayout out_layout_;  ///< output.region/stride/chunk/compression of the wind fields
  std::unique_ptr<grid::Decomposition> decomp_;
  std::unique_ptr<solvers::mac::MacSolver> mac_;
  double step_time_ = 0.05, air_density_ = 1.2;
  bool owns_petsc_ = false;  ///< this scenario started PETSc, so its destructor finalises it
  long long step_ = 0, substeps_ = 0, last_substeps_ = 0;
  long long poisson_its_ = 0, last_poisson_its_ = 0;
};

}  // namespace biota::scenarios
