#pragma once
/// \file lbm_layout_variants.hpp
/// \brief Storage-layout / streaming-scheme variants of one periodic BGK step, for the layout
/// experiment (tests/benchmarks/lbm_layout_bench.cpp) and its correctness test
/// (tests/unit/lbm/test_layout_variants.cpp).
///
/// Every variant runs the same pointwise arithmetic, the production `collide<L, false>` with zero
/// force, so all of them must agree bitwise with variant (a) = the production sweep
/// `stream_collide<L, false, ForceMode::kNone, false, false>` on a `grid::Field`.
///
/// Periodicity: one process, a 1-cell ghost layer on every side (the production layout:
/// x-stride n+2, 64-byte aligned component planes). Pull schemes refresh every ghost cell from its
/// periodic image by a plain copy before the sweep (`fill_ghosts`); push schemes write into the
/// ghost layer and fold those writes back onto their periodic images after the sweep
/// (`fold_ghosts`). Both stand in for the MPI halo exchange and are part of the timed step.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include "grid/field.hpp"
#include "solvers/lbm/collision.hpp"
#include "solvers/lbm/stream_collide.hpp"

namespace biota::bench::lbm_layout {

using grid::Field;
using solvers::lbm::Relaxation;

inline int wrap(int i, int n) {
  return i < 0 ? i + n : (i >= n ? i - n : i);
}

/// \brief Calls fn(i, j, k, wi, wj, wk) for every ghost cell (i, j, k) of an n^3 box with one ghost
/// layer, (wi, wj, wk) being its periodic image.
template <class Fn>
void for_each_ghost(int n, Fn&& fn) {
  for (int k = -1; k <= n; ++k)
    for (int j = -1; j <= n; ++j) {
      const int wk = wrap(k, n), wj = wrap(j, n);
      if (wk != k || wj != j) {
        for (int i = -1; i <= n; ++i) fn(i, j, k, wrap(i, n), wj, wk);
      } else {
        fn(-1, j, k, n - 1, wj, wk);
        fn(n, j, k, 0, wj, wk);
      }
    }
}

/// \brief Periodic refresh of every ghost cell of every component (SoA), row-wise copies.
inline void fill_ghosts(Field<double>& f) {
  const int n = f.cells().x;
  for (int q = 0; q < f.ncomp(); ++q) {
    double* p = f.component(q);
    for (int k = -1; k <= n; ++k)
      for (int j = -1; j <= n; ++j) {
        const int wk = wrap(k, n), wj = wrap(j, n);
        const std::ptrdiff_t d = f.index(0, j, k), s = f.index(0, wj, wk);
        if (d != s) std::copy(p + s, p + s + n, p + d);
        p[d - 1] = p[s + n - 1];
        p[d + n] = p[s];
      }
  }
}

/// \brief Push-side periodic closure (SoA): a population q written into ghost cell g by an owned
/// cell g - c_q is moved onto the periodic image of g. Slot `slot[q]` holds direction q.
template <class L>
void fold_ghosts(Field<double>& f, const int* slot) {
  const int n = f.cells().x;
  auto inside = [n](int i) { return i >= 0 && i < n; };
  for_each_ghost(n, [&](int i, int j, int k, int wi, int wj, int wk) {
    const std::ptrdiff_t g = f.index(i, j, k), w = f.index(wi, wj, wk);
    for (int q = 1; q < L::Q; ++q)
      if (inside(i - L::c[q][0]) && inside(j - L::c[q][1]) && inside(k - L::c[q][2]))
        f.component(slot[q])[w] = f.component(slot[q])[g];
  });
}

/// \brief Equilibrium at a smooth, non-trivial periodic (rho, u) field, identical for every
/// variant.
template <class L>
void init_state(int n, auto&& set) {
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double x = 6.283185307179586 * i / n, y = 6.283185307179586 * j / n,
                     z = 6.283185307179586 * k / n;
        const double rho = 1.0 + 0.01 * std::sin(x + 2 * y) * std::cos(z);
        const double ux = 0.05 * std::sin(y) * std::cos(z);
        const double uy = 0.04 * std::sin(z + x);
        const double uz = -0.03 * std::cos(x) * std::sin(2 * y);
        for (int q = 0; q < L::Q; ++q)
          set(q, i, j, k, solvers::lbm::equilibrium<L>(q, rho, ux, uy, uz));
      }
}

template <class L>
void offsets(const Field<double>& f, std::ptrdiff_t* off) {
  for (int q = 0; q < L::Q; ++q)
    off[q] = L::c[q][0] + L::c[q][1] * f.stride_y() + L::c[q][2] * f.stride_z();
}

// ---------------------------------------------------------------------------------------------
/// \brief Common interface: step(), get(q, i, j, k) in natural layout (valid after an even number
/// of steps for AA), set(q, i, j, k, v) for initialisation.
template <class L>
struct SoaTwoGrid {
  Field<double> a, b;
  Relaxation r;
  explicit SoaTwoGrid(int n, double tau)
      : a({n, n, n}, L::Q, 1), b({n, n, n}, L::Q, 1), r(Relaxation::bgk(tau)) {}
  double get(int q, int i, int j, int k) const { return a(i, j, k, q); }
  void set(int q, int i, int j, int k, double v) { a(i, j, k, q) = v; }
};

