#pragma once
/// \file poisson_solver.hpp
/// \brief Cell-centred pressure Poisson problem on the Decomposition, solved with PETSc KSP.
///
/// The operator is the standard 7-point Laplacian L on cells of size dx. At a domain face it is
/// homogeneous Neumann (walls, inflow: the face flux is prescribed) or homogeneous Dirichlet
/// with p = 0 on the face (outflow), or periodic. Solid cells (mask > 0.5) get identity rows and
/// their faces are Neumann for the fluid. The PETSc DMDA has exactly the Decomposition's blocks
/// (built on a communicator reordered to PETSc's x-fastest rank order), so vectors are copied
/// cell by cell without any redistribution.
#include <array>
#include <memory>
#include <string>

#include "core/types.hpp"
#include "grid/decomposition.hpp"
#include "grid/field.hpp"

namespace biota::linalg {

/// \brief Condition on one face of the box for the pressure.
enum class PressureBC { kNeumann, kDirichlet, kPeriodic };
/// \brief [axis][side] (side 0 = low, 1 = high).
using PressureBCs = std::array<std::array<PressureBC, 2>, 3>;

/// \brief Result of one solve.
struct SolveStats {
  int iterations = 0;
  double residual_norm = 0;  ///< final residual norm as reported by KSP
  double rhs_norm = 0;       ///< 2-norm of the (scaled) right-hand side
  double seconds = 0;
  bool stopped_on_max_residual = false;  ///< the `max_residual` target ended the solve
};

/// \brief Solves L p = rhs. Options prefix `poisson_`; default `-poisson_ksp_type cg
/// -poisson_pc_type gmg` (our matrix-free geometric multigrid, geometric_multigrid.hpp; options
/// `-poisson_gmg_sweeps`, `-poisson_gmg_omega`, `-poisson_gmg_levels`), unpreconditioned residual
/// norm, rtol 1e-10 or the caller's max-residual target, whichever comes first; `pfmg` (hypre
/// PFMG on a MATHYPRESTRUCT matrix), `gamg`, `hypre` (BoomerAMG) and `mg` (cell-centred PCMG)
/// select the others.
class PoissonSolver {
 public:
  /// \param solid optional cell mask (1 solid, 0 fluid) with at least one valid ghost layer.
  /// \param options deck options (e.g. "-poisson_ksp_rtol 1e-8"); the command line wins.
  /// \param options_key deck key `options` came from (named in error messages).
  PoissonSolver(const grid::Decomposition& decomp, double dx, PressureBCs bcs,
                const grid::Field<core::Real>* solid = nullptr, const std::string& options = "",
                const std::string& options_key = "poisson options");
  ~PoissonSolver();
  PoissonSolver(const PoissonSolver&) = delete;
  PoissonSolver& operator=(const PoissonSolver&) = delete;

  /// \brief Solve; `p` (owned cells) is the initial guess and the result. Throws
  /// std::runtime_error if KSP does not converge. With a null space (no Dirichlet face) the
  /// compatible part of rhs is used and the solution has zero mean over fluid cells.
  /// `max_residual` > 0 also stops the solve as soon as max over cells |rhs - L p| <= max_residual
  /// (checked on the true residual; the MAC projection passes its divergence target here), unless
  /// the options set a tolerance explicitly (`-poisson_ksp_rtol`/`_atol`: then KSP's test alone).
  SolveStats solve(const grid::Field<core::Real>& rhs, grid::Field<core::Real>& p,
                   double max_residual = 0);
  /// \brief True when the options set -poisson_ksp_rtol or -poisson_ksp_atol (`max_residual`
  /// of solve() is then ignored).
  bool explicit_tolerance() const;
  /// \brief True when the operator has the constant (over fluid cells) null space.
  bool singular() const { return singular_; }
  /// \brief The DMDA's owned box in global cells (equals decomp.local_box(); checked in tests).
  grid::Box petsc_owned_box() const;
  /// \brief Rank in PETSc's communicator of this process, and PETSc's process grid.
  int petsc_rank() const;
  /// \brief KSP and PC type names actually used (e.g. "cg + pfmg"; "cg + mg (cell-centred, 6
  /// levels)").
  std::string description() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  bool singular_ = false;
  int levels_ = 0;  // of the cell-centred multigrid, when it is used
};

}  // namespace biota::linalg
