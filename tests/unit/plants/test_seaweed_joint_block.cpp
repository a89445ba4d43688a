#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/quat.hpp"
#include "models/plants/seaweed_joint_block.hpp"

using biota::core::Quat;
using biota::core::Vec3;
using namespace biota::models::plants;

// Bend torque of a joint whose child is turned by `angle` about a fixed axis (parent
// orientation the identity, nothing moving, bend_k = 1): T = -rotation vector. The block takes
// the angle from a series below 11 degrees and from libm above; both must give
// Quat::rotation_vector (libm) to round-off.
TEST(SeaweedJointBlock, BendTorqueIsTheRotationVectorAcrossTheSeriesBound) {
  const Vec3 axis{0.6, 0.0, 0.8};
  for (double angle = 1e-7; angle < 3.0; angle *= 1.9) {
    JointBlock b{};
    for (int l = 0; l < kJointBlock; ++l) {
      const double a = angle * (1 + 0.01 * l);
      const Quat qc = Quat::axis_angle(axis, a);
      b.qc.w[l] = qc.w, b.qc.x[l] = qc.x, b.qc.y[l] = qc.y, b.qc.z[l] = qc.z;
      b.qp.w[l] = 1;
    }
    evaluate_joint_block(b, 1.0, 0.0, 1.0, 0.0);
    for (int l = 0; l < kJointBlock; ++l) {
      const Quat qc{b.qc.w[l], b.qc.x[l], b.qc.y[l], b.qc.z[l]};
      const Vec3 rv = qc.rotation_vector();
      const double tol = 4e-16 * std::max(angle, 1e-300);
      EXPECT_NEAR(b.T.x[l], -rv.x, tol) << angle;
      EXPECT_NEAR(b.T.y[l], -rv.y, tol) << angle;
      EXPECT_NEAR(b.T.z[l], -rv.z, tol) << angle;
    }
  }
}

// gather_lane (vector gather on AVX-512 / AVX2, a loop otherwise) fills each lane from its slot,
// with repeated, descending and far-apart slots as the joint list has them.
TEST(SeaweedJointBlock, GatherLaneReadsEachLaneFromItsSlot) {
  std::vector<double> src(5000);
  for (std::size_t k = 0; k < src.size(); ++k) src[k] = 0.5 + static_cast<double>(k) * 1.25;
  const std::size_t idx[kJointBlock] = {4999, 0, 17, 17, 3000, 2, 1, 4096};
  double dst[kJointBlock] = {};
  gather_lane(dst, src.data(), idx);
  for (int l = 0; l < kJointBlock; ++l) EXPECT_EQ(dst[l], src[idx[l]]) << l;
}
