#pragma once
/// \file plane_weights.hpp
/// \brief Weights of points summed per plane of cells along each split axis: the input of
/// weighted_block_starts when the load to cut is particles (the seaweed's spheres at start-up,
/// the flock's boids in the load balance).
#include <mpi.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "core/types.hpp"

namespace biota::grid {

/// \brief See file comment. Planes are cells of `dx` from `origin`; a point outside the grid
/// counts for the nearest end plane, a NaN one for the first. Axes the rank grid `dims` does not
/// split keep no planes.
class PlaneWeights {
 public:
  PlaneWeights(const core::Index3& dims, const core::Index3& cells, double dx,
               const core::Vec3& origin = {})
      : dx_(dx), origin_(origin) {
    for (int a = 0; a < 3; ++a)
      if (dims[a] > 1) planes_[a].assign(static_cast<std::size_t>(cells[a]), 0.0);
  }

  /// \brief Add weight `w` at point `x` (m).
  void add(const core::Vec3& x, double w = 1.0) {
    for (int a = 0; a < 3; ++a) {
      auto& p = planes_[a];
      if (p.empty()) continue;
      // A NaN coordinate counts for plane 0 (std::clamp passes NaN through, and its cast
      // to an index wrote past the planes).
      const double c = std::floor((x[a] - origin_[a]) / dx_);
      p[c > 0 ? static_cast<std::size_t>(std::min(c, static_cast<double>(p.size() - 1))) : 0] += w;
    }
  }

  /// \brief Sum every rank's weights (collective over `comm`, one reduction for all axes).
  void sum_over(MPI_Comm comm) {
    std::vector<double> all;
    for (const auto& p : planes_) all.insert(all.end(), p.begin(), p.end());
    MPI_Allreduce(MPI_IN_PLACE, all.data(), static_cast<int>(all.size()), MPI_DOUBLE, MPI_SUM,
                  comm);
    auto it = all.begin();
    for (auto& p : planes_) {
      std::copy(it, it + static_cast<std::ptrdiff_t>(p.size()), p.begin());
      it += static_cast<std::ptrdiff_t>(p.size());
    }
  }

  /// \brief The weights per plane, per axis (empty where the rank grid does not split).
  const std::array<std::vector<double>, 3>& planes() const { return planes_; }

 private:
  double dx_;
  core::Vec3 origin_;
  std::array<std::vector<double>, 3> planes_;
};

}  // namespace biota::grid
