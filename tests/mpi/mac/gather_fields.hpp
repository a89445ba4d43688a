#pragma once
// Shared by the MAC tests: the solver's cell-centred fields gathered to one rank for comparisons
// between rank counts.
#include <mpi.h>

#include <vector>

#include "solvers/mac/mac_solver.hpp"

/// Global cell arrays (velocity xyz, pressure) gathered to rank 0 of `comm`, x fastest.
inline std::vector<double> gather_global_fields(const biota::solvers::mac::MacSolver& s,
                                                MPI_Comm comm) {
  const auto& d = s.decomposition();
  const auto N = d.global_cells();
  auto v = s.cell_velocity();
  auto pr = s.cell_pressure();
  std::vector<double> local;
  const auto b = d.local_box();
  local.insert(local.end(), {double(b.lo.x), double(b.lo.y), double(b.lo.z), double(b.hi.x),
                             double(b.hi.y), double(b.hi.z)});
  local.insert(local.end(), v.begin(), v.end());
  local.insert(local.end(), pr.begin(), pr.end());
  int size, rank, n = static_cast<int>(local.size());
  MPI_Comm_size(comm, &size);
  MPI_Comm_rank(comm, &rank);
  std::vector<int> counts(size), displs(size);
  MPI_Gather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm);
  int tot = 0;
  for (int r = 0; r < size; ++r) displs[r] = tot, tot += counts[r];
  std::vector<double> all(rank == 0 ? tot : 0);
  MPI_Gatherv(local.data(), n, MPI_DOUBLE, all.data(), counts.data(), displs.data(), MPI_DOUBLE, 0,
              comm);
  std::vector<double> out;
  if (rank != 0) return out;
  const long long cells = N.product();
  out.assign(4 * cells, 0);
  for (int r = 0; r < size; ++r) {
    const double* q = all.data() + displs[r];
    const int lo[3] = {int(q[0]), int(q[1]), int(q[2])}, hi[3] = {int(q[3]), int(q[4]), int(q[5])};
    const long long m = 1LL * (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
    const double* vel = q + 6;
    const double* pp = vel + 3 * m;
    long long t = 0;
    for (int k = lo[2]; k < hi[2]; ++k)
      for (int j = lo[1]; j < hi[1]; ++j)
        for (int i = lo[0]; i < hi[0]; ++i, ++t) {
          const long long g = (1LL * k * N.y + j) * N.x + i;
          for (int c = 0; c < 3; ++c) out[3 * g + c] = vel[3 * t + c];
          out[3 * cells + g] = pp[t];
        }
  }
  return out;
}
