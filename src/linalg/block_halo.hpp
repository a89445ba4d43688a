#pragma once
/// \file block_halo.hpp
/// \brief Ghost layers of a rank's block of a cell array (x fastest), used by the levels of
/// the geometric multigrid (whose coarse blocks are not a grid::Decomposition's). Axes are
/// exchanged one after the other over the ghosted extent of the earlier axes, so edge and corner
/// ghosts are filled too (trilinear interpolation reads them).
#include <mpi.h>

#include <array>
#include <cstddef>
#include <vector>

#include "core/types.hpp"

namespace biota::linalg {

/// \brief Owned extent `n` of a block with `width` ghost layers (one unless said): index of local
/// cell (i, j, k), each in [-width, n + width).
struct GhostedBlock {
  core::Index3 n{};
  int width = 1;
  std::ptrdiff_t sy = 0, sz = 0;
  std::size_t size = 0;
  explicit GhostedBlock(const core::Index3& owned = {}, int ghost_width = 1)
      : n(owned),
        width(ghost_width),
        sy(owned.x + 2 * ghost_width),
        sz(std::ptrdiff_t(owned.x + 2 * ghost_width) * (owned.y + 2 * ghost_width)),
        size(std::size_t(owned.x + 2 * ghost_width) * (owned.y + 2 * ghost_width) *
             (owned.z + 2 * ghost_width)) {}
  std::ptrdiff_t index(int i, int j, int k) const {
    return (i + width) + sy * (j + width) + sz * (k + width);
  }
};

/// \brief Face neighbours (MPI_PROC_NULL at a non-periodic box face; possibly this rank itself on
/// a periodic axis of one rank) on `comm`.
class BlockHalo {
 public:
  BlockHalo(MPI_Comm comm, const GhostedBlock& block, std::array<std::array<int, 2>, 3> neighbors);
  /// \brief Fill the ghost layers of `a` (block.size values) from the neighbours' owned cells
  /// (each neighbour's block must be at least as thick as the ghost width).
  void exchange(std::vector<double>& a);

 private:
  MPI_Comm comm_;
  GhostedBlock b_;
  std::array<std::array<int, 2>, 3> nb_;
  std::vector<double> send_, recv_;
};

}  // namespace biota::linalg
