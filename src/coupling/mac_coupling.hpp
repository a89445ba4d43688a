#pragma once
/// \file mac_coupling.hpp
/// \brief Grid <-> particle transfer on the staggered MAC grid (solvers/mac): each velocity
/// component is interpolated trilinearly at its own face positions, the 3D form of tree.md
/// eq. (19), and a force is spread with the same per-component weights (so the transfer is
/// adjoint and spreading conserves momentum to round-off).
///
/// Face layout (MacSolver): component c at local index (i, j, k) sits on the low face of cell
/// (i, j, k) along axis c, i.e. at x_c = i dx and at cell centres (index + 1/2) dx on the other
/// two axes. A rank owns the faces with local indices 0..n-1 (its cells' low faces).
///
/// Walls (non-periodic axes): along the component's own axis the point is clamped to the faces
/// 0..N (N: the high wall face, held in the last rank's first high ghost layer); across, to the
/// first/last cell centre, as in the collocated TrilinearCoupling. Weights landing on wall faces
/// belong to fixed normal velocities and do nothing there.
///
/// Scaling: values are spread as given. The MAC body force is a force per unit mass at faces
/// (m/s^2), so a caller spreading a force F [N] passes F / (rho_air dx^3).
#include <cassert>
#include <cmath>

#include "coupling/trilinear_coupling.hpp"

namespace biota::coupling {

/// \brief Per-component trilinear stencils on the MAC faces of one decomposition.
class MacCoupling {
 public:
  /// \param dx cell size (m); \param origin physical position of the grid's lower corner (m).
  MacCoupling(const grid::Decomposition& decomp, Real dx, Vec3 origin = {})
      : decomp_(decomp), dx_(dx), origin_(origin) {}

  /// \brief Stencil of component c (0, 1, 2) at physical position p: local index of the lower
  /// face/cell corner and the 2x2x2 weights.
  Stencil stencil(const Vec3& p, int c) const {
    Stencil s;
    int lo[3];
    Real f[3];
    for (int d = 0; d < 3; ++d) {
      const bool normal = d == c;
      Real g = (p[d] - origin_[d]) / dx_ - (normal ? 0.0 : 0.5);  // global face/centre coord
      const int n = decomp_.global_cells()[d];
      int i0;
      if (!decomp_.periodic(d)) {
        const int top = normal ? n : n - 1;
        g = g < 0 ? 0 : (g > top ? top : g);
        i0 = static_cast<int>(std::floor(g));
        if (i0 == top) i0 = top - 1;  // keep the upper stencil point on the last face/centre
      } else {
        i0 = static_cast<int>(std::floor(g));
      }
      lo[d] = i0 - decomp_.local_box().lo[d];
      f[d] = g - i0;
    }
    s.i = lo[0], s.j = lo[1], s.k = lo[2];
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        for (int e = 0; e < 2; ++e)
          s.w[a][b][e] = (a ? f[0] : 1 - f[0]) * (b ? f[1] : 1 - f[1]) * (e ? f[2] : 1 - f[2]);
    return s;
  }

  /// \brief Velocity at p: component c from its own faces (ghost faces must be current).
  Vec3 interpolate_at(const grid::Field<Real>& u, const Vec3& p) const {
    Vec3 v;
    for (int c = 0; c < 3; ++c) {
      const Stencil s = stencil(p, c);
      assert(stencil_in_field(u, s));
      Real sum = 0;
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
          for (int e = 0; e < 2; ++e) sum += s.w[a][b][e] * u(s.i + a, s.j + b, s.k + e, c);
      v[c] = sum;
    }
    return v;
  }
  /// \brief Add component c of `value` to the faces of component c with its stencil, ghost
  /// faces included; follow with HaloExchange::reverse_sum() on the field so ghost
  /// contributions reach their owners.
  void spread_at(grid::Field<Real>& f, const Vec3& p, const Vec3& value) const {
    for (int c = 0; c < 3; ++c) {
      const Stencil s = stencil(p, c);
      assert(stencil_in_field(f, s));
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
          for (int e = 0; e < 2; ++e) f(s.i + a, s.j + b, s.k + e, c) += s.w[a][b][e] * value[c];
    }
  }
  /// \brief Like spread_at() but into owned faces only (see TrilinearCoupling::spread_owned()
  /// for why: bitwise rank-count independence when owned and ghost particles are spread).
  void spread_owned_at(grid::Field<Real>& f, const Vec3& p, const Vec3& value) const {
    const auto n = decomp_.local_cells();
    for (int c = 0; c < 3; ++c) {
      const Stencil s = stencil(p, c);
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
          for (int e = 0; e < 2; ++e) {
            const int i = s.i + a, j = s.j + b, k = s.k + e;
            if (i < 0 || j < 0 || k < 0 || i >= n.x || j >= n.y || k >= n.z) continue;
            f(i, j, k, c) += s.w[a][b][e] * value[c];
          }
    }
  }
  /// \brief Farthest a point outside this rank's box can lie and still put weight on an owned
  /// face: one cell (the box's low faces are owned).
  Real reach() const { return dx_; }
  Real dx() const { return dx_; }

 private:
  const grid::Decomposition& decomp_;
  Real dx_;
  Vec3 origin_;
};

}  // namespace biota::coupling
