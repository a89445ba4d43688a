#pragma once
/// \file mac_solver.hpp
/// \brief Incompressible Navier-Stokes (tree.md eqs. 12-13) on a staggered MAC grid with a
/// fractional-step projection (eqs. 17-18 in the consistent form of errata 13).
///
/// Layout: component c of the velocity field at local cell (i,j,k) is the velocity normal to the
/// LOW face of that cell along axis c (x = i dx for u). A rank therefore owns exactly the faces
/// of its own cells' low sides: a face shared by two ranks belongs to the upper one only, and the
/// global face N of a bounded axis lives in the first high ghost layer of the last rank, where the
/// boundary condition sets it. Pressure (phi = p/rho) lives at cell centres.
///
/// One step (time_scheme = "rk2", default; "euler" is the paper's eq. 17 with one stage):
///   u1      = P[ u^n + dt F(u^n) ]
///   u^{n+1} = P[ u^n/2 + (u1 + dt F(u1))/2 ]          (SSP-RK2 / Heun)
/// with F = -(u.grad)u + nu lap u + f (second-order upwind advection, 7-point diffusion, body
/// force at faces) and P the projection: solve L psi = div u*, u = u* - grad psi, phi = psi/dt_s.
#include <array>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/memory.hpp"
#include "core/timers.hpp"
#include "core/types.hpp"
#include "grid/decomposition.hpp"
#include "grid/field.hpp"
#include "grid/halo_exchange.hpp"
#include "linalg/poisson_solver.hpp"
#include "solvers/mac/boundary.hpp"

namespace biota::solvers::mac {

using core::Index3;
using core::Real;
using core::Vec3;

/// \brief Time integration of the explicit terms.
enum class TimeScheme { kEuler, kRK2 };

/// \brief Everything the solver needs, in SI units (m, s).
struct MacParams {
  Index3 cells{};                ///< global cells
  Real dx = 1;                   ///< cubic cell size (m)
  Boundaries boundaries{};       ///< per face
  InflowProfile inflow{};        ///< for inflow faces
  int vertical_axis = 2;         ///< log profile and ground heights are measured along it
  Real ground_roughness = 0.03;  ///< z0 of "ground" faces (m)
  Real viscosity = 1.5e-5;       ///< nu (m^2/s)
  Real cfl = 0.5;                ///< dt <= cfl dx / (max|u|+max|v|+max|w|)
  Real diffusion_number = 0.15;  ///< dt <= diffusion_number dx^2 / nu (stable below 1/6)
  Real dt_max = 1e30;            ///< s
  Real fixed_dt = 0;             ///< > 0: use this dt (tests); limits are still checked
  TimeScheme scheme = TimeScheme::kRK2;
  Vec3 initial_velocity{};          ///< m/s, everywhere (then projected)
  bool initial_from_inflow = true;  ///< start from the inflow profile where there is inflow
  Vec3 body_force{};                ///< uniform force per unit mass (m/s^2), e.g. a channel drive
  std::function<bool(const Index3&)> solid;  ///< global cell -> solid obstacle (optional)
  /// Relative divergence max|div u| dx / max|u| the projection leaves: the Poisson solve stops
  /// once its largest cell residual guarantees this with a safety factor (docs/wind.md); 0 or an
  /// explicit -poisson_ksp_rtol/_atol: KSP's tolerance alone.
  Real divergence_target = 1e-10;
  std::string poisson_options;  ///< PETSc options under -poisson_
  std::string poisson_options_key = "wind.poisson_options";
};

/// \brief Statistics of the last step.
struct StepStats {
  Real dt = 0, dt_cfl = 0, dt_viscous = 0;
  int poisson_iterations = 0;  ///< summed over the stages of the step
  double poisson_seconds = 0;
  Real max_divergence = 0;  ///< max |div u| dx / max|u| after the last projection
};

/// \brief The staggered incompressible solver on one Decomposition.
class MacSolver {
 public:
  /// Ghost layers of every field: second-order upwinding reaches two faces upstream.
  static constexpr int kGhosts = 2;
  /// \brief Messages and bytes sent by this rank's halo exchanges (PETSc's own traffic not
  /// counted).
  core::CommCounter halo_sent() const {
    core::CommCounter c = halo_u_->sent();
    c += halo_ustar_->sent();
    c += halo_psi_->sent();
    return c;
  }
  /// Sections added to `timers`: wind.advection, wind.diffusion, wind.poisson, wind.correction,
  /// wind.halo, wind.boundary.
  MacSolver(const grid::Decomposition& decomp, MacParams params, core::Timers& timers);
  ~MacSolver();
  /// \brief What a solver on `decomp` allocates on this rank, for core::check_memory: the MAC
  /// fields (u, u*, rhs, force: 3 reals; phi, psi, div, solid: 1) with their ghost layers, the
  /// pressure solve (7-point matrix, multigrid hierarchy, Krylov vectors: ~300 B per cell) and
  /// an output step (8 reals per cell).
  static std::vector<core::MemoryItem> memory_estimate(const grid::Decomposition& decomp) {
    const core::Index3 n = decomp.local_cells();
    const double cells =
        double(n.x + 2 * kGhosts) * double(n.y + 2 * kGhosts) * double(n.z + 2 * kGhosts);
    const double owned = double(n.x) * double(n.y) * double(n.z);
    return {{"fields", 16 * 8 * cells}, {"pressure solve", 300 * owned}, {"output", 8 * 8 * owned}};
  }
  MacSolver(const MacSolver&) = delete;  // the halo exchanges point into the member fields
  MacSolver& operator=(const MacSolver&) = delete;

