#include "app/lbm_bench.hpp"

#include <fmt/format.h>

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "app/bench_stats.hpp"
#include "app/stream_probe.hpp"
#include "grid/decomposition.hpp"
#include "grid/field.hpp"
#include "solvers/lbm/lattice.hpp"
#include "solvers/lbm/lbm_solver.hpp"
#include "solvers/lbm/rank_speed.hpp"
#include "solvers/lbm/stream_collide.hpp"

namespace biota::app {
namespace {

// The RRZE lbm-benchmark-kernels peer (docs/performance-lbm.md): $BIOTA_LBM_PEER, else
// ../shared/peers/run-lbm-peer.sh next to the working directory or the source tree.
std::string find_peer() {
  if (const char* env = std::getenv("BIOTA_LBM_PEER")) return env;
  for (const std::string& dir : {std::string("."), std::string(BIOTA_SOURCE_DIR)}) {
    const auto p = std::filesystem::path(dir) / ".." / "shared" / "peers" / "run-lbm-peer.sh";
    if (std::filesystem::exists(p)) return std::filesystem::weakly_canonical(p).string();
  }
  return {};
}

// Rank 0 runs the peer with one thread per rank while the other ranks wait without spinning
// (a busy MPI barrier would take the cores the peer's threads need). Returns the peer's lines
// and its list-aa-pv-soa figure (0 when absent).
double run_peer(MPI_Comm comm, int threads, int size, std::vector<std::string>& lines) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  double best = 0;
  if (rank == 0) {
    const std::string cmd =
        fmt::format("'{}' {} {}x{}x{} 2>&1", find_peer(), threads, size, size, size);
    if (FILE* pipe = popen(cmd.c_str(), "r")) {
      char buf[512];
      while (std::fgets(buf, sizeof buf, pipe)) {
        std::string line(buf);
        if (!line.empty() && line.back() == '\n') line.pop_back();
        lines.push_back(line);
        const auto at = line.find(": ");
        if (line.rfind("rrze list-aa-pv-soa", 0) == 0 && at != std::string::npos)
          best = std::atof(line.c_str() + at + 2);
      }
      pclose(pipe);
    }
  }
  MPI_Request req;
  MPI_Ibarrier(comm, &req);
  for (int done = 0; !done;) {
    MPI_Test(&req, &done, MPI_STATUS_IGNORE);
    if (!done) usleep(20000);
  }
  MPI_Bcast(&best, 1, MPI_DOUBLE, 0, comm);
  return best;
}

// The former production scheme, kept as a benchmark variant: two population buffers, fused
// pull-stream + collide (D3Q19 BGK, Guo force field), on each rank's block, no boundaries or halo.
double two_grid_mlups(MPI_Comm comm, const grid::Decomposition& decomp, int steps) {
  using L = solvers::lbm::D3Q19;
  const auto n = decomp.local_cells();
  grid::Field<double> a(n, L::Q, 1), b(n, L::Q, 1), force(n, 3, 1, 1e-6);
  // Every cell of both buffers at rest, ghosts too: they stay there and feed the edge cells.
  for (int q = 0; q < L::Q; ++q)
    for (auto* g : {&a, &b}) std::fill(g->component(q), g->component(q) + g->plane_size(), L::w[q]);
  solvers::lbm::SweepArgs args{&a,      &b,      &force,        nullptr,
                               nullptr, nullptr, {0, 0, -1e-7}, solvers::lbm::Relaxation::bgk(0.6)};
  auto sweep = [&] {
    solvers::lbm::stream_collide<L, false, solvers::lbm::ForceMode::kField, false, false>(args);
    grid::Field<double>* next = const_cast<grid::Field<double>*>(args.src);
    args.src = args.dst;
    args.dst = next;
  };
  for (int s = 0; s < 4; ++s) sweep();
  MPI_Barrier(comm);
  const double t0 = MPI_Wtime();
  for (int s = 0; s < steps; ++s) sweep();
  MPI_Barrier(comm);
  const double t = MPI_Wtime() - t0;
  return double(decomp.global_cells().product()) * steps / t / 1e6;
}

struct Case {
  const char* lattice;
  const char* collision;
  std::string name() const { return std::string(lattice) + "/" + collision; }
};

struct CaseResult {
  double mlups = 0;      ///< single steps (LbmSolver::step)
  double fused = 0;      ///< the same steps as fused pairs (LbmSolver::advance)
  double halo_pct = 0;   ///< slowest rank's halo time, % of the single-step time
  double bound_pct = 0;  ///< slowest rank's boundary time, % of the single-step time
};

// One case in the tank configuration (walls, free-slip top, inlet jet, outlet annulus, Guo
// forcing on), on equal blocks or on `starts` (--balance-speed).
CaseResult time_case(MPI_Comm comm, const LbmBenchOptions& opts, const Case& c,
                     const std::array<std::vector<int>, 3>& starts) {
  solvers::lbm::LbmParams p;
  p.lattice = c.lattice;
  p.trt = std::string(c.collision) == "trt";
  p.cells = {opts.size, opts.size, opts.size};
  p.dx = 1.0 / opts.size;
  p.dt = 1.0 / 600.0;
  p.viscosity = 0.033 / 3.0 * p.dx * p.dx / p.dt;
  using solvers::lbm::FaceType;
  p.faces = {FaceType::kWall, FaceType::kWall, FaceType::kWall,
             FaceType::kWall, FaceType::kWall, FaceType::kFreeSlip};
  p.inlet.face = 4;
  p.inlet.center[0] = p.inlet.center[1] = 0.5;
  p.inlet.radius = 0.08;
  p.inlet.speed = 0.3;
  p.outlet.face = 4;
  p.outlet.center[0] = p.outlet.center[1] = 0.5;
  p.outlet.r_min = 0.35;
  p.body_force = {0, 0, -1e-3};
  p.overlap_halo = opts.overlap;
  p.report_choices = false;
  grid::Decomposition decomp(comm, p.cells, p.periodic(), {0, 0, 0}, {}, starts);
  solvers::lbm::LbmSolver lbm(decomp, p);
  lbm.enable_force_field();
  // Nonzero in every cell, so every cell loads it (the sweep skips the loads where it is +0).
  lbm.force().fill(1e-9);
  // Warm-up, long enough for the solver's timed choice of overlapping the halo exchange.
  for (int s = 0; s < 30; ++s) lbm.step(false);
  const double h0 = lbm.time_halo(), b0 = lbm.time_boundary();
  const double cells = double(opts.size) * opts.size * opts.size * opts.steps;
  MPI_Barrier(comm);
  const double t0 = MPI_Wtime();
  for (int s = 0; s < opts.steps; ++s) lbm.step(false);
  MPI_Barrier(comm);
  const double t = MPI_Wtime() - t0;
  double halo = lbm.time_halo() - h0, halo_max = 0;
  MPI_Allreduce(&halo, &halo_max, 1, MPI_DOUBLE, MPI_MAX, comm);
  double bound = lbm.time_boundary() - b0, bound_max = 0;
  MPI_Allreduce(&bound, &bound_max, 1, MPI_DOUBLE, MPI_MAX, comm);
  // The same steps as fused pairs (LbmSolver::advance, what the seaweed sub-cycle runs).
  MPI_Barrier(comm);
  const double tf0 = MPI_Wtime();
  lbm.advance(opts.steps, solvers::lbm::LbmSolver::PairMode::kFused);
  MPI_Barrier(comm);
  const double tf = MPI_Wtime() - tf0;
  return {cells / t / 1e6, cells / tf / 1e6, 100 * halo_max / t, 100 * bound_max / t};
}

}  // namespace

