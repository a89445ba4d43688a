#pragma once
/// \file geometric_multigrid.hpp
/// \brief Matrix-free cell-centred geometric multigrid V-cycle for the pressure Poisson operator
/// A = -dx^2 L (`-poisson_pc_type gmg`, the preconditioner of CG; docs/wind.md and
/// docs/decisions.md).
///
/// Levels pair cells 2c, 2c+1 along every axis with more than two cells, each rank keeping the
/// coarse cells of its own block (linalg::cell_levels, shared with the PCMG hierarchy). Every
/// level holds a 7-point operator as face coefficients: on the finest level 1 between two fluid
/// cells, 0 at a solid or Neumann face, 2 at a Dirichlet face (p = 0 on the face); a coarse face
/// gets the sum of the fine faces it covers times (fine centre distance / coarse centre
/// distance), the rediscretisation that equals the Galerkin operator of the uniform grid.
/// Symmetric red-black Gauss-Seidel smoothing (red then black before the coarse correction,
/// black then red after), trilinear interpolation between coarse cell centres and its transpose
/// as restriction, a dense pseudo-inverse on the coarsest level (at most 512 cells, on every
/// rank; also the singular pure-Neumann case). The V-cycle is a symmetric positive
/// semi-definite operator, as CG needs.
#include <mpi.h>

#include <array>
#include <memory>
#include <vector>

#include "core/types.hpp"
#include "linalg/poisson_solver.hpp"

namespace biota::linalg {

class GeometricMultigrid {
 public:
  /// \param comm Cartesian communicator of the decomposition (neighbours in its numbering).
  /// \param starts per axis the block starts of every rank (dims[a] + 1 entries).
  /// \param solid owned cells, x fastest (1 solid), or empty; `solid_ghosts` the same for the
  /// ghosted block (one layer), used for the faces across the block boundary.
  /// \param sweeps red-black sweeps before and after the coarse correction on every level.
  /// \param omega over-relaxation factor of those sweeps (1: Gauss-Seidel).
  GeometricMultigrid(MPI_Comm comm, const core::Index3& cells,
                     const std::array<std::vector<int>, 3>& starts, const core::Index3& coords,
                     const PressureBCs& bcs, const std::vector<char>& solid_ghosted, int sweeps,
                     double omega, int max_levels);
  ~GeometricMultigrid();
  GeometricMultigrid(const GeometricMultigrid&) = delete;
  GeometricMultigrid& operator=(const GeometricMultigrid&) = delete;

  /// \brief z = M^{-1} r on owned cells (x fastest), one V-cycle from a zero guess.
  void apply(const double* r, double* z);
  /// \brief y = A x on owned cells (x fastest): the finest level's operator, equal to the
  /// assembled one (identity rows for solid cells), for CG's products.
  void multiply(const double* x, double* y);
  int levels() const;
  /// \brief Whether the hierarchy (every level's cell counts) is the one a single rank builds:
  /// then the V-cycle, and CG around it, give the same bits on this decomposition as on one
  /// rank (docs/wind.md, "Decomposition invariance"). Thin blocks stop an axis's coarsening
  /// early.
  bool hierarchy_of_one_rank() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace biota::linalg
