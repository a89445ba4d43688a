/// \file lbm_layout_bench.cpp
/// \brief Storage-layout / streaming-scheme experiment: single-threaded BGK on a periodic 100^3
/// box for each variant of lbm_layout_variants.hpp, beside a STREAM triad measured in the same
/// binary. See docs/performance-lbm-layout.md.
///
/// One benchmark iteration = one time step of the whole box, ghost refresh / fold-back included
/// (it stands in for the halo exchange). Counters:
///   MLUPS        million lattice-site updates per second (time measured around the loop)
///   B_per_update bytes moved per update the scheme is assumed to need: 24Q two-grid with
///                write-allocate, 16Q in place (AA) or with non-temporal stores
///   GBps_eff     MLUPS * B_per_update, the memory bandwidth the variant implies
/// The roofline percentages are computed in the doc from the best triad of the same run.
#include <benchmark/benchmark.h>

#include <chrono>
#include <vector>

#include "lbm_layout_variants.hpp"
#include "solvers/lbm/lattice.hpp"

namespace {

using namespace biota::bench::lbm_layout;
using biota::solvers::lbm::D3Q15;
using biota::solvers::lbm::D3Q19;

constexpr double kTau = 0.6;

// STREAM triad a = b + s c, 24 bytes per element counted (STREAM convention, as in
// `biota bench lbm`); 20M doubles per array (480 MB per pass), far beyond the caches.
void BM_StreamTriad(benchmark::State& state) {
  const std::size_t n = 20'000'000;
  std::vector<double, biota::grid::AlignedAllocator<double>> a(n, 0.0), b(n, 1.0), c(n, 2.0);
  double s = 3.0, secs = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    double* __restrict pa = a.data();
    const double* __restrict pb = b.data();
    const double* __restrict pc = c.data();
    for (std::size_t i = 0; i < n; ++i) pa[i] = pb[i] + s * pc[i];
    benchmark::ClobberMemory();
    secs += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    s += 1.0;
  }
  state.counters["GBps"] = 24.0 * n * state.iterations() / secs / 1e9;
}
BENCHMARK(BM_StreamTriad)->Unit(benchmark::kMillisecond)->MinTime(1.0)->UseRealTime();

// The periodic ghost refresh alone (all Q planes), to show its share of a pull step.
template <class L>
void BM_GhostFill(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  biota::grid::Field<double> f({n, n, n}, L::Q, 1, 1.0);
  for (auto _ : state) {
    fill_ghosts(f);
    benchmark::ClobberMemory();
  }
  state.SetLabel(L::name);
}
BENCHMARK(BM_GhostFill<D3Q19>)->Arg(100)->Unit(benchmark::kMillisecond);

template <class V, class L>
void run(benchmark::State& state, double bytes_per_q, const char* label) {
  const int n = static_cast<int>(state.range(0));
  V v(n, kTau);
  init_state<L>(n, [&](int q, int i, int j, int k, double x) { v.set(q, i, j, k, x); });
  for (int s = 0; s < 4; ++s) v.step();  // warm-up: page faults, second buffer touched
  double secs = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    v.step();
    benchmark::ClobberMemory();
    secs += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  benchmark::DoNotOptimize(v.get(1, 0, 0, 0));
  const double cells = double(n) * n * n;
  const double mlups = cells * state.iterations() / secs / 1e6;
  state.counters["MLUPS"] = mlups;
  state.counters["B_per_update"] = bytes_per_q * L::Q;
  state.counters["GBps_eff"] = mlups * bytes_per_q * L::Q / 1e3;
  state.SetLabel(std::string(L::name) + " " + label);
}

#define LAYOUT_BENCH(name, V, bytes, label)                                                   \
  void name##_19(benchmark::State& s) {                                                       \
    run<V<D3Q19>, D3Q19>(s, bytes, label);                                                    \
  }                                                                                           \
  void name##_15(benchmark::State& s) {                                                       \
    run<V<D3Q15>, D3Q15>(s, bytes, label);                                                    \
  }                                                                                           \
  BENCHMARK(name##_19)->Arg(100)->Unit(benchmark::kMillisecond)->MinTime(1.0)->UseRealTime(); \
  BENCHMARK(name##_15)->Arg(100)->Unit(benchmark::kMillisecond)->MinTime(1.0)->UseRealTime()

LAYOUT_BENCH(BM_a_SoaPull, SoaPull, 24, "(a) SoA two-grid pull [production]");
LAYOUT_BENCH(BM_b_AosPull, AosPull, 24, "(b) AoS two-grid pull");
LAYOUT_BENCH(BM_c_SoaPush, SoaPush, 24, "(c) SoA two-grid push");
LAYOUT_BENCH(BM_d_SoaAA, SoaAA, 16, "(d) SoA AA in-place");
LAYOUT_BENCH(BM_e_SoaPullNt, SoaPullNt, 16, "(e) SoA two-grid pull, NT stores");

}  // namespace

BENCHMARK_MAIN();
