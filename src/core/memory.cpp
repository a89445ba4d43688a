#include "core/memory.hpp"

#include <fmt/format.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <sstream>

#include "core/error.hpp"

namespace biota::core {

double available_memory_bytes(std::string* source) {
  double avail = -1;
  std::string from;
  {
    std::ifstream in("/proc/meminfo");
    std::string key;
    double kb = 0;
    std::string unit;
    while (in >> key >> kb >> unit)
      if (key == "MemAvailable:") {
        avail = kb * 1024.0;
        from = "MemAvailable in /proc/meminfo";
        break;
      }
  }
  if (avail < 0) {
    avail = double(sysconf(_SC_AVPHYS_PAGES)) * double(sysconf(_SC_PAGESIZE));
    from = "sysconf(_SC_AVPHYS_PAGES)";
  }
  for (const int res : {RLIMIT_AS, RLIMIT_DATA}) {
    rlimit lim{};
    if (getrlimit(res, &lim) == 0 && lim.rlim_cur != RLIM_INFINITY &&
        double(lim.rlim_cur) < avail) {
      avail = double(lim.rlim_cur);
      from = res == RLIMIT_AS ? "ulimit -v (RLIMIT_AS)" : "ulimit -d (RLIMIT_DATA)";
    }
  }
  if (source) *source = from;
  return avail;
}

std::string format_bytes(double b) {
  if (b >= 1e12) return fmt::format("{:.3g} TB", b / 1e12);
  if (b >= 1e9) return fmt::format("{:.3g} GB", b / 1e9);
  if (b >= 1e6) return fmt::format("{:.3g} MB", b / 1e6);
  return fmt::format("{:.3g} kB", b / 1e3);
}

void check_memory(MPI_Comm comm, const Config& cfg, const std::vector<MemoryItem>& items,
                  const std::string& keys) {
  check_memory(comm, cfg.source(), items, keys);
}

void check_memory(MPI_Comm comm, const std::string& input, const std::vector<MemoryItem>& items,
                  const std::string& keys) {
  double mine = 0;
  for (const auto& it : items) mine += it.bytes;
  MPI_Comm node;
  MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
  int node_ranks = 1;
  MPI_Comm_size(node, &node_ranks);
  MPI_Comm_free(&node);
  std::string source;
  const double avail = available_memory_bytes(&source);
  // Largest rank estimate, and the worst node's need / availability (shortfall first).
  double worst_rank = 0;
  MPI_Allreduce(&mine, &worst_rank, 1, MPI_DOUBLE, MPI_MAX, comm);
  struct {
    double ratio;
    int rank;
  } local{worst_rank * node_ranks / std::max(avail, 1.0), 0}, worst{};
  MPI_Comm_rank(comm, &local.rank);
  MPI_Allreduce(&local, &worst, 1, MPI_DOUBLE_INT, MPI_MAXLOC, comm);
  double numbers[3] = {worst_rank * node_ranks, avail, double(node_ranks)};
  MPI_Bcast(numbers, 3, MPI_DOUBLE, worst.rank, comm);
  if (local.rank == 0) {
    std::string parts;
    for (const auto& it : items)
      parts += fmt::format("{}{} {}", parts.empty() ? "" : ", ", it.what, format_bytes(it.bytes));
    fmt::print("memory: about {} per rank ({}), {} for the {} ranks of a node; {} available ({})\n",
               format_bytes(worst_rank), parts, format_bytes(numbers[0]), int(numbers[2]),
               format_bytes(numbers[1]), source);
  }
  if (worst.ratio > 1.0)
    throw InputError(fmt::format(
        "{}: {} need about {} of memory per node ({} per rank x {} ranks) but {} are available "
        "({}); use a smaller grid or more nodes",
        input, keys, format_bytes(numbers[0]), format_bytes(worst_rank), int(numbers[2]),
        format_bytes(numbers[1]), source));
}

}  // namespace biota::core
