#pragma once
/// \file compact_near.hpp
/// \brief The compacted distance test under the neighbour searches (the seaweed cell list, the
/// boids' perception): over the points k < n of SoA arrays X, Y, Z, the offset d_k = X_k - x and
/// r2_k = (dx dx + dy dy) + dz dz (separate multiplies and adds, as core::dot), and the index
/// base + k and r2_k of every point with r2_k < radius2 that also passes the caller's lane test,
/// written to out / out_r2 in increasing k. No branch per point: a branch that is taken about
/// half the time mispredicts, and each miss discards the next points' work in flight. AVX-512:
/// 8 lanes, masked loads, a register compress and plain stores (the compress-to-memory form is
/// slow on AMD); AVX2: 4 lanes packed by a permutation table; otherwise a scalar loop that writes
/// every point and advances the output by the test. Every point, the tail included, goes through
/// the same arithmetic, so a decision never depends on where the point sits in the array.
#if defined(__AVX512F__) || defined(__AVX2__)
#include <immintrin.h>
#endif

// The vector width compact_near() runs at, for the lane tests of its callers (see KeepAll).
#if defined(__AVX512F__) && defined(__AVX512VL__)
#define BIOTA_COMPACT_NEAR_LANES 8
#elif defined(__AVX2__)
#define BIOTA_COMPACT_NEAR_LANES 4
#else
#define BIOTA_COMPACT_NEAR_LANES 1
#endif

#include <array>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "core/types.hpp"

namespace biota::core {

#if defined(__AVX512F__) || defined(__AVX2__)
/// \brief For each 4-bit lane mask, the 32-bit lane permutation (_mm256_permutevar8x32) that
/// packs the selected 64-bit lanes of a 4-lane vector to the front, in order.
inline constexpr auto kPack4 = [] {
  std::array<std::array<int, 8>, 16> t{};
  for (int m = 0; m < 16; ++m) {
    int o = 0;
    for (int l = 0; l < 4; ++l)
      if (m & (1 << l)) t[m][o++] = 2 * l, t[m][o++] = 2 * l + 1;
    for (; o < 8; ++o) t[m][o] = 0;
  }
  return t;
}();
#endif

/// \brief The lane test of a search that keeps every point within the radius. A test is called
/// with the offsets and r2 of a group of lanes and returns which lanes to keep: an __mmask8 for
/// 8 lanes (AVX-512), an all-ones/all-zeros __m256d for 4 (AVX2), a bool for one point.
struct KeepAll {
#if BIOTA_COMPACT_NEAR_LANES == 8
  __mmask8 operator()(__m512d, __m512d, __m512d, __m512d) const {
    return 0xFF;
  }
#elif BIOTA_COMPACT_NEAR_LANES == 4
  __m256d operator()(__m256d, __m256d, __m256d, __m256d r2) const {
    return _mm256_cmp_pd(r2, r2, _CMP_EQ_OQ);  // all ones (r2 is never NaN for finite points)
  }
#endif
  bool operator()(Real, Real, Real, Real) const {
    return true;
  }
};

/// \brief See the file comment. `out` and `out_r2` need room for n + 8 entries. Index is
/// std::uint64_t or std::uint32_t (half the bytes to compress and store where base + n fits).
template <class Index, class Test = KeepAll>
[[gnu::always_inline]] inline std::size_t compact_near(const Real* X, const Real* Y, const Real* Z,
                                                       std::size_t n, const Vec3& x, Real radius2,
                                                       Index base, Index* out, Real* out_r2,
                                                       const Test& test = {}) {
  static_assert(std::is_same_v<Index, std::uint64_t> || std::is_same_v<Index, std::uint32_t>);
  [[maybe_unused]] constexpr bool kWide = sizeof(Index) == 8;  // unused by the scalar loop
  std::size_t cnt = 0;
#if BIOTA_COMPACT_NEAR_LANES == 8
  const __m512d px = _mm512_set1_pd(x.x), py = _mm512_set1_pd(x.y), pz = _mm512_set1_pd(x.z);
  const __m512d rr = _mm512_set1_pd(radius2);
  // base + k + lane, carried across iterations: 8 lanes of 64 or of 32 bits.
  __m512i idx = _mm512_add_epi64(_mm512_set1_epi64(static_cast<long long>(base)),
                                 _mm512_set_epi64(7, 6, 5, 4, 3, 2, 1, 0));
  __m256i idx32 = _mm256_add_epi32(_mm256_set1_epi32(static_cast<int>(base)),
                                   _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
  // One group of 8 points at k (lanes outside tm not loaded and not kept).
  auto group = [&](std::size_t k, __mmask8 tm) {
    const __m512d dx = _mm512_sub_pd(_mm512_maskz_loadu_pd(tm, X + k), px);
    const __m512d dy = _mm512_sub_pd(_mm512_maskz_loadu_pd(tm, Y + k), py);
    const __m512d dz = _mm512_sub_pd(_mm512_maskz_loadu_pd(tm, Z + k), pz);
    const __m512d r2 = _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(dx, dx), _mm512_mul_pd(dy, dy)),
                                     _mm512_mul_pd(dz, dz));
    const __mmask8 m = tm & _mm512_cmp_pd_mask(r2, rr, _CMP_LT_OQ) & test(dx, dy, dz, r2);
    if constexpr (kWide) {
      _mm512_storeu_si512(out + cnt, _mm512_maskz_compress_epi64(m, idx));
      idx = _mm512_add_epi64(idx, _mm512_set1_epi64(8));
    } else {
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + cnt),
                          _mm256_maskz_compress_epi32(m, idx32));
      idx32 = _mm256_add_epi32(idx32, _mm256_set1_epi32(8));
    }
    _mm512_storeu_pd(out_r2 + cnt, _mm512_maskz_compress_pd(m, r2));
    cnt += static_cast<std::size_t>(__builtin_popcount(m));
  };
  std::size_t k = 0;
  for (; k + 8 <= n; k += 8) group(k, __mmask8(0xFF));
  if (k < n) group(k, __mmask8((1u << (n - k)) - 1));
