#pragma once
/// \file lbm_solver.hpp
/// \brief Lattice-Boltzmann water solver: D3Q15/D3Q19, BGK/TRT, Guo forcing, bounce-back walls and
/// solids, free-slip, velocity inlet patch (the fountain jet), pressure / zero-gradient outlet.
///
/// Storage: structure of arrays, one population buffer streamed in place with the AA pattern
/// (aa_sweep.hpp): steps alternate between a neighbour step (from the post-collision state) and a
/// local step (from the streamed state). Boundaries are applied before each sweep by writing, into
/// the location a boundary link reads, the value the link must deliver; the sweep itself has no
/// boundary branches. Checkpoints and the macroscopic fields see the post-collision populations
/// in natural order on either step parity. See docs/lbm.md.
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/config.hpp"
#include "core/memory.hpp"
#include "core/types.hpp"
#include "grid/decomposition.hpp"
#include "grid/field.hpp"
#include "grid/ghost_fold.hpp"
#include "grid/halo_exchange.hpp"
#include "solvers/lbm/timed_choice.hpp"
#include "solvers/lbm/unit_converter.hpp"

namespace biota::io {
class CheckpointWriter;
class CheckpointReader;
}  // namespace biota::io

namespace biota::solvers::lbm {

using core::Index3;
using core::Real;
using core::Vec3;

/// \brief Boundary type of one box face.
enum class FaceType { kPeriodic, kWall, kFreeSlip, kPressure, kZeroGradient };

/// \brief Velocity inlet on a disc of one face, speed ramped and optionally pulsed in time.
struct InletPatch {
  int face = -1;               ///< 2*axis + side, -1 = none
  double center[2] = {0, 0};   ///< disc centre on the face [m] (tangential axes in x, y, z order)
  double radius = 0;           ///< [m]
  double speed = 0;            ///< peak speed into the domain [m/s]
  bool parabolic = true;       ///< u(r) = speed (1 - r^2/R^2), else uniform
  double ramp_time = 0;        ///< [s] smooth start, 0 = none
  double pulse_amplitude = 0;  ///< relative amplitude of a sinusoidal pulsation
  double pulse_period = 1;     ///< [s]
  /// \brief Time factor of the speed at time t (ramp times pulsation).
  double time_factor(double t) const;
};

/// \brief Outlet on an annulus r_min <= r <= r_max of one face.
struct OutletPatch {
  int face = -1;
  double center[2] = {0, 0};
  double r_min = 0, r_max = 1e300;
  FaceType type = FaceType::kPressure;
};

/// \brief Everything the solver needs; from a deck with `from_config`.
struct LbmParams {
  std::string lattice = "D3Q15";
  bool trt = false;
  double magic = 3.0 / 16.0;
  Index3 cells{32, 32, 32};
  double dx = 0.01, dt = 1e-3, density = 998.0, viscosity = 1e-6, reference_velocity = 0.0;
  std::array<FaceType, 6> faces{FaceType::kPeriodic, FaceType::kPeriodic, FaceType::kPeriodic,
                                FaceType::kPeriodic, FaceType::kPeriodic, FaceType::kPeriodic};
  Vec3 body_force{};  ///< uniform force density [N/m^3]
  InletPatch inlet;
  OutletPatch outlet;
  double max_mach = 0.3;
  /// Overlap the neighbour step's halo exchange with the sweep where possible and faster
  /// (bitwise the same; off only for benchmark A/B runs, not a deck key).
  bool overlap_halo = true;
  /// Print which way the timed choices (overlap, fused pairs) went, on rank 0 (not a deck key).
  bool report_choices = true;
  /// \brief Read and check the `lbm.*` keys (tau/Mach stability is checked here: InputError).
  static LbmParams from_config(const core::Config& cfg);
  std::array<bool, 3> periodic() const {
    return {faces[0] == FaceType::kPeriodic, faces[2] == FaceType::kPeriodic,
            faces[4] == FaceType::kPeriodic};
  }
};

/// \brief The LBM solver on one Decomposition. Lattice units inside; `units()` converts.
class LbmSolver {
 public:
  /// \brief Declare every `lbm.*` key.
  static void declare_config(core::ConfigSchema& schema);
  /// \brief Bytes this rank will allocate for `params` on `decomp` (for core::check_memory):
  /// populations, macroscopic fields, solid flags and boundary links, output arrays.
  static std::vector<core::MemoryItem> memory_estimate(const grid::Decomposition& decomp,
                                                       const LbmParams& params);

  LbmSolver(const grid::Decomposition& decomp, const LbmParams& params);
  ~LbmSolver();

