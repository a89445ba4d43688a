#pragma once
/// \file flock_neighbours.hpp
/// \brief Neighbour sums of the boids of one cell-list bin, over one shared candidate list.
///
/// All boids of a bin visit the same rows of bins, so the candidates are gathered once per bin:
/// in visit order, dropping the ones that can be no boid's neighbour (not eligible, or at least
/// the perception radius away from the bounding box of the bin's points). Each boid then runs the
/// vectorised perception test over one contiguous array (no per-row loop and tails) and sums over
/// the accepted candidates in visit order. The accepted set and its order are exactly those of
/// the per-boid row walk, so the sums are bitwise the same (decomposition invariance holds).
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "core/types.hpp"
#include "models/flock/boid_rules.hpp"
#include "particles/ordered_cell_list.hpp"

namespace biota::scenarios {

/// \brief Rows of bins per slab for OrderedCellList::for_each_bin_in_slabs(): the rows a slab's
/// gathers read, rows + 2m in each of 2m + 1 planes (m = reach, 56 bytes per point), take about
/// half of this core's L2. On small grids that is every row, so the order is the flat one.
long long slab_rows(const particles::OrderedCellList& cells, int reach);

/// \brief See file comment.
class BinNeighbours {
 public:
  /// \brief Gather the candidates of the bin holding slots [first, last) of `cells` (slot-ordered
  /// velocities vx, vy, vz and eligibility flags, 0 or 1, with 8 readable bytes past the slots),
  /// keeping those that may lie within `radius2` of a point of the bin.
  void gather(const particles::OrderedCellList& cells, std::size_t first, std::size_t last,
              const double* vx, const double* vy, const double* vz, const std::uint8_t* eligible,
              double radius2);

  /// \brief The kAverage sums (separation, velocity, position, count; no nearest neighbour) of
  /// the boid at x with velocity v and cruising distance d_star, in the bin gathered last, as
  /// accumulate_neighbour() forms them over the perceived candidates in visit order.
  models::flock::NeighbourSums sums(const core::Vec3& x, const core::Vec3& v, double radius2,
                                    double fov_cos, double d_star);

  /// \brief Candidates kept by the last gather().
  std::size_t size() const { return n_; }

 private:
  std::size_t n_ = 0;
  std::vector<double> c_[6];        // candidates of the bin: x, y, z, vx, vy, vz (SoA), visit order
  std::vector<std::uint64_t> acc_;  // accepted candidates of one boid
  std::vector<double> acc_r2_;      // their squared distances
  std::vector<std::pair<std::size_t, std::size_t>> rows_;  // slot ranges of the last gather
};

}  // namespace biota::scenarios
