#pragma once
/// \file seaweed_joint_block.hpp
/// \brief The seaweed joint law (stretch spring-damper at the anchor plus the 3-DOF rotational
/// spring-damper, see SeaweedBodies) for a block of joints at once, in structure-of-arrays form,
/// so the compiler turns each step into vector instructions. Every lane performs exactly the
/// operations of the scalar Vec3/Quat code in the same order (the build uses -ffp-contract=off,
/// and vector add/mul/div/sqrt are the same IEEE operations as scalar ones). The bend angle
/// 2 atan2(s, w) comes from a series below 11 degrees and from libm above (the .cpp), so the
/// results equal those of Quat::rotation_vector to round-off, on every rank alike.
#if defined(__AVX512F__) || defined(__AVX2__)
#include <immintrin.h>
#endif

#include <cstddef>

#include "core/types.hpp"

namespace biota::models::plants {

using core::Real;

inline constexpr int kJointBlock = 8;

/// \brief Inputs and outputs of kJointBlock joints (lane l = one joint; child c, parent p).
struct JointBlock {
  using Lane = Real[kJointBlock];
  struct V {
    Lane x, y, z;
  };
  struct Q {
    Lane w, x, y, z;
  };
  // Inputs: orientations, the child's rest anchor (in its frame; the parent's is 0 - ac in the
  // parent's frame), positions, velocities, angular velocities of child and parent. The rest
  // relative orientation is the identity (seaweed_layout()).
  Q qc, qp;
  V ac, xc, xp, vc, vp, wc, wp;
  // Outputs: force on the child F, rotational torque on the child T, the child's total torque
  // cross(r_c, F) + T, the parent's cross(r_p, -F) - T (its force is -F), and |F|, |T|.
  V F, T, tc, tp;
  Lane fm, tm;
};

/// \brief One input lane of a block from scattered slots: dst[l] = src[idx[l]] for every lane.
/// With AVX-512 or AVX2 a vector gather puts the lanes into a register and one vector store
/// writes them: eight scalar stores read back as one vector by evaluate_joint_block stall the
/// store-to-load forwarding (measured: the whole particle step 5-8% slower,
/// docs/performance-seaweed.md session 16). The same values either way, so the results do not
/// change.
inline void gather_lane(Real* dst, const Real* src, const std::size_t* idx) {
  static_assert(kJointBlock == 8 && sizeof(std::size_t) == sizeof(long long));
  // The masked forms with an all-true mask: the unmasked intrinsics read an undefined source
  // register (GCC warns).
#if defined(__AVX512F__)
  _mm512_storeu_pd(dst, _mm512_mask_i64gather_pd(_mm512_setzero_pd(), __mmask8(0xFF),
                                                 _mm512_loadu_si512(idx), src, sizeof(Real)));
#elif defined(__AVX2__)
  const auto* i = reinterpret_cast<const __m256i*>(idx);
  const __m256d zero = _mm256_setzero_pd(), all = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
  _mm256_storeu_pd(dst,
                   _mm256_mask_i64gather_pd(zero, src, _mm256_loadu_si256(i), all, sizeof(Real)));
  _mm256_storeu_pd(
      dst + 4, _mm256_mask_i64gather_pd(zero, src, _mm256_loadu_si256(i + 1), all, sizeof(Real)));
#else
  for (int l = 0; l < kJointBlock; ++l) dst[l] = src[idx[l]];
#endif
}

/// \brief Evaluate the joint law on all lanes of `b` (see JointBlock for the operation order).
void evaluate_joint_block(JointBlock& b, Real joint_k, Real joint_c, Real bend_k, Real bend_c);

}  // namespace biota::models::plants
