#pragma once
/// \file memory.hpp
/// \brief Memory check before the big allocations: a grid too large for the machine ended in
/// std::bad_alloc printed by every rank; now it is one input error naming the keys.
#include <mpi.h>

#include <string>
#include <vector>

#include "core/config.hpp"

namespace biota::core {

/// \brief One part of a scenario's memory estimate on one rank.
struct MemoryItem {
  std::string what;  ///< e.g. "populations"
  double bytes = 0;
};

/// \brief Bytes this process may still allocate: MemAvailable of /proc/meminfo (else
/// sysconf(_SC_AVPHYS_PAGES) pages), capped by RLIMIT_AS and RLIMIT_DATA; `source` says which.
double available_memory_bytes(std::string* source = nullptr);

/// \brief Human-readable size, e.g. "1.23 GB".
std::string format_bytes(double bytes);

/// \brief Compare the estimate of this rank (`items`) with the memory of its node. Collective.
///
/// The need of a node is the largest per-rank estimate times the ranks on the node
/// (MPI_COMM_TYPE_SHARED); every rank learns the worst node, rank 0 prints the estimate, and if a
/// node lacks memory every rank throws the same InputError naming `keys` (the deck keys that set
/// the size), needed and available.
void check_memory(MPI_Comm comm, const Config& cfg, const std::vector<MemoryItem>& items,
                  const std::string& keys);
/// \brief The same for input that is not a deck (a benchmark's command line): `input` leads the
/// message where the deck's name would, and `keys` names the options.
void check_memory(MPI_Comm comm, const std::string& input, const std::vector<MemoryItem>& items,
                  const std::string& keys);

}  // namespace biota::core