  /// \brief Advance one lattice time step. With `update_macroscopic` the density and velocity
  /// fields are stored during the sweep and their ghosts refreshed (needed for coupling/output).
  void step(bool update_macroscopic = true);
  /// \brief How advance() runs a pair of steps: fused plane by plane, as two single steps, or
  /// whichever of the two timed faster in the first pairs of the run (the same bits either way).
  enum class PairMode { kAuto, kFused, kSingle };
  /// \brief `steps` steps without the macroscopic update. Pairs of a neighbour step and the local
  /// step after it can run fused plane by plane along z when the rank's x axis has no neighbour
  /// (the local step of a plane runs as soon as the neighbour step has passed the plane after it,
  /// while its populations are still in cache): the same bits as `steps` calls of step(false).
  void advance(int steps, PairMode mode = PairMode::kAuto);
  long long step_index() const { return step_; }
  double time() const { return step_ * units_.dt(); }

  /// \brief Set every owned cell to equilibrium with `init(global cell index, rho, u)` (lattice).
  void initialize(const std::function<void(const Index3&, double&, Vec3&)>& init);
  /// \brief Per-cell force density (3 components, lattice units, 1 ghost layer) applied by Guo
  /// forcing on top of the uniform body force once `enable_force_field()` was called.
  /// Every call marks the field changed (the sweep then re-derives which cells of each row carry a
  /// force, once): write through a fresh call, not through a reference kept from an earlier step.
  grid::Field<Real>& force() {
    force_spans_stale_ = true;
    return force_;
  }
  void enable_force_field() { use_force_field_ = true; }
  /// \brief Macroscopic density / velocity (lattice units) as of the last step that stored them.
  const grid::Field<Real>& density() const { return rho_; }
  const grid::Field<Real>& velocity() const { return u_; }
  /// \brief Recompute density and velocity from the populations (e.g. after initialize/restart).
  void update_macroscopic();
  /// \brief The same for the owned cells inside `regions` only (boxes of local cell indices,
  /// clipped to the owned block, may overlap), then the ghost refresh. Cells outside keep the
  /// values of an earlier update: for callers that read the fields only where they say.
  void update_macroscopic(std::span<const grid::Box> regions);
  /// \brief Mark solid cells (`is_solid_global` of a global, wrapped cell index) on owned and
  /// ghost cells and rebuild the bounce-back links. Local: no communication.
  void set_solid(const std::function<bool(const Index3&)>& is_solid_global);

  const UnitConverter& units() const { return units_; }
  const LbmParams& params() const { return params_; }
  const grid::Decomposition& decomposition() const { return decomp_; }
  int q() const { return nq_; }
  /// \brief Sum of all populations over all ranks (lattice mass).
  double total_mass() const;
  /// \brief Throws core::UnstableError naming step, cell and position if a population is not
  /// finite or the density leaves [rho_min, rho_max].
  void check_health(double rho_min = 0.5, double rho_max = 2.0) const;
  /// \brief Test hook: set one population of this rank's first fluid cell to NaN.
  void poison_for_test();
  /// \brief Lattice updates performed by this rank so far (owned fluid cells x steps).
  double cell_updates() const { return updates_; }

  void write_checkpoint(io::CheckpointWriter& w) const;
  void read_checkpoint(io::CheckpointReader& r);

  /// \brief Timers of the last steps: stream-collide, halo, boundaries [s] on this rank.
  double time_collide() const { return t_collide_; }
  double time_halo() const { return t_halo_; }
  /// \brief Messages and bytes sent by this rank's halo exchanges (populations and velocity).
  core::CommCounter halo_sent() const {
    core::CommCounter c = halo_->sent();
    c += halo_u_->sent();
    return c;
  }
  double time_boundary() const { return t_boundary_; }

