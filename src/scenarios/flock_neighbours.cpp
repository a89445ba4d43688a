#include "scenarios/flock_neighbours.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>

#include <unistd.h>

namespace biota::scenarios {

namespace mf = models::flock;
using core::Vec3;

namespace {

/// \brief Copy the candidates k in the slot ranges `rows` that are eligible and whose squared
/// distance to the box [lo, hi] is below radius2 from the slot arrays in = (x, y, z, vx, vy, vz)
/// to out, in order; returns their number. `size`: slots in the arrays (the AVX2 tail reads past
/// a row's end below it); `eligible` has 8 readable bytes past them. The outputs need room for the
/// rows' total + 8 entries. One call per bin (not per row): the broadcasts and the setup are paid
/// once.
/// The box distance is rounded the way the per-boid r2 is (((ex² + ey²) + ez²), each e no larger
/// than the boid's |d|): rounding is monotonic, so it never exceeds the r2 of any point in the
/// box, and every candidate that a point of the box can perceive is kept.
std::size_t keep_near_box(const double* const in[6], const std::uint8_t* eligible,
                          const std::pair<std::size_t, std::size_t>* rows, std::size_t nrows,
                          [[maybe_unused]] std::size_t size, const Vec3& lo, const Vec3& hi,
                          double radius2, double* const out[6]) {
  const double *X = in[0], *Y = in[1], *Z = in[2];
  std::size_t n = 0;
#if defined(__AVX512F__)
  const __m512d lx = _mm512_set1_pd(lo.x), ly = _mm512_set1_pd(lo.y), lz = _mm512_set1_pd(lo.z);
  const __m512d hx = _mm512_set1_pd(hi.x), hy = _mm512_set1_pd(hi.y), hz = _mm512_set1_pd(hi.z);
  const __m512d rr = _mm512_set1_pd(radius2), zero = _mm512_setzero_pd();
  auto gap = [&](__m512d c, __m512d l, __m512d h) {
    return _mm512_max_pd(_mm512_max_pd(_mm512_sub_pd(l, c), _mm512_sub_pd(c, h)), zero);
  };
  for (std::size_t r = 0; r < nrows; ++r) {
    const std::size_t last = rows[r].second;
    for (std::size_t k = rows[r].first; k < last; k += 8) {
      const __mmask8 tm = last - k >= 8 ? __mmask8(0xFF) : __mmask8((1u << (last - k)) - 1);
      const __m512d cx = _mm512_maskz_loadu_pd(tm, X + k), cy = _mm512_maskz_loadu_pd(tm, Y + k),
                    cz = _mm512_maskz_loadu_pd(tm, Z + k);
      const __m512d ex = gap(cx, lx, hx), ey = gap(cy, ly, hy), ez = gap(cz, lz, hz);
      const __m512d e2 = _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(ex, ex), _mm512_mul_pd(ey, ey)),
                                       _mm512_mul_pd(ez, ez));
      // Eight flags in one 8-byte load (the array's padding covers the tail), widened to lanes.
      const __m512i el =
          _mm512_cvtepu8_epi64(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(eligible + k)));
      const __mmask8 m =
          _mm512_cmp_pd_mask(e2, rr, _CMP_LT_OQ) & _mm512_mask_test_epi64_mask(tm, el, el);
      // Register compress, then a plain store (the compress-to-memory form is slow on AMD).
      _mm512_storeu_pd(out[0] + n, _mm512_maskz_compress_pd(m, cx));
      _mm512_storeu_pd(out[1] + n, _mm512_maskz_compress_pd(m, cy));
      _mm512_storeu_pd(out[2] + n, _mm512_maskz_compress_pd(m, cz));
      for (int c = 3; c < 6; ++c)
        _mm512_storeu_pd(out[c] + n,
                         _mm512_maskz_compress_pd(m, _mm512_maskz_loadu_pd(tm, in[c] + k)));
      n += static_cast<std::size_t>(__builtin_popcount(m));
    }
  }