  /// \brief Advance one step with the adaptive (or fixed) dt, but at most `dt_limit` (so a
  /// caller can land exactly on a coupling or output time).
  void step(Real dt_limit = 1e300);
  /// \brief The dt the next step will use and the two limits (collective).
  StepStats next_dt() const;
  const StepStats& last_stats() const { return stats_; }
  double time() const { return time_; }
  long long step_index() const { return step_; }
  void set_clock(double time, long long step) { time_ = time, step_ = step; }

  /// \brief Face velocities (see the layout above); ghosts valid between steps.
  grid::Field<Real>& velocity() { return u_; }
  const grid::Field<Real>& velocity() const { return u_; }
  /// \brief Pressure phi = p/rho (m^2/s^2) at cell centres of the last projection.
  grid::Field<Real>& pressure() { return phi_; }
  const grid::Field<Real>& pressure() const { return phi_; }
  /// \brief Body force per unit mass at faces, same layout as the velocity (coupling writes
  /// here; ghosts ignored). Added to MacParams::body_force.
  grid::Field<Real>& force() { return force_; }
  /// \brief Refill ghosts and boundary faces after the owned faces were changed from outside
  /// (restart, initial conditions). Collective.
  void refresh();
  /// \brief Project the current velocity (used once at start). Collective.
  void project_initial();

  /// \brief Face values on the high boundary of bounded axes (outside the owned cells):
  /// rows (axis, global i, j, k, value) for checkpoints; and their restore.
  std::vector<double> boundary_face_rows() const;
  void set_boundary_face_rows(const std::vector<double>& rows);

  // ---- diagnostics / output (owned cells, x fastest) ----------------------------------------
  std::vector<double> cell_velocity() const;        ///< interleaved xyz, m/s
  std::vector<double> vorticity_magnitude() const;  ///< 1/s
  std::vector<double> divergence() const;           ///< 1/s
  std::vector<double> cell_pressure() const;        ///< m^2/s^2
  /// \brief max |div u| dx / max |u| over the domain (collective).
  Real relative_divergence() const;
  /// \brief max |u_c| over owned faces, per component (collective).
  Vec3 max_speed() const;
  /// \brief Kinetic energy per unit mass integrated over the domain, 0.5 sum |u|^2 dx^3, with face
  /// velocities averaged to cells (collective).
  Real kinetic_energy() const;
  /// \brief False if any owned value is not finite (collective).
  bool finite() const;
  const MacParams& params() const { return p_; }
  const grid::Decomposition& decomposition() const { return d_; }
  std::string poisson_description() const { return poisson_->description(); }

 private:
  /// Calls visit(div u) (1/s) for every owned cell in storage order.
  template <class Visit>
  void for_each_cell_divergence(Visit&& visit) const;
  void compute_rhs(const grid::Field<Real>& u, grid::Field<Real>& rhs);  // F(u) on owned faces
  // out = a_old u_old + (1-a_old)(u + dt F(u)) on owned and boundary faces; out may alias u_old,
  // not u
  void predict(const grid::Field<Real>& u, const grid::Field<Real>& u_old, Real a_old, Real dt,
               grid::Field<Real>& out);
  void project(grid::Field<Real>& u, Real dt_stage);
  void exchange_velocity(grid::Field<Real>& u);
  /// \brief Call f(loc, index) for every line of cells normal to axis `a` (tangential ghost rows
  /// included); `loc` is the line's local cell with loc[a] = 0, `index` its linear index.
  template <class F>
  void for_each_face_line(const grid::Field<Real>& field, int a, F&& f) const;
  void apply_velocity_bc(grid::Field<Real>& u);
  void apply_pressure_bc(grid::Field<Real>& p);
  Real inflow_normal(int axis, int side, int i, int j, int k) const;
  bool bounded_low(int a) const { return !d_.periodic(a) && d_.local_box().lo[a] == 0; }
  bool bounded_high(int a) const {
    return !d_.periodic(a) && d_.local_box().hi[a] == d_.global_cells()[a];
  }
  BoundaryType type(int a, int s) const { return p_.boundaries[a][s].type; }

  const grid::Decomposition& d_;
  MacParams p_;
  core::Timers& timers_;
  Index3 n_;
  grid::Field<Real> u_, ustar_, rhs_, force_, phi_, psi_, div_, solid_;
  std::vector<std::array<unsigned char, 3>> open_;  // per local index: face c open for flow
  std::unique_ptr<grid::HaloExchange> halo_u_, halo_ustar_, halo_psi_;
  std::unique_ptr<linalg::PoissonSolver> poisson_;
  double time_ = 0;
  long long step_ = 0;
  StepStats stats_;
};

}  // namespace biota::solvers::mac
