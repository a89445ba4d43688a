#include "core/timers.hpp"

#include <fmt/format.h>

#include <vector>

namespace biota::core {

std::string Timers::report(MPI_Comm comm, double wall_total) const {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  std::string out;
  if (rank == 0)
    out = fmt::format("{:<22} {:>10} {:>10} {:>10} {:>7}\n", "section", "min [s]", "avg [s]",
                      "max [s]", "%total");
  double accounted = 0;
  for (const auto& [name, t] : sections_) {
    double mn = 0, mx = 0, sum = 0;
    MPI_Allreduce(&t, &mn, 1, MPI_DOUBLE, MPI_MIN, comm);
    MPI_Allreduce(&t, &mx, 1, MPI_DOUBLE, MPI_MAX, comm);
    MPI_Allreduce(&t, &sum, 1, MPI_DOUBLE, MPI_SUM, comm);
    accounted += sum / size;
    if (rank == 0)
      out += fmt::format("{:<22} {:>10.3f} {:>10.3f} {:>10.3f} {:>6.1f}%\n", name, mn, sum / size,
                         mx, wall_total > 0 ? 100.0 * (sum / size) / wall_total : 0.0);
  }
  if (rank == 0)
    out += fmt::format("{:<22} {:>10} {:>10.3f} {:>10} {:>6.1f}%\n{:<22} {:>10} {:>10.3f}\n",
                       "other", "", wall_total - accounted, "",
                       wall_total > 0 ? 100.0 * (wall_total - accounted) / wall_total : 0.0,
                       "total wall", "", wall_total);
  return out;
}

}  // namespace biota::core
