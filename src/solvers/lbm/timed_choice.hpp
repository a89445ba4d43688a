#pragma once
/// \file timed_choice.hpp
/// \brief A choice between two ways of doing the same work (the same bits either way) made by
/// timing them: after `warmup` uses, `trials` uses of each way alternate and the faster way, by
/// its fastest use (noise on a shared host only adds time), is kept. The trial repeats every
/// `period` uses, so a choice made under a transient (start-up page faults, a busy host) does
/// not stay for the whole run. The slowest rank's times decide, so every rank chooses the same.
#include <mpi.h>

#include <algorithm>

namespace biota::solvers::lbm {

class TimedChoice {
 public:
  TimedChoice(int warmup, int trials, int period, bool initial)
      : warmup_(warmup), trials_(trials), period_(period), chosen_(initial) {}

  /// \brief Whether the next use is part of a trial (its way then alternates).
  bool deciding() const {
    const long long phase = uses_ % period_;
    return phase >= warmup_ && phase < warmup_ + 2 * trials_;
  }
  /// \brief The way for the next use: alternating inside a trial, else the current choice.
  bool pick() const { return deciding() ? (uses_ % period_ - warmup_) % 2 == 0 : chosen_; }
  bool chosen() const { return chosen_; }
  /// \brief The fastest trial use of each way [s], as of the last decision.
  double best(bool way) const { return decided_[way ? 1 : 0]; }

  /// \brief Record a use of `way` that took `seconds`. Collective (on `comm`) at the last use of
  /// a trial; returns true when that decision changed the choice or was the first.
  bool record(bool way, double seconds, MPI_Comm comm) {
    const bool in_trial = deciding();
    const long long phase = uses_++ % period_;
    if (!in_trial) return false;
    seconds_[way ? 1 : 0] = std::min(seconds_[way ? 1 : 0], seconds);
    if (phase != warmup_ + 2 * trials_ - 1) return false;
    MPI_Allreduce(MPI_IN_PLACE, seconds_, 2, MPI_DOUBLE, MPI_MAX, comm);
    const bool changed = !decided_once_ || chosen_ != (seconds_[1] < seconds_[0]);
    chosen_ = seconds_[1] < seconds_[0];
    decided_once_ = true;
    decided_[0] = seconds_[0], decided_[1] = seconds_[1];
    seconds_[0] = seconds_[1] = 1e300;
    return changed;
  }
  int trials() const { return trials_; }

 private:
  int warmup_, trials_, period_;
  bool chosen_, decided_once_ = false;
  long long uses_ = 0;
  double seconds_[2] = {1e300, 1e300};  ///< fastest use of [way false, way true] in this trial
  double decided_[2] = {0, 0};
};

}  // namespace biota::solvers::lbm
