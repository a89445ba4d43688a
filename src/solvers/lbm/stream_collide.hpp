#pragma once
/// \file stream_collide.hpp
/// \brief The fused pull-stream + collide sweep over a rank's owned cells.
#include <cstdint>

#include "grid/field.hpp"
#include "solvers/lbm/collision.hpp"

namespace biota::solvers::lbm {

/// \brief Where the force density comes from.
enum class ForceMode { kNone, kUniform, kField };

/// \brief Arguments of one sweep.
struct SweepArgs {
  const grid::Field<double>* src;
  grid::Field<double>* dst;
  const grid::Field<double>* force;
  grid::Field<double>* rho;
  grid::Field<double>* u;
  const std::uint8_t* solid;
  double uniform_force[3];
  Relaxation relax;
};

/// \brief dst(x) = collide(src(x - c_i)) for every owned cell; solid cells are reset to rest.
/// Template parameters remove every per-cell branch the configuration does not need.
template <class L, bool kTrt, ForceMode kForce, bool kMacro, bool kSolids>
void stream_collide(const SweepArgs& a) {
  constexpr int Q = L::Q;
  const auto& src = *a.src;
  auto& dst = *a.dst;
  const auto n = src.cells();
  std::ptrdiff_t off[Q];
  for (int q = 0; q < Q; ++q)
    off[q] = L::c[q][0] + L::c[q][1] * src.stride_y() + L::c[q][2] * src.stride_z();
  const double* sp[Q];
  double* dp[Q];
  for (int q = 0; q < Q; ++q) {
    sp[q] = src.component(q) - off[q];
    dp[q] = dst.component(q);
  }
  const double* fx = kForce == ForceMode::kField ? a.force->component(0) : nullptr;
  const double* fy = kForce == ForceMode::kField ? a.force->component(1) : nullptr;
  const double* fz = kForce == ForceMode::kField ? a.force->component(2) : nullptr;
  double* rp = kMacro ? a.rho->component(0) : nullptr;
  double* ux = kMacro ? a.u->component(0) : nullptr;
  double* uy = kMacro ? a.u->component(1) : nullptr;
  double* uz = kMacro ? a.u->component(2) : nullptr;
  for (int k = 0; k < n.z; ++k)
    for (int j = 0; j < n.y; ++j) {
      const std::ptrdiff_t row = src.index(0, j, k);
#pragma GCC ivdep
      for (std::ptrdiff_t c = row; c < row + n.x; ++c) {
        double f[Q];
        if constexpr (kSolids) {
          if (a.solid[c]) {
#pragma GCC unroll 32
            for (int q = 0; q < Q; ++q) dp[q][c] = L::w[q];
            continue;
          }
        }
#pragma GCC unroll 32
        for (int q = 0; q < Q; ++q) f[q] = sp[q][c];
        double gx = 0, gy = 0, gz = 0;
        if constexpr (kForce == ForceMode::kUniform) {
          gx = a.uniform_force[0];
          gy = a.uniform_force[1];
          gz = a.uniform_force[2];
        } else if constexpr (kForce == ForceMode::kField) {
          gx = a.uniform_force[0] + fx[c];
          gy = a.uniform_force[1] + fy[c];
          gz = a.uniform_force[2] + fz[c];
        }
        double rho, vx, vy, vz;
        collide<L, kTrt>(f, a.relax, gx, gy, gz, rho, vx, vy, vz);
#pragma GCC unroll 32
        for (int q = 0; q < Q; ++q) dp[q][c] = f[q];
        if constexpr (kMacro) {
          rp[c] = rho;
          ux[c] = vx;
          uy[c] = vy;
          uz[c] = vz;
        }
      }
    }
}

}  // namespace biota::solvers::lbm
