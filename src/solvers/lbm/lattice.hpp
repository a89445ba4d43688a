#pragma once
/// \file lattice.hpp
/// \brief Compile-time lattice descriptors D3Q15 and D3Q19 (velocities, weights, opposites).
///
/// D3Q15 follows the seaweed paper's eq. (11) with the errata of the digest: c_0 = (0,0,0),
/// weights 2/9 (rest), 1/9 (6 axis), 1/72 (8 body diagonals). D3Q19: 1/3, 1/18, 1/36.
#include <array>

namespace biota::solvers::lbm {

/// \brief D3Q15 lattice (seaweed paper eq. 11 with errata 1 and 2).
struct D3Q15 {
  static constexpr int Q = 15;
  static constexpr const char* name = "D3Q15";
  static constexpr std::array<std::array<int, 3>, Q> c = {{{0, 0, 0},
                                                           {1, 0, 0},
                                                           {-1, 0, 0},
                                                           {0, 1, 0},
                                                           {0, -1, 0},
                                                           {0, 0, 1},
                                                           {0, 0, -1},
                                                           {1, 1, 1},
                                                           {-1, -1, -1},
                                                           {1, 1, -1},
                                                           {-1, -1, 1},
                                                           {1, -1, 1},
                                                           {-1, 1, -1},
                                                           {-1, 1, 1},
                                                           {1, -1, -1}}};
  static constexpr std::array<double, Q> w = {2.0 / 9,  1.0 / 9,  1.0 / 9,  1.0 / 9,  1.0 / 9,
                                              1.0 / 9,  1.0 / 9,  1.0 / 72, 1.0 / 72, 1.0 / 72,
                                              1.0 / 72, 1.0 / 72, 1.0 / 72, 1.0 / 72, 1.0 / 72};
  static constexpr std::array<int, Q> opp = {0, 2, 1, 4, 3, 6, 5, 8, 7, 10, 9, 12, 11, 14, 13};
};

/// \brief D3Q19 lattice.
struct D3Q19 {
  static constexpr int Q = 19;
  static constexpr const char* name = "D3Q19";
  static constexpr std::array<std::array<int, 3>, Q> c = {{{0, 0, 0},
                                                           {1, 0, 0},
                                                           {-1, 0, 0},
                                                           {0, 1, 0},
                                                           {0, -1, 0},
                                                           {0, 0, 1},
                                                           {0, 0, -1},
                                                           {1, 1, 0},
                                                           {-1, -1, 0},
                                                           {1, -1, 0},
                                                           {-1, 1, 0},
                                                           {1, 0, 1},
                                                           {-1, 0, -1},
                                                           {1, 0, -1},
                                                           {-1, 0, 1},
                                                           {0, 1, 1},
                                                           {0, -1, -1},
                                                           {0, 1, -1},
                                                           {0, -1, 1}}};
  static constexpr std::array<double, Q> w = {1.0 / 3,  1.0 / 18, 1.0 / 18, 1.0 / 18, 1.0 / 18,
                                              1.0 / 18, 1.0 / 18, 1.0 / 36, 1.0 / 36, 1.0 / 36,
                                              1.0 / 36, 1.0 / 36, 1.0 / 36, 1.0 / 36, 1.0 / 36,
                                              1.0 / 36, 1.0 / 36, 1.0 / 36, 1.0 / 36};
  static constexpr std::array<int, Q> opp = {0, 2,  1,  4,  3,  6,  5,  8,  7, 10,
                                             9, 12, 11, 14, 13, 16, 15, 18, 17};
};

}  // namespace biota::solvers::lbm
