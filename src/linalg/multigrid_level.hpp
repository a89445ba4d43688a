#pragma once
/// \file multigrid_level.hpp
/// \brief One level of the matrix-free geometric multigrid (geometric_multigrid.hpp) and the
/// kernels that work on it: red-black smoothing, residual, restriction, interpolation, operator
/// product. Private to src/linalg.
#include <array>
#include <cstddef>
#include <memory>
#include <vector>

#include "core/types.hpp"
#include "linalg/block_halo.hpp"

namespace biota::linalg::multigrid {

/// \brief A level's block of cells (one ghost layer), its 7-point operator as face coefficients,
/// its work vectors and the transfer weights to the next coarser level.
struct Level {
  core::Index3 N{}, lo{}, n{};
  GhostedBlock blk;
  std::array<bool, 3> periodic{};
  std::array<std::vector<double>, 3> width;  // per axis, every global cell, in finest cells
  std::array<std::vector<double>, 3> coef;   // coefficient of each cell's high face, ghosted
  std::vector<double> diag, inv_diag, x, b, r;
  std::vector<char> solid;  // finest level only: identity rows of the operator
  // Coefficient of an interior face per axis on this level; per owned cell (ghosted index)
  // whether its six faces have exactly those coefficients, so the constant-coefficient kernels
  // apply; and per row (j, k) whether its cells 1 .. n.x-2 all do (the row's loop then needs no
  // test but at its two ends). The kernel chosen for a cell depends on the cell alone, never on
  // where a rank's block ends: the same bits on any decomposition (the two kernels round
  // differently).
  std::array<double, 3> regular_coef{1, 1, 1};
  std::vector<char> regular_cell, regular_row;
  std::unique_ptr<BlockHalo> halo;
  // To the next coarser level, per axis: interpolation from two coarse cells per owned fine
  // index (local coarse index, -1 and n allowed; a missing second cell has weight 0), and its
  // transpose, the restriction from four fine cells per owned coarse index (local fine index,
  // -2 to n + 1: where a block starts at an odd index, a coarse cell's fine cells 2c - 1 .. 2c + 2
  // reach two cells into the next block). The residual is written to `r_wide`, which has two
  // ghost layers (`wide`, `wide_halo`), so every coarse cell gets the same four terms in the same
  // order as on one rank.
  std::array<std::array<std::vector<int>, 2>, 3> p_index;
  std::array<std::array<std::vector<double>, 2>, 3> p_weight;
  std::array<std::array<std::vector<int>, 4>, 3> r_index;
  std::array<std::array<std::vector<double>, 4>, 3> r_weight;
  std::vector<double> work_x, work_y;  // restriction's intermediate sums
  GhostedBlock wide;
  std::unique_ptr<BlockHalo> wide_halo;
  std::vector<double> r_wide;

  std::ptrdiff_t stride(int a) const { return a == 0 ? 1 : a == 1 ? blk.sy : blk.sz; }
  /// Centre distance across the high face of global cell g (half width at a non-periodic face).
  double high_distance(int a, int g) const {
    const auto& w = width[a];
    if (g + 1 < N[a]) return 0.5 * (w[g] + w[g + 1]);
    if (periodic[a]) return 0.5 * (w[g] + w[0]);
    return 0.5 * w[g];
  }
};

/// \brief One colour (0 red, 1 black: parity of the global cell index) of a Gauss-Seidel sweep
/// over x, over-relaxed by `omega`. Ghosts of x must be current.
void smooth(Level& v, int colour, double omega);
/// \brief The first red half-sweep from x = 0; writes every owned cell.
void smooth_from_zero(Level& v, double omega);
/// \brief r_wide = b - A x on owned cells (0 on empty rows), on a level that restricts. Ghosts
/// of x must be current; those of r_wide are the caller's (wide_halo).
void residual(Level& v);
/// \brief c.b = R f.r_wide (R = transpose of the interpolation). Both ghost layers of f.r_wide
/// must be current.
void restrict_to(Level& f, Level& c);
/// \brief f.x += P c.x on fluid cells. Ghosts of c.x must be current; uses c.r as work space.
void prolong_add(Level& c, Level& f);
/// \brief out = A in (owned cells, x fastest) on the finest level: identity rows for solids.
void multiply(Level& v, const double* in, double* out);

}  // namespace biota::linalg::multigrid
