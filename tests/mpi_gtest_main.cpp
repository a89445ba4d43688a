// Shared main for MPI tests: every rank runs the tests, only rank 0 prints, and a failure on any
// rank fails the whole test (the exit code is the max over ranks).
#include <gtest/gtest.h>
#include <mpi.h>

#include "core/mpi_io_workaround.hpp"

int main(int argc, char** argv) {
  biota::core::select_reliable_mpi_io();
  MPI_Init(&argc, &argv);
  ::testing::InitGoogleTest(&argc, argv);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank != 0) {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  int local = RUN_ALL_TESTS();
  int global = 0;
  MPI_Allreduce(&local, &global, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  MPI_Finalize();
  return global;
}
