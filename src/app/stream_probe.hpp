#pragma once
/// \file stream_probe.hpp
/// \brief The machine's memory bandwidth measured in the same run as a benchmark figure, so the
/// figure can be read beside the limit of the host it ran on (the benchmarks' shared probe).
#include <mpi.h>

namespace biota::app {

/// \brief STREAM triad a = b + s c on every rank at once (ranks share the memory bus), 20e6
/// elements per rank, best of 5. Returns the aggregate bandwidth in GB/s counting 24 bytes per
/// element (STREAM convention). Collective.
double stream_triad(MPI_Comm comm);

}  // namespace biota::app
