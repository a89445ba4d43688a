#pragma once
/// \file seaweed_scenario.hpp
/// \brief The seaweed paper's experiment: a population of Ulva grown for `growth.cycles` cycles,
/// turned into rigid-sphere bodies and put into the LBM fountain tank. Physics step 1/60 s with
/// the LBM sub-cycled; drag coupling two-way by default (`seaweed.two_way = false`: the paper's
/// one-way setting). Entanglement metrics go to <output.dir>/seaweed_clusters.csv.
#include <fstream>
#include <memory>

#include "coupling/trilinear_coupling.hpp"
#include "grid/decomposition.hpp"
#include "grid/halo_exchange.hpp"
#include "io/csv_series.hpp"
#include "io/output_layout.hpp"
#include "models/plants/seaweed_mechanics.hpp"
#include "particles/particle_comm.hpp"
#include "scenarios/scenario.hpp"
#include "solvers/lbm/lbm_solver.hpp"

namespace biota::scenarios {

/// \brief Seaweed population in the LBM tank.
class SeaweedScenario : public Scenario {
 public:
  static void declare_config(core::ConfigSchema& schema);
  explicit SeaweedScenario(const RunContext& ctx);

  void step() override;
  long long step_index() const override { return step_; }
  double time() const override { return step_ * dt_; }
  double dt() const override { return dt_; }
  void write_output() override;
  void write_checkpoint(const std::string& path) override;
  void read_checkpoint(const std::string& path) override;
  void check_health() override;
  std::string progress() override;
  std::vector<std::string> timer_sections() const override;
  /// \brief The plant bodies (tests and diagnostics).
  const models::plants::SeaweedBodies& bodies() const { return *bodies_; }
  /// \brief The fluid solver (tests and diagnostics).
  const solvers::lbm::LbmSolver& lbm() const { return *lbm_; }
  core::CommCounter comm_sent() const override {
    core::CommCounter c = lbm_->halo_sent();
    c += pcomm_->sent();
    return c;
  }

 private:
  void write_particles();
  void record_metrics();
  void open_csv();
  void check_spheres_finite();
  void check_particle_halo(const models::plants::MechanicsParams& mpar, double dx);
  /// Spheres per plane of cells along each axis the rank grid `dims` splits (others empty), the
  /// same on every rank: of the grown population, or on a restart of the checkpoint's spheres
  /// (they drift; this rank's share of the rows is kept in restart_rows_). Collective.
  std::array<std::vector<double>, 3> spheres_per_plane(const core::Index3& dims,
                                                       const solvers::lbm::LbmParams& params,
                                                       const models::plants::Population& pop,
                                                       double spacing);
  std::vector<double> restart_rows_;  // this rank's share of the restart's particle rows
  int restart_width_ = 0;
  bool restart_rows_read_ = false;  // collective decision: a rank's share may be empty
  std::vector<double> rank_speed_;  // measured at start-up (seaweed.balance.rank_speed)
  long long last_broken_total();
  /// \brief Owned cells whose velocity the next step's sampling reads (directly or as a
  /// neighbour's ghosts): local boxes for LbmSolver::update_macroscopic.
  std::vector<grid::Box> sampled_velocity_cells() const;

  RunContext ctx_;
  io::OutputLayout out_layout_;  ///< output.region/stride/chunk/compression of the LBM fields
  std::unique_ptr<grid::Decomposition> decomp_;
  std::unique_ptr<solvers::lbm::LbmSolver> lbm_;
  std::unique_ptr<particles::ParticleComm> pcomm_;
  std::unique_ptr<coupling::TrilinearCoupling> coupling_;
  std::unique_ptr<models::plants::SeaweedBodies> bodies_;
  double dt_ = 1.0 / 60;
  int lbm_substeps_ = 10;
  bool two_way_ = true;
  int metrics_every_ = 6;
  int n_plants_ = 0;
  long long step_ = 0;
  models::plants::ClusterMetrics last_{};
  io::CsvSeries csv_;
  bool csv_started_ = false;
  double t_lbm_[3] = {0, 0, 0};
};

}  // namespace biota::scenarios
