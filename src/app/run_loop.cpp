#include "app/run_loop.hpp"

#include <fmt/format.h>

#include <atomic>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <memory>
#include <stdexcept>

#include "app/restart_check.hpp"
#include "core/agreement.hpp"
#include "core/error.hpp"
#include "core/timers.hpp"
#include "io/output_layout.hpp"

namespace biota::app {
namespace {

std::atomic<int> g_signal{0};
extern "C" void on_signal(int sig) {
  g_signal.store(sig);
}

bool rank0(MPI_Comm comm) {
  int r = 0;
  MPI_Comm_rank(comm, &r);
  return r == 0;
}

// Create `dir` on rank 0; every rank learns whether it worked (InputError naming `key` if not).
void ensure_dir(MPI_Comm comm, const core::Config& cfg, const std::string& key,
                const std::string& dir, bool with_vtk) {
  std::string err;
  if (rank0(comm)) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (with_vtk && !ec)
      std::filesystem::create_directories(std::filesystem::path(dir) / "vtk", ec);
    const auto probe = std::filesystem::path(dir) / ".biota_write_test";
    FILE* f = ec ? nullptr : std::fopen(probe.c_str(), "w");
    if (!f)
      err = ec ? ec.message() : "directory is not writable";
    else {
      std::fclose(f);
      std::filesystem::remove(probe, ec);
    }
  }
  int len = static_cast<int>(err.size());
  MPI_Bcast(&len, 1, MPI_INT, 0, comm);
  err.resize(len);
  MPI_Bcast(err.data(), len, MPI_CHAR, 0, comm);
  // A directory derived from another key (checkpoint.dir's default) is named too.
  const std::string where = cfg.get_string(key) == dir ? "" : "(" + dir + ") ";
  if (len) cfg.fail(key, where + "cannot be used as a directory: " + err);
}

// Bytes of the regular files under `dir` written at or after `since` (rank 0; output steps are
// rare, so a walk is cheap). Modification times, not the growth of the tree: a rerun or restart
// into the same directory overwrites files of the same size, which grew the tree by nothing.
long long bytes_written_since(const std::string& dir, std::filesystem::file_time_type since) {
  long long total = 0;
  std::error_code ec;
  for (auto it = std::filesystem::recursive_directory_iterator(dir, ec);
       !ec && it != std::filesystem::recursive_directory_iterator(); it.increment(ec))
    if (it->is_regular_file(ec) && it->last_write_time(ec) >= since)
      total += static_cast<long long>(it->file_size(ec));
  return total;
}

// Wall time and bytes of the output steps or checkpoints of this run (bytes: on disk, rank 0).
struct IoTally {
  int count = 0;
  double seconds = 0;
  long long bytes = 0;
  void add(double s, long long b) {
    ++count;
    seconds += s;
    bytes += b;
  }
  std::string line(const char* what) const {
    if (count == 0) return {};
    return fmt::format("{:<22} {:>5} writes, {:.3f} s, {:.3f} MB per write, {:.1f} MB/s\n", what,
                       count, seconds / count, 1e-6 * double(bytes) / count,
                       seconds > 0 ? 1e-6 * double(bytes) / seconds : 0.0);
  }
};

// Point-to-point traffic per rank and step, min/avg/max over ranks; the "comm:" line is also the
// machine-readable record the scaling driver (postproc/scaling.py) parses.
std::string traffic_report(MPI_Comm comm, const core::CommCounter& c, long long steps) {
  int size = 1, rank = 0;
  MPI_Comm_size(comm, &size);
  MPI_Comm_rank(comm, &rank);
  const double per[2] = {steps > 0 ? double(c.messages) / steps : 0.0,
                         steps > 0 ? double(c.bytes) / steps : 0.0};
  double mn[2], mx[2], sum[2];
  MPI_Allreduce(per, mn, 2, MPI_DOUBLE, MPI_MIN, comm);
  MPI_Allreduce(per, mx, 2, MPI_DOUBLE, MPI_MAX, comm);
  MPI_Allreduce(per, sum, 2, MPI_DOUBLE, MPI_SUM, comm);
  if (rank != 0) return {};
  return fmt::format(
      "comm: ranks {} messages/rank/step min {:.2f} avg {:.2f} max {:.2f} bytes/rank/step min "
      "{:.0f} avg {:.0f} max {:.0f}\n",
      size, mn[0], sum[0] / size, mx[0], mn[1], sum[1] / size, mx[1]);
}

}  // namespace

