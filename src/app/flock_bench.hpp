#pragma once
/// \file flock_bench.hpp
/// \brief `biota bench flock`: boid updates per second per core of the flock scenario's full step
/// (rules + migration + ghosts + cell list) at ~20 neighbours, and sandpile topplings per second.
#include <mpi.h>

#include <vector>

namespace biota::app {

/// \brief Options of the flock benchmark.
struct FlockBenchOptions {
  std::vector<long long> boids = {10000, 100000, 1000000};  ///< prey counts
  int steps = 20;                                           ///< timed steps per case
  int reach = 1;                                            ///< flock.domain.bin_reach
  /// flock.balance.interval (0: the even cut throughout). The deck default: with 3 warm-up and
  /// up to 13 timed steps the benchmark then keeps the even cut (uniform boids, equal work).
  int balance_interval = 16;
  double neighbours = 20;  ///< target mean number of boids within the perception radius
  /// Rounds per case; on several ranks each round times rank 0 alone, then all ranks, and the
  /// efficiency printed is the median of the rounds' (the host drifts between rounds).
  int rounds = 1;
};

/// \brief Run the benchmark on `comm`; prints a table on rank 0. Returns 0.
int run_flock_bench(MPI_Comm comm, const FlockBenchOptions& opts);

}  // namespace biota::app
