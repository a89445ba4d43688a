#pragma once
/// \file block_halo.hpp
/// \brief One-cell ghost layer of a rank's block of a cell array (x fastest), used by the levels of
/// the geometric multigrid (whose coarse blocks are not a grid::Decomposition's). Axes are
/// exchanged one after the other over the ghosted extent of the earlier axes, so edge and corner
/// ghosts are filled too (trilinear interpolation reads them).
#include <mpi.h>

#include <array>
#include <cstddef>
#include <vector>

#include "core/types.hpp"

namespace biota::linalg {

/// \brief Owned extent `n` of a block with one ghost layer: index of local cell (i, j, k), each
/// in [-1, n].
struct GhostedBlock {
  core::Index3 n{};
  std::ptrdiff_t sy = 0, sz = 0;
  std::size_t size = 0;
  explicit GhostedBlock(const core::Index3& owned = {})
      : n(owned),
        sy(owned.x + 2),
        sz(std::ptrdiff_t(owned.x + 2) * (owned.y + 2)),
        size(std::size_t(owned.x + 2) * (owned.y + 2) * (owned.z + 2)) {}
  std::ptrdiff_t index(int i, int j, int k) const { return (i + 1) + sy * (j + 1) + sz * (k + 1); }
};

/// \brief Face neighbours (MPI_PROC_NULL at a non-periodic box face; possibly this rank itself on
/// a periodic axis of one rank) on `comm`.
class BlockHalo {
 public:
  BlockHalo(MPI_Comm comm, const GhostedBlock& block, std::array<std::array<int, 2>, 3> neighbors);
  /// \brief Fill the ghost layer of `a` (block.size values) from the neighbours' owned cells.
  void exchange(std::vector<double>& a);

 private:
  MPI_Comm comm_;
  GhostedBlock b_;
  std::array<std::array<int, 2>, 3> nb_;
  std::vector<double> send_, recv_;
};

}  // namespace biota::linalg
