#pragma once
/// \file flock_scenario.hpp
/// \brief The flock paper's experiment (spec boids.md): prey boids take off in chaos-game order,
/// school, are attacked by predators, and break up in sandpile avalanches; 1/f (fBm) noise on the
/// cruising distance, maximum speed and heading. Model and decisions: docs/flock.md.
///
/// Parallel layout: the boids are one partitioned particles::ParticleSet (migration to face
/// neighbours, ghosts within the perception radius). The sandpile (L³ sites, one per prey) is small
/// and replicated: every rank adds the same grains in the same order, so every rank holds the
/// same lattice without communication. Everything that feeds the dynamics is
/// decomposition-invariant to the last bit (see docs/flock.md, "Decomposition invariance").
#include <array>
#include <cstdint>
#include <fstream>
#include <memory>
#include <unordered_map>
#include <vector>

#include "grid/decomposition.hpp"
#include "io/csv_series.hpp"
#include "io/output_layout.hpp"
#include "models/flock/boid_noise.hpp"
#include "models/flock/boid_rules.hpp"
#include "models/flock/sandpile.hpp"
#include "particles/ordered_cell_list.hpp"
#include "particles/particle_comm.hpp"
#include "scenarios/flock_neighbours.hpp"
#include "scenarios/scenario.hpp"

namespace biota::scenarios {

/// \brief One boid as gathered for tests and diagnostics.
struct BoidRecord {
  core::GlobalId id;
  core::Vec3 x, v;
};

/// \brief Boids + predators + replicated 3D sandpile; see file comment.
class FlockScenario : public Scenario {
 public:
  static void declare_config(core::ConfigSchema& schema);
  /// \brief The deck's lengths and speeds against each other and the rank grid: a boid moves
  /// less than its perception radius per frame and launches no faster than its top speed; the
  /// radius fits the thinnest rank block (the ghost layer) and gives at most 2^26 cell-list bins
  /// on a rank. Fails with the key, value and allowed range (core::Config::fail).
  static void check_scales(const core::Config& c, const grid::Decomposition& decomp, double dx);
  explicit FlockScenario(const RunContext& ctx);

  void step() override;
  long long step_index() const override { return step_; }
  core::CommCounter comm_sent() const override {
    core::CommCounter c = sent_before_balance_;
    return c += pcomm_->sent();
  }
  double time() const override { return step_ * dt_; }
  double dt() const override { return dt_; }
  void write_output() override;
  void write_checkpoint(const std::string& path) override;
  void read_checkpoint(const std::string& path) override;
  void check_health() override;
  void poison_for_test() override;
  std::string progress() override;
  std::vector<std::string> timer_sections() const override;

  /// \brief Every boid (prey then predators), sorted by id, on every rank. Collective.
  std::vector<BoidRecord> gather_boids() const;
  /// \brief The replicated sandpile (identical on every rank).
  const models::flock::Sandpile& sandpile() const { return *sandpile_; }
  /// \brief Global number of boids (prey + predators).
  long long global_count() const { return n_prey_ + n_pred_; }
  /// \brief Mean number of perceived neighbours per prey update since reset (this rank).
  double mean_neighbours() const {
    return prey_updates_ ? double(neighbour_sum_) / double(prey_updates_) : 0.0;
  }
  /// \brief Restart the neighbour statistics.
  void reset_neighbour_count() { neighbour_sum_ = prey_updates_ = 0; }
  /// \brief Boids this rank owns now.
  std::size_t owned_boids() const { return set_->n_owned(); }
  /// \brief Number of times the load balance moved the cut between ranks.
  long long balance_moves() const { return balance_moves_; }
  /// \brief This rank's first cell along each axis (the current cut; tests, diagnostics).
  core::Index3 local_first_cell() const { return decomp_->local_box().lo; }
  /// \brief Polarisation of the flying prey at the last statistics row.
  double last_polarisation() const { return last_phi_; }

 private:
  using Predator = BoidRecord;
  struct NearestPrey {
    double d2;
    core::GlobalId id;  // kNone if no prey is flying
    core::Vec3 x;
  };
  static constexpr core::GlobalId kNone = ~core::GlobalId{0};

  void place_boids();
  void begin_step();  // migrate + ghosts + cell list
  /// Store the owned boids in the order of the last step's cell list (of a list of the owned boids
  /// built here on the first step), so the rules phase and the cell-list build read memory nearly
  /// in order. Every kReorderInterval steps: at 4 m/s and
  /// 0.05 s a boid changes bin about every 10 steps, and with 16 steps between reorders the
  /// 1e6-boid step ran ~4% slower than with 4 (performance-flock.md, session 30). The storage
  /// order changes no result.
  void reorder_by_cell();
  static constexpr long long kReorderInterval = 4;
  /// Move the cut between ranks by measured speed (flock_decomposition.cpp); before a migration.
  void rebalance();
  /// Whether the load balance runs: several ranks and flock.balance.interval > 0.
  bool balancing() const { return balance_interval_ > 0 && decomp_->size() > 1; }
  std::vector<Predator> gather_predators() const;
  /// \brief (id, x, v) of every owned boid on every rank that passes `keep`, sorted by id.
  std::vector<BoidRecord> gather_records(bool predators_only) const;
  std::vector<NearestPrey> nearest_prey(const std::vector<Predator>& preds) const;
  void drive_sandpile(const std::vector<Predator>& preds, const std::vector<NearestPrey>& near);
  double heading_angle(core::GlobalId id);
  void record_order(const std::vector<NearestPrey>& near);
  void open_csv(bool resume);
  // Inline: asked for every slot and every boid in each step (performance-flock.md, session 24).
  bool flying(core::GlobalId id) const {
    if (!is_prey(id)) return step_ >= pred_start_step_;
    return static_cast<double>(id) * takeoff_interval_ <= (static_cast<double>(step_) + 0.5) * dt_;
  }
  bool is_prey(core::GlobalId id) const { return id < static_cast<core::GlobalId>(n_prey_); }
  bool fleeing(core::GlobalId id) const {
    return is_prey(id) && flee_until_[id % flee_until_.size()] > step_;
  }
  core::Vec3 min_image(core::Vec3 d) const;

