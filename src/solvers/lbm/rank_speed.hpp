#pragma once
/// \file rank_speed.hpp
/// \brief How fast each rank runs the LBM sweep, measured with every rank sweeping at once, for a
/// rank cut that gives a slower core fewer cells. Shared cloud hosts give unequal cores: on the
/// 2-core development VM one vCPU ran the sweep at 0.4-0.5x the other for minutes at a time (no
/// steal time reported), and an equal cut runs at the pace of the slow one (docs/decisions.md).
#include <mpi.h>

#include <vector>

#include "solvers/lbm/lbm_solver.hpp"

namespace biota::solvers::lbm {

/// \brief Relative speed of every rank of `comm` (the fastest is 1; within 10% of it counts as
/// 1), from the median of five timed runs of 8 in-place steps on a private walled box of the deck's
/// lattice (96 x 96 x 40 cells, beyond the last-level cache like a production block, or the deck's
/// grid where smaller), all ranks at once so that they share the memory bandwidth as in the run.
/// Collective; every rank gets the same vector. Takes ~0.3-0.6 s at full size.
std::vector<double> measure_rank_speeds(MPI_Comm comm, const LbmParams& params);

}  // namespace biota::solvers::lbm
