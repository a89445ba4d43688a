#include <gtest/gtest.h>
#include <mpi.h>
#include <string>

#include "core/error.hpp"
#include "grid/decomposition.hpp"
#include "grid/field.hpp"
#include "grid/halo_exchange.hpp"

using namespace biota::grid;

namespace {
// A value that identifies (global cell, component) uniquely.
double tag(const Index3& g, int c) {
  return ((c * 1000.0 + g.z) * 1000.0 + g.y) * 1000.0 + g.x;
}

void check_exchange(Index3 n, std::array<bool, 3> periodic, int ghosts) {
  Decomposition d(MPI_COMM_WORLD, n, periodic);
  const Index3 m = d.local_cells(), lo = d.local_box().lo;
  Field<double> f(m, 3, ghosts, -1.0);
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < m.z; ++k)
      for (int j = 0; j < m.y; ++j)
        for (int i = 0; i < m.x; ++i) f(i, j, k, c) = tag({lo.x + i, lo.y + j, lo.z + k}, c);
  HaloExchange halo(d, f);
  halo.exchange();
  long long checked = 0;
  for (int c = 0; c < 3; ++c)
    for (int k = -ghosts; k < m.z + ghosts; ++k)
      for (int j = -ghosts; j < m.y + ghosts; ++j)
        for (int i = -ghosts; i < m.x + ghosts; ++i) {
          Index3 g{lo.x + i, lo.y + j, lo.z + k};
          bool outside = false;
          for (int a = 0; a < 3; ++a)
            if (!periodic[a] && (g[a] < 0 || g[a] >= n[a])) outside = true;
          const double expect = outside ? -1.0 : tag(d.wrap(g), c);
          ASSERT_EQ(f(i, j, k, c), expect) << "cell " << i << "," << j << "," << k << " comp " << c;
          ++checked;
        }
  EXPECT_GT(checked, m.product() * 3);
}
}  // namespace

TEST(HaloExchange, FillsFacesEdgesAndCornersPeriodic) {
  check_exchange({10, 9, 8}, {true, true, true}, 1);
}
TEST(HaloExchange, FillsFacesEdgesAndCornersMixed) {
  check_exchange({10, 9, 8}, {true, false, true}, 1);
}
TEST(HaloExchange, TwoGhostLayers) {
  check_exchange({12, 11, 10}, {true, true, false}, 2);
}

TEST(HaloExchange, SelectedComponentsOnly) {
  Decomposition d(MPI_COMM_WORLD, {8, 8, 8}, {true, true, true});
  Field<double> f(d.local_cells(), 2, 1, 0.0);
  for (int k = 0; k < d.local_cells().z; ++k)
    for (int j = 0; j < d.local_cells().y; ++j)
      for (int i = 0; i < d.local_cells().x; ++i) f(i, j, k, 0) = f(i, j, k, 1) = 1.0;
  FaceComponents faces;
  for (int a = 0; a < 3; ++a)
    faces[a] = {std::vector<int>{0},
                std::vector<int>{1}};  // low ghosts get comp 0, high get comp 1
  HaloExchange halo(d, f, faces);
  halo.exchange();
  EXPECT_EQ(f(-1, 0, 0, 0), 1.0);
  EXPECT_EQ(f(-1, 0, 0, 1), 0.0);
  EXPECT_EQ(f(d.local_cells().x, 0, 0, 1), 1.0);
  EXPECT_EQ(f(d.local_cells().x, 0, 0, 0), 0.0);
}

TEST(HaloExchange, ReverseSumAddsGhostContributionsToOwners) {
  // Every rank deposits 1 into each of its owned and ghost cells; after the reverse sum the total
  // over owned cells equals the number of deposits that land inside the (periodic) domain.
  const Index3 n{9, 7, 6};
  Decomposition d(MPI_COMM_WORLD, n, {true, true, true});
  const Index3 m = d.local_cells();
  Field<double> f(m, 1, 1, 1.0);
  HaloExchange halo(d, f);
  halo.reverse_sum();
  double local = 0;
  for (int k = 0; k < m.z; ++k)
    for (int j = 0; j < m.y; ++j)
      for (int i = 0; i < m.x; ++i) local += f(i, j, k);
  double total = 0;
  MPI_Allreduce(&local, &total, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  double deposits = double(m.x + 2) * (m.y + 2) * (m.z + 2), all = 0;
  MPI_Allreduce(&deposits, &all, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_EQ(total, all);
  // Ghosts are zeroed.
  EXPECT_EQ(f(-1, -1, -1), 0.0);
  // A corner cell receives its own deposit plus 7 periodic images (3 faces, 3 edges, 1 corner)
  // only when one rank spans the whole domain; in general each owned cell gets 1 + (number of
  // ghost images of it in the domain), which we check globally above.
}

// Ghost width 2 with a 1-cell rank block: the neighbour would pack its own (stale) ghost layer
// into our second ghost layer. Rejected on every rank alike with one message naming the key; a
// 2-cell block is accepted and exchanges exactly.
TEST(HaloExchange, RejectsBlocksThinnerThanTheHalo) {
  int P = 0;
  MPI_Comm_size(MPI_COMM_WORLD, &P);
  for (bool periodic : {false, true}) {
    Decomposition thin(MPI_COMM_WORLD, {P == 1 ? 1 : 2 * P - 1, 4, 3}, {periodic, false, false},
                       {P, 1, 1});
    Field<double> f(thin.local_cells(), 1, 2, 0.0);
    if (P == 1) {  // no other rank along x (a periodic self-copy keeps a uniform 1-cell axis)
      EXPECT_NO_THROW(HaloExchange(thin, f));
      continue;
    }
    try {
      HaloExchange h(thin, f);
      ADD_FAILURE() << "1-cell blocks accepted with a 2-cell halo, periodic " << periodic;
    } catch (const biota::core::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("cells along x"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("ranks"), std::string::npos) << e.what();
    }
    try {
      check_halo_width(thin, 2, {"deck.toml", {"wind.nx", "wind.ny", "wind.nz"}});
      ADD_FAILURE() << "1-cell blocks passed the check, periodic " << periodic;
    } catch (const biota::core::InputError& e) {
      const std::string expected = "deck.toml: wind.nx = " + std::to_string(2 * P - 1);
      EXPECT_EQ(std::string(e.what()).rfind(expected, 0), 0u) << e.what();
    }
  }
  // 2 cells per rank, periodic: every ghost layer equals the global index it images.
  const int n = 2 * P;
  Decomposition ok(MPI_COMM_WORLD, {n, 3, 3}, {true, false, false}, {P, 1, 1});
  Field<double> f(ok.local_cells(), 1, 2, -1.0);
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 2; ++i) f(i, j, k) = ok.local_box().lo.x + i;
  HaloExchange h(ok, f);
  h.exchange();
  for (int i = -2; i < 4; ++i) {
    const int g = ((ok.local_box().lo.x + i) % n + n) % n;
    EXPECT_EQ(f(i, 1, 1), g) << "local x " << i;
  }
}