 private:
  struct Link {
    std::int64_t s;      ///< cell the population is pulled from (ghost or solid)
    std::int64_t x;      ///< fluid cell it streams into
    std::int64_t x2;     ///< free-slip source cell
    std::int32_t q, q2;  ///< population index, free-slip source population
    std::int32_t type;   ///< FaceType or inlet (-1)
    double coef;         ///< inlet: 6 w_q (c_q.n) profile
  };
  /// \brief The links of one step parity as linear indices into the population buffer (dst is
  /// written from src), grouped by kind so that each kind is one tight loop.
  struct BoundaryPlan {
    std::vector<std::array<std::int64_t, 2>> copies;  ///< wall, free slip, zero gradient
    /// The copies as runs: base[dst + k stride] = base[src + k stride], k < count (a face's links
    /// of one direction are a plane of cells, so long unit-stride runs on the y and z faces).
    struct CopyRun {
      std::int64_t dst, src, stride, count;
    };
    std::vector<CopyRun> runs;
    std::vector<std::array<std::int64_t, 2>> inlet;  ///< moving wall, + coef * u_in
    std::vector<double> inlet_coef;
    struct Pressure {
      std::int64_t dst, src, cell;  ///< src: the opposite population of cell
      std::int32_t q;
    };
    std::vector<Pressure> pressure;  ///< consecutive per cell
  };
  void build_links();
  void build_plans(const std::vector<Link>& links);
  /// \brief Append link `l` to `plan` for the step from the post (`streamed` false) or the
  /// streamed state.
  void add_link(BoundaryPlan& plan, const Link& l, bool streamed) const;
  static void compress_copies(BoundaryPlan& plan);
  void apply_boundaries(const BoundaryPlan& plan);
  /// \brief The values apply_boundaries() would write, appended as (target, value) pairs.
  void stage_boundaries(const BoundaryPlan& plan,
                        std::vector<std::pair<std::int64_t, double>>& staged) const;
  /// \brief Every (target, value) of a plan's links, handed to `store` (targets never overlap
  /// sources, so the order of the stores is free).
  template <class Store>
  void visit_boundaries(const BoundaryPlan& plan, Store&& store) const;
  /// \brief Sweep the owned cells; with `overlap_` only the rows [begin, end) along overlap_axis_.
  void sweep(bool macro, int begin = 0, int end = -1);
  /// \brief Sweep rows y in [j0, j1), z in [k0, k1) as a neighbour (`from_post`) or local step.
  void sweep_rows(bool macro, bool from_post, int j0, int j1, int k0, int k1);
  /// \brief A neighbour step and the local step after it, fused along z (see advance()).
  void fused_step_pair();
  /// \brief The local-step links split for fused_step_pair() by the z plane of the cell they
  /// feed, apart those feeding the first/last layer along an axis with neighbours (the ghost fold
  /// writes there, so their values are staged and stored after it).
  void build_fused_plans(const std::vector<Link>& links);
  bool fused_ = false;  ///< fusion possible on this rank grid
  /// Fused pairs or single steps (advance(), PairMode::kAuto): the first trial after two warm-up
  /// pairs, four pairs each way, again every 500 pairs.
  TimedChoice fuse_choice_{2, 4, 500, false};
  bool deferred_y_ = false, deferred_z_ = false;
  std::vector<BoundaryPlan> local_plan_by_z_, local_plan_deferred_by_z_;
  BoundaryPlan local_plan_after_fold_;
  std::vector<std::pair<std::int64_t, double>> staged_;
  /// \brief A neighbour step with the halo exchange and the ghost fold in flight during parts of
  /// the interior sweep (see step()).
  void overlapped_neighbour_step(bool macro);
  /// Whether a neighbour step overlaps its communication with the sweep (which splits the sweep
  /// into four pieces): timed on the neighbour steps without the macroscopic update, the first
  /// trial after two of them, four each way, again every 1000; steps with the update take the
  /// current choice.
  TimedChoice overlap_choice_{2, 4, 1000, true};
  /// \brief One line on rank 0 (unless params.report_choices is off) saying which way `c` went,
  /// with the fastest trial of each way.
  void report_choice(const TimedChoice& c, const char* what, const char* if_true,
                     const char* if_false, const char* true_is, const char* false_is) const;
  /// \brief post[q][c] is the post-collision population q of cell c in either state.
  void post_view(const double* post[32]) const;

  const grid::Decomposition& decomp_;
  LbmParams params_;
  UnitConverter units_;
  int nq_;
  std::vector<std::array<int, 3>> c_;
  std::vector<double> w_;
  std::vector<int> opp_;
  grid::Field<Real> f_, force_, rho_, u_;
  std::vector<std::ptrdiff_t> offset_;  ///< linear index offset of c_q
  bool streamed_ = false;               ///< f_ holds the streamed state (after a neighbour step)
  std::vector<std::uint8_t> solid_;
  bool has_solids_ = false, use_force_field_ = false;
  /// Per owned row j + ny k: the cells [lo, hi) whose force field is not +0 in every component.
  std::vector<int> force_lo_, force_hi_;
  bool force_spans_stale_ = true;
  void update_force_spans();
  std::unique_ptr<grid::HaloExchange> halo_, halo_u_;  ///< before a neighbour step; velocity
  std::unique_ptr<grid::GhostFold> fold_;              ///< after a neighbour step
  BoundaryPlan plans_[2];  ///< [streamed_]; with overlap_, [0] holds the links not in late_plan_
  /// Overlap of the neighbour step's communication with its sweep, when exactly one axis (y or z)
  /// has neighbours: the neighbour-step links that touch that axis's ghost layers (applied after
  /// the exchange lands), and the rows next to each face (band_) swept after them.
  bool overlap_ = false;
  int overlap_axis_ = -1;
  int band_[2] = {1, 1};
  BoundaryPlan late_plan_;
  long long step_ = 0;
  double updates_ = 0, t_collide_ = 0, t_halo_ = 0, t_boundary_ = 0;
};

/// \brief Parse a face key value ("periodic", "wall", ...); InputError on unknown names.
FaceType parse_face_type(const core::Config& cfg, const std::string& key);

}  // namespace biota::solvers::lbm
