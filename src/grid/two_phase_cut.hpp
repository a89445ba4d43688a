#pragma once
/// \file two_phase_cut.hpp
/// \brief Rank cuts for a step made of two phases that each wait for the slowest rank: a grid
/// phase (one unit of work per cell) and an item phase (particles, `item_cost` units each).
#include <array>
#include <vector>

#include "core/types.hpp"

namespace biota::grid {

using core::Index3;

/// \brief Estimated cost of one step under the cut `starts` (Decomposition's block starts; axes
/// the rank grid does not split: empty): the slowest rank's cells plus item_cost times the
/// slowest rank's items, each divided by the rank's speed (`rank_speed` in row-major rank order;
/// empty: all 1). A rank's items are the total times the product of its blocks' shares of
/// `items[a]` (per plane counts), exact when one axis is split.
double two_phase_cost(const Index3& dims, const Index3& cells,
                      const std::array<std::vector<int>, 3>& starts,
                      const std::array<std::vector<double>, 3>& items, double item_cost,
                      const std::vector<double>& rank_speed);

/// \brief The cut of least two_phase_cost among those that balance cells + w items for w = 0
/// (equal cells) and w = item_cost times 2^k, k = -4 ... 10 (towards equal items): a cut that
/// balances the sum of the two works can leave each phase waiting on another rank, since the
/// phases synchronise separately. Ties go to the smaller w. The best of them is then refined one
/// plane at a time while the cost falls. Deterministic: every rank gets the
/// same cut from the same counts. Blocks at least max(min_cells, half an even block) thick.
std::array<std::vector<int>, 3> two_phase_block_starts(
    const Index3& dims, const Index3& cells, const std::array<std::vector<double>, 3>& items,
    double item_cost, const std::vector<double>& rank_speed, int min_cells);

}  // namespace biota::grid