void install_signal_handlers() {
  std::signal(SIGTERM, on_signal);
  std::signal(SIGINT, on_signal);
  // mpirun forwards SIGUSR1 to the ranks and keeps waiting; on SIGTERM it sends SIGKILL 1 s later
  // (odls_base_sigkill_timeout), too soon for a large checkpoint. Batch jobs send SIGUSR1.
  std::signal(SIGUSR1, on_signal);
}

void declare_common_config(core::ConfigSchema& s) {
  s.add_string("scenario", std::nullopt, {}, "scenario to run (tank, seaweed, wind, flock, ...)");
  s.add_int("run.steps", std::nullopt, 0, 1'000'000'000'000,
            "(optional) last step number; the run ends at run.steps or run.end_time, whichever "
            "comes first");
  s.add_real("run.end_time", std::nullopt, 0.0, std::nullopt, "s", "(optional) simulated end time");
  s.add_int("run.progress_interval", 100, 1, 1'000'000'000'000, "steps between progress lines");
  s.add_int("run.health_interval", 100, 1, 1'000'000'000'000,
            "steps between checks for non-finite or out-of-range state");
  s.add_int("seed", 12345, 0, 1'000'000'000'000'000'000,
            "seed of the scenario's random streams (Philox key): the flock, the moss, the "
            "forest's tree sites; the seaweed's growth has growth.seed and a tree species its "
            "own seed");
  s.add_string("output.dir", "out", {}, "directory for HDF5/XDMF/VTK output");
  s.add_int("output.interval", 0, 0, 1'000'000'000'000,
            "steps between output steps (0: only the first and last step)");
  io::declare_output_layout_config(s);
  s.add_string("checkpoint.dir", "", {},
               "directory for checkpoints (empty: <output.dir>/checkpoints)");
  s.add_int("checkpoint.interval", 0, 0, 1'000'000'000'000,
            "steps between checkpoints (0: only at the end and on SIGTERM/SIGINT)");
}

void warn_unused_keys(const core::Config& cfg, bool root) {
  const auto keys = cfg.unused_given_keys();
  if (!root || keys.empty()) return;
  std::string list;
  for (const auto& k : keys) list += (list.empty() ? "" : ", ") + k;
  fmt::print(stderr,
             "biota: warning: {}: given but not used by this run (a key of another mode of the "
             "scenario has no effect; docs/deck-reference.md): {}\n",
             cfg.source(), list);
}

namespace {
void require_run_length(const core::Config& cfg) {
  if (!cfg.has("run.steps") && !cfg.has("run.end_time"))
    cfg.fail("run.steps", "and run.end_time are both missing; give at least one");
}
}  // namespace

LoopSettings loop_settings(const core::Config& cfg, double dt) {
  require_run_length(cfg);
  LoopSettings loop;
  loop.last_step = cfg.has("run.steps") ? cfg.get_int("run.steps") : LLONG_MAX;
  if (cfg.has("run.end_time")) {
    const double end_time = cfg.get_real("run.end_time");
    const long long end_step = std::llround(end_time / dt);
    // A positive end time that rounds to step 0 selects no step: a unit slip (seconds for a
    // scenario whose step is a day), not a request for an empty run.
    if (end_time > 0 && end_step == 0)
      cfg.fail("run.end_time",
               fmt::format("s is shorter than half of the scenario's time step ({} s), so the run "
                           "would take no step; allowed: 0 or >= {} s",
                           dt, 0.5 * dt));
    loop.last_step = std::min(loop.last_step, end_step);
  }
  loop.out_every = cfg.get_int("output.interval");
  loop.ckpt_every = cfg.get_int("checkpoint.interval");
  loop.progress_every = cfg.get_int("run.progress_interval");
  loop.health_every = cfg.get_int("run.health_interval");
  loop.checkpoint_dir = checkpoint_dir(cfg);
  return loop;
}