#elif BIOTA_COMPACT_NEAR_LANES == 4
  const __m256d px = _mm256_set1_pd(x.x), py = _mm256_set1_pd(x.y), pz = _mm256_set1_pd(x.z);
  const __m256d rr = _mm256_set1_pd(radius2);
  const __m256i lanes = _mm256_set_epi64x(3, 2, 1, 0), four = _mm256_set1_epi64x(4);
  __m256i idx = _mm256_add_epi64(_mm256_set1_epi64x(static_cast<long long>(base)), lanes);
  // One group of 4 points with offsets (dx, dy, dz); in the tail, `valid` (the lanes inside n)
  // is and-ed into the decision.
  auto group = [&](__m256d dx, __m256d dy, __m256d dz, bool tail, __m256d valid) {
    const __m256d r2 = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)),
                                     _mm256_mul_pd(dz, dz));
    __m256d m = _mm256_and_pd(_mm256_cmp_pd(r2, rr, _CMP_LT_OQ), test(dx, dy, dz, r2));
    if (tail) m = _mm256_and_pd(m, valid);
    const int bits = _mm256_movemask_pd(m);
    const __m256i perm = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(kPack4[bits].data()));
    const __m256i packed = _mm256_permutevar8x32_epi32(idx, perm);
    if constexpr (kWide)
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + cnt), packed);
    else  // the low halves of the four 64-bit lanes
      _mm_storeu_si128(reinterpret_cast<__m128i*>(out + cnt),
                       _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(
                           packed, _mm256_setr_epi32(0, 2, 4, 6, 0, 0, 0, 0))));
    _mm256_storeu_pd(out_r2 + cnt,
                     _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(r2), perm)));
    cnt += static_cast<std::size_t>(__builtin_popcount(bits));
    idx = _mm256_add_epi64(idx, four);
  };
  std::size_t k = 0;
  // Full vectors: plain loads and no lane mask (maskload is slow on AMD); the tail: masked loads
  // of the same values through the same code.
  for (; k + 4 <= n; k += 4)
    group(_mm256_sub_pd(_mm256_loadu_pd(X + k), px), _mm256_sub_pd(_mm256_loadu_pd(Y + k), py),
          _mm256_sub_pd(_mm256_loadu_pd(Z + k), pz), false, rr);
  if (k < n) {
    const __m256i tm = _mm256_cmpgt_epi64(_mm256_set1_epi64x(static_cast<long long>(n - k)), lanes);
    group(_mm256_sub_pd(_mm256_maskload_pd(X + k, tm), px),
          _mm256_sub_pd(_mm256_maskload_pd(Y + k, tm), py),
          _mm256_sub_pd(_mm256_maskload_pd(Z + k, tm), pz), true, _mm256_castsi256_pd(tm));
  }
#else
  for (std::size_t k = 0; k < n; ++k) {
    const Real dx = X[k] - x.x, dy = Y[k] - x.y, dz = Z[k] - x.z;
    const Real r2 = dx * dx + dy * dy + dz * dz;
    out[cnt] = static_cast<Index>(base + k);
    out_r2[cnt] = r2;
    cnt += (r2 < radius2) & test(dx, dy, dz, r2);
  }
#endif
  return cnt;
}

}  // namespace biota::core
