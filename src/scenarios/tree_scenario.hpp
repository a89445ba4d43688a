#pragma once
/// \file tree_scenario.hpp
/// \brief Trees swaying in the MAC wind (tree paper sections 3-6; docs/tree.md): a stand of
/// node-link trees grown from L-system files, two-way coupled to the wind scenario's staggered
/// MAC solver through coupling::MacCoupling (eq. 19 in 3D) and coupling::RemoteSamples.
///
/// Parallel layout: a tree is owned whole by the rank whose box holds its root (the length
/// correction (11) runs root to tips through the whole tree); its nodes are sampled and spread
/// as particles on the ranks whose boxes hold them, so a tree may span any number of ranks.
/// Every tree's update depends only on its own state and the wind at its nodes, and the
/// spreading is ordered by global node id, so the stand evolves bitwise the same on any rank
/// count whenever the wind does (docs/tree.md "Decomposition invariance").
///
/// One scenario step is wind.step_time: wind sampled at the nodes, tree.substeps tree steps with
/// that wind, the reaction -K_b F_w (F_w averaged over the sub-steps) spread at the sampling
/// points into the MAC body force (per unit mass: / (rho_air dx^3)), then the wind step.
#include <memory>
#include <set>
#include <utility>
#include <vector>

#include "coupling/mac_coupling.hpp"
#include "coupling/remote_samples.hpp"
#include "io/csv_series.hpp"
#include "models/plants/branch_contacts.hpp"
#include "models/plants/tree_stand.hpp"
#include "particles/particle_comm.hpp"
#include "scenarios/wind_scenario.hpp"

namespace biota::scenarios {

/// \brief The `tree` scenario; see the file comment.
class TreeScenario : public WindScenario {
 public:
  static void declare_config(core::ConfigSchema& schema);
  explicit TreeScenario(const RunContext& ctx);

  void step() override;
  void write_output() override;
  void check_health() override;
  std::string progress() override;
  std::vector<std::string> timer_sections() const override;
  core::CommCounter comm_sent() const override {
    core::CommCounter c = WindScenario::comm_sent();
    c += pcomm_->sent();
    return c;
  }

  /// \brief The trees this rank owns and their sites (tests, diagnostics).
  const std::vector<models::plants::NodeLinkTree>& trees() const { return trees_; }
  const std::vector<models::plants::TreeSite>& owned_sites() const { return owned_; }
  const std::vector<models::plants::TreeSite>& sites() const { return sites_; }
  /// \brief Sum over every node of every tree of the wind force F_w (3) of the last step (N),
  /// averaged over its sub-steps. Collective.
  core::Vec3 total_wind_force() const;
  /// \brief Branch contacts found in the last step (all ranks).
  long long last_contacts() const { return last_contacts_; }
  /// \brief K_b (tree.k_branch), air density (kg/m^3) and cell size (m).
  double k_branch() const { return k_branch_; }
  double air_density() const { return air_density_; }
  /// \brief Tip displacement (m) of the owned tree with index t: |P - P(0)| of its highest node.
  double tip_displacement(std::size_t t) const;

 protected:
  std::string checkpoint_name() const override { return "tree"; }
  void write_extra(io::CheckpointWriter& w) override;
  void read_extra(io::CheckpointReader& r) override;

 private:
  void open_csv();
  void record_csv();
  /// \brief Branch contact forces on the nodes of every owned tree (every rank sees every link:
  /// one all-gather of the capsules per scenario step). Collective.
  void contact_forces(std::vector<std::vector<core::Vec3>>& extra);

  std::unique_ptr<particles::ParticleComm> pcomm_;
  std::unique_ptr<coupling::MacCoupling> transfer_;
  std::unique_ptr<coupling::RemoteSamples> samples_;
  std::vector<models::plants::TreeSite> sites_, owned_;
  std::vector<models::plants::NodeLinkTree> trees_;
  std::vector<std::size_t> tip_;             ///< highest node of each owned tree
  std::vector<std::vector<core::Vec3>> fw_;  ///< last step's F_w per node, per owned tree
  bool contacts_ = false;
  /// Per owned tree: link pairs (node, node) overlapping in the rest shape (not collisions).
  std::vector<std::set<std::pair<std::int64_t, std::int64_t>>> grown_together_;
  models::plants::ContactParams contact_;
  long long last_contacts_ = 0;
  double k_branch_ = 0.1;
  int substeps_ = 1;
  bool two_way_ = true;
  int csv_every_ = 1;
  bool csv_started_ = false;
  io::CsvSeries csv_;
};

}  // namespace biota::scenarios
