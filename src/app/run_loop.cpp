#include "app/run_loop.hpp"

#include <fmt/format.h>

#include <atomic>
#include <cmath>
#include <csignal>
#include <filesystem>

#include "core/error.hpp"
#include "core/timers.hpp"

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
  if (len) cfg.fail(key, "cannot be used as a directory: " + err);
}

}  // namespace

void install_signal_handlers() {
  std::signal(SIGTERM, on_signal);
  std::signal(SIGINT, on_signal);
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
            "seed of every random stream (Philox key)");
  s.add_string("output.dir", "out", {}, "directory for HDF5/XDMF/VTK output");
  s.add_int("output.interval", 0, 0, 1'000'000'000'000,
            "steps between output steps (0: only the first and last step)");
  s.add_string("checkpoint.dir", "out/checkpoints", {}, "directory for checkpoints");
  s.add_int("checkpoint.interval", 0, 0, 1'000'000'000'000,
            "steps between checkpoints (0: only at the end and on SIGTERM/SIGINT)");
}

int run_scenario(MPI_Comm comm, const core::Config& cfg, const std::string& restart_path,
                 const std::vector<std::string>& solver_options) {
  const bool root = rank0(comm);
  if (!cfg.has("run.steps") && !cfg.has("run.end_time"))
    cfg.fail("run.steps", "and run.end_time are both missing; give at least one");
  const std::string out_dir = cfg.get_string("output.dir");
  const std::string ckpt_dir = cfg.get_string("checkpoint.dir");
  const std::string name = cfg.get_string("scenario");

  scenarios::ScenarioInfo info;
  for (auto& s : scenarios::all_scenarios())
    if (s.name == name) info = s;
  core::Timers timers;
  scenarios::RunContext ctx{comm, cfg, timers, out_dir, solver_options};
  auto scenario = info.create(ctx);  // validates the scenario's own keys before any output
  if (!restart_path.empty()) {
    if (!std::filesystem::exists(restart_path))
      throw core::InputError(restart_path + ": --restart checkpoint does not exist");
    scenario->read_checkpoint(restart_path);
    if (root)
      fmt::print("restarted from {} at step {}, t = {:.6g} s\n", restart_path,
                 scenario->step_index(), scenario->time());
  }
  ensure_dir(comm, cfg, "output.dir", out_dir, true);
  ensure_dir(comm, cfg, "checkpoint.dir", ckpt_dir, false);

  const double dt = scenario->dt();
  long long last_step = cfg.has("run.steps") ? cfg.get_int("run.steps") : LLONG_MAX;
  if (cfg.has("run.end_time"))
    last_step = std::min(last_step,
                         static_cast<long long>(std::llround(cfg.get_real("run.end_time") / dt)));
  const long long out_every = cfg.get_int("output.interval");
  const long long ckpt_every = cfg.get_int("checkpoint.interval");
  const long long progress_every = cfg.get_int("run.progress_interval");
  const long long health_every = cfg.get_int("run.health_interval");
  std::string last_checkpoint = restart_path.empty() ? "(none)" : restart_path;
  auto checkpoint = [&](const char* why) {
    const std::string path = fmt::format("{}/{}_{:08d}.h5", ckpt_dir, name, scenario->step_index());
    scenario->write_checkpoint(path);
    last_checkpoint = path;
    if (root) fmt::print("checkpoint ({}) written: {}\n", why, path);
  };

  const double wall0 = MPI_Wtime();
  const long long first_step = scenario->step_index();
  if (root)
    fmt::print("running '{}' from step {} to step {} (dt = {:.6g} s, end time {:.6g} s)\n", name,
               first_step, last_step, dt, last_step * dt);
  try {
    if (restart_path.empty() || out_every > 0) scenario->write_output();
    while (scenario->step_index() < last_step) {
      scenario->step();
      const long long s = scenario->step_index();
      if (s % health_every == 0 || s == last_step) scenario->check_health();
      if (s % progress_every == 0 || s == last_step) {
        std::string extra = scenario->progress();
        const double elapsed = MPI_Wtime() - wall0;
        const double eta = elapsed / double(s - first_step) * double(last_step - s);
        if (root)
          fmt::print("step {:>8}/{}  t = {:10.4f} s  {}  wall {:7.1f} s  ETA {:7.1f} s\n", s,
                     last_step, scenario->time(), extra, elapsed, eta);
      }
      if ((out_every > 0 && s % out_every == 0) || s == last_step) scenario->write_output();
      if (ckpt_every > 0 && s % ckpt_every == 0 && s != last_step) checkpoint("interval");
      // A batch scheduler sends SIGTERM before killing the job: checkpoint and leave cleanly.
      int local = g_signal.load(), any = 0;
      MPI_Allreduce(&local, &any, 1, MPI_INT, MPI_MAX, comm);
      if (any) {
        if (root) fmt::print("received signal {}: writing a checkpoint and stopping\n", any);
        checkpoint("signal");
        break;
      }
    }
    if (!g_signal.load() && scenario->step_index() == last_step) checkpoint("end of run");
  } catch (const core::UnstableError& e) {
    if (root)
      fmt::print(stderr, "biota: error: {}\nbiota: last good checkpoint: {}\n", e.what(),
                 last_checkpoint);
    return core::kExitUnstable;
  }
  const double wall = MPI_Wtime() - wall0;
  std::string table = timers.report(comm, wall);
  if (root)
    fmt::print("\ntiming breakdown ({} steps):\n{}", scenario->step_index() - first_step, table);
  return core::kExitOk;
}

}  // namespace biota::app
