#pragma once
/// \file aa_simd.hpp
/// \brief The cell update of the AA sweep (aa_sweep.hpp) written on explicit vector registers:
/// `collide` on 8 (AVX-512) or 4 (AVX2) cells at once, the same operations in the same order per
/// lane, so the same bits as the scalar code (the build uses -ffp-contract=off; vector add, mul,
/// div and fma are the scalar IEEE operations lane by lane, a negation flips the sign bit as
/// unary minus does).
///
/// Why not leave it to the compiler: GCC 12 vectorises the scalar cell loop, but its loop keeps
/// the 2Q stream pointers and the input copy of the solids on the stack and reloads them per
/// vector; one D3Q19 cell with Guo forcing took about 40 cycles in L1 and L2 alike. Written out,
/// 30-35 (jobs/dev/lbm_in_core.cpp; docs/performance.md, session 35). Without AVX2 there is no
/// vector path and the scalar loop does every cell.
#if defined(__AVX512F__) || (defined(__AVX2__) && defined(__FMA__))
#include <immintrin.h>
#endif

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "solvers/lbm/collision.hpp"
#include "solvers/lbm/stream_collide.hpp"  // ForceMode

namespace biota::solvers::lbm {

/// \brief Where one sweep reads and writes.
template <class L>
struct AaCellStreams {
  double* read[L::Q];   ///< cell c reads population q at read[q][c]
  double* write[L::Q];  ///< and writes its post-collision q at write[q][c]
  const double* force[3];
  const std::uint8_t* solid;
  double *rho, *ux, *uy, *uz;
};

#if defined(__AVX512F__)
#define BIOTA_AA_SIMD_LANES 8
struct AaVec {
  using V = __m512d;
  using Mask = __mmask8;
  static constexpr int kLanes = 8;
  static V load(const double* p) { return _mm512_loadu_pd(p); }
  static void store(double* p, V v) { _mm512_storeu_pd(p, v); }
  static V set1(double x) { return _mm512_set1_pd(x); }
  static V zero() { return _mm512_setzero_pd(); }
  static V add(V a, V b) { return _mm512_add_pd(a, b); }
  static V sub(V a, V b) { return _mm512_sub_pd(a, b); }
  static V mul(V a, V b) { return _mm512_mul_pd(a, b); }
  static V div(V a, V b) { return _mm512_div_pd(a, b); }
  static V fma(V a, V b, V c) { return _mm512_fmadd_pd(a, b, c); }
  static V neg(V a) { return _mm512_xor_pd(a, _mm512_set1_pd(-0.0)); }
  /// Lanes whose solid flag (one byte per cell) is set.
  static Mask solid(const std::uint8_t* s) {
    // The masked form with all lanes set is the plain widening; the plain intrinsic makes GCC 12
    // warn (-Wmaybe-uninitialized inside avx512fintrin.h) at every instantiation.
    const __m512i v = _mm512_maskz_cvtepu8_epi64(
        __mmask8(0xFF), _mm_loadl_epi64(reinterpret_cast<const __m128i*>(s)));
    return _mm512_test_epi64_mask(v, v);
  }
  /// m ? b : a per lane.
  static V select(Mask m, V b, V a) { return _mm512_mask_blend_pd(m, a, b); }
};
#elif defined(__AVX2__) && defined(__FMA__)
#define BIOTA_AA_SIMD_LANES 4
struct AaVec {
  using V = __m256d;
  using Mask = __m256d;
  static constexpr int kLanes = 4;
  static V load(const double* p) { return _mm256_loadu_pd(p); }
  static void store(double* p, V v) { _mm256_storeu_pd(p, v); }
  static V set1(double x) { return _mm256_set1_pd(x); }
  static V zero() { return _mm256_setzero_pd(); }
  static V add(V a, V b) { return _mm256_add_pd(a, b); }
  static V sub(V a, V b) { return _mm256_sub_pd(a, b); }
  static V mul(V a, V b) { return _mm256_mul_pd(a, b); }
  static V div(V a, V b) { return _mm256_div_pd(a, b); }
  static V fma(V a, V b, V c) { return _mm256_fmadd_pd(a, b, c); }
  static V neg(V a) { return _mm256_xor_pd(a, _mm256_set1_pd(-0.0)); }
  static Mask solid(const std::uint8_t* s) {
    int four;
    std::memcpy(&four, s, sizeof four);
    const __m256i v = _mm256_cvtepu8_epi64(_mm_cvtsi32_si128(four));
    return _mm256_castsi256_pd(
        _mm256_xor_si256(_mm256_cmpeq_epi64(v, _mm256_setzero_si256()), _mm256_set1_epi64x(-1)));
  }
  static V select(Mask m, V b, V a) { return _mm256_blendv_pd(a, b, m); }
};
#else
#define BIOTA_AA_SIMD_LANES 0
#endif

#if BIOTA_AA_SIMD_LANES > 0
/// \brief The per-cell constants of collide, formed as collide forms them, broadcast once per
/// sweep. kTrt selects omega_minus for the odd part; force: see aa_sweep.hpp.
struct AaVecConstants {
  AaVec::V op, neg_op, one, half, c15, m3sp, b, cc, bm, cm, neg_hp, neg_hm;
  AaVec::V g0[3];  ///< the uniform force
  AaVec::V gc[3];  ///< the force of cells that load none
  AaVecConstants(const Relaxation& r, bool trt, ForceMode force, const double uniform[3]) {
    using S = AaVec;
    const double o_p = r.omega_plus, o_m = trt ? r.omega_minus : r.omega_plus;
    const double sp = 1.0 - 0.5 * o_p, sm = 1.0 - 0.5 * o_m;
    op = S::set1(o_p), neg_op = S::set1(-o_p), one = S::set1(1.0), half = S::set1(0.5);
    c15 = S::set1(1.5), m3sp = S::set1(-3.0 * sp), b = S::set1(4.5 * o_p), cc = S::set1(9.0 * sp);
    bm = S::set1(3.0 * o_m), cm = S::set1(3.0 * sm);
    neg_hp = S::set1(-(0.5 * o_p)), neg_hm = S::set1(-(0.5 * o_m));
    for (int i = 0; i < 3; ++i) {
      g0[i] = S::set1(uniform[i]);
      gc[i] = force == ForceMode::kNone      ? S::set1(0.0)
              : force == ForceMode::kUniform ? g0[i]
                                             : S::set1(uniform[i] + 0.0);
    }
  }
};

/// \brief cdot of collision.hpp on vectors: only the non-zero components of c, the first one
/// negated by a sign flip where c < 0. (collision.hpp's cdot as a template on GCC's vector
/// operators gave the same bits but a D3Q19 cell 4-7% slower in L2: kept apart.)
[[gnu::always_inline]] inline AaVec::V cdot_v(const std::array<int, 3>& c, AaVec::V x, AaVec::V y,
                                              AaVec::V z) {
  using S = AaVec;
  S::V s = S::zero();
  bool any = false;
  const S::V v[3] = {x, y, z};
  for (int a = 0; a < 3; ++a) {
    if (c[a] == 0) continue;
    s = any ? (c[a] > 0 ? S::add(s, v[a]) : S::sub(s, v[a])) : (c[a] > 0 ? v[a] : S::neg(v[a]));
    any = true;
  }
  return s;
}

/// \brief The cells [begin, begin + k W) of one row piece, W = AaVec::kLanes, k as large as fits
/// below end; returns the first cell not done (the caller's scalar loop takes the rest). The
/// template parameters are those of aa_stream_collide; kLoad: this piece reads the force field.
template <class L, bool kTrt, ForceMode kForce, bool kLoad, bool kMacro, bool kSolids>
[[gnu::always_inline]] inline std::ptrdiff_t aa_cells_simd(const AaCellStreams<L>& a,
                                                           const AaVecConstants& k,
                                                           std::ptrdiff_t begin,
                                                           std::ptrdiff_t end) {
  using S = AaVec;
  using V = S::V;
  constexpr int Q = L::Q, P = (Q - 1) / 2, W = S::kLanes;
  std::ptrdiff_t c = begin;
  for (; c + W <= end; c += W) {
    V f[Q];
#pragma GCC unroll 32
    for (int q = 0; q < Q; ++q) f[q] = S::load(a.read[q] + c);
    V gx = k.gc[0], gy = k.gc[1], gz = k.gc[2];
    if constexpr (kForce == ForceMode::kField && kLoad) {
      gx = S::add(k.g0[0], S::load(a.force[0] + c));
      gy = S::add(k.g0[1], S::load(a.force[1] + c));
      gz = S::add(k.g0[2], S::load(a.force[2] + c));
    }
    // collide(): moments over the opposite pairs.
    V s[P], d[P];
    V m = f[0], jx = S::zero(), jy = S::zero(), jz = S::zero();
#pragma GCC unroll 32
    for (int p = 0; p < P; ++p) {
      const int q = 2 * p + 1;
      s[p] = S::add(f[q], f[q + 1]);
      d[p] = S::sub(f[q], f[q + 1]);
      m = S::add(m, s[p]);
      if (L::c[q][0] != 0) jx = L::c[q][0] > 0 ? S::add(jx, d[p]) : S::sub(jx, d[p]);
      if (L::c[q][1] != 0) jy = L::c[q][1] > 0 ? S::add(jy, d[p]) : S::sub(jy, d[p]);
      if (L::c[q][2] != 0) jz = L::c[q][2] > 0 ? S::add(jz, d[p]) : S::sub(jz, d[p]);
    }
    const V inv_rho = S::div(k.one, m);
    const V ux = S::mul(S::add(jx, S::mul(k.half, gx)), inv_rho);
    const V uy = S::mul(S::add(jy, S::mul(k.half, gy)), inv_rho);
    const V uz = S::mul(S::add(jz, S::mul(k.half, gz)), inv_rho);
    const V uu = S::add(S::add(S::mul(ux, ux), S::mul(uy, uy)), S::mul(uz, uz));
    const V uf = S::add(S::add(S::mul(ux, gx), S::mul(uy, gy)), S::mul(uz, gz));
    const V av = S::fma(S::mul(k.op, m), S::sub(k.one, S::mul(k.c15, uu)), S::mul(k.m3sp, uf));
    const V b = S::mul(k.b, m), bm = S::mul(k.bm, m);
    V out[Q];
    out[0] = S::fma(k.neg_op, f[0], S::fma(S::set1(L::w[0]), av, f[0]));
#pragma GCC unroll 32
    for (int p = 0; p < P; ++p) {
      const int q = 2 * p + 1;
      const V w = S::set1(L::w[q]);
      const V cu = cdot_v(L::c[q], ux, uy, uz);
      const V cf = cdot_v(L::c[q], gx, gy, gz);
      const V even = S::mul(w, S::fma(cu, S::fma(b, cu, S::mul(k.cc, cf)), av));
      const V odd = S::mul(w, S::fma(bm, cu, S::mul(k.cm, cf)));
      const V dp = S::fma(k.neg_hp, s[p], even), dm = S::fma(k.neg_hm, d[p], odd);
      out[q] = S::add(f[q], S::add(dp, dm));
      out[q + 1] = S::add(f[q + 1], S::sub(dp, dm));
    }
    if constexpr (kSolids) {
      // A solid cell keeps what it holds: slot q written here held the streamed opp(q).
      const S::Mask solid = S::solid(a.solid + c);
#pragma GCC unroll 32
      for (int q = 0; q < Q; ++q) S::store(a.write[q] + c, S::select(solid, f[L::opp[q]], out[q]));
      if constexpr (kMacro) {
        S::store(a.rho + c, S::select(solid, S::load(a.rho + c), m));
        S::store(a.ux + c, S::select(solid, S::load(a.ux + c), ux));
        S::store(a.uy + c, S::select(solid, S::load(a.uy + c), uy));
        S::store(a.uz + c, S::select(solid, S::load(a.uz + c), uz));
      }
    } else {
#pragma GCC unroll 32
      for (int q = 0; q < Q; ++q) S::store(a.write[q] + c, out[q]);
      if constexpr (kMacro) {
        S::store(a.rho + c, m);
        S::store(a.ux + c, ux);
        S::store(a.uy + c, uy);
        S::store(a.uz + c, uz);
      }
    }
  }
  return c;
}
#endif

}  // namespace biota::solvers::lbm
