#pragma once
/// \file petsc_environment.hpp
/// \brief PETSc start-up and shutdown, and checked PETSc options, without exposing petsc.h.
///
/// MPI must be initialised first; PETSc then does not finalise MPI. The app calls `initialize`
/// with the arguments that followed `--` on its command line; solvers call `ensure_initialized`
/// so tests and tools work without the app.
#include <string>
#include <vector>

namespace biota::linalg {

/// \brief Start PETSc on MPI_COMM_WORLD with `petsc_args` (options only, no program name),
/// e.g. {"-poisson_ksp_monitor", "-log_view"}. Idempotent: options given on a later call are
/// inserted into the database. Throws core::InputError on a malformed option list.
void initialize(const std::vector<std::string>& petsc_args);
/// \brief Same, from a C argv whose argv[0] is a program name (argv after `--`, with a name).
void initialize(int argc, char** argv);
/// \brief Start PETSc without options if nobody did.
void ensure_initialized();
/// \brief Finalise PETSc (before MPI_Finalize; every PETSc object must be gone). No-op if PETSc
/// was not started here. PETSc 3.18 can be initialised again afterwards (checked). The owner of
/// the PETSc objects calls it (the wind scenario's destructor, test environments, the benchmark).
void finalize();
/// \brief True between initialize and finalize.
bool initialized();
/// \brief PETSc version string, e.g. "3.18.5" (for `biota --version`).
std::string version();

/// \brief Add options from a deck string (e.g. "-poisson_ksp_rtol 1e-10 -poisson_pc_type mg")
/// unless the command line already set them (the command line wins). Every option must start
/// with `-<prefix>`; otherwise throws core::InputError naming `key`.
void insert_prefixed_options(const std::string& options, const std::string& prefix,
                             const std::string& key);
/// \brief Remove every option named in `options` from the database (a benchmark comparing
/// solvers in one run sets one configuration after the other).
void clear_options(const std::string& options);
/// \brief Throw core::InputError listing every option under `-<prefix>` that no PETSc object
/// has queried (a misspelt or non-existent option). Call after the objects are set up.
void check_unused_options(const std::string& prefix, const std::string& source);

/// \brief The message of the last error PETSc raised, on one line. PETSc's own handler is
/// replaced by one that records it and returns: the default one prints a page per error and,
/// on ranks other than 0 of a parallel communicator, sleeps before aborting (so a collective
/// error looked like one rank failing alone, docs/robustness.md).
std::string last_error_message();

}  // namespace biota::linalg
