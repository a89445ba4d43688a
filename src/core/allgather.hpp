#pragma once
// Concatenation of every rank's vector, in rank order, on every rank (MPI_Allgatherv with the
// counts agreed first). For records the ranks hold in different numbers; callers that need a
// rank-independent order sort the result by a global id.
#include <mpi.h>

#include <vector>

namespace biota::core {

inline std::vector<double> allgather_concat(MPI_Comm comm, const std::vector<double>& mine) {
  int ranks = 0;
  MPI_Comm_size(comm, &ranks);
  const int count = static_cast<int>(mine.size());
  std::vector<int> counts(ranks), displs(ranks);
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
  int total = 0;
  for (int r = 0; r < ranks; ++r) displs[r] = total, total += counts[r];
  std::vector<double> all(total);
  MPI_Allgatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), displs.data(),
                 MPI_DOUBLE, comm);
  return all;
}

}  // namespace biota::core
