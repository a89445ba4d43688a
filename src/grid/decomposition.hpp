#pragma once
/// \file decomposition.hpp
/// \brief Cartesian block decomposition of a global cell grid over MPI ranks.
#include <mpi.h>

#include <array>
#include <string>
#include <vector>

#include "core/types.hpp"

namespace biota::grid {

using core::Index3;

/// \brief Half-open box of global cell indices [lo, hi).
struct Box {
  Index3 lo, hi;
  Index3 extent() const { return {hi.x - lo.x, hi.y - lo.y, hi.z - lo.z}; }
  bool contains(const Index3& c) const {
    return c.x >= lo.x && c.x < hi.x && c.y >= lo.y && c.y < hi.y && c.z >= lo.z && c.z < hi.z;
  }
};

/// \brief Split `n` cells into `parts` blocks; the first n % parts blocks get one extra cell.
/// Returns the first cell of block `index` (index == parts gives n).
constexpr int block_start(int n, int parts, int index) {
  const int base = n / parts, rem = n % parts;
  return index * base + (index < rem ? index : rem);
}

/// \brief Block starts (parts + 1 values, 0 to planes.size()) that split the planes along an
/// axis into `parts` blocks of nearly equal summed weight (each cut at the first plane where the
/// running sum reaches its share), every block at least `min_cells` planes thick.
std::vector<int> weighted_block_starts(const std::vector<double>& plane_weight, int parts,
                                       int min_cells);

/// \brief As above, for blocks of unequal capacity: block i gets the share capacity[i] / (sum of
/// all capacities) of the summed weight (e.g. a rank's measured speed, so a slower core gets
/// fewer planes). Equal capacities give the cuts of the overload above, bit for bit.
std::vector<int> weighted_block_starts(const std::vector<double>& plane_weight,
                                       const std::vector<double>& capacity, int min_cells);

/// \brief Per axis, the capacity of each block of the rank grid `dims` for weighted_block_starts,
/// from the speed of every rank (ranks in the row-major order Decomposition lays them out): the
/// slowest rank of a slab of blocks sets the slab's pace. Axes with one block get no entry.
std::array<std::vector<double>, 3> block_capacities(const Index3& dims,
                                                    const std::vector<double>& rank_speed);

/// \brief Block starts for Decomposition on every axis the rank grid `dims` splits (others
/// empty): each block gets its capacity's share (block_capacities of `rank_speed`; empty: all
/// equal) of the plane weights (`plane_weight[a]`; empty: every plane 1), every block at least
/// max(min_cells, half an even block) thick.
std::array<std::vector<int>, 3> balanced_block_starts(
    const Index3& dims, const Index3& cells, const std::array<std::vector<double>, 3>& plane_weight,
    const std::vector<double>& rank_speed, int min_cells = 1);

/// \brief The deck keys that set a grid's cells, named in the error when the ranks do not fit.
struct GridKeys {
  std::string source;                ///< deck file (empty: not from a deck)
  std::array<std::string, 3> cells;  ///< e.g. {"lbm.nx", "lbm.ny", "lbm.nz"}
};

/// \brief The rank grid (MPI_Cart_create) and this rank's block of a global cell grid.
///
/// Cells are the unit: a grid of `global_cells` cells of size `dx`, origin at 0. Uneven splits are
/// allowed (100 cells on 3 ranks gives 34, 33, 33).
class Decomposition {
 public:
  /// \param dims rank grid; zeros are filled by MPI_Dims_create's counts, placed on the free axes
  /// to cut the fewest faces, ties keeping the fewest ranks on z (the vertical) and then on x
  /// (the unit stride): 2 ranks on a cube give 1 x 2 x 1, so the halo is whole rows. Where MPI's
  /// counts put more ranks than cells on an axis: the most compact rank grid that fits the cells.
  /// \param keys deck keys named in the error message.
  /// \throws core::InputError (the same on every rank) if no rank grid gives each rank a cell.
  /// \param starts optional cuts per axis: empty (even blocks, block_start) or dims[a] + 1
  /// increasing cell indices from 0 to global_cells[a], the first cell of each block (a
  /// load-balanced cut; every rank must pass the same). rank_grid() gives the dims first.
  Decomposition(MPI_Comm comm, Index3 global_cells, std::array<bool, 3> periodic,
                Index3 dims = {0, 0, 0}, const GridKeys& keys = {},
                const std::array<std::vector<int>, 3>& starts = {});
  /// \brief The rank grid the constructor picks for `size` ranks (see above; no MPI calls but
  /// MPI_Dims_create). \throws core::InputError if none gives each rank a cell.
  static Index3 rank_grid(int size, Index3 cells, Index3 dims = {0, 0, 0},
                          const GridKeys& keys = {});
  ~Decomposition();
  Decomposition(const Decomposition&) = delete;
  Decomposition& operator=(const Decomposition&) = delete;

  MPI_Comm comm() const { return cart_; }
  int rank() const { return rank_; }
  int size() const { return size_; }
  const Index3& dims() const { return dims_; }
  const Index3& coords() const { return coords_; }
  const Index3& global_cells() const { return global_; }
  bool periodic(int d) const { return periodic_[d]; }
  const std::array<bool, 3>& periodic() const { return periodic_; }
  /// \brief This rank's interior cells.
  const Box& local_box() const { return box_; }
  Index3 local_cells() const { return box_.extent(); }
  /// \brief Box of the rank at Cartesian coordinates `c`.
  Box box_of(const Index3& c) const;
  /// \brief Neighbour rank across face (d, side), side 0 = low, 1 = high; MPI_PROC_NULL at a wall.
  int neighbor(int d, int side) const { return neighbors_[d][side]; }
  /// \brief First cell of block `index` (0..dims[axis]) along `axis`.
  int block_start_of(int axis, int index) const;
  /// \brief Block (rank coordinate) along `axis` holding cell `cell` (clamped into the grid).
  int block_of(int axis, int cell) const;
  /// \brief Cells of the thinnest block along `axis`.
  int thinnest(int axis) const;
  /// \brief Cells of the widest block along `axis`.
  int widest(int axis) const;
  /// \brief Rank owning global cell `c` (wrapped on periodic axes).
  int owner_of_cell(Index3 c) const;
  /// \brief Rank owning the point `p` given in cell units (cell i spans [i, i+1)).
  int owner_of_point(const core::Vec3& p) const;
  /// \brief Wrap a global cell index into [0, N) on periodic axes.
  Index3 wrap(Index3 c) const;

 private:
  MPI_Comm cart_ = MPI_COMM_NULL;
  int rank_ = 0, size_ = 1;
  Index3 global_, dims_, coords_;
  std::array<bool, 3> periodic_;
  Box box_;
  std::array<std::array<int, 2>, 3> neighbors_{};
  std::array<std::vector<int>, 3> starts_;  ///< dims[a] + 1 block starts per axis
};

}  // namespace biota::grid
