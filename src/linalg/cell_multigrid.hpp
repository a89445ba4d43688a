#pragma once
/// \file cell_multigrid.hpp
/// \brief Cell-centred geometric multigrid hierarchy for PETSc's PCMG (`-poisson_pc_type mg`).
///
/// PETSc's own DMDA coarsening is vertex-centred ((M-1)/(Mc-1) must be an integer), which does not
/// fit the cell-centred pressure grid. This builds the hierarchy by hand: each level pairs cells
/// 2c, 2c+1 into coarse cell c along every axis with more than two cells (an odd count leaves a
/// one-cell coarse cell at the high end), each rank keeps the coarse cells of its own fine cells
/// (block [ceil(lo/2), ceil(hi/2)) per axis), interpolation is tensor-product linear between coarse
/// cell centres (with the pressure condition at the box faces), and the coarse operators are
/// Galerkin products P^T A P (PCMGSetGalerkin), so solid cells and boundary conditions need no
/// rediscretisation.
#include <petscksp.h>

#include <array>
#include <vector>

#include "core/types.hpp"
#include "linalg/poisson_solver.hpp"

namespace biota::linalg {

/// \brief Block structure of one level: per axis the block starts of every rank (P[a] + 1 entries).
struct CellLevel {
  core::Index3 cells;
  std::array<std::vector<int>, 3> starts;
};

/// \brief The levels from fine to coarse: halve every axis with more than two cells until the
/// coarsest has at most `max_coarse_cells` cells, no axis can be halved without emptying a rank's
/// block, or `max_levels` levels exist.
std::vector<CellLevel> cell_levels(const CellLevel& fine, int max_levels,
                                   long long max_coarse_cells);

/// \brief 1D interpolation weights of fine cell `i` (level with `n` cells) from the coarse level
/// with `nc` cells: up to two (coarse index, weight) pairs; `count` says how many.
struct Weights1D {
  int count = 0;
  std::array<int, 2> index{};
  std::array<double, 2> weight{};
};
Weights1D interpolation_weights(int i, int n, int nc, PressureBC lo, PressureBC hi);

/// \brief Turn `pc` into a PCMG over the cell levels of the fine grid: levels, interpolation,
/// Galerkin coarse operators, and defaults (Chebyshev/Jacobi smoothing, a redundant SVD solve on
/// the coarsest level, which also handles the singular pure-Neumann case) that options under the
/// KSP's prefix may override. `coords` and `dims` are the rank grid (PETSc ranks x fastest).
/// Returns the number of levels.
int setup_cell_multigrid(PC pc, MPI_Comm comm, const CellLevel& fine, const core::Index3& dims,
                         const core::Index3& coords, const PressureBCs& bcs, int max_levels);

}  // namespace biota::linalg
