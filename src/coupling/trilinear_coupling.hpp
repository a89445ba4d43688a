#pragma once
/// \file trilinear_coupling.hpp
/// \brief Grid <-> particle transfer with trilinear weights over cell centres.
///
/// Choice (documented in docs/seaweed.md): trilinear rather than the 4-point immersed-boundary
/// delta. Its stencil (2x2x2 cells) fits in one ghost layer for every owned particle, the weights
/// are non-negative and sum to one (so spreading conserves momentum exactly), and interpolation is
/// exact for linear fields. The sphere diameter (1 cm) is about one lattice spacing in the paper's
/// setting, so the wider, smoother 4-point kernel buys little. The same weights are used for
/// interpolation and spreading, so the transfer is adjoint and the coupling conserves momentum.
/// On a wall (non-periodic) axis the sampling point is clamped to the first/last cell centre, so no
/// weight ever lands outside the domain.
#include <cassert>
#include <cmath>

#include "core/types.hpp"
#include "grid/decomposition.hpp"
#include "grid/field.hpp"

namespace biota::coupling {

using core::Real;
using core::Vec3;

/// \brief Cells and weights of one particle: local index of the lower corner and 2x2x2 weights.
struct Stencil {
  int i = 0, j = 0, k = 0;
  Real w[2][2][2]{};
};

/// \brief True when the 2x2x2 stencil lies inside the field's ghosted block (debug checks).
inline bool stencil_in_field(const grid::Field<Real>& field, const Stencil& s) {
  const int g = field.ghosts();
  const auto& n = field.cells();
  return s.i >= -g && s.j >= -g && s.k >= -g && s.i + 1 < n.x + g && s.j + 1 < n.y + g &&
         s.k + 1 < n.z + g;
}

/// \brief Builds stencils for owned particles and applies them to ghosted fields.
class TrilinearCoupling {
 public:
  /// \param dx cell size (m); \param origin physical position of the grid's lower corner (m).
  TrilinearCoupling(const grid::Decomposition& decomp, Real dx, Vec3 origin = {})
      : decomp_(decomp), dx_(dx), origin_(origin) {}

  /// \brief Stencil of a particle at physical position p (p must lie in this rank's box, or
  /// within one cell of it when used with spread_owned()).
  Stencil stencil(const Vec3& p) const {
    Stencil s;
    int lo[3];
    Real f[3];
    for (int d = 0; d < 3; ++d) {
      Real c = (p[d] - origin_[d]) / dx_ - 0.5;  // global cell-centre coordinate
      const int n = decomp_.global_cells()[d];
      if (!decomp_.periodic(d)) c = c < 0 ? 0 : (c > n - 1 ? n - 1 : c);
      const int i0 = static_cast<int>(std::floor(c));
      lo[d] = i0 - decomp_.local_box().lo[d];
      f[d] = c - i0;
    }
    s.i = lo[0], s.j = lo[1], s.k = lo[2];
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        for (int c = 0; c < 2; ++c)
          s.w[a][b][c] = (a ? f[0] : 1 - f[0]) * (b ? f[1] : 1 - f[1]) * (c ? f[2] : 1 - f[2]);
    return s;
  }
  /// \brief Local cells [lo, hi) that interpolate_at(field, p) reads (the 2x2x2 stencil).
  grid::Box stencil_box(const Vec3& p) const {
    const Stencil s = stencil(p);
    return {{s.i, s.j, s.k}, {s.i + 2, s.j + 2, s.k + 2}};
  }
  /// \brief Interpolate components 0..2 of `field` (ghosts must be current).
  static Vec3 interpolate(const grid::Field<Real>& field, const Stencil& s) {
    // Out of the block: an owned particle drifted more than (ghosts - 1/2) cells out of its
    // rank's box before migrating (the Verlet skin is validated against this at start-up).
    assert(stencil_in_field(field, s));
    Vec3 v;
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        for (int c = 0; c < 2; ++c) {
          const Real w = s.w[a][b][c];
          if (w == 0) continue;
          for (int d = 0; d < 3; ++d) v[d] += w * field(s.i + a, s.j + b, s.k + c, d);
        }
    return v;
  }
  /// \brief Add `value` (components 0..2) with the stencil's weights; follow with
  /// HaloExchange::reverse_sum() so that contributions in ghost cells reach their owners.
  static void spread(grid::Field<Real>& field, const Stencil& s, const Vec3& value) {
    assert(stencil_in_field(field, s));
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        for (int c = 0; c < 2; ++c) {
          const Real w = s.w[a][b][c];
          if (w == 0) continue;
          for (int d = 0; d < 3; ++d) field(s.i + a, s.j + b, s.k + c, d) += w * value[d];
        }
  }
  /// \brief Like spread() but only into this rank's owned cells (weights landing in ghost cells
  /// are dropped). Used when every rank spreads all particles, owned and ghost, whose stencil
  /// touches its cells, in a fixed particle order: each cell's sum is then formed in the same
  /// order on any rank count, without a reverse halo sum (bitwise decomposition invariance).
  void spread_owned(grid::Field<Real>& field, const Stencil& s, const Vec3& value) const {
    const auto n = decomp_.local_cells();
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        for (int c = 0; c < 2; ++c) {
          const Real w = s.w[a][b][c];
          const int i = s.i + a, j = s.j + b, k = s.k + c;
          if (w == 0 || i < 0 || j < 0 || k < 0 || i >= n.x || j >= n.y || k >= n.z) continue;
          for (int d = 0; d < 3; ++d) field(i, j, k, d) += w * value[d];
        }
  }
  Real dx() const { return dx_; }

  // ---- the point-wise interface shared with MacCoupling (used by particle_transfer.hpp) ----
  /// \brief Interpolate the 3 components of `field` at p.
  Vec3 interpolate_at(const grid::Field<Real>& field, const Vec3& p) const {
    return interpolate(field, stencil(p));
  }
  /// \brief spread() at p (owned and ghost cells; follow with HaloExchange::reverse_sum()).
  void spread_at(grid::Field<Real>& field, const Vec3& p, const Vec3& value) const {
    spread(field, stencil(p), value);
  }
  /// \brief spread_owned() at p.
  void spread_owned_at(grid::Field<Real>& field, const Vec3& p, const Vec3& value) const {
    spread_owned(field, stencil(p), value);
  }
  /// \brief Farthest a point outside this rank's box can lie and still put weight on an owned
  /// cell: half a cell (the owned boundary cell's centre is dx/2 inside).
  Real reach() const { return 0.5 * dx_; }

 private:
  const grid::Decomposition& decomp_;
  Real dx_;
  Vec3 origin_;
};

}  // namespace biota::coupling
