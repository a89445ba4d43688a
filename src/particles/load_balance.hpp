#pragma once
/// \file load_balance.hpp
/// \brief Dynamic load balance of a particle decomposition by measured speed (the idea of LAMMPS
/// `fix balance` shift): every rank reports the seconds its particle work took since the last
/// balance and how much estimated work (e.g. neighbours visited) that was; the cut planes along
/// each split axis move so that every rank gets estimated work in proportion to its measured
/// speed. A rank on a slower core gets less; a dense cluster counts for its neighbours.
///
/// The cut only decides where particles are computed; a model whose results do not depend on
/// the decomposition (the flock's, docs/flock.md) gives the same bits before and after a move.
#include <mpi.h>

#include <array>
#include <vector>

#include "grid/decomposition.hpp"

namespace biota::particles {

/// \brief What rebalance_starts decided.
struct BalanceDecision {
  /// Slowest rank's work seconds over the mean (1 = balanced); 0 when a rank reported no work.
  double imbalance = 0;
  /// The new cut (Decomposition's `starts`) when it moves, else empty on every axis.
  std::array<std::vector<int>, 3> starts;
  bool moves() const { return !starts[0].empty() || !starts[1].empty() || !starts[2].empty(); }
};

/// \brief Collective over `d`'s communicator; every rank gets the same decision. `x`: positions
/// (m) of the rank's `n` owned particles (x[0..2] columns), in cells of `dx` from `origin`;
/// `cost`: each particle's estimated work (e.g. the neighbours it visited; null: 1 each), the
/// weight of its plane. `work_seconds` and `work_units`: this rank's particle work since the
/// last balance, in seconds and in the units of `cost`; their ratio is the rank's speed. No move
/// when the imbalance is at most 1 + tolerance or a rank reports no work. Blocks stay at least
/// `min_cells` thick (the particle ghost cutoff).
BalanceDecision rebalance_starts(const grid::Decomposition& d, const double* const x[3],
                                 const float* cost, std::size_t n, double dx,
                                 const core::Vec3& origin, double work_seconds, double work_units,
                                 double tolerance, int min_cells);

}  // namespace biota::particles
