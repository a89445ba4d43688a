#pragma once
/// \file aa_sweep.hpp
/// \brief The production LBM sweep: in-place streaming on one population buffer, AA pattern
/// (Bailey et al. 2009), fused with the collision.
///
/// Two kinds of step alternate. Write f*_q(x) for the post-collision population q of cell x.
///  - From the post state (slot opp(q) of cell x holds f*_q(x)): every cell x reads its streamed
///    population q from slot opp(q) of x - c_q, collides, and writes f*'_q(x) into slot q of
///    x + c_q: exactly the locations it read. Afterwards the buffer is in the streamed state.
///  - From the streamed state (slot q of x holds what streams into x): every cell reads slot q of
///    x, collides and writes f*'_q(x) into slot opp(q) of x. Purely local.
/// Both do the arithmetic of `collide`, so they give the bits of a two-grid pull sweep
/// (`stream_collide`), which is kept as a benchmark variant. Solid cells keep what they hold
/// (a select, so the loop still vectorises); the boundary code gives their links meaning.
#include <algorithm>
#include <cstdint>

#include "grid/field.hpp"
#include "solvers/lbm/aa_simd.hpp"
#include "solvers/lbm/collision.hpp"
#include "solvers/lbm/stream_collide.hpp"

namespace biota::solvers::lbm {

/// \brief Arguments of one in-place sweep (`f` is read and written).
struct AaSweepArgs {
  grid::Field<double>* f;
  const grid::Field<double>* force;
  grid::Field<double>* rho;
  grid::Field<double>* u;
  const std::uint8_t* solid;
  double uniform_force[3];
  Relaxation relax;
  /// With a force field: row r = j + ny k carries a force only in cells [force_lo[r], force_hi[r])
  /// (all others hold +0 in every component); null: everywhere.
  const int* force_lo = nullptr;
  const int* force_hi = nullptr;
  /// Rows swept: y in [j_begin, j_end), z in [k_begin, k_end), all of x. Cells are independent
  /// (each writes exactly the locations it read), so any split of the rows gives the same bits.
  int j_begin = 0, j_end = 0, k_begin = 0, k_end = 0;
};

/// \brief One in-place step over the owned cells; `kFromPost` selects the neighbour step.
/// With a force field, the cells of a row outside its force span skip the three force loads:
/// their force is uniform + (+0), the same bits as the loads would give.
template <class L, bool kTrt, ForceMode kForce, bool kMacro, bool kSolids, bool kFromPost>
void aa_stream_collide(const AaSweepArgs& a) {
  constexpr int Q = L::Q;
  auto& fld = *a.f;
  const auto n = fld.cells();
  // The stream pointers and fields once, for the vector cells and the scalar loop alike.
  AaCellStreams<L> streams;
  auto& rp = streams.read;
  auto& wp = streams.write;
  for (int q = 0; q < Q; ++q) {
    const std::ptrdiff_t off =
        L::c[q][0] + L::c[q][1] * fld.stride_y() + L::c[q][2] * fld.stride_z();
    rp[q] = kFromPost ? fld.component(L::opp[q]) - off : fld.component(q);
    wp[q] = kFromPost ? fld.component(q) + off : fld.component(L::opp[q]);
  }
  for (int i = 0; i < 3; ++i)
    streams.force[i] = kForce == ForceMode::kField ? a.force->component(i) : nullptr;
  streams.solid = a.solid;
  streams.rho = kMacro ? a.rho->component(0) : nullptr;
  streams.ux = kMacro ? a.u->component(0) : nullptr;
  streams.uy = kMacro ? a.u->component(1) : nullptr;
  streams.uz = kMacro ? a.u->component(2) : nullptr;
  const double *fx = streams.force[0], *fy = streams.force[1], *fz = streams.force[2];
  double *rhop = streams.rho, *ux = streams.ux, *uy = streams.uy, *uz = streams.uz;
#if BIOTA_AA_SIMD_LANES > 0
  const AaVecConstants constants(a.relax, kTrt, kForce, a.uniform_force);
#endif
  // kLoad: read the force field (kField only); otherwise a kField sweep adds +0 to the uniform
  // part, as the loads of a zero force would.
  auto cells = [&]<bool kLoad>(std::ptrdiff_t begin, std::ptrdiff_t end)
      __attribute__((always_inline)) {
#if BIOTA_AA_SIMD_LANES > 0
    // Whole vectors on explicit registers (aa_simd.hpp, the same bits); the rest below.
    begin = aa_cells_simd<L, kTrt, kForce, kLoad, kMacro, kSolids>(streams, constants, begin, end);
#endif
    // Each cell writes exactly the locations it read and no other cell touches them.
#pragma GCC ivdep
    for (std::ptrdiff_t c = begin; c < end; ++c) {
      double f[Q], in[Q];
#pragma GCC unroll 32
      for (int q = 0; q < Q; ++q) in[q] = f[q] = rp[q][c];
      double gx = 0, gy = 0, gz = 0;
      if constexpr (kForce == ForceMode::kUniform) {
        gx = a.uniform_force[0];
        gy = a.uniform_force[1];
        gz = a.uniform_force[2];
      } else if constexpr (kForce == ForceMode::kField && kLoad) {
        gx = a.uniform_force[0] + fx[c];
        gy = a.uniform_force[1] + fy[c];
        gz = a.uniform_force[2] + fz[c];
      } else if constexpr (kForce == ForceMode::kField) {
        gx = a.uniform_force[0] + 0.0;
        gy = a.uniform_force[1] + 0.0;
        gz = a.uniform_force[2] + 0.0;
      }
      double rho, vx, vy, vz;
      collide<L, kTrt>(f, a.relax, gx, gy, gz, rho, vx, vy, vz);
      if constexpr (kSolids) {
        // Location of slot q written here held the streamed population opp(q) read above.
        const bool s = a.solid[c];
#pragma GCC unroll 32
        for (int q = 0; q < Q; ++q) wp[q][c] = s ? in[L::opp[q]] : f[q];
      } else {
#pragma GCC unroll 32
        for (int q = 0; q < Q; ++q) wp[q][c] = f[q];
      }
      if constexpr (kMacro) {
        if constexpr (kSolids) {  // solid cells keep their macroscopic values
          const bool s = a.solid[c];
          rho = s ? rhop[c] : rho;
          vx = s ? ux[c] : vx;
          vy = s ? uy[c] : vy;
          vz = s ? uz[c] : vz;
        }
        rhop[c] = rho;
        ux[c] = vx;
        uy[c] = vy;
        uz[c] = vz;
      }
    }
  };
  // The cells in chunks of two cache lines per stream; each chunk first prefetches every stream
  // it touches kPrefetchAhead cells further on: the Q populations for writing (each line read is
  // written back), the force field where it is loaded, the solid mask, the macroscopic outputs.
  // With the hardware prefetchers alone one core swept 100^3 at about 60% of its in-cache rate:
  // they do not run 19-26 streams far enough ahead (D3Q15 suffered less than D3Q19), and any
  // stream left to them stalls the others. docs/performance.md, session 23.
  constexpr std::ptrdiff_t kChunk = 16, kPrefetchAhead = 128;
  static_assert(kChunk * sizeof(double) == 2 * 64, "two cache lines per stream and chunk");
  // The address is formed as an integer: near the end of the field it points past the array,
  // which a prefetch may (it never faults). The prefetches are written in the loop itself: GCC
  // takes a function that only prefetches for a pure one and drops its calls.
  const auto ahead = [](const void* p, std::ptrdiff_t bytes) {
    return reinterpret_cast<const void*>(reinterpret_cast<std::uintptr_t>(p) +
                                         static_cast<std::uintptr_t>(bytes));
  };
  constexpr std::ptrdiff_t kLine0 = kPrefetchAhead * std::ptrdiff_t{sizeof(double)},
                           kLine1 = kLine0 + 64;
  auto chunks = [&]<bool kLoad>(std::ptrdiff_t begin, std::ptrdiff_t end)
      __attribute__((always_inline)) {
    for (std::ptrdiff_t c0 = begin; c0 < end; c0 += kChunk) {
#pragma GCC unroll 32
      for (int q = 0; q < Q; ++q) {
        __builtin_prefetch(ahead(rp[q] + c0, kLine0), 1);
        __builtin_prefetch(ahead(rp[q] + c0, kLine1), 1);
      }
      if constexpr (kForce == ForceMode::kField && kLoad)
        for (const double* g : {fx, fy, fz}) {
          __builtin_prefetch(ahead(g + c0, kLine0), 0);
          __builtin_prefetch(ahead(g + c0, kLine1), 0);
        }
      if constexpr (kSolids) __builtin_prefetch(ahead(a.solid + c0, kPrefetchAhead), 0);
      if constexpr (kMacro)
        for (double* m : {rhop, ux, uy, uz}) {
          __builtin_prefetch(ahead(m + c0, kLine0), 1);
          __builtin_prefetch(ahead(m + c0, kLine1), 1);
        }
      cells.template operator()<kLoad>(c0, std::min(c0 + kChunk, end));
    }
  };
  for (int k = a.k_begin; k < a.k_end; ++k)
    for (int j = a.j_begin; j < a.j_end; ++j) {
      const std::ptrdiff_t row = fld.index(0, j, k);
      if constexpr (kForce == ForceMode::kField) {
        const std::size_t r = j + static_cast<std::size_t>(n.y) * k;
        const int lo = a.force_lo ? a.force_lo[r] : 0, hi = a.force_lo ? a.force_hi[r] : n.x;
        chunks.template operator()<false>(row, row + lo);
        chunks.template operator()<true>(row + lo, row + hi);
        chunks.template operator()<false>(row + hi, row + n.x);
      } else {
        chunks.template operator()<true>(row, row + n.x);
      }
    }
}

}  // namespace biota::solvers::lbm
