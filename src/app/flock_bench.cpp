#include "app/flock_bench.hpp"

#include <fmt/format.h>

#include <time.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "app/bench_stats.hpp"
#include "app/stream_probe.hpp"
#include "core/agreement.hpp"
#include "core/config.hpp"
#include "core/error.hpp"
#include "core/timers.hpp"
#include "models/flock/sandpile.hpp"
#include "scenarios/flock_scenario.hpp"

namespace biota::app {

int run_flock_bench(MPI_Comm comm, const FlockBenchOptions& opts) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  core::ConfigSchema schema;
  schema.add_string("scenario", std::nullopt, {}, "scenario");
  schema.add_int("seed", 12345, 0, 1'000'000'000'000'000'000, "seed");
  scenarios::FlockScenario::declare_config(schema);
  const double R = 3.0;
  constexpr int kWarmup = 3;
  // The host's limit beside the figures: the boid step waits on memory, so its rate moves with
  // the bandwidth each rank gets (measured alone, before the cases, on the same ranks).
  const double bw = stream_triad(comm);
  if (rank == 0)
    fmt::print("STREAM triad (all ranks at once): {:.2f} GB/s, {:.2f} GB/s per rank\n", bw,
               bw / size);
  if (rank == 0)
    fmt::print(
        "flock benchmark: {} rank(s), uniform random boids in a periodic box, perception radius "
        "{} m (bins of radius/{}), target {} boids within it, no predator, no noise, {} timed "
        "steps\n"
        "(updates/s/core: wall clock; per CPU-s: per second of CPU time the ranks received, which "
        "differs on a shared machine; on several ranks each case runs on rank 0 alone first)\n"
        "{:>9} {:>8} {:>10} {:>12} {:>14} {:>14} {:>8} {:>8} {:>8}\n",
        size, R, opts.reach, opts.neighbours, opts.steps, "boids", "box [m]", "perceived",
        "step [ms]", "updates/s/core", "per CPU-s", "rules %", "comm %", "other %");
  // One case on `c` (all ranks of c take part); the row is printed by rank 0 of `comm`.
  struct CaseResult {
    double side = 0, step_ms = 0, rate = 0, rate_cpu = 0, rules_pct = 0, comm_pct = 0,
           perceived = 0;
    long long moves = 0, owned_min = 0, owned_max = 0;
  };
  // Density for `neighbours` boids in the perception sphere; box a multiple of dx = R.
  const double density = opts.neighbours / (4.0 / 3 * std::numbers::pi * R * R * R);
  const auto box_side = [&](long long n) {
    return R * std::ceil(std::cbrt(double(n) / density) / R);
  };
  // A periodic box needs 3 perception radii (FlockScenario); at this density that is a least
  // count. Every rank checks it before any case runs.
  for (long long n : opts.boids)
    if (box_side(n) < 3 * R) {
      long long least = static_cast<long long>(density * 8 * R * R * R);
      while (box_side(least) < 3 * R) ++least;
      throw core::InputError(fmt::format(
          "bench flock: --boids {} gives a {:g} m periodic box at {:g} boids per perception "
          "sphere, under the 3 perception radii ({:g} m) a periodic box needs; allowed: at least "
          "{} boids",
          n, box_side(n), opts.neighbours, 3 * R, least));
    }
  const auto run_case = [&](MPI_Comm c, long long n) {
    int csize = 1;
    MPI_Comm_size(c, &csize);
    const double side = box_side(n);
    const std::string deck = fmt::format(
        "scenario = \"flock\"\nseed = 1\n[flock]\nstats_interval = 1000000\n"
        "[flock.domain]\nsize = [{0}, {0}, {0}]\ndx = {1}\nboundary = \"periodic\"\nbin_reach = "
        "{3}\n"
        "[flock.balance]\ninterval = {4}\n"
        "[flock.boids]\nperception_radius = {1}\n[flock.prey]\ncount = {2}\n"
        "[flock.predator]\ncount = 0\n[flock.sandpile]\nsize = 4\n"
        "[flock.noise]\nheading = 0.0\ncruising_distance = 0.0\nmax_speed = 0.0\n"
        "[flock.takeoff]\nifs = \"uniform\"\n",
        side, R, n, opts.reach, opts.balance_interval);
    // Errors of the generated deck name the option that set it (e.g. `bench flock --boids
    // 20000000 (rank 0 alone): flock.prey.count = 20000000 prey ... need about 6.24 GB ...`).
    const auto cfg = core::Config::from_string(
        schema, deck,
        csize < size ? fmt::format("bench flock --boids {} (rank 0 alone)", n)
                     : fmt::format("bench flock --boids {} on {} rank(s)", n, csize));
    core::Timers timers;
    scenarios::RunContext ctx{c, cfg, timers, "bench_flock_out"};
    scenarios::FlockScenario sc(ctx);
    for (int k = 0; k < kWarmup; ++k) sc.step();
    timers = core::Timers{};
    sc.reset_neighbour_count();
    auto cpu_now = [] {
      timespec ts{};
      clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
      return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
    };
    MPI_Barrier(c);
    const double t0 = MPI_Wtime(), c0 = cpu_now();
    for (int k = 0; k < opts.steps; ++k) sc.step();
    double cpu = cpu_now() - c0;
    MPI_Barrier(c);
    const double t = MPI_Wtime() - t0;
    MPI_Allreduce(MPI_IN_PLACE, &cpu, 1, MPI_DOUBLE, MPI_SUM, c);
    double sec[2] = {timers.total("rules"), timers.total("comm")};
    MPI_Allreduce(MPI_IN_PLACE, sec, 2, MPI_DOUBLE, MPI_MAX, c);
    long long owned[2] = {static_cast<long long>(sc.owned_boids()), 0};
    owned[1] = -owned[0];
    MPI_Allreduce(MPI_IN_PLACE, owned, 2, MPI_LONG_LONG, MPI_MAX, c);
    CaseResult r;
    r.side = side;
    r.step_ms = 1e3 * t / opts.steps;
    r.rate = double(n) * opts.steps / t / csize;
    r.rate_cpu = double(n) * opts.steps / cpu;  // per CPU-second actually received
    r.rules_pct = 100 * sec[0] / t;
    r.comm_pct = 100 * sec[1] / t;
    r.perceived = sc.mean_neighbours();
    r.moves = sc.balance_moves();
    r.owned_max = owned[0];
    r.owned_min = -owned[1];
    return r;
  };
  const auto print_row = [&](long long n, const CaseResult& r, const std::string& note) {
    fmt::print(
        "{:>9} {:>8.0f} {:>10.1f} {:>12.2f} {:>14.3e} {:>14.3e} {:>8.1f} {:>8.1f} {:>8.1f}{}\n", n,
        r.side, r.perceived, r.step_ms, r.rate, r.rate_cpu, r.rules_pct, r.comm_pct,
        100 - r.rules_pct - r.comm_pct, note);
  };
  // On several ranks, rank 0 also runs each case alone first (the others wait): the parallel
  // efficiency then compares two figures of the same minutes, not of two runs.
  MPI_Comm solo = MPI_COMM_NULL;
  if (size > 1) MPI_Comm_split(comm, rank == 0 ? 0 : MPI_UNDEFINED, 0, &solo);
  // A case that fails on rank 0 alone (its memory is checked there first) must not leave the
  // other ranks waiting for it: every case ends in an agreement.
  core::ErrorAgreement agreement(comm);
  for (long long n : opts.boids) {
    std::vector<double> efficiency;
    for (int round = 0; round < opts.rounds; ++round) {
      CaseResult alone;
      // The other ranks wait asleep, not in a busy-polling wait that would hold a core.
      agreement.run(
          [&] {
            if (solo == MPI_COMM_NULL) return;
            alone = run_case(solo, n);
            print_row(n, alone, "  (rank 0 alone)");
          },
          0, core::ErrorAgreement::Wait::kSleep);
      CaseResult all;
      agreement.run([&] { all = run_case(comm, n); });
      if (rank != 0) continue;
      print_row(n, all, size > 1 ? fmt::format("  ({} ranks)", size) : std::string());
      if (size == 1) continue;
      efficiency.push_back(100 * all.rate / alone.rate);
      fmt::print(
          "{:>9} parallel efficiency {:.0f}% (updates/s/core on {} ranks over rank 0 alone)\n", "",
          efficiency.back(), size);
      if (opts.balance_interval > 0 && opts.balance_interval <= kWarmup + opts.steps)
        fmt::print(
            "{:>9} load balance (flock.balance.interval = {}): the cut moved {} time(s) in "
            "{} warm-up and {} timed steps; boids per rank now {} to {}\n",
            "", opts.balance_interval, all.moves, kWarmup, opts.steps, all.owned_min,
            all.owned_max);
    }
    if (rank == 0 && efficiency.size() > 1) {
      std::string each;
      for (double e : efficiency) each += fmt::format(" {:.0f}", e);
      fmt::print("{:>9} parallel efficiency, median of {} rounds: {:.0f}% (rounds:{})\n", n,
                 efficiency.size(), median(efficiency), each);
    }
  }
  if (solo != MPI_COMM_NULL) MPI_Comm_free(&solo);
  // Sandpile: topplings/s in the critical state (replicated, so every rank does the same work).
  for (int L : {16, 32}) {
    models::flock::Sandpile s(L, L, L, 1);
    const std::uint64_t burn = 4 * static_cast<std::uint64_t>(s.num_sites());
    for (std::uint64_t k = 0; k < burn; ++k)
      s.add_grain(s.random_site(k), models::flock::ToppleOrder::kStack);
    for (auto order : {models::flock::ToppleOrder::kStack, models::flock::ToppleOrder::kWaves}) {
      const std::int64_t t0p = s.topplings();
      const double t0 = MPI_Wtime();
      std::uint64_t d = burn;
      while (MPI_Wtime() - t0 < 1.0)
        for (int k = 0; k < 1000; ++k) s.add_grain(s.random_site(d++), order);
      const double t = MPI_Wtime() - t0;
      if (rank == 0)
        fmt::print("sandpile L = {:>2} {:<5}: {:.3e} topplings/s ({:.1f} per drive)\n", L,
                   order == models::flock::ToppleOrder::kStack ? "stack" : "waves",
                   double(s.topplings() - t0p) / t, double(s.topplings() - t0p) / double(d - burn));
    }
  }
  return 0;
}

}  // namespace biota::app
