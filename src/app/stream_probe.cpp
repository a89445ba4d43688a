#include "app/stream_probe.hpp"

#include <algorithm>
#include <cstddef>
#include <vector>

#include "grid/field.hpp"

namespace biota::app {

double stream_triad(MPI_Comm comm) {
  const std::size_t n = 20'000'000;
  std::vector<double, grid::AlignedAllocator<double>> a(n, 0.0), b(n, 1.0), c(n, 2.0);
  double best = 1e30;
  for (int rep = 0; rep < 5; ++rep) {
    MPI_Barrier(comm);
    const double t0 = MPI_Wtime();
    const double s = 3.0 + rep;
    double* __restrict pa = a.data();
    const double* __restrict pb = b.data();
    const double* __restrict pc = c.data();
    for (std::size_t i = 0; i < n; ++i) pa[i] = pb[i] + s * pc[i];
    MPI_Barrier(comm);
    best = std::min(best, MPI_Wtime() - t0);
  }
  volatile double sink = a[n / 2];
  (void)sink;
  int size = 1;
  MPI_Comm_size(comm, &size);
  return 24.0 * n * size / best / 1e9;
}

}  // namespace biota::app
