#pragma once
/// \file seaweed_joint_block.hpp
/// \brief The seaweed joint law (stretch spring-damper at the anchor plus the 3-DOF rotational
/// spring-damper, see SeaweedBodies) for a block of joints at once, in structure-of-arrays form,
/// so the compiler turns each step into vector instructions. Every lane performs exactly the
/// operations of the scalar Vec3/Quat code in the same order (the build uses -ffp-contract=off,
/// and vector add/mul/div/sqrt are the same IEEE operations as scalar ones). The bend angle
/// 2 atan2(s, w) comes from a series below 11 degrees and from libm above (the .cpp), so the
/// results equal those of Quat::rotation_vector to round-off, on every rank alike.
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
  // Inputs: orientations, rest anchors (child frame of each sphere), positions, velocities,
  // angular velocities of child and parent, and the rest relative orientation.
  Q qc, qp, qr;
  V ac, ap, xc, xp, vc, vp, wc, wp;
  // Outputs: force on the child F, rotational torque on the child T, the child's total torque
  // cross(r_c, F) + T, the parent's cross(r_p, -F) - T (its force is -F), and |F|, |T|.
  V F, T, tc, tp;
  Lane fm, tm;
};

/// \brief Evaluate the joint law on all lanes of `b` (see JointBlock for the operation order).
void evaluate_joint_block(JointBlock& b, Real joint_k, Real joint_c, Real bend_k, Real bend_c);

}  // namespace biota::models::plants
