#pragma once
/// \file lbm_bench.hpp
/// \brief `biota bench lbm`: MLUPS of the production LBM sweep beside the memory bandwidth
/// measured in the same run (STREAM triad) and the roofline it implies.
#include <mpi.h>

#include <string>
#include <vector>

namespace biota::app {

/// \brief Options of the LBM benchmark.
struct LbmBenchOptions {
  int size = 100;                  ///< cells per axis
  int steps = 200;                 ///< timed steps per case and round
  int rounds = 3;                  ///< rounds of the peer and every case, one after the other
  std::vector<std::string> cases;  ///< "D3Q19/bgk" etc.; empty = all four
  bool peer = true;                ///< run the RRZE peer (run-lbm-peer.sh) when it is found
  bool two_grid = true;            ///< also time the former two-grid pull sweep (kernel only)
  bool overlap = true;             ///< overlap the halo exchange with the sweep (production)
  bool balance_speed = false;      ///< cut by the measured rank speeds instead of equal blocks
};

/// \brief Run the benchmark on `comm`; prints a table on rank 0. Returns 0.
int run_lbm_bench(MPI_Comm comm, const LbmBenchOptions& opts);

}  // namespace biota::app
