/// \file main.cpp
/// \brief The `biota` executable: run, check, bench, reference, --version.
#include <fmt/format.h>
#include <hdf5.h>
#include <mpi.h>
#include <vtkVersion.h>
#include <CLI/CLI.hpp>
#include <cstdio>

#include <toml++/toml.h>

#include "app/flock_bench.hpp"
#include "app/lbm_bench.hpp"
#include "app/lsystem_command.hpp"
#include "app/run_loop.hpp"
#include "core/agreement.hpp"
#include "core/config.hpp"
#include "core/error.hpp"
#include "core/mpi_io_workaround.hpp"
#include "core/revision.hpp"
#include "linalg/petsc_environment.hpp"
#include "scenarios/scenario.hpp"

#ifndef BIOTA_VERSION
#define BIOTA_VERSION "unknown"
#endif
#ifndef BIOTA_BUILD_TYPE
#define BIOTA_BUILD_TYPE "unknown"
#endif

namespace {

using namespace biota;

/// Owns MPI for the life of the process (the only singleton the design allows).
struct MpiEnvironment {
  MpiEnvironment(int& argc, char**& argv) {
    core::select_reliable_mpi_io();
    MPI_Init(&argc, &argv);
    // Every HDF5 failure becomes Biota's own one-line error (naming the file and dataset), once;
    // HDF5's default prints its whole error stack on every rank.
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  ~MpiEnvironment() { MPI_Finalize(); }
};

bool is_root() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r == 0;
}

// The vector instructions of this build (docs/clusters.md: which -march for compute nodes).
constexpr const char* kInstructions =
#if defined(__AVX512F__)
    "AVX-512 and FMA";
#elif defined(__AVX2__) && defined(__FP_FAST_FMA)
    "AVX2 and FMA";
#elif defined(__FP_FAST_FMA)
    "FMA, no AVX2";
#else
    "no hardware FMA";  // warn_if_no_fast_fma() says what that costs
#endif

// Said once on rank 0 before a run or benchmark: without hardware FMA, std::fma (which keeps the
// LBM's bits the same on every build) is a libm call (docs/clusters.md).
void warn_if_no_fast_fma(bool root) {
#if !defined(__FP_FAST_FMA)
  if (root)
    fmt::print(stderr,
               "biota: warning: this build has no hardware FMA, so the lattice-Boltzmann sweep "
               "runs about ten times slower; rebuild with -DCMAKE_CXX_FLAGS=-march=x86-64-v3 (or "
               "BIOTA_NATIVE=ON on the compute node), see docs/clusters.md\n");
#endif
}

std::string version_text() {
  char mpi[MPI_MAX_LIBRARY_VERSION_STRING];
  int len = 0;
  MPI_Get_library_version(mpi, &len);
  std::string mpi_line(mpi, len);
  mpi_line = mpi_line.substr(0, mpi_line.find_first_of(",\n"));
  unsigned maj = 0, min = 0, rel = 0;
  H5get_libversion(&maj, &min, &rel);
  return fmt::format(
      "biota {} (revision {}, {} build, {})\n"
      "  MPI: {}\n"
      "  HDF5: {}.{}.{} (parallel)\n"
      "  PETSc: {}\n"
      "  VTK: {}\n"
      "  toml++: {}.{}.{}\n"
      "  fmt: {}\n"
      "  compiler: {}\n"
      "  instructions: {}",
      BIOTA_VERSION, core::revision(), BIOTA_BUILD_TYPE, __DATE__, mpi_line, maj, min, rel,
      linalg::version(), vtkVersion::GetVTKVersion(), TOML_LIB_MAJOR, TOML_LIB_MINOR,
      TOML_LIB_PATCH, FMT_VERSION, __VERSION__, kInstructions);
}

// The deck names its scenario; read just that key so the full schema can be assembled.
scenarios::ScenarioInfo scenario_of(const std::string& deck,
                                    const std::vector<std::string>& overrides) {
  std::vector<scenarios::ScenarioInfo> all = scenarios::all_scenarios();
  std::string names;
  for (auto& s : all) names += (names.empty() ? "" : ", ") + s.name;
  core::ConfigSchema only;
  only.add_string("scenario", std::nullopt, {}, "scenario");
  const std::string text = core::read_deck_text(deck);
  std::string name;
  try {
    auto table = toml::parse(text, deck);
    if (auto v = table["scenario"].value<std::string>()) name = *v;
  } catch (const toml::parse_error& e) {
    throw core::InputError(fmt::format("{}:{}:{}: TOML syntax error: {}", deck,
                                       e.source().begin.line, e.source().begin.column,
                                       e.description()));
  }
  for (const auto& ov : overrides)
    if (ov.rfind("scenario=", 0) == 0) name = core::override_string_value(ov.substr(9));
  if (name.empty())
    throw core::InputError(deck + ": required key 'scenario' is missing; allowed: one of {" +
                           names + "}");
  for (auto& s : all)
    if (s.name == name) return s;
  throw core::InputError(fmt::format(
      "{}: scenario = \"{}\" is not a known scenario; allowed: one of {{{}}}", deck, name, names));
}

// `biota bench` has one option list for both benchmarks; an option of the other one was ignored
// without a word (`bench flock --size 50` ran the flock's own sizes).
void reject_options_of_the_other_bench(const CLI::App& bench, const std::string& what) {
  static const std::vector<std::string> lbm_only = {
      "--size", "--case", "--no-peer", "--no-two-grid", "--no-overlap", "--balance-speed"};
  static const std::vector<std::string> flock_only = {"--boids", "--reach", "--balance-interval"};
  for (const auto& option : what == "flock" ? lbm_only : flock_only)
    if (bench.count(option) > 0)
      throw core::InputError(fmt::format("bench {}: {} is an option of `biota bench {}` only", what,
                                         option, what == "flock" ? "lbm" : "flock"));
}

core::ConfigSchema schema_for(const scenarios::ScenarioInfo& info) {
  core::ConfigSchema schema;
  app::declare_common_config(schema);
  std::vector<std::string> names;
  for (auto& s : scenarios::all_scenarios()) names.push_back(s.name);
  core::KeySpec spec = *schema.find("scenario");
  spec.choices = names;
  schema.add("scenario", spec);
  info.declare_config(schema);
  return schema;
}

}  // namespace

