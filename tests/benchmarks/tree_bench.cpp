// Tree node-link speed (issue 9 section 6): node updates per second per core of one coupled tree
// step -- wind interpolated at every node on the staggered MAC faces (coupling::RemoteSamples +
// MacCoupling), the node-link update (3)-(11), and the reaction spread back (owned + ghost
// particles in id order) -- for a stand of the paper's Fig. 1 trees (3 derivations: 126 nodes,
// 6.67 m) on a square grid 2.5 m apart in a uniform 5 m/s wind (cells of 1 m, 10 m high).
//   mpiexec -n 1 build/tests/benchmarks/biota_bench_tree 10000 20
// arguments: nodes (rounded to whole trees), steps. Prints the split and the rates.
#include <mpi.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "coupling/mac_coupling.hpp"
#include "coupling/remote_samples.hpp"
#include "models/plants/tree_stand.hpp"

using namespace biota;
namespace mp = models::plants;
using Clock = std::chrono::steady_clock;

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  {
    int rank = 0, size = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    const long long want = argc > 1 ? std::stoll(argv[1]) : 10000;
    const int steps = argc > 2 ? std::stoi(argv[2]) : 20;
    mp::TreeSpecies sp;
    sp.lsystem = mp::parse_lsystem("axiom: F\nderivations: 3\nangle: 20\nF -> F[+F]F[-F][F]\n",
                                   "paper_fig1");
    mp::NodeLinkParams p;
    p.gravity = {};
    const long long per_tree = 126;
    const long long ntrees = std::max(1LL, want / per_tree);
    const int side = static_cast<int>(std::ceil(std::sqrt(double(ntrees))));
    const double spacing = 2.5, dx = 1.0;
    const int ncell = static_cast<int>(std::ceil(side * spacing / dx)) + 2;
    grid::Decomposition decomp(MPI_COMM_WORLD, {ncell, ncell, 10}, {true, true, false});
    grid::Field<core::Real> u(decomp.local_cells(), 3, 2), f(decomp.local_cells(), 3, 2);
    for (std::size_t q = 0; q < u.plane_size(); ++q) u.component(0)[q] = 5.0;
    particles::ParticleComm pcomm(decomp, dx);
    coupling::MacCoupling transfer(decomp, dx);
    coupling::RemoteSamples samples(pcomm);
    std::vector<mp::NodeLinkTree> trees;
    std::vector<std::uint64_t> tid;
    for (long long t = 0; t < ntrees; ++t) {
      mp::TreeSite s;
      s.id = static_cast<std::uint64_t>(t);
      s.base = {dx + spacing * (t % side), dx + spacing * (t / side), 0.0};
      s.height = 6.67;
      if (pcomm.owner_of(s.base) != rank) continue;
      trees.push_back(mp::build_tree(sp, s, p, 10'000'000));
      tid.push_back(s.id);
    }
    long long nodes = 0;
    for (const auto& t : trees) nodes += static_cast<long long>(t.size());
    long long total = nodes;
    MPI_Allreduce(MPI_IN_PLACE, &total, 1, MPI_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
    double t_interp = 0, t_tree = 0, t_spread = 0;
    const double dt = 1.0 / 30;
    std::vector<core::GlobalId> ids;
    std::vector<core::Vec3> at, force, w, fw;
    for (int s = 0; s < steps; ++s) {
      MPI_Barrier(MPI_COMM_WORLD);
      auto c0 = Clock::now();
      ids.clear(), at.clear();
      for (std::size_t t = 0; t < trees.size(); ++t)
        for (std::size_t k = 0; k < trees[t].size(); ++k)
          if (trees[t].parents()[k] >= 0) {
            ids.push_back(mp::tree_node_id(tid[t], k));
            at.push_back(trees[t].positions()[k]);
          }
      const auto wind = samples.interpolate(transfer, u, ids, at);
      auto c1 = Clock::now();
      force.assign(ids.size(), {});
      std::size_t m = 0, m2 = 0;
      for (auto& tr : trees) {
        w.assign(tr.size(), {});
        for (std::size_t k = 0; k < tr.size(); ++k)
          if (tr.parents()[k] >= 0) w[k] = wind[m++];
        tr.step(dt, w, &fw);
        for (std::size_t k = 0; k < tr.size(); ++k)
          if (tr.parents()[k] >= 0) force[m2++] = fw[k];
      }
      auto c2 = Clock::now();
      f.fill(0.0);
      samples.spread(transfer, f, ids, at, force, -0.1 / (1.2 * dx * dx * dx));
      auto c3 = Clock::now();
      t_interp += std::chrono::duration<double>(c1 - c0).count();
      t_tree += std::chrono::duration<double>(c2 - c1).count();
      t_spread += std::chrono::duration<double>(c3 - c2).count();
    }
    double tm[3] = {t_interp, t_tree, t_spread};
    MPI_Allreduce(MPI_IN_PLACE, tm, 3, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    if (rank == 0) {
      const double all = tm[0] + tm[1] + tm[2];
      const double upd = double(total) * steps;
      std::printf("tree bench: %lld trees, %lld nodes, %d steps, %d rank(s), grid %dx%dx10\n",
                  ntrees, total, steps, size, ncell, ncell);
      std::printf("  interpolate %.4f s, node-link update %.4f s, spread %.4f s per step\n",
                  tm[0] / steps, tm[1] / steps, tm[2] / steps);
      std::printf("  coupled step: %.3g node updates/s/core; node-link update alone: %.3g\n",
                  upd / all / size, upd / tm[1] / size);
    }
  }
  MPI_Finalize();
  return 0;
}
