// Cycles per cell update of the production AA sweep (solvers/lbm/aa_sweep.hpp) on a block small
// enough for L1 or L2, or large enough for memory: is the sweep held up by the memory or by the
// core? A development probe, not part of the build (docs/performance.md, session 35).
//
//   g++ -std=c++20 -O3 -DNDEBUG -march=native -ffp-contract=off -Isrc
//       jobs/dev/lbm_in_core.cpp src/grid/huge_pages.cpp -o /tmp/lbm_in_core   (one line)
//   /tmp/lbm_in_core D3Q19 16 1 2      # 16 x 1 x 2 cells: L1;  32 8 8: L2;  100 100 40: memory
//
// Both kinds of step alternate (neighbour step, local step) with a force field in every cell
// (as `biota bench lbm`), or in none with FORCE=0 (every row outside its force span). Add
// -DMEMORY_ONLY for the same loads and stores with two operations per population instead of the
// collision. Prints the best of 9 trials; the clock comes from a chain of dependent adds.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "solvers/lbm/aa_sweep.hpp"
#include "solvers/lbm/lattice.hpp"

using namespace biota;
using namespace biota::solvers::lbm;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// Core clock in Hz: 4e8 dependent integer adds take one cycle each.
double clock_hz() {
  long x = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (long i = 0; i < 100000000; ++i)
    __asm__ volatile("add $1, %0\n\tadd $1, %0\n\tadd $1, %0\n\tadd $1, %0" : "+r"(x));
  return 4e8 / seconds_since(t0);
}

template <class L>
void run(int nx, int ny, int nz, bool force_everywhere) {
  grid::Field<double> f({nx, ny, nz}, L::Q, 1);
  for (int q = 0; q < L::Q; ++q)
    for (std::size_t i = 0; i < f.plane_size(); ++i)
      f.component(q)[i] = L::w[q] * (1 + 1e-3 * double((i * 7 + q) % 13));
  grid::Field<double> force({nx, ny, nz}, 3, 1, 1e-6);
  [[maybe_unused]] AaSweepArgs a{
      &f, &force, nullptr, nullptr, nullptr, {0, 0, 0}, Relaxation::bgk(0.8)};
  std::vector<int> span_lo(std::size_t(ny) * nz, nx), span_hi(span_lo);  // empty force spans
  if (!force_everywhere) a.force_lo = span_lo.data(), a.force_hi = span_hi.data();
  a.j_end = ny, a.k_end = nz;
  auto step_pair = [&] {
#ifdef MEMORY_ONLY
    // The sweep's accesses (every cell reads Q slots and writes them back, both kinds of step)
    // without its arithmetic: each population scaled.
    for (bool from_post : {true, false}) {
      double* rp[L::Q];
      double* wp[L::Q];
      for (int q = 0; q < L::Q; ++q) {
        const std::ptrdiff_t off =
            L::c[q][0] + L::c[q][1] * f.stride_y() + L::c[q][2] * f.stride_z();
        rp[q] = from_post ? f.component(L::opp[q]) - off : f.component(q);
        wp[q] = from_post ? f.component(q) + off : f.component(L::opp[q]);
      }
      for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j) {
          const std::ptrdiff_t row = f.index(0, j, k);
#pragma GCC ivdep
          for (std::ptrdiff_t c = row; c < row + nx; ++c) {
            double v[L::Q];
#pragma GCC unroll 32
            for (int q = 0; q < L::Q; ++q) v[q] = rp[q][c];
#pragma GCC unroll 32
            for (int q = 0; q < L::Q; ++q) wp[q][c] = v[q] * 0.999 + 1e-6;
          }
        }
    }
#else
    aa_stream_collide<L, false, ForceMode::kField, false, false, true>(a);
    aa_stream_collide<L, false, ForceMode::kField, false, false, false>(a);
#endif
  };
#ifdef MEMORY_ONLY
  const char* kWhat[2] = {"accesses only", "accesses only"};
#else
  const char* kWhat[2] = {"force nowhere", "force everywhere"};
#endif
  const double cells = 2.0 * nx * ny * nz;
  const long pairs = std::max(1L, long(2e8 / cells));
  for (long i = 0; i < pairs / 10 + 1; ++i) step_pair();
  double best = 1e30;
  for (int trial = 0; trial < 9; ++trial) {
    const auto t0 = std::chrono::steady_clock::now();
    for (long i = 0; i < pairs; ++i) step_pair();
    best = std::min(best, seconds_since(t0));
  }
  const double hz = clock_hz(), per_cell = best / (cells * pairs);
  std::printf("%s %dx%dx%d, %s: %.1f MLUPS, %.1f cycles per cell at %.2f GHz (check %.9g)\n",
              L::name, nx, ny, nz, kWhat[force_everywhere], 1e-6 / per_cell, per_cell * hz,
              hz * 1e-9, f.component(3)[f.index(1, 1, 1)]);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 5) {
    std::fprintf(stderr, "usage: %s D3Q15|D3Q19 nx ny nz\n", argv[0]);
    return 2;
  }
  const int nx = std::atoi(argv[2]), ny = std::atoi(argv[3]), nz = std::atoi(argv[4]);
  const bool force_everywhere =
      !(std::getenv("FORCE") && std::strcmp(std::getenv("FORCE"), "0") == 0);
  if (std::strcmp(argv[1], "D3Q15") == 0)
    run<D3Q15>(nx, ny, nz, force_everywhere);
  else
    run<D3Q19>(nx, ny, nz, force_everywhere);
}
