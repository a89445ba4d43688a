#pragma once
/// \file scenario.hpp
/// \brief The one polymorphic level of the app: a scenario wires solvers and models together and
/// advances them one step at a time. The time loop (src/app) owns run length, output cadence,
/// checkpoints, signals and the timing table.
#include <mpi.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/comm_counter.hpp"
#include "core/config.hpp"
#include "core/timers.hpp"

namespace biota::scenarios {

/// \brief What the time loop hands a scenario.
struct RunContext {
  MPI_Comm comm;
  const core::Config& config;
  core::Timers& timers;
  std::string output_dir;  ///< output.dir, created by the app
  /// \brief Command-line words after `--` (e.g. PETSc options such as -poisson_ksp_type cg).
  std::vector<std::string> solver_options = {};
  /// \brief The checkpoint this run restarts from (empty: a fresh start). The scenario reads it
  /// through read_checkpoint(); its constructor may look at it first (e.g. where the particles
  /// are now, to cut the grid between the ranks).
  std::string restart_path = {};
};

/// \brief A runnable scenario (tank, seaweed, wind, flock, ...).
class Scenario {
 public:
  virtual ~Scenario() = default;
  /// \brief Advance one step (of the scenario's own dt).
  virtual void step() = 0;
  virtual long long step_index() const = 0;
  /// \brief Simulated time in seconds.
  virtual double time() const = 0;
  /// \brief Simulated seconds per step (used for run.end_time and the ETA).
  virtual double dt() const = 0;
  /// \brief Write one output step (HDF5 + XDMF + VTK). Collective.
  virtual void write_output() = 0;
  /// \brief Write a checkpoint to `path` (collective, atomic) / restore from one.
  virtual void write_checkpoint(const std::string& path) = 0;
  virtual void read_checkpoint(const std::string& path) = 0;
  /// \brief Throw core::UnstableError naming step and position if the state became unphysical.
  virtual void check_health() = 0;
  /// \brief Test hook only (BIOTA_TEST_FAIL=health@<rank>): make this rank's state non-finite so
  /// that the next check_health must find it. Default: throw UnstableError on this rank.
  virtual void poison_for_test();
  /// \brief Extra progress-line text, e.g. "MLUPS 45.1". Collective (may reduce).
  virtual std::string progress() { return {}; }
  /// \brief Timer sections to list in the timing table, in order.
  virtual std::vector<std::string> timer_sections() const = 0;
  /// \brief Point-to-point messages and bytes this rank has sent so far (halo exchanges and
  /// particle communication; collectives and library-internal traffic such as PETSc's excluded).
  virtual core::CommCounter comm_sent() const { return {}; }
};

/// \brief Registry entry: the scenario's config keys and its factory.
struct ScenarioInfo {
  std::string name;
  std::string description;
  std::function<void(core::ConfigSchema&)> declare_config;
  std::function<std::unique_ptr<Scenario>(const RunContext&)> create;
};

/// \brief Every scenario the executable knows (explicit list, PETSc `register_all` style).
std::vector<ScenarioInfo> all_scenarios();

}  // namespace biota::scenarios
