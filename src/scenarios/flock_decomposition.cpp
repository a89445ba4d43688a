// FlockScenario's decomposition: the start of a step (migration, ghosts, cell lists) and the
// dynamic load balance that moves the cut between ranks (deck keys flock.balance.*, docs/flock.md).
#include <algorithm>
#include <cmath>

#include "particles/load_balance.hpp"
#include "scenarios/flock_scenario.hpp"

namespace biota::scenarios {

void FlockScenario::begin_step() {
  if (balancing() && step_ % balance_interval_ == 0) rebalance();
  if (step_ % kReorderInterval == 0 || cells_.size() == 0) reorder_by_cell();
  pcomm_->migrate(*set_, /*keep_order=*/false);  // the reorder above restores the order
  pcomm_->build_ghosts(*set_, radius_);
  const std::size_t n = set_->n_total();
  // The velocities ride along into slot order (the rules read them there).
  const double* const velocity[3] = {set_->real(a_vel_, 0), set_->real(a_vel_, 1),
                                     set_->real(a_vel_, 2)};
  cells_.build(set_->real(particles::ParticleSet::kPos, 0),
               set_->real(particles::ParticleSet::kPos, 1),
               set_->real(particles::ParticleSet::kPos, 2), set_->u64(particles::ParticleSet::kId),
               n, lo_, radius_, bin_reach_, velocity);
  eligible_.resize(n + 8);  // the gather reads 8 flags at a time, past the slots at the end
  const core::GlobalId* ids = cells_.ids();
  for (std::size_t k = 0; k < n; ++k) eligible_[k] = is_prey(ids[k]) && flying(ids[k]);
  std::fill(eligible_.begin() + n, eligible_.end(), 0);
}

void FlockScenario::reorder_by_cell() {
  // The last step's cell list (owned and ghosts): its slots in order, ghosts left out. Positions
  // have moved by one step since, which is close enough for a storage order, and no migration has
  // changed the set since. Its owned slots are then exactly [0, n_owned), a permutation; a list
  // from before a restart may give a worse order, never a wrong one (no result depends on it).
  const std::size_t no = set_->n_owned();
  std::vector<std::size_t> order;
  order.reserve(no);
  for (std::size_t k = 0; k < cells_.size(); ++k)
    if (const std::size_t i = cells_.index(k); i < no) order.push_back(i);
  if (order.size() != no) {  // no list for this set (the first step): bin the owned boids now
    cells_.build(set_->real(particles::ParticleSet::kPos, 0),
                 set_->real(particles::ParticleSet::kPos, 1),
                 set_->real(particles::ParticleSet::kPos, 2),
                 set_->u64(particles::ParticleSet::kId), no, lo_, radius_, bin_reach_);
    order.resize(no);
    for (std::size_t k = 0; k < no; ++k) order[k] = cells_.index(k);
  }
  bool moved = false;
  for (std::size_t k = 0; k < no; ++k) moved |= order[k] != k;
  if (moved) set_->reorder_owned(order);  // boids at rest (before take-off) keep their order
}

void FlockScenario::rebalance() {
  // The rules phase is the per-boid work; its wall time on a rank includes whatever slows that
  // rank's core, which is what the cut has to follow.
  const double rules = ctx_.timers.total("rules");
  double seconds = rules - rules_seconds_at_balance_;
  const double work = work_since_balance_;
  rules_seconds_at_balance_ = rules;
  work_since_balance_ = 0;
  if (!(seconds > 0)) seconds = 0;  // the timers were reset (benchmarks): measure afresh
  const double* x[3] = {set_->real(particles::ParticleSet::kPos, 0),
                        set_->real(particles::ParticleSet::kPos, 1),
                        set_->real(particles::ParticleSet::kPos, 2)};
  // Blocks at least the ghost cutoff (the perception radius) thick.
  const double dx = pcomm_->cell_size();
  const int min_cells = std::max(1, static_cast<int>(std::ceil(radius_ / dx - 1e-12)));
  // boid_cost_: the last rules phase's work per owned slot (no migration since).
  const auto decision = particles::rebalance_starts(
      *decomp_, x, boid_cost_.size() == set_->n_owned() ? boid_cost_.data() : nullptr,
      set_->n_owned(), dx, lo_, seconds, work, balance_tolerance_, min_cells);
  if (!decision.moves()) return;
  sent_before_balance_ += pcomm_->sent();
  // The old ParticleComm refers to the old decomposition: replace both, then migrate.
  pcomm_.reset();
  decomp_ =
      std::make_unique<grid::Decomposition>(ctx_.comm, decomp_->global_cells(), decomp_->periodic(),
                                            decomp_->dims(), grid_keys_, decision.starts);
  pcomm_ = std::make_unique<particles::ParticleComm>(*decomp_, dx);
  ++balance_moves_;
}

}  // namespace biota::scenarios