  RunContext ctx_;
  io::OutputLayout out_layout_;  ///< output.chunk/compression of the sandpile lattice
  std::uint64_t seed_ = 0;
  double dt_ = 0.05;
  long long step_ = 0;
  long long n_prey_ = 0, n_pred_ = 0;
  // Domain and boids.
  std::unique_ptr<grid::Decomposition> decomp_;
  std::unique_ptr<particles::ParticleComm> pcomm_;
  // Load balance: what a new cut's Decomposition and ParticleComm need beyond the old ones, and
  // the work since the last check.
  grid::GridKeys grid_keys_;
  int balance_interval_ = 0;
  double balance_tolerance_ = 0;
  double rules_seconds_at_balance_ = 0;
  double work_since_balance_ = 0;  ///< sum of the work estimates over the rules phases since
  /// Per owned slot, the last rules phase's work estimate: 1 + candidates tested + neighbours
  /// (kept only while the balance runs: several ranks and flock.balance.interval > 0).
  std::vector<float> boid_cost_;
  long long balance_moves_ = 0;
  core::CommCounter sent_before_balance_;  ///< sent by the ParticleComms of earlier cuts
  std::unique_ptr<particles::ParticleSet> set_;
  int a_vel_ = 0, a_dstar_ = 0, a_vmax_ = 0;
  bool periodic_ = false;
  core::Vec3 lo_{}, hi_{};
  double wall_margin_ = 0, wall_weight_ = 0;
  int bin_reach_ = 1;
  // Rules.
  double radius_ = 0, fov_cos_ = -1, w_sep_ = 0, w_ali_ = 0, w_coh_ = 0, a_max_ = 0, v_min_ = 0;
  models::flock::AlignmentMode align_mode_ = models::flock::AlignmentMode::kAverage;
  double flee_radius_ = 0, w_flee_ = 0, w_flee_boost_ = 0;
  long long flee_frames_ = 0;
  double pred_vmax_ = 0, pred_amax_ = 0, w_chase_ = 0;
  long long pred_start_step_ = 0;
  core::Vec3 pred_start_{};
  // Take-off.
  double takeoff_interval_ = 0, takeoff_speed_ = 0;
  core::Vec3 takeoff_dir_{};
  // Noise.
  double noise_heading_ = 0;
  int noise_levels_ = 8;
  double noise_hurst_ = 0.2;
  models::flock::FbmSignal noise_signal_ = models::flock::FbmSignal::kPath;
  std::unordered_map<core::GlobalId, std::pair<std::uint64_t, std::vector<double>>> noise_cache_;
  // Sandpile coupling.
  std::unique_ptr<models::flock::Sandpile> sandpile_;
  /// \brief A communicator this object frees (after the decomposition built on it).
  struct OwnedComm {
    MPI_Comm comm = MPI_COMM_NULL;
    ~OwnedComm();
  };
  /// The replicated sandpile is written by the first min(ranks, L) ranks: more ranks than L would
  /// leave a rank without a site along an axis (L = 1 on 2 ranks aborted).
  OwnedComm lattice_comm_;
  std::unique_ptr<grid::Decomposition> lattice_;  ///< null on ranks outside lattice_comm_
  std::vector<long long> flee_until_;  // per site: prey of the site flee while step < value
  double trigger_radius_ = 0;
  int grains_per_frame_ = 1;
  models::flock::ToppleOrder topple_order_ = models::flock::ToppleOrder::kWaves;
  long long avalanches_ = 0;
  long long neighbour_sum_ = 0, prey_updates_ = 0;
  // Neighbour search (rebuilt every step, carrying the velocities) and, per slot, whether the
  // boid is a flying prey (one byte: the candidate gather reads 8 flags in one load, 8 bytes
  // past the slots included).
  particles::OrderedCellList cells_;
  std::vector<std::uint8_t> eligible_;
  BinNeighbours bin_;            // candidates shared by the boids of one bin (kAverage)
  std::vector<core::Vec3> acc_;  // step(): accelerations of the owned boids (reused)
  std::vector<char> launch_;     // step(): boids launched this step
  // Statistics.
  int stats_every_ = 1;
  double last_phi_ = 0;
  std::array<std::vector<double>, 3> unit_;  // record_order's scratch: unit velocities, by axis
  long long last_fleeing_ = 0, last_flying_ = 0;
  io::CsvSeries order_csv_, aval_csv_;
};

}  // namespace biota::scenarios