int main(int argc, char** argv) {
  // Words after "--" belong to the solvers (PETSc options), not to biota's own parser.
  std::vector<std::string> solver_options;
  int own_argc = argc;
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "--") {
      own_argc = i;
      for (int j = i + 1; j < argc; ++j) solver_options.emplace_back(argv[j]);
      break;
    }
  MpiEnvironment mpi(argc, argv);
  const bool root = is_root();
  // Line-buffered stdout: in a batch job stdout is a file, and fully buffered progress lines
  // reached the job log only in 4 kB blocks (a user tailing it, or a scheduler test waiting for
  // "step N/M", saw them late). Rank 0 prints a few lines per progress interval: no cost.
  std::setvbuf(stdout, nullptr, _IOLBF, BUFSIZ);

  CLI::App cli{"Biota: living systems in moving fluids (MPI)"};
  cli.require_subcommand(0, 1);
  // A flag takes no value: `--balance-speed=3` is an error, not "true" (every flag, also of the
  // subcommands, which inherit these defaults).
  cli.option_defaults()->disable_flag_override();
  bool show_version = false;
  cli.add_flag("--version", show_version, "print version, build type and dependency versions");
  std::string deck, restart;
  std::vector<std::string> overrides;
  auto* run = cli.add_subcommand("run", "run a deck");
  run->add_option("deck", deck, "TOML input deck")->required();
  run->add_option("--set", overrides, "override a deck key: --set key=value (repeatable)");
  run->add_option("--restart", restart,
                  "continue from this checkpoint file, or `latest`: the newest complete one in "
                  "checkpoint.dir");
  auto* check = cli.add_subcommand("check", "validate a deck without running it");
  check->add_option("deck", deck, "TOML input deck")->required();
  check->add_option("--set", overrides, "override a deck key: --set key=value (repeatable)");
  auto* reference = cli.add_subcommand("reference", "print the deck reference (markdown)");
  auto* bench = cli.add_subcommand("bench", "benchmarks: `biota bench lbm` / `biota bench flock`");
  std::string bench_what = "lbm";
  app::LbmBenchOptions bench_opts;
  bench->add_option("what", bench_what, "what to benchmark")
      ->check(CLI::IsMember({"lbm", "flock"}));
  bench->add_option("--size", bench_opts.size, "lbm: cells per axis")
      ->check(CLI::Range(1, 100'000));
  bench->add_option("--steps", bench_opts.steps, "timed steps per case")
      ->check(CLI::Range(1, 1'000'000));
  bench
      ->add_option("--rounds", bench_opts.rounds,
                   "lbm: rounds of the peer and every case, one after the other (medians); "
                   "flock: rounds of each case on rank 0 alone and on all ranks (median "
                   "efficiency; default 1)")
      ->check(CLI::Range(1, 100));
  bench
      ->add_option("--case", bench_opts.cases, "lbm: only these cases, e.g. D3Q19/bgk (repeatable)")
      ->check(CLI::IsMember({"D3Q15/bgk", "D3Q15/trt", "D3Q19/bgk", "D3Q19/trt"}));
  bench->add_flag("!--no-peer", bench_opts.peer, "lbm: do not run the RRZE peer kernels");
  bench->add_flag("!--no-two-grid", bench_opts.two_grid,
                  "lbm: do not time the former two-grid sweep");
  bench->add_flag("!--no-overlap", bench_opts.overlap,
                  "lbm: exchange the halo before the sweep instead of during it (A/B)");
  bench->add_flag("--balance-speed", bench_opts.balance_speed,
                  "lbm: cut the grid by the ranks' measured sweep speed (as the seaweed does) "
                  "instead of into equal blocks");
  app::FlockBenchOptions flock_opts;
  bench->add_option("--boids", flock_opts.boids, "flock: prey counts (repeatable)")
      ->check(CLI::Range(1LL, 100'000'000LL));  // flock.prey.count's range, 0 excluded
  bench->add_option("--reach", flock_opts.reach, "flock: neighbour bins of radius/reach")
      ->check(CLI::Range(1, 4));  // flock.domain.bin_reach's range
  bench
      ->add_option("--balance-interval", flock_opts.balance_interval,
                   "flock: steps between load-balance checks (flock.balance.interval; 0: the "
                   "even cut)")
      ->check(CLI::Range(0, 1000000));
  app::LSystemCommandOptions lsys;
  auto* lsystem = cli.add_subcommand(
      "lsystem", "derive an L-system file and print its modules and turtle geometry");
  lsystem->add_option("file", lsys.file, ".lsys grammar file")->required();
  lsystem->add_option("--derivations", lsys.derivations, "derivation steps (default: the file's)")
      ->check(CLI::Range(0, 1000));
  // The ranges of the decks' seeds: CLI11 reads "-1" into an unsigned as 2^64 - 1.
  lsystem->add_option("--seed", lsys.seed, "seed of the stochastic productions")
      ->check(CLI::Range(std::uint64_t{0}, std::uint64_t{1'000'000'000'000'000'000}));
  lsystem->add_option("--tree-id", lsys.tree_id, "tree id (second key of the random stream)")
      ->check(CLI::Range(std::uint64_t{0}, std::uint64_t{1'000'000'000'000'000'000}));
  lsystem->add_option("--max-modules", lsys.max_modules, "stop with an error above this length")
      ->check(CLI::Range(1LL, 1'000'000'000LL));
  lsystem->add_option("--vtk", lsys.vtk, "write the segments as polylines with radius (.vtp)");
  lsystem->add_flag("--print-string", lsys.print_string, "print the derived string");
  try {
    cli.parse(own_argc, argv);
  } catch (const CLI::ParseError& e) {
    int code = root ? cli.exit(e) : (e.get_exit_code() == 0 ? 0 : core::kExitInput);
    return code == 0 ? 0 : core::kExitInput;
  }
  try {
    if (show_version) {
      if (root) fmt::print("{}\n", version_text());
      return 0;
    }
    if (*reference) {
      if (root) {
        fmt::print("# Deck reference\n\nGenerated by `biota reference` from the config schema.\n");
        for (auto& s : scenarios::all_scenarios())
          fmt::print("\n## scenario = \"{}\"\n\n{}\n\n{}", s.name, s.description,
                     schema_for(s).reference_markdown());
      }
      return 0;
    }
    if (*lsystem) return app::run_lsystem_command(lsys, root);
    if (*bench || *run || *check) warn_if_no_fast_fma(root);
    if (*bench) reject_options_of_the_other_bench(*bench, bench_what);
    if (*bench && bench_what == "flock") {
      // Options shared with the lbm benchmark override the flock's own defaults only when given.
      if (bench->count("--steps") > 0) flock_opts.steps = bench_opts.steps;
      if (bench->count("--rounds") > 0) flock_opts.rounds = bench_opts.rounds;
      return app::run_flock_bench(MPI_COMM_WORLD, flock_opts);
    }
    if (*bench) return app::run_lbm_bench(MPI_COMM_WORLD, bench_opts);
    if (*run || *check) {
      // `--restart "$CKPT"` with an empty variable would start from scratch without a word.
      if (run->count("--restart") > 0 && restart.empty())
        throw core::InputError(
            "--restart \"\": give a checkpoint file or `latest` (or leave --restart out to start "
            "from the deck)");
      auto info = scenario_of(deck, overrides);
      auto schema = schema_for(info);
      auto cfg = core::Config::from_file(schema, deck, overrides);
      if (root)
        fmt::print("# effective configuration of {} (biota {}, revision {})\n{}\n", deck,
                   BIOTA_VERSION, core::revision(), cfg.effective_toml());
      if (*check) {
        // Build the scenario (no output) so that derived checks (tau, Mach, ...) run too.
        core::Timers timers;
        scenarios::RunContext ctx{MPI_COMM_WORLD, cfg, timers, cfg.get_string("output.dir"),
                                  solver_options};
        const auto scenario = info.create(ctx);
        app::loop_settings(cfg, scenario->dt());  // the run's length and cadences, as a run
        const std::string& name = cfg.get_string("scenario");
        app::warn_unused_keys(cfg, root);
        if (root) fmt::print("{}: OK (scenario {})\n", deck, name);
        return 0;
      }
      app::install_signal_handlers();
      return app::run_scenario(MPI_COMM_WORLD, cfg, restart, solver_options);
    }
    if (root) fmt::print("{}", cli.help());
    return 0;
  } catch (const core::AgreedError& e) {  // every rank has it: print once, exit cleanly
    if (root) fmt::print(stderr, "biota: error: {}\n", e.what());
    return e.exit_code();
  } catch (const core::InputError& e) {
    if (root) fmt::print(stderr, "biota: error: {}\n", e.what());
    return core::kExitInput;
  } catch (const std::exception& e) {  // on this rank only: the others may wait in a collective
    fmt::print(stderr, "biota: fatal error: {}\n", e.what());
    MPI_Abort(MPI_COMM_WORLD, core::kExitRuntime);
    return core::kExitRuntime;
  }
}