int run_scenario(MPI_Comm comm, const core::Config& cfg, const std::string& restart_arg,
                 const std::vector<std::string>& solver_options) {
  const bool root = rank0(comm);
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  require_run_length(cfg);  // before the set-up, which may take a while
  const std::string out_dir = cfg.get_string("output.dir");
  const std::string name = cfg.get_string("scenario");

  // Every phase below runs under the agreement: an error on one rank reaches all ranks there
  // (AgreedError on every rank), or the job is aborted with that rank's message
  // (docs/robustness.md).
  core::ErrorAgreement agreement(comm);
  std::string restart_path = restart_arg;
  if (restart_path == "latest") agreement.run([&] { restart_path = latest_checkpoint(comm, cfg); });
  if (!restart_path.empty()) agreement.run([&] { check_restart(comm, cfg, restart_path); });

  scenarios::ScenarioInfo info;
  for (auto& s : scenarios::all_scenarios())
    if (s.name == name) info = s;
  core::Timers timers;
  scenarios::RunContext ctx{comm, cfg, timers, out_dir, solver_options, restart_path};
  std::unique_ptr<scenarios::Scenario> scenario;
  agreement.run([&] { scenario = info.create(ctx); });  // validates the scenario's own keys
  if (!restart_path.empty()) {
    agreement.run([&] { scenario->read_checkpoint(restart_path); });
    if (root)
      fmt::print("restarted from {} at step {}, t = {:.6g} s\n", restart_path,
                 scenario->step_index(), scenario->time());
  }
  const double dt = scenario->dt();
  const LoopSettings loop = loop_settings(cfg, dt);
  ensure_dir(comm, cfg, "output.dir", out_dir, true);
  ensure_dir(comm, cfg, "checkpoint.dir", loop.checkpoint_dir, false);

  std::string last_checkpoint = restart_path.empty() ? "(none)" : restart_path;
  agreement.set_note("last good checkpoint: " + last_checkpoint);
  // One phase of the loop: the test hook fails it on one rank, then every rank agrees.
  auto phase = [&](const char* what, auto&& fn) {
    agreement.run([&] {
      fn();
      if (core::fault_injected(what, rank, scenario->step_index()))
        throw std::runtime_error(
            fmt::format("test hook: injected failure in {} at step {} on rank {}", what,
                        scenario->step_index(), rank));
    });
  };
  IoTally out_io, ckpt_io;
  auto output = [&]() {
    const double t0 = MPI_Wtime();
    // The file system's clock, read from a file it stamps (it may differ from the system clock).
    std::filesystem::file_time_type since{};
    if (root) {
      const auto stamp = std::filesystem::path(out_dir) / ".biota_output_clock";
      std::ofstream(stamp).put('\n');
      std::error_code ec;
      since = std::filesystem::last_write_time(stamp, ec);
      std::filesystem::remove(stamp, ec);
    }
    phase("output", [&] { scenario->write_output(); });
    out_io.add(MPI_Wtime() - t0, root ? bytes_written_since(out_dir, since) : 0);
  };
  long long checkpointed_step = -1;  // the step of last_checkpoint when this run wrote it
  auto checkpoint = [&](const char* why) {
    if (checkpointed_step == scenario->step_index()) {
      // This step's checkpoint is written already (an interval one, then a signal): writing it
      // again would only add time before a launcher's kill (mpirun SIGKILLs 1 s after SIGTERM).
      if (root)
        fmt::print("checkpoint ({}) written: {} (at this step already)\n", why, last_checkpoint);
      return;
    }
    const std::string path =
        fmt::format("{}/{}_{:08d}.h5", loop.checkpoint_dir, name, scenario->step_index());
    const double t0 = MPI_Wtime();
    phase("checkpoint", [&] { scenario->write_checkpoint(path); });
    std::error_code ec;
    ckpt_io.add(MPI_Wtime() - t0,
                root ? static_cast<long long>(std::filesystem::file_size(path, ec)) : 0);
    last_checkpoint = path;
    checkpointed_step = scenario->step_index();
    agreement.set_note("last good checkpoint: " + last_checkpoint);
    if (root) fmt::print("checkpoint ({}) written: {}\n", why, path);
  };

  const double wall0 = MPI_Wtime();
  const long long first_step = scenario->step_index();
  if (root) {
    // A restart past the deck's end: say so rather than run 0 steps.
    if (first_step > loop.last_step)
      fmt::print(
          "nothing to run: the restart is at step {} (t = {:.6g} s), past run.end_time = "
          "{:.6g} s (step {}); raise run.end_time to go on\n",
          first_step, first_step * dt, loop.last_step * dt, loop.last_step);
    else
      fmt::print("running '{}' from step {} to step {} (dt = {:.6g} s, end time {:.6g} s)\n", name,
                 first_step, loop.last_step, dt, loop.last_step * dt);
    fmt::print("output in {}, checkpoints in {}\n", out_dir, loop.checkpoint_dir);
  }
  std::string table, traffic;
  try {
    if (restart_path.empty() || loop.out_every > 0) output();
    warn_unused_keys(cfg, root);  // after set-up and the first output have read their keys
    int stop_signal = 0;          // reduced over ranks: every rank takes the same decisions from it
    while (scenario->step_index() < loop.last_step) {
      // The step's agreement carries the signal flag: one small allreduce per step, as before.
      int any_signal = 0;
      agreement.run(
          [&] {
            if (core::fault_injected("step", rank, scenario->step_index() + 1))
              throw std::runtime_error(
                  fmt::format("test hook: injected failure before step {} on rank {}",
                              scenario->step_index() + 1, rank));
            scenario->step();
            if (core::fault_injected("step_after", rank, scenario->step_index()))
              throw std::runtime_error(
                  fmt::format("test hook: injected failure after step {} on rank {}",
                              scenario->step_index(), rank));
          },
          0);
      const long long s = scenario->step_index();
      if (s % loop.health_every == 0 || s == loop.last_step)
        agreement.run([&] {
          if (core::fault_injected("health", rank, s)) scenario->poison_for_test();
          scenario->check_health();
        });
      if (s % loop.progress_every == 0 || s == loop.last_step) {
        std::string extra;
        phase("progress", [&] { extra = scenario->progress(); });
        const double elapsed = MPI_Wtime() - wall0;
        const double eta = elapsed / double(s - first_step) * double(loop.last_step - s);
        if (root)
          fmt::print("step {:>8}/{}  t = {:10.4f} s  {}  wall {:7.1f} s  ETA {:7.1f} s\n", s,
                     loop.last_step, scenario->time(), extra, elapsed, eta);
      }
      if ((loop.out_every > 0 && s % loop.out_every == 0) || s == loop.last_step) output();
      if (loop.ckpt_every > 0 && s % loop.ckpt_every == 0 && s != loop.last_step)
        checkpoint("interval");
      // A batch scheduler sends SIGTERM before killing the job: checkpoint and leave cleanly.
      // Test hook: a real SIGTERM raised on one rank at one step (the fault suite).
      if (core::fault_injected("sigterm", rank, s)) std::raise(SIGTERM);
      any_signal = agreement.run([] {}, g_signal.load());
      // Test hook: a signal that reaches this rank after the others have agreed on the last step.
      if (core::fault_injected("late_signal", rank, s)) g_signal.store(SIGTERM);
      if (any_signal) {
        stop_signal = any_signal;
        if (root)
          fmt::print("received signal {}: writing a checkpoint and stopping{}\n", any_signal,
                     any_signal == SIGUSR1
                         ? ""
                         : " (Ctrl-C or SIGTERM to mpirun leaves the ranks about 1 s before "
                           "SIGKILL, too short for a large checkpoint; kill -USR1 <mpirun's "
                           "pid> waits for it: docs/getting-started.md)");
        checkpoint("signal");
        break;
      }
    }
    // Decided from the reduced flag: a rank's own flag may have been set after the last agreement.
    if (!stop_signal && scenario->step_index() == loop.last_step) checkpoint("end of run");
    const double wall = MPI_Wtime() - wall0;
    phase("end", [&] {
      table = timers.report(comm, wall);
      traffic = traffic_report(comm, scenario->comm_sent(), scenario->step_index() - first_step);
    });
  } catch (const core::AgreedError& e) {
    if (root)
      fmt::print(stderr, "biota: error: {}\nbiota: last good checkpoint: {}\n", e.what(),
                 last_checkpoint);
    return e.exit_code();
  }
  if (root)
    fmt::print("\ntiming breakdown ({} steps):\n{}{}{}{}", scenario->step_index() - first_step,
               table, traffic, out_io.line("output"), ckpt_io.line("checkpoint"));
  return core::kExitOk;
}

}  // namespace biota::app
