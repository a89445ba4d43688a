/// \file flock_kernels_bench.cpp
/// \brief Throughput of the flock kernels: sandpile topplings per second in the critical state.
#include <benchmark/benchmark.h>

#include <thread>

#include "models/flock/sandpile.hpp"

namespace {

using biota::models::flock::Sandpile;
using biota::models::flock::ToppleOrder;

// Drives a critical L^3 sandpile; items processed = topplings, so the report is topplings/s.
// The burn-in (4 grains per site) brings the pile into the stationary critical state first; it is
// excluded from the timing.
void BM_SandpileTopplings(benchmark::State& state) {
  const int l = static_cast<int>(state.range(0));
  const auto order = state.range(1) == 0 ? ToppleOrder::kStack : ToppleOrder::kWaves;
  Sandpile s(l, l, l, 1);
  const std::uint64_t burn = 4 * static_cast<std::uint64_t>(s.num_sites());
  for (std::uint64_t k = 0; k < burn; ++k) s.add_grain(s.random_site(k), ToppleOrder::kStack);
  std::uint64_t drive = burn;
  const std::int64_t t0 = s.topplings();
  for (auto _ : state) {
    const auto a = s.add_grain(s.random_site(drive++), order);
    benchmark::DoNotOptimize(a);
  }
  const std::int64_t topplings = s.topplings() - t0;
  state.SetItemsProcessed(topplings);
  state.counters["topplings_per_drive"] =
      static_cast<double>(topplings) / static_cast<double>(state.iterations());
  state.counters["hw_threads"] = std::thread::hardware_concurrency();
  state.SetLabel(order == ToppleOrder::kStack ? "stack" : "waves");
}
BENCHMARK(BM_SandpileTopplings)
    ->ArgsProduct({{32, 64}, {0, 1}})
    ->ArgNames({"L", "waves"})
    ->Unit(benchmark::kMicrosecond)
    ->MinTime(2.0);

}  // namespace

BENCHMARK_MAIN();