/// (a) SoA, two grids, fused pull-stream + collide: the production kernel itself.
template <class L>
struct SoaPull : SoaTwoGrid<L> {
  using SoaTwoGrid<L>::SoaTwoGrid;
  void step() {
    fill_ghosts(this->a);
    solvers::lbm::SweepArgs s{&this->a, &this->b, nullptr,   nullptr,
                              nullptr,  nullptr,  {0, 0, 0}, this->r};
    solvers::lbm::stream_collide<L, false, solvers::lbm::ForceMode::kNone, false, false>(s);
    this->a.swap(this->b);
  }
};

/// (c) SoA, two grids, fused collide + push-stream; ghost writes folded back.
template <class L>
struct SoaPush : SoaTwoGrid<L> {
  using SoaTwoGrid<L>::SoaTwoGrid;
  void step() {
    constexpr int Q = L::Q;
    const int n = this->a.cells().x;
    std::ptrdiff_t off[Q];
    offsets<L>(this->a, off);
    const double* sp[Q];
    double* dp[Q];
#pragma GCC unroll 32
    for (int q = 0; q < Q; ++q) {
      sp[q] = this->a.component(q);
      dp[q] = this->b.component(q) + off[q];
    }
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j) {
        const std::ptrdiff_t row = this->a.index(0, j, k);
#pragma GCC ivdep
        for (std::ptrdiff_t c = row; c < row + n; ++c) {
          double f[Q], rho, ux, uy, uz;
#pragma GCC unroll 32
          for (int q = 0; q < Q; ++q) f[q] = sp[q][c];
          solvers::lbm::collide<L, false>(f, this->r, 0, 0, 0, rho, ux, uy, uz);
#pragma GCC unroll 32
          for (int q = 0; q < Q; ++q) dp[q][c] = f[q];
        }
      }
    int slot[Q];
#pragma GCC unroll 32
    for (int q = 0; q < Q; ++q) slot[q] = q;
    fold_ghosts<L>(this->b, slot);
    this->a.swap(this->b);
  }
};

/// Non-temporal copy of n doubles to dst: movnti up to a 64-byte boundary, 256-bit streaming stores
/// for whole cache lines, movnti tail. Every store is non-temporal, so no line is read for
/// ownership (the row's first and last lines are written partially: they hold ghost cells).
inline void nt_copy(double* dst, const double* src, std::ptrdiff_t n) {
#if defined(__SSE2__) && defined(__x86_64__)
  std::ptrdiff_t i = 0;
  auto movnti = [&](std::ptrdiff_t k) {
    long long v;
    std::memcpy(&v, src + k, sizeof v);
    _mm_stream_si64(reinterpret_cast<long long*>(dst + k), v);
  };
  for (; i < n && (reinterpret_cast<std::uintptr_t>(dst + i) & 63) != 0; ++i) movnti(i);
#if defined(__AVX__)
  for (; i + 8 <= n; i += 8) {
    _mm256_stream_pd(dst + i, _mm256_loadu_pd(src + i));
    _mm256_stream_pd(dst + i + 4, _mm256_loadu_pd(src + i + 4));
  }
#else
  for (; i + 2 <= n; i += 2) _mm_stream_pd(dst + i, _mm_loadu_pd(src + i));
#endif
  for (; i < n; ++i) movnti(i);
#else
  std::copy(src, src + n, dst);
#endif
}

inline void nt_fence() {
#if defined(__SSE2__)
  _mm_sfence();
#endif
}

/// (e) SoA, two grids, pull, non-temporal stores: a row is collided into an L1-resident SoA row
/// buffer (same vectorised loop as (a)), then streamed to the destination planes.
template <class L>
struct SoaPullNt : SoaTwoGrid<L> {
  std::vector<double, grid::AlignedAllocator<double>> buf;
  SoaPullNt(int n, double tau) : SoaTwoGrid<L>(n, tau), buf(static_cast<std::size_t>(L::Q) * n) {}
  void step() {
    constexpr int Q = L::Q;
    fill_ghosts(this->a);
    const int n = this->a.cells().x;
    std::ptrdiff_t off[Q];
    offsets<L>(this->a, off);
    const double* sp[Q];
    double* dp[Q];
#pragma GCC unroll 32
    for (int q = 0; q < Q; ++q) {
      sp[q] = this->a.component(q) - off[q];
      dp[q] = this->b.component(q);
    }
    double* rb = buf.data();
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j) {
        const std::ptrdiff_t row = this->a.index(0, j, k);
#pragma GCC ivdep
        for (std::ptrdiff_t i = 0; i < n; ++i) {
          double f[Q], rho, ux, uy, uz;
#pragma GCC unroll 32
          for (int q = 0; q < Q; ++q) f[q] = sp[q][row + i];
          solvers::lbm::collide<L, false>(f, this->r, 0, 0, 0, rho, ux, uy, uz);
#pragma GCC unroll 32
          for (int q = 0; q < Q; ++q) rb[q * n + i] = f[q];
        }
#pragma GCC unroll 32
        for (int q = 0; q < Q; ++q) nt_copy(dp[q] + row, rb + q * n, n);
      }
    nt_fence();
    this->a.swap(this->b);
  }
};

