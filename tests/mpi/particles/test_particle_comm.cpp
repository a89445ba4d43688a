// Particle migration, ghosts and reverse scatter on 1, 2 and 3 ranks, checked against brute force
// over the gathered global particle set.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <tuple>
#include <vector>

#include "core/rng.hpp"
#include "particles/cell_list.hpp"
#include "particles/particle_comm.hpp"

using namespace biota;
using core::Vec3;
using particles::ParticleComm;
using particles::ParticleLayout;
using particles::ParticleSet;

namespace {

struct Gathered {
  std::vector<std::uint64_t> ids;
  std::vector<Vec3> pos;
};

Gathered gather_owned(const ParticleSet& s, MPI_Comm comm) {
  int P = 0;
  MPI_Comm_size(comm, &P);
  int n = static_cast<int>(s.n_owned());
  std::vector<int> counts(P), disp(P);
  MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
  int total = 0;
  for (int r = 0; r < P; ++r) disp[r] = total, total += counts[r];
  Gathered g;
  g.ids.resize(total);
  std::vector<std::uint64_t> my_ids(s.u64(ParticleSet::kId), s.u64(ParticleSet::kId) + n);
  MPI_Allgatherv(my_ids.data(), n, MPI_UINT64_T, g.ids.data(), counts.data(), disp.data(),
                 MPI_UINT64_T, comm);
  std::vector<double> mine(3 * n), all(3 * total);
  for (int i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d) mine[3 * i + d] = s.pos(i)[d];
  for (int r = 0; r < P; ++r) counts[r] *= 3, disp[r] *= 3;
  MPI_Allgatherv(mine.data(), 3 * n, MPI_DOUBLE, all.data(), counts.data(), disp.data(), MPI_DOUBLE,
                 comm);
  g.pos.resize(total);
  for (int i = 0; i < total; ++i) g.pos[i] = {all[3 * i], all[3 * i + 1], all[3 * i + 2]};
  return g;
}

struct Geometry {
  core::Index3 cells;
  std::array<bool, 3> periodic;
};

class ParticleComm3D : public ::testing::TestWithParam<Geometry> {};

constexpr double kDx = 0.1;

TEST_P(ParticleComm3D, RandomMovesKeepEveryParticleOnceAndGhostsMatchBruteForce) {
  const Geometry setup = GetParam();
  grid::Decomposition decomp(MPI_COMM_WORLD, setup.cells, setup.periodic);
  ParticleComm comm(decomp, kDx, {0.0, 0.0, 0.0});
  ParticleLayout layout;
  const int tag = layout.add_real("tag", 1, true, true);
  const int force = layout.add_real("force", 3, false, false);
  ParticleSet set(layout);
  const int rank = decomp.rank(), P = decomp.size();
  const int per_rank = 400;
  const std::uint64_t total = static_cast<std::uint64_t>(per_rank) * P;
  Vec3 L;
  for (int d = 0; d < 3; ++d) L[d] = setup.cells[d] * kDx;
  // Particles start anywhere; redistribute sends them home.
  for (int k = 0; k < per_rank; ++k) {
    const std::uint64_t id = static_cast<std::uint64_t>(rank) * per_rank + k;
    core::Rng rng(5, id, 0, core::RngPurpose::kTest);
    const auto i =
        set.add_owned(id, {rng.uniform(0, L.x), rng.uniform(0, L.y), rng.uniform(0, L.z)});
    set.real(tag)[i] = 0.5 * static_cast<double>(id);
  }
  comm.redistribute(set);
  double minw = 1e30;
  for (int d = 0; d < 3; ++d) minw = std::min(minw, comm.hi()[d] - comm.lo()[d]);
  MPI_Allreduce(MPI_IN_PLACE, &minw, 1, MPI_DOUBLE, MPI_MIN, MPI_COMM_WORLD);
  const double cutoff = 0.45 * minw;
  for (int round = 1; round <= 25; ++round) {
    // Moves up to 0.9 of the smallest rank width along every axis: faces, edges and corners.
    for (std::size_t i = 0; i < set.n_owned(); ++i) {
      core::Rng rng(5, set.id(i), round, core::RngPurpose::kTest);
      Vec3 p = set.pos(i);
      for (int d = 0; d < 3; ++d) {
        p[d] += rng.uniform(-0.9, 0.9) * minw;
        if (!setup.periodic[d]) p[d] = std::clamp(p[d], 0.0, L[d] * (1 - 1e-12));
      }
      set.set_pos(i, p);
    }
    comm.migrate(set);
    for (std::size_t i = 0; i < set.n_owned(); ++i) {
      ASSERT_EQ(comm.owner_of(set.pos(i)), rank);
      ASSERT_EQ(set.real(tag)[i], 0.5 * static_cast<double>(set.id(i)));
    }
    auto g = gather_owned(set, MPI_COMM_WORLD);
    ASSERT_EQ(g.ids.size(), total);
    std::sort(g.ids.begin(), g.ids.end());
    for (std::uint64_t k = 0; k < total; ++k) ASSERT_EQ(g.ids[k], k) << "lost or duplicated";
  }

  // Ghosts: every periodic image of every particle inside [lo - rc, hi + rc) that is not one of
  // my owned originals.
  comm.build_ghosts(set, cutoff);
  auto g = gather_owned(set, MPI_COMM_WORLD);
  using Key = std::tuple<std::uint64_t, long long, long long, long long>;
  auto key = [](std::uint64_t id, const Vec3& p) {
    return Key{id, std::llround(p.x * 1e7), std::llround(p.y * 1e7), std::llround(p.z * 1e7)};
  };
  std::multiset<Key> expected, got;
  for (std::size_t k = 0; k < g.ids.size(); ++k)
    for (int sx = -1; sx <= 1; ++sx)
      for (int sy = -1; sy <= 1; ++sy)
        for (int sz = -1; sz <= 1; ++sz) {
          const int s[3] = {sx, sy, sz};
          bool ok = true, inside = true;
          Vec3 p = g.pos[k];
          for (int d = 0; d < 3; ++d) {
            if (s[d] != 0 && !setup.periodic[d]) ok = false;
            p[d] += s[d] * L[d];
            if (p[d] < comm.lo()[d] - cutoff || p[d] >= comm.hi()[d] + cutoff) ok = false;
            if (p[d] < comm.lo()[d] || p[d] >= comm.hi()[d]) inside = false;
          }
          if (ok && !(inside && sx == 0 && sy == 0 && sz == 0)) expected.insert(key(g.ids[k], p));
        }
  for (std::size_t i = set.n_owned(); i < set.n_total(); ++i) {
    got.insert(key(set.id(i), set.pos(i)));
    ASSERT_EQ(set.real(tag)[i], 0.5 * static_cast<double>(set.id(i)));
  }
  EXPECT_EQ(got.size(), expected.size());
  EXPECT_TRUE(got == expected);

  // Forward refresh after a small move of the owners.
  for (std::size_t i = 0; i < set.n_owned(); ++i) {
    set.real(ParticleSet::kPos, 0)[i] += 1e-3;
    set.real(tag)[i] += 1.0;
  }
  comm.update_ghosts(set);
  for (std::size_t i = set.n_owned(); i < set.n_total(); ++i)
    ASSERT_EQ(set.real(tag)[i], 0.5 * static_cast<double>(set.id(i)) + 1.0);
  for (std::size_t i = 0; i < set.n_owned(); ++i) set.real(ParticleSet::kPos, 0)[i] -= 1e-3;
  comm.update_ghosts(set);

  // Reverse scatter: pair forces, each pair computed once (both owned, or on the rank owning the
  // smaller id), ghost contributions summed back, compared with the serial minimum-image sums.
  const double rc = 0.4 * minw;
  auto pair_force = [&](const Vec3& d) {
    const double r2 = core::dot(d, d);
    return d * (1.0 / (r2 + 0.01));
  };
  set.zero_real(force);
  particles::CellList cells(set.real(ParticleSet::kPos, 0), set.real(ParticleSet::kPos, 1),
                            set.real(ParticleSet::kPos, 2), set.n_total(), rc);
  const std::size_t no = set.n_owned();
  cells.for_each_pair([&](std::size_t i, std::size_t j, double) {
    const bool oi = i < no, oj = j < no;
    if (!oi && !oj) return;
    if (oi != oj) {
      const std::size_t own = oi ? i : j, other = oi ? j : i;
      if (!(set.id(own) < set.id(other))) return;
    }
    const Vec3 f = pair_force(set.pos(i) - set.pos(j));
    set.add_vec3(force, i, f);
    set.add_vec3(force, j, -f);
  });
  comm.reverse_sum(set, {force});
  for (std::size_t i = set.n_owned(); i < set.n_total(); ++i) ASSERT_EQ(set.vec3(force, i), Vec3{});
  // Serial reference.
  std::vector<std::size_t> idx(g.ids.size());
  for (std::size_t k = 0; k < g.ids.size(); ++k) idx[k] = k;
  std::vector<std::size_t> where(g.ids.size());
  for (std::size_t k = 0; k < g.ids.size(); ++k) where[g.ids[k]] = k;
  for (std::size_t i = 0; i < set.n_owned(); ++i) {
    const Vec3 pi = g.pos[where[set.id(i)]];
    Vec3 ref;
    double scale = 0;
    for (std::size_t k = 0; k < g.ids.size(); ++k) {
      if (g.ids[k] == set.id(i)) continue;
      Vec3 d = pi - g.pos[k];
      for (int a = 0; a < 3; ++a)
        if (setup.periodic[a]) d[a] -= L[a] * std::round(d[a] / L[a]);
      if (core::dot(d, d) < rc * rc) {
        ref += pair_force(d);
        scale += core::norm(pair_force(d));
      }
    }
    const Vec3 f = set.vec3(force, i);
    for (int a = 0; a < 3; ++a) ASSERT_NEAR(f[a], ref[a], 1e-12 * (1 + scale));
  }
}

INSTANTIATE_TEST_SUITE_P(Layouts, ParticleComm3D,
                         ::testing::Values(Geometry{{12, 10, 9}, {true, true, true}},
                                           Geometry{{11, 13, 10}, {true, false, false}},
                                           Geometry{{10, 9, 14}, {false, false, true}}));

}  // namespace
