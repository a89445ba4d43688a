#pragma once
/// \file restart_check.hpp
/// \brief Restart safety: the deck of a restart must match the checkpoint's stored configuration
/// except for the keys listed in `restart_may_change()`; `--restart latest` finds the newest
/// complete checkpoint.
#include <mpi.h>

#include <string>
#include <vector>

#include "core/config.hpp"

namespace biota::app {

/// \brief The one list of keys a restart may change (run length, cadence, output, solver
/// options). A trailing ".*" matches a whole table. Everything else is state the checkpoint
/// depends on.
const std::vector<std::string>& restart_may_change();

/// \brief Check `path` before any state is read (collective): an HDF5 file, a biota checkpoint of
/// a format this build reads, complete, of the deck's scenario, with the deck's values for every
/// key not in restart_may_change(). Throws core::InputError with one line otherwise.
void check_restart(MPI_Comm comm, const core::Config& cfg, const std::string& path);

/// \brief The checkpoint directory: `checkpoint.dir`, or `<output.dir>/checkpoints` when it is
/// empty (the default), so that `--set output.dir=...` moves a run's checkpoints with its output
/// and two runs with different output directories never overwrite each other's checkpoints.
std::string checkpoint_dir(const core::Config& cfg);

/// \brief Newest (highest step) complete checkpoint `<dir>/<scenario>_<step>.h5` (collective;
/// rank 0 looks, every rank gets the path). `.tmp` and incomplete files never count. Throws
/// core::InputError naming checkpoint.dir if there is none.
std::string latest_checkpoint(MPI_Comm comm, const core::Config& cfg);

}  // namespace biota::app