/// (d) SoA, one grid, AA pattern (Bailey et al. 2009). Even step: read slot q of x, write the
/// post-collision q into slot opp(q) of x (purely local). Odd step: read direction q from slot
/// opp(q) of x - c_q, write it into slot q of x + c_q. After an odd step the layout is natural.
template <class L>
struct SoaAA {
  Field<double> a;
  Relaxation r;
  long parity = 0;
  SoaAA(int n, double tau) : a({n, n, n}, L::Q, 1), r(Relaxation::bgk(tau)) {}
  double get(int q, int i, int j, int k) const { return a(i, j, k, q); }
  void set(int q, int i, int j, int k, double v) { a(i, j, k, q) = v; }
  void step() {
    constexpr int Q = L::Q;
    const int n = a.cells().x;
    std::ptrdiff_t off[Q];
    offsets<L>(a, off);
    const double* rp[Q];
    double* wp[Q];
    const bool odd = parity++ & 1;
    if (odd) fill_ghosts(a);
#pragma GCC unroll 32
    for (int q = 0; q < Q; ++q) {
      rp[q] = odd ? a.component(L::opp[q]) - off[q] : a.component(q);
      wp[q] = odd ? a.component(q) + off[q] : a.component(L::opp[q]);
    }
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j) {
        const std::ptrdiff_t row = a.index(0, j, k);
        // Reads and writes of different cells never alias (each cell writes exactly the
        // locations it read), so the row vectorises like the two-grid sweep.
#pragma GCC ivdep
        for (std::ptrdiff_t c = row; c < row + n; ++c) {
          double f[Q], rho, ux, uy, uz;
#pragma GCC unroll 32
          for (int q = 0; q < Q; ++q) f[q] = rp[q][c];
          solvers::lbm::collide<L, false>(f, r, 0, 0, 0, rho, ux, uy, uz);
#pragma GCC unroll 32
          for (int q = 0; q < Q; ++q) wp[q][c] = f[q];
        }
      }
    if (odd) {
      int slot[Q];
#pragma GCC unroll 32
      for (int q = 0; q < Q; ++q) slot[q] = q;
      fold_ghosts<L>(a, slot);
    }
  }
};

/// (b) AoS (cell-major, Q contiguous doubles per cell), two grids, pull.
template <class L>
struct AosPull {
  static constexpr int Q = L::Q;
  int n, s;
  std::vector<double, grid::AlignedAllocator<double>> a, b;
  Relaxation r;
  AosPull(int n_, double tau)
      : n(n_),
        s(n_ + 2),
        a(static_cast<std::size_t>(s) * s * s * Q),
        b(a.size()),
        r(Relaxation::bgk(tau)) {}
  std::ptrdiff_t idx(int i, int j, int k) const {
    return (static_cast<std::ptrdiff_t>(k + 1) * s + (j + 1)) * s + (i + 1);
  }
  double get(int q, int i, int j, int k) const { return a[idx(i, j, k) * Q + q]; }
  void set(int q, int i, int j, int k, double v) { a[idx(i, j, k) * Q + q] = v; }
  void fill() {
    for (int k = -1; k <= n; ++k)
      for (int j = -1; j <= n; ++j) {
        const int wk = wrap(k, n), wj = wrap(j, n);
        double* p = a.data();
        const std::ptrdiff_t d = idx(0, j, k) * Q, sr = idx(0, wj, wk) * Q;
        if (d != sr) std::copy(p + sr, p + sr + std::ptrdiff_t(n) * Q, p + d);
        std::copy(p + sr + std::ptrdiff_t(n - 1) * Q, p + sr + std::ptrdiff_t(n) * Q, p + d - Q);
        std::copy(p + sr, p + sr + Q, p + d + std::ptrdiff_t(n) * Q);
      }
  }
  void step() {
    fill();
    std::ptrdiff_t off[Q];
#pragma GCC unroll 32
    for (int q = 0; q < Q; ++q)
      off[q] = (L::c[q][0] + L::c[q][1] * s + L::c[q][2] * std::ptrdiff_t(s) * s) * Q - q;
    const double* sp = a.data();
    double* dp = b.data();
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j) {
        const std::ptrdiff_t row = idx(0, j, k);
#pragma GCC ivdep
        for (std::ptrdiff_t c = row; c < row + n; ++c) {
          double f[Q], rho, ux, uy, uz;
#pragma GCC unroll 32
          for (int q = 0; q < Q; ++q) f[q] = sp[c * Q - off[q]];
          solvers::lbm::collide<L, false>(f, r, 0, 0, 0, rho, ux, uy, uz);
#pragma GCC unroll 32
          for (int q = 0; q < Q; ++q) dp[c * Q + q] = f[q];
        }
      }
    a.swap(b);
  }
};

}  // namespace biota::bench::lbm_layout
