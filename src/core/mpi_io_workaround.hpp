#pragma once
/// \file mpi_io_workaround.hpp
/// \brief Select OpenMPI's ROMIO MPI-IO component before MPI_Init.
///
/// OpenMPI 4.1.4's default OMPIO component corrupts collective HDF5 hyperslab I/O on uneven
/// decompositions (tests/mpi/io: 7 failures in 12 runs at 3 ranks, 0 in 12 with ROMIO). A user's
/// own OMPI_MCA_io setting wins. Call first thing in main(), before MPI_Init.
#include <cstdlib>

namespace biota::core {

inline void select_reliable_mpi_io() {
  setenv("OMPI_MCA_io", "romio321", /*overwrite=*/0);
}

}  // namespace biota::core
