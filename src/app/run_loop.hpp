#pragma once
/// \file run_loop.hpp
/// \brief The time loop: run length, progress line, output and checkpoint cadence, signals,
/// health checks and the timing table.
#include <mpi.h>

#include <string>
#include <vector>

#include "core/config.hpp"
#include "scenarios/scenario.hpp"

namespace biota::app {

/// \brief Declare the keys every deck understands (run.*, seed, output.*, checkpoint.*).
void declare_common_config(core::ConfigSchema& schema);

/// \brief What the time loop reads from the deck: the last step (run.steps and run.end_time over
/// the scenario's `dt`), the cadences and the checkpoint directory. \throws InputError for a run of
/// no step or no length. `biota check` calls it too, so it checks the run's length as a run does.
struct LoopSettings {
  long long last_step = 0, out_every = 0, ckpt_every = 0, progress_every = 1, health_every = 1;
  std::string checkpoint_dir;  ///< checkpoint.dir, or <output.dir>/checkpoints
};
LoopSettings loop_settings(const core::Config& cfg, double dt);

/// \brief Run `scenario_name` with `cfg`, optionally restarting from `restart_path`.
/// Returns the process exit code.
int run_scenario(MPI_Comm comm, const core::Config& cfg, const std::string& restart_path,
                 const std::vector<std::string>& solver_options);

/// \brief On `root`, one warning line naming the keys the deck or `--set` gave that the run has
/// not read (Config::unused_given_keys): a key of another mode of the scenario does nothing, and
/// a user who set it expects it to. Not an error: a deck may keep them for switching modes.
void warn_unused_keys(const core::Config& cfg, bool root);

/// \brief Install SIGTERM/SIGINT/SIGUSR1 handlers that request a checkpoint and a clean exit.
void install_signal_handlers();

}  // namespace biota::app