#elif defined(__AVX2__)
  const __m256d lx = _mm256_set1_pd(lo.x), ly = _mm256_set1_pd(lo.y), lz = _mm256_set1_pd(lo.z);
  const __m256d hx = _mm256_set1_pd(hi.x), hy = _mm256_set1_pd(hi.y), hz = _mm256_set1_pd(hi.z);
  const __m256d rr = _mm256_set1_pd(radius2), zero = _mm256_setzero_pd();
  const __m256i lanes = _mm256_set_epi64x(3, 2, 1, 0);
  auto gap = [&](__m256d c, __m256d l, __m256d h) {
    return _mm256_max_pd(_mm256_max_pd(_mm256_sub_pd(l, c), _mm256_sub_pd(c, h)), zero);
  };
  std::size_t k = 0, last = 0;
  // Four slots from k on; in the tail (k + 4 > last) only the lanes below last are kept. The
  // tail reads the slots after the row (other bins' points: plain values, masked off) as long as
  // they exist (k + 4 <= size); only at the very end of the arrays does it take masked loads.
  auto group = [&](bool tail) {
    const __m256i tm =
        tail ? _mm256_cmpgt_epi64(_mm256_set1_epi64x(static_cast<long long>(last - k)), lanes)
             : _mm256_set1_epi64x(-1);
    const bool masked_loads = tail && k + 4 > size;
    auto load = [&](const double* a) {
      return masked_loads ? _mm256_maskload_pd(a + k, tm) : _mm256_loadu_pd(a + k);
    };
    const __m256d cx = load(X), cy = load(Y), cz = load(Z);
    const __m256d ex = gap(cx, lx, hx), ey = gap(cy, ly, hy), ez = gap(cz, lz, hz);
    const __m256d e2 = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(ex, ex), _mm256_mul_pd(ey, ey)),
                                     _mm256_mul_pd(ez, ez));
    int flags;  // four flags in one 4-byte load (the array's padding covers the tail)
    std::memcpy(&flags, eligible + k, sizeof flags);
    const __m256i el = _mm256_cvtepu8_epi64(_mm_cvtsi32_si128(flags));
    __m256d m =
        _mm256_andnot_pd(_mm256_castsi256_pd(_mm256_cmpeq_epi64(el, _mm256_setzero_si256())),
                         _mm256_cmp_pd(e2, rr, _CMP_LT_OQ));
    if (tail) m = _mm256_and_pd(m, _mm256_castsi256_pd(tm));
    const int bits = _mm256_movemask_pd(m);
    const __m256i perm =
        _mm256_loadu_si256(reinterpret_cast<const __m256i*>(core::kPack4[bits].data()));
    auto pack = [&](__m256d a) {
      return _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(a), perm));
    };
    _mm256_storeu_pd(out[0] + n, pack(cx));
    _mm256_storeu_pd(out[1] + n, pack(cy));
    _mm256_storeu_pd(out[2] + n, pack(cz));
    for (int c = 3; c < 6; ++c) _mm256_storeu_pd(out[c] + n, pack(load(in[c])));
    n += static_cast<std::size_t>(__builtin_popcount(bits));
  };
  for (std::size_t r = 0; r < nrows; ++r) {
    k = rows[r].first, last = rows[r].second;
    for (; k + 4 <= last; k += 4) group(false);
    if (k < last) group(true);
  }
#else
  // Branch-free: write, then advance (the compiler keeps this scalar; cheap next to the mask).
  for (std::size_t r = 0; r < nrows; ++r)
    for (std::size_t k = rows[r].first; k < rows[r].second; ++k) {
      const double ex = std::max(std::max(lo.x - X[k], X[k] - hi.x), 0.0);
      const double ey = std::max(std::max(lo.y - Y[k], Y[k] - hi.y), 0.0);
      const double ez = std::max(std::max(lo.z - Z[k], Z[k] - hi.z), 0.0);
      for (int c = 0; c < 6; ++c) out[c][n] = in[c][k];
      n += (eligible[k] != 0) & (ex * ex + ey * ey + ez * ez < radius2);
    }
#endif
  return n;
}

}  // namespace

long long slab_rows(const particles::OrderedCellList& cells, int reach) {
  static const double l2_bytes = [] {
    const long v = sysconf(_SC_LEVEL2_CACHE_SIZE);
    return v > 0 ? double(v) : 512.0 * 1024;  // not reported (some VMs, other libcs)
  }();
  constexpr double kBytesPerPoint = 6 * 8 + 1;  // x, y, z, vx, vy, vz, eligibility
  const double points_per_bin =
      double(cells.size()) / double(std::max<std::size_t>(cells.bins(), 1));
  const double row_bytes =
      double(2 * reach + 1) * double(cells.bins_along(0)) * points_per_bin * kBytesPerPoint;
  const double rows = 0.5 * l2_bytes / std::max(row_bytes, 1.0) - 2.0 * reach;
  return std::clamp(static_cast<long long>(rows), 1LL, std::max(cells.bins_along(1), 1LL));
}

