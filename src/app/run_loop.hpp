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

/// \brief Run `scenario_name` with `cfg`, optionally restarting from `restart_path`.
/// Returns the process exit code.
int run_scenario(MPI_Comm comm, const core::Config& cfg, const std::string& restart_path,
                 const std::vector<std::string>& solver_options);

/// \brief Install SIGTERM/SIGINT/SIGUSR1 handlers that request a checkpoint and a clean exit.
void install_signal_handlers();

}  // namespace biota::app
