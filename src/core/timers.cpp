#include "core/timers.hpp"

#include <fmt/format.h>

#include <set>
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
  // Agree on the union of section names first: a section known to some ranks only (a code path
  // taken on one rank) must not pair one rank's reduction with another's.
  std::string mine;
  for (const auto& [name, t] : sections_) mine += name + '\n';
  int len = static_cast<int>(mine.size());
  std::vector<int> lens(size), offs(size, 0);
  MPI_Allgather(&len, 1, MPI_INT, lens.data(), 1, MPI_INT, comm);
  for (int r = 1; r < size; ++r) offs[r] = offs[r - 1] + lens[r - 1];
  std::string all(offs[size - 1] + lens[size - 1], '\0');
  MPI_Allgatherv(mine.data(), len, MPI_CHAR, all.data(), lens.data(), offs.data(), MPI_CHAR, comm);
  std::set<std::string> names;
  for (std::size_t a = 0, b; a < all.size(); a = b + 1) {
    b = all.find('\n', a);
    names.insert(all.substr(a, b - a));
  }
  std::vector<double> t, mn(names.size()), mx(names.size()), sum(names.size());
  for (const auto& n : names) t.push_back(total(n));
  const int n = static_cast<int>(t.size());
  MPI_Allreduce(t.data(), mn.data(), n, MPI_DOUBLE, MPI_MIN, comm);
  MPI_Allreduce(t.data(), mx.data(), n, MPI_DOUBLE, MPI_MAX, comm);
  MPI_Allreduce(t.data(), sum.data(), n, MPI_DOUBLE, MPI_SUM, comm);
  double accounted = 0;
  int i = 0;
  for (const auto& name : names) {
    const double avg = sum[i] / size;
    accounted += avg;
    if (rank == 0)
      out += fmt::format("{:<22} {:>10.3f} {:>10.3f} {:>10.3f} {:>6.1f}%\n", name, mn[i], avg,
                         mx[i], wall_total > 0 ? 100.0 * avg / wall_total : 0.0);
    ++i;
  }
  if (rank == 0)
    out += fmt::format("{:<22} {:>10} {:>10.3f} {:>10} {:>6.1f}%\n{:<22} {:>10} {:>10.3f}\n",
                       "other", "", wall_total - accounted, "",
                       wall_total > 0 ? 100.0 * (wall_total - accounted) / wall_total : 0.0,
                       "total wall", "", wall_total);
  return out;
}

}  // namespace biota::core