int run_lbm_bench(MPI_Comm comm, const LbmBenchOptions& opts) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const std::string peer = opts.peer ? find_peer() : std::string();
  const double bw = stream_triad(comm);
  // The cases' decomposition (walls on every face), printed because the split axis decides how
  // contiguous the halo is.
  const grid::GridKeys keys{"bench lbm", {"--size", "--size", "--size"}};
  const grid::Decomposition layout(comm, {opts.size, opts.size, opts.size}, {false, false, false},
                                   {0, 0, 0}, keys);
  {
    // Before the first population is allocated: a size the machine cannot hold ended in
    // std::bad_alloc on one rank. The largest case is D3Q19; the two-grid variant holds two
    // population buffers and a force field beside it.
    solvers::lbm::LbmParams d3q19;
    d3q19.lattice = "D3Q19";
    auto items = solvers::lbm::LbmSolver::memory_estimate(layout, d3q19);
    const auto n = layout.local_cells();
    if (opts.two_grid)
      items.push_back({"two-grid variant",
                       (2.0 * 19 + 3) * 8 * double(n.x + 2) * double(n.y + 2) * double(n.z + 2)});
    core::check_memory(comm, "bench lbm", items,
                       fmt::format("--size {} ({}^3 cells)", opts.size, opts.size));
  }
  // --balance-speed: blocks in proportion to the ranks' sweep speed, measured once here.
  std::array<std::vector<int>, 3> starts;
  std::vector<double> speed;
  if (opts.balance_speed) {
    solvers::lbm::LbmParams probe;
    probe.lattice = "D3Q19";
    probe.cells = {opts.size, opts.size, opts.size};
    speed = solvers::lbm::measure_rank_speeds(comm, probe);
    starts = grid::balanced_block_starts(layout.dims(), probe.cells, {}, speed);
  }
  if (rank == 0) {
    fmt::print(
        "biota bench lbm: {}^3 cells, {} ranks ({} x {} x {}), {} timed steps per case, {} "
        "round(s)\n",
        opts.size, size, layout.dims().x, layout.dims().y, layout.dims().z, opts.steps,
        opts.rounds);
    fmt::print("STREAM triad (all ranks at once): {:.2f} GB/s\n", bw);
    if (!opts.overlap) fmt::print("halo exchange not overlapped with the sweep (--no-overlap)\n");
    if (opts.balance_speed) {
      std::string line = "rank speeds (in-place sweep, fastest = 1):";
      for (double v : speed) line += fmt::format(" {:.2f}", v);
      for (int a = 0; a < 3; ++a)
        if (!starts[a].empty()) {
          line += fmt::format("; {} blocks", "xyz"[a]);
          for (std::size_t i = 0; i + 1 < starts[a].size(); ++i)
            line += fmt::format(" {}", starts[a][i + 1] - starts[a][i]);
        }
      fmt::print("{} (--balance-speed)\n", line);
    }
    if (!opts.peer)
      fmt::print("peer: not run (--no-peer)\n");
    else if (peer.empty())
      fmt::print(
          "peer: run-lbm-peer.sh not found (looked at $BIOTA_LBM_PEER, ../shared/peers/ and {}/../"
          "shared/peers/); no peer figure\n",
          BIOTA_SOURCE_DIR);
  }
  std::vector<Case> cases;
  for (Case c :
       {Case{"D3Q15", "bgk"}, Case{"D3Q15", "trt"}, Case{"D3Q19", "bgk"}, Case{"D3Q19", "trt"}})
    if (opts.cases.empty() ||
        std::find(opts.cases.begin(), opts.cases.end(), c.name()) != opts.cases.end())
      cases.push_back(c);
  // The host's speed drifts over minutes on shared VMs, so the peer and every case run once per
  // round, one after the other, and each ratio is taken within its round: a slow minute then
  // hits both sides of a ratio alike instead of one of them.
  std::vector<double> peer_mflups(opts.rounds, 0.0);
  std::vector<std::vector<CaseResult>> results(cases.size(), std::vector<CaseResult>(opts.rounds));
  for (int r = 0; r < opts.rounds; ++r) {
    if (!peer.empty()) {
      std::vector<std::string> peer_lines;
      peer_mflups[r] = run_peer(comm, size, opts.size, peer_lines);
      if (rank == 0)
        for (const auto& l : peer_lines) fmt::print("round {} peer ({}): {}\n", r + 1, peer, l);
    }
    std::string line = fmt::format("round {} MLUPS (single / fused):", r + 1);
    for (std::size_t c = 0; c < cases.size(); ++c) {
      results[c][r] = time_case(comm, opts, cases[c], starts);
      line += fmt::format("  {} {:.1f} / {:.1f}", cases[c].name(), results[c][r].mlups,
                          results[c][r].fused);
    }
    if (rank == 0) fmt::print("{}\n", line);
    std::fflush(stdout);
  }
  if (rank == 0)
    fmt::print("{:<6} {:<4} {:>9} {:>13} {:>9} {:>9} {:>7} {:>7} {:>7} {:>9} {:>7} {:>7}\n",
               "lattice", "coll", "MLUPS", "min-max", "roof(16Q)", "roof(24Q)", "%16Q", "halo%",
               "bound%", "x peer", "fused", "x peer");
  // Per-round values of a case, and its per-round ratios to the peer (bare D3Q19 without
  // boundaries, forcing or MPI: like lattices only).
  const auto column = [&](std::size_t c, double CaseResult::*field) {
    std::vector<double> v;
    for (const auto& res : results[c]) v.push_back(res.*field);
    return v;
  };
  const auto peer_ratio = [&](std::size_t c, double CaseResult::*field) -> std::string {
    if (peer_mflups[0] <= 0 || std::string(cases[c].lattice) != "D3Q19") return "-";
    std::vector<double> ratio;
    for (int r = 0; r < opts.rounds; ++r)
      if (peer_mflups[r] > 0) ratio.push_back(results[c][r].*field / peer_mflups[r]);
    return fmt::format("{:.2f}", median(ratio));
  };
  for (std::size_t c = 0; c < cases.size(); ++c) {
    const auto mlups = column(c, &CaseResult::mlups);
    const double med = median(mlups);
    const int q = std::string(cases[c].lattice) == "D3Q15" ? 15 : 19;
    // 16Q: read Q + write Q doubles (the in-place bound); 24Q adds the write-allocate of the
    // second buffer that a two-grid scheme without non-temporal stores pays.
    const double roof16 = bw * 1e9 / (16.0 * q) / 1e6, roof24 = bw * 1e9 / (24.0 * q) / 1e6;
    if (rank == 0)
      fmt::print(
          "{:<6} {:<4} {:>9.1f} {:>6.1f}-{:<6.1f} {:>9.1f} {:>9.1f} {:>6.0f}% {:>6.1f}% {:>6.1f}% "
          "{:>9} {:>7.1f} {:>7}\n",
          cases[c].lattice, cases[c].collision, med, *std::min_element(mlups.begin(), mlups.end()),
          *std::max_element(mlups.begin(), mlups.end()), roof16, roof24, 100 * med / roof16,
          median(column(c, &CaseResult::halo_pct)), median(column(c, &CaseResult::bound_pct)),
          peer_ratio(c, &CaseResult::mlups), median(column(c, &CaseResult::fused)),
          peer_ratio(c, &CaseResult::fused));
  }
  // D3Q15 moves 15/19 of D3Q19's bytes per cell: the bandwidth-bound speed-up is 19/15.
  for (const char* coll : {"bgk", "trt"}) {
    std::size_t i15 = cases.size(), i19 = cases.size();
    for (std::size_t c = 0; c < cases.size(); ++c)
      if (std::string(cases[c].collision) == coll)
        (std::string(cases[c].lattice) == "D3Q15" ? i15 : i19) = c;
    if (i15 == cases.size() || i19 == cases.size()) continue;
    std::vector<double> ratio;
    for (int r = 0; r < opts.rounds; ++r)
      ratio.push_back(results[i15][r].mlups / results[i19][r].mlups);
    if (rank == 0)
      fmt::print("D3Q15 / D3Q19 {}: {:.2f} (median of the rounds' ratios; 19/15 = 1.27)\n", coll,
                 median(ratio));
  }
  if (opts.two_grid) {
    grid::Decomposition decomp(comm, {opts.size, opts.size, opts.size}, {false, false, false});
    const double mlups = two_grid_mlups(comm, decomp, opts.steps);
    const double last_peer = peer_mflups[opts.rounds - 1];
    if (rank == 0)
      fmt::print(
          "D3Q19  bgk  {:>9.1f}  (former two-grid pull sweep, kernel only: no boundaries, "
          "no halo) x peer {} (last round's)\n",
          mlups, last_peer > 0 ? fmt::format("{:.2f}", mlups / last_peer) : std::string("-"));
  }
  if (rank == 0) {
    fmt::print(
        "MLUPS, halo%, bound%, fused: medians over the rounds; min-max: the rounds' spread\n");
    if (peer_mflups[0] > 0) {
      std::string rounds;
      for (double v : peer_mflups) rounds += fmt::format(" {:.1f}", v);
      fmt::print(
          "x peer: median over the rounds of MLUPS / the peer's list-aa-pv-soa MFLUP/s with {} "
          "thread(s) in the same round (rounds:{})\n",
          size, rounds);
    }
    fmt::print(
        "fused: the same steps as pairs fused plane by plane (LbmSolver::advance; the seaweed "
        "sub-cycle)\n");
  }
  return 0;
}

}  // namespace biota::app
