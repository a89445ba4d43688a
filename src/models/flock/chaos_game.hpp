#pragma once
/// \file chaos_game.hpp
/// \brief Chaos game (random iterated function system) for the take-off order (spec boids.md 2.7).
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "core/types.hpp"

namespace biota::models::flock {

/// \brief One affine map w(x) = A x + T chosen with probability p (eq. 6.1).
///
/// Always stored in 3D; a 2D map uses the upper-left 2 × 2 block of A and (T.x, T.y), and leaves
/// z = 0, so 2D and 3D share one code path.
struct AffineMap {
  /// \brief Linear part A, row-major 3 × 3.
  std::array<double, 9> a{1, 0, 0, 0, 1, 0, 0, 0, 1};
  /// \brief Translation T.
  core::Vec3 t{};
  /// \brief Probability P_i of choosing this map.
  double p = 0;
  /// \brief A x + T.
  core::Vec3 apply(const core::Vec3& x) const {
    return {a[0] * x.x + a[1] * x.y + a[2] * x.z + t.x, a[3] * x.x + a[4] * x.y + a[5] * x.z + t.y,
            a[6] * x.x + a[7] * x.y + a[8] * x.z + t.z};
  }
};

/// \brief Random IFS in 2D or 3D; generate() returns points in generation order, which is the
/// take-off order of the boids placed on them (spec 2.7).
class ChaosGame {
 public:
  /// \brief Maps with their probabilities; probabilities must be >= 0 and sum to 1 within 1e-9
  /// (they are then renormalised exactly).
  /// \throws std::invalid_argument if dim is not 2 or 3, maps is empty, or the probabilities are
  /// invalid.
  ChaosGame(int dim, std::vector<AffineMap> maps);

  /// \brief Maps from a flat list of reals.
  ///
  /// 2D: 7 reals per map, `a b c d e f p`, in the order of eq. 6.1 (x' = a x + b y + e,
  /// y' = c x + d y + f), the classic IFS code table layout of Barnsley.
  /// 3D: 13 reals per map, `a11 a12 a13 a21 a22 a23 a31 a32 a33 t1 t2 t3 p` (A row-major, then T,
  /// then p).
  /// \throws std::invalid_argument if the length is not a positive multiple of 7 (2D) or 13 (3D).
  static ChaosGame from_flat(int dim, std::span<const double> values);

  /// \brief Sierpinski gasket (spec 2.7 example): A_i = I/2, T = (0,0), (1/2,0), (1/4,1/2),
  /// P_i = 1/3. Attractor: triangle (0,0), (1,0), (1/2,1); dimension log 3 / log 2 ≈ 1.585.
  static ChaosGame sierpinski_gasket();
  /// \brief Barnsley fern, the standard 4 maps (stem 1%, main frond 85%, two leaflets 7% each).
  /// Attractor inside x ∈ [-2.1820, 2.6558], y ∈ [0, 9.9983].
  static ChaosGame barnsley_fern();
  /// \brief Sierpinski tetrahedron (3D): A_i = I/2, T_i = v_i/2 for the vertices v_i of the
  /// regular tetrahedron of edge 1 with a face on z = 0; dimension log 4 / log 2 = 2.
  static ChaosGame sierpinski_tetrahedron();

  /// \brief N points of the orbit, in generation order.
  ///
  /// Starts at the fixed point of the first map (solving (I - A_1) x = T_1; the origin if that is
  /// singular), which lies on the attractor, then discards `transient` iterates so that any other
  /// start would also have converged. Map choices come from one core::Rng stream keyed by
  /// (seed, stream_id, 0, RngPurpose::kChaosGame): the orbit is a serial chain, so build it
  /// identically wherever it is needed (every rank or one) and index it by boid id.
  std::vector<core::Vec3> generate(std::size_t n, std::uint64_t seed, std::uint64_t stream_id = 0,
                                   int transient = 32) const;

  /// \brief 2 or 3.
  int dim() const { return dim_; }
  /// \brief The maps, probabilities normalised.
  const std::vector<AffineMap>& maps() const { return maps_; }
  /// \brief Start point of generate() (fixed point of the first map).
  core::Vec3 start_point() const;

 private:
  int dim_;
  std::vector<AffineMap> maps_;
  std::vector<double> cumulative_;  // cumulative probabilities, last entry exactly 1
};

}  // namespace biota::models::flock
