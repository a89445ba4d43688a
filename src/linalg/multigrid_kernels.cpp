#include <algorithm>
#include <cstddef>

#include "linalg/multigrid_level.hpp"

namespace biota::linalg::multigrid {

namespace {
/// The 7-point stencil's neighbour sum on a level: general (per-face coefficients) and for a
/// cell of a regular row (the level's interior coefficients).
struct Stencil {
  const double *cx, *cy, *cz;
  std::ptrdiff_t sy, sz;
  double rx, ry, rz, rdiag;
  explicit Stencil(const Level& v)
      : cx(v.coef[0].data()),
        cy(v.coef[1].data()),
        cz(v.coef[2].data()),
        sy(v.blk.sy),
        sz(v.blk.sz),
        rx(v.regular_coef[0]),
        ry(v.regular_coef[1]),
        rz(v.regular_coef[2]),
        rdiag(2 * (rx + ry + rz)) {}
  double general(const double* x, std::ptrdiff_t q) const {
    return cx[q] * x[q + 1] + cx[q - 1] * x[q - 1] + cy[q] * x[q + sy] + cy[q - sy] * x[q - sy] +
           cz[q] * x[q + sz] + cz[q - sz] * x[q - sz];
  }
  double regular(const double* x, std::ptrdiff_t q) const {
    return rx * (x[q + 1] + x[q - 1]) + ry * (x[q + sy] + x[q - sy]) + rz * (x[q + sz] + x[q - sz]);
  }
};
}  // namespace

namespace {
/// One colour of a red-black sweep; `kRelaxed` with over-relaxation `omega`, else plain
/// Gauss-Seidel (the default, one multiplication and load fewer per cell).
template <bool kRelaxed>
void smooth_colour(Level& v, int colour, double omega) {
  const Stencil st(v);
  const double *b = v.b.data(), *id = v.inv_diag.data();
  double* x = v.x.data();
  const double rinv = 1.0 / st.rdiag;
  const char* cell_regular = v.regular_cell.data();
  const int parity0 = v.lo.x + v.lo.y + v.lo.z, nx = v.n.x;
  auto update = [&](std::ptrdiff_t q, double gs) {
    if constexpr (kRelaxed)
      x[q] += omega * (gs - x[q]);
    else
      x[q] = gs;
  };
  for (int k = 0; k < v.n.z; ++k)
    for (int j = 0; j < v.n.y; ++j) {
      const int i0 = (colour - parity0 - j - k) & 1;
      const auto row = v.blk.index(0, j, k);
      auto general = [&](std::ptrdiff_t q) { update(q, id[q] * (b[q] + st.general(x, q))); };
      auto regular = [&](std::ptrdiff_t q) { update(q, rinv * (b[q] + st.regular(x, q))); };
      auto either = [&](std::ptrdiff_t q) { cell_regular[q] ? regular(q) : general(q); };
      if (v.regular_row[j + std::size_t(v.n.y) * k]) {
        int i = i0;
        if (i == 0) {
          either(row);
          i = 2;
        }
        for (; i < nx - 1; i += 2) regular(row + i);
        if (i == nx - 1) either(row + i);
      } else {
        for (int i = i0; i < nx; i += 2) either(row + i);
      }
    }
}
}  // namespace

void smooth(Level& v, int colour, double omega) {
  if (omega == 1)
    smooth_colour<false>(v, colour, omega);
  else
    smooth_colour<true>(v, colour, omega);
}

void smooth_from_zero(Level& v, double omega) {
  // The first red half-sweep from x = 0 (neighbours all zero), writing every owned cell, so the
  // cycle needs no separate clearing pass; ghosts of this level are cleared by the exchange that
  // follows, except at the box faces, where they stay zero.
  const double *b = v.b.data(), *id = v.inv_diag.data();
  double* x = v.x.data();
  const int parity0 = v.lo.x + v.lo.y + v.lo.z;
  for (int k = 0; k < v.n.z; ++k)
    for (int j = 0; j < v.n.y; ++j) {
      const int i0 = (0 - parity0 - j - k) & 1;
      const auto row = v.blk.index(0, j, k);
      for (int i = 0; i < v.n.x; ++i) x[row + i] = 0;
      for (int i = i0; i < v.n.x; i += 2) x[row + i] = omega * id[row + i] * b[row + i];
    }
}

void residual(Level& v) {
  const Stencil st(v);
  const double *b = v.b.data(), *d = v.diag.data(), *x = v.x.data();
  const char* cell_regular = v.regular_cell.data();
  const int nx = v.n.x;
  for (int k = 0; k < v.n.z; ++k)
    for (int j = 0; j < v.n.y; ++j) {
      const auto row = v.blk.index(0, j, k);
      double* r = v.r_wide.data() + v.wide.index(0, j, k);  // the row in the two-layer block
      auto general = [&](int i) {
        const auto q = row + i;
        r[i] = d[q] > 0 ? b[q] - (d[q] * x[q] - st.general(x, q)) : 0.0;
      };
      auto regular = [&](int i) {
        const auto q = row + i;
        r[i] = b[q] - (st.rdiag * x[q] - st.regular(x, q));
      };
      auto either = [&](int i) { cell_regular[row + i] ? regular(i) : general(i); };
      if (v.regular_row[j + std::size_t(v.n.y) * k] && nx > 2) {
        either(0);
        for (int i = 1; i < nx - 1; ++i) regular(i);
        either(nx - 1);
      } else {
        for (int i = 0; i < nx; ++i) either(i);
      }
    }
}

void multiply(Level& v, const double* in, double* out) {
  std::vector<double>& x = v.r;  // free outside a V-cycle
  const int nx = v.n.x;
  std::size_t p = 0;
  for (int k = 0; k < v.n.z; ++k)
    for (int j = 0; j < v.n.y; ++j, p += nx)
      std::copy(in + p, in + p + nx, &x[v.blk.index(0, j, k)]);
  v.halo->exchange(x);
  const Stencil st(v);
  const double* d = v.diag.data();
  const char* solid = v.solid.data();
  const char* cell_regular = v.regular_cell.data();
  p = 0;
  for (int k = 0; k < v.n.z; ++k)
    for (int j = 0; j < v.n.y; ++j, p += nx) {
      const auto row = v.blk.index(0, j, k);
      double* y = out + p;
      auto general = [&](int i) {
        const auto q = row + i;
        y[i] = solid[q] ? x[q] : d[q] * x[q] - st.general(x.data(), q);
      };
      auto regular = [&](int i) { y[i] = st.rdiag * x[row + i] - st.regular(x.data(), row + i); };
      auto either = [&](int i) { cell_regular[row + i] ? regular(i) : general(i); };
      if (v.regular_row[j + std::size_t(v.n.y) * k] && nx > 2) {
        either(0);
        for (int i = 1; i < nx - 1; ++i) regular(i);
        either(nx - 1);
      } else {
        for (int i = 0; i < nx; ++i) either(i);
      }
    }
}

void restrict_to(Level& f, Level& c) {
  // Separable: along x for every fine row (two layers of ghost rows too), then y, then z, from
  // the residual with two ghost layers (Level::r_wide: residual() and the caller's exchange).
  const int ncx = c.n.x, ncy = c.n.y, nfy4 = f.n.y + 4;
  {
    const int *i0 = f.r_index[0][0].data(), *i1 = f.r_index[0][1].data(),
              *i2 = f.r_index[0][2].data(), *i3 = f.r_index[0][3].data();
    const double *w0 = f.r_weight[0][0].data(), *w1 = f.r_weight[0][1].data(),
                 *w2 = f.r_weight[0][2].data(), *w3 = f.r_weight[0][3].data();
    for (int k = -2; k <= f.n.z + 1; ++k)
      for (int j = -2; j <= f.n.y + 1; ++j) {
        const double* r = f.r_wide.data() + f.wide.index(0, j, k);
        double* out = f.work_x.data() + std::size_t((j + 2) + nfy4 * (k + 2)) * ncx;
        for (int I = 0; I < ncx; ++I)
          out[I] = w0[I] * r[i0[I]] + w1[I] * r[i1[I]] + w2[I] * r[i2[I]] + w3[I] * r[i3[I]];
      }
  }
  for (int k = -2; k <= f.n.z + 1; ++k)
    for (int J = 0; J < ncy; ++J) {
      double* out = f.work_y.data() + (std::size_t(k + 2) * ncy + J) * ncx;
      std::fill(out, out + ncx, 0.0);
      for (int m = 0; m < 4; ++m) {
        const double w = f.r_weight[1][m][J];
        const double* in =
            f.work_x.data() + std::size_t((f.r_index[1][m][J] + 2) + nfy4 * (k + 2)) * ncx;
        for (int I = 0; I < ncx; ++I) out[I] += w * in[I];
      }
    }
  for (int K = 0; K < c.n.z; ++K)
    for (int J = 0; J < ncy; ++J) {
      double* out = c.b.data() + c.blk.index(0, J, K);
      std::fill(out, out + ncx, 0.0);
      for (int m = 0; m < 4; ++m) {
        const double w = f.r_weight[2][m][K];
        const double* in = f.work_y.data() + (std::size_t(f.r_index[2][m][K] + 2) * ncy + J) * ncx;
        for (int I = 0; I < ncx; ++I) out[I] += w * in[I];
      }
    }
}

void prolong_add(Level& c, Level& f) {
  // Per fine row: the four coarse rows combined first (y and z weights), then along x.
  std::vector<double>& t = c.r;  // coarse work row (the coarse residual is free here)
  const int ncx2 = c.n.x + 2;
  const int *i0 = f.p_index[0][0].data(), *i1 = f.p_index[0][1].data();
  const double *w0 = f.p_weight[0][0].data(), *w1 = f.p_weight[0][1].data();
  for (int k = 0; k < f.n.z; ++k)
    for (int j = 0; j < f.n.y; ++j) {
      double* row = t.data() + 1;  // coarse x index -1 .. n
      std::fill(row - 1, row - 1 + ncx2, 0.0);
      for (int mz = 0; mz < 2; ++mz)
        for (int my = 0; my < 2; ++my) {
          const double w = f.p_weight[2][mz][k] * f.p_weight[1][my][j];
          if (w == 0) continue;
          const double* in = c.x.data() + c.blk.index(0, f.p_index[1][my][j], f.p_index[2][mz][k]);
          for (int I = -1; I <= c.n.x; ++I) row[I] += w * in[I];
        }
      const auto q0 = f.blk.index(0, j, k);
      double* x = f.x.data() + q0;
      const double* d = f.diag.data() + q0;
      for (int i = 0; i < f.n.x; ++i) {
        const double s = w0[i] * row[i0[i]] + w1[i] * row[i1[i]];
        x[i] += d[i] > 0 ? s : 0.0;  // solid cells stay at zero
      }
    }
}

}  // namespace biota::linalg::multigrid