void BinNeighbours::gather(const particles::OrderedCellList& cells, std::size_t first,
                           std::size_t last, const double* vx, const double* vy, const double* vz,
                           const std::uint8_t* eligible, double radius2) {
  const double *X = cells.x(), *Y = cells.y(), *Z = cells.z();
  const double* const in[6] = {X, Y, Z, vx, vy, vz};
  Vec3 lo{X[first], Y[first], Z[first]}, hi = lo;
  for (std::size_t k = first + 1; k < last; ++k) {
    lo = {std::min(lo.x, X[k]), std::min(lo.y, Y[k]), std::min(lo.z, Z[k])};
    hi = {std::max(hi.x, X[k]), std::max(hi.y, Y[k]), std::max(hi.z, Z[k])};
  }
  // The bin's rows of candidate slots first (their total bounds the output), then one pass.
  rows_.clear();
  std::size_t total = 0;
  cells.for_each_near_block(lo, [&](std::size_t row_first, std::size_t row_last) {
    rows_.emplace_back(row_first, row_last);
    total += row_last - row_first;
  });
  if (c_[0].size() < total + 8)
    for (auto& c : c_) c.resize(2 * total + 64);
  double* const out[6] = {c_[0].data(), c_[1].data(), c_[2].data(),
                          c_[3].data(), c_[4].data(), c_[5].data()};
  n_ = keep_near_box(in, eligible, rows_.data(), rows_.size(), cells.size(), lo, hi, radius2, out);
  if (acc_.size() < n_ + 8) acc_.resize(2 * n_ + 8), acc_r2_.resize(2 * n_ + 8);
}

mf::NeighbourSums BinNeighbours::sums(const Vec3& x, const Vec3& v, double radius2, double fov_cos,
                                      double d_star) {
  const std::size_t cnt =
      mf::perceive_compact_r2(c_[0].data(), c_[1].data(), c_[2].data(), n_, x, v, core::dot(v, v),
                              radius2, fov_cos, fov_cos * fov_cos, acc_.data(), acc_r2_.data());
  const double d2 = d_star * d_star;
  const std::uint64_t* acc = acc_.data();  // locals: no reloads via `this`
  const double* r2s = acc_r2_.data();
  const double *X = c_[0].data(), *Y = c_[1].data(), *Z = c_[2].data();
  const double *VX = c_[3].data(), *VY = c_[4].data(), *VZ = c_[5].data();
  // The sums of accumulate_neighbour(), in the same order (bitwise). With AVX2 a neighbour's
  // (x, y, z, 0) fills the lanes of one vector: each component gets the same adds in the same
  // order, one vector operation instead of three scalar ones.
#if defined(__AVX2__)
  const __m256d xb = _mm256_setr_pd(x.x, x.y, x.z, 0.0);
  __m256d sep = _mm256_setzero_pd(), vel = _mm256_setzero_pd(), pos = _mm256_setzero_pd();
  for (std::size_t a = 0; a < cnt; ++a) {
    const std::size_t j = acc[a];
    const __m256d d = _mm256_sub_pd(_mm256_setr_pd(X[j], Y[j], Z[j], 0.0), xb);
    const double r2 = r2s[a];  // = core::dot(d, d), from the perception test
    if (r2 < d2) {             // the square root only for the few pairs closer than d*
      const double r = std::sqrt(r2);
      sep = _mm256_sub_pd(sep, _mm256_mul_pd(d, _mm256_set1_pd((d_star - r) / r)));
    }
    vel = _mm256_add_pd(vel, _mm256_setr_pd(VX[j], VY[j], VZ[j], 0.0));
    pos = _mm256_add_pd(pos, d);
  }
  alignas(32) double out[3][4];
  _mm256_store_pd(out[0], sep), _mm256_store_pd(out[1], vel), _mm256_store_pd(out[2], pos);
  const Vec3 sep_sum{out[0][0], out[0][1], out[0][2]}, vel_sum{out[1][0], out[1][1], out[1][2]},
      pos_sum{out[2][0], out[2][1], out[2][2]};
#else
  // In locals: the result `s` may alias the inputs as far as the compiler knows, so summing into
  // it stored every step.
  Vec3 sep{}, vel{}, pos{};
  for (std::size_t a = 0; a < cnt; ++a) {
    const std::size_t j = acc[a];
    const Vec3 d{X[j] - x.x, Y[j] - x.y, Z[j] - x.z};
    const double r2 = r2s[a];  // = core::dot(d, d), from the perception test
    if (r2 < d2) {             // the square root only for the few pairs closer than d*
      const double r = std::sqrt(r2);
      sep -= d * ((d_star - r) / r);
    }
    vel += Vec3{VX[j], VY[j], VZ[j]};
    pos += d;
  }
  const Vec3 sep_sum = sep, vel_sum = vel, pos_sum = pos;
#endif
  // Built at the end (the nearest-neighbour fields keep their defaults): no clear of the whole
  // struct before the loop.
  return {sep_sum, vel_sum, pos_sum, static_cast<int>(cnt)};
}

}  // namespace biota::scenarios
