#pragma once
/// \file box_counting.hpp
/// \brief Box-counting (Minkowski–Bouligand) dimension of a point set.
#include <cstdint>
#include <span>
#include <vector>

#include "core/types.hpp"

namespace biota::models::flock {

/// \brief Result of box_counting_dimension().
struct BoxCounting {
  /// \brief Least-squares slope of log N(ε) against log(1/ε).
  double dimension = 0;
  /// \brief Standard error of that slope (scatter of the points about the line).
  double dimension_error = 0;
  /// \brief Levels k used, box edge ε = side / 2^k.
  std::vector<int> levels;
  /// \brief Occupied boxes N(ε) per level.
  std::vector<std::int64_t> counts;
};

/// \brief Box-counting dimension from dyadic boxes at levels level_min..level_max.
///
/// Boxes tile the bounding cube of the points (the smallest axis-aligned cube with the
/// lower corner at the componentwise minimum and edge = the largest extent over the first `dim`
/// axes); at level k the edge is side / 2^k and points on the upper face go to the last box. Only
/// the first `dim` coordinates are used (2 or 3). Choose level_max so that the points oversample
/// the finest boxes (N points >> N(ε_min)), otherwise the count saturates and the slope drops.
/// \throws std::invalid_argument for dim not 2 or 3, fewer than 2 levels, level_max > 20, or
/// an empty or degenerate point set.
BoxCounting box_counting_dimension(std::span<const core::Vec3> points, int dim, int level_min,
                                   int level_max);

}  // namespace biota::models::flock
