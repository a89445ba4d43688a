#include <gtest/gtest.h>
#include <mpi.h>

#include <filesystem>

#include "core/error.hpp"
#include "io/checkpoint.hpp"
#include "io/hdf5_util.hpp"
#include "io/output_step.hpp"

using namespace biota;

namespace {
double value(const grid::Index3& g, int c) {
  return c * 1e6 + g.z * 1e4 + g.y * 1e2 + g.x + 0.25;
}
std::string tmp_dir() {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  auto dir = std::filesystem::temp_directory_path() / ("biota_io_test_np" + std::to_string(size));
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank == 0) std::filesystem::create_directories(dir / "vtk");
  MPI_Barrier(MPI_COMM_WORLD);
  return dir.string();
}
}  // namespace

TEST(Checkpoint, FieldReadBackOnADifferentDecomposition) {
  const grid::Index3 n{11, 7, 5};
  const std::string path = tmp_dir() + "/field.h5";
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank == 0) std::filesystem::remove(path);  // left by an earlier run
  MPI_Barrier(MPI_COMM_WORLD);
  {
    grid::Decomposition d(MPI_COMM_WORLD, n, {false, false, false});
    grid::Field<double> f(d.local_cells(), 2, 1);
    const auto lo = d.local_box().lo;
    for (int c = 0; c < 2; ++c)
      for (int k = 0; k < d.local_cells().z; ++k)
        for (int j = 0; j < d.local_cells().y; ++j)
          for (int i = 0; i < d.local_cells().x; ++i)
            f(i, j, k, c) = value({lo.x + i, lo.y + j, lo.z + k}, c);
    io::CheckpointWriter w(d, path);
    w.write_field("f", f, 0, 2);
    w.write_attribute("step", std::int64_t{42});
    w.write_attribute("name", std::string("tank"));
    std::vector<double> rows = {double(rank), double(rank) + 0.5};
    w.write_rows("particles", rows, 2);
    w.write_replicated("rep", {1.0, 2.0, 3.0});
    EXPECT_FALSE(std::filesystem::exists(path));  // only the .tmp exists before commit
    w.commit();
  }
  EXPECT_TRUE(std::filesystem::exists(path));
  // Read back with all ranks stacked along z instead of the default split.
  grid::Decomposition d2(MPI_COMM_WORLD, n, {false, false, false}, {1, 1, 0});
  grid::Field<double> g(d2.local_cells(), 2, 1);
  io::CheckpointReader r(d2, path);
  r.read_field("f", g, 0, 2);
  const auto lo = d2.local_box().lo;
  for (int c = 0; c < 2; ++c)
    for (int k = 0; k < d2.local_cells().z; ++k)
      for (int j = 0; j < d2.local_cells().y; ++j)
        for (int i = 0; i < d2.local_cells().x; ++i)
          ASSERT_EQ(g(i, j, k, c), value({lo.x + i, lo.y + j, lo.z + k}, c));
  EXPECT_EQ(r.read_attribute_int("step"), 42);
  EXPECT_EQ(r.read_attribute_string("name"), "tank");
  int ncols = 0;
  auto rows = r.read_all_rows("particles", ncols);
  EXPECT_EQ(ncols, 2);
  EXPECT_EQ(rows.size(), 2u * d2.size());
  for (int p = 0; p < d2.size(); ++p) EXPECT_EQ(rows[2 * p], p);  // rank order
  EXPECT_EQ(r.read_replicated("rep").size(), 3u);
  EXPECT_TRUE(r.has("/fields/f"));
  EXPECT_FALSE(r.has("/fields/nothing"));
}

// A component range that does not start at 0 lands in components 0.. of the dataset, and
// write_components / read_components (the LBM's path: one component at a time through a callback)
// store the same layout as write_field, on any decomposition.
TEST(Checkpoint, ComponentRangesAndCallbacks) {
  const grid::Index3 n{9, 6, 4};
  const std::string path = tmp_dir() + "/components.h5";
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank == 0) std::filesystem::remove(path);
  MPI_Barrier(MPI_COMM_WORLD);
  {
    grid::Decomposition d(MPI_COMM_WORLD, n, {false, false, false});
    const auto e = d.local_cells();
    const auto lo = d.local_box().lo;
    grid::Field<double> f(e, 4, 1);
    for (int c = 0; c < 4; ++c)
      for (int k = 0; k < e.z; ++k)
        for (int j = 0; j < e.y; ++j)
          for (int i = 0; i < e.x; ++i) f(i, j, k, c) = value({lo.x + i, lo.y + j, lo.z + k}, c);
    io::CheckpointWriter w(d, path);
    w.write_field("middle", f, 1, 2);  // components 1 and 2 of f as 0 and 1
    w.write_components("called", 3, [&](int c, double* block) {
      for (int k = 0; k < e.z; ++k)
        for (int j = 0; j < e.y; ++j)
          for (int i = 0; i < e.x; ++i) *block++ = value({lo.x + i, lo.y + j, lo.z + k}, 2 - c);
    });
    w.commit();
  }
  grid::Decomposition d2(MPI_COMM_WORLD, n, {false, false, false}, {1, 1, 0});
  const auto e = d2.local_cells();
  const auto lo = d2.local_box().lo;
  io::CheckpointReader r(d2, path);
  grid::Field<double> g(e, 3, 1);
  r.read_field("middle", g, 1, 2);  // into components 1 and 2 of g
  for (int k = 0; k < e.z; ++k)
    for (int j = 0; j < e.y; ++j)
      for (int i = 0; i < e.x; ++i)
        for (int c = 1; c < 3; ++c)
          ASSERT_EQ(g(i, j, k, c), value({lo.x + i, lo.y + j, lo.z + k}, c));
  int seen = 0;
  r.read_components("called", 3, [&](int c, const double* block) {
    EXPECT_EQ(c, seen++);  // in component order
    for (int k = 0; k < e.z; ++k)
      for (int j = 0; j < e.y; ++j)
        for (int i = 0; i < e.x; ++i)
          ASSERT_EQ(*block++, value({lo.x + i, lo.y + j, lo.z + k}, 2 - c));
  });
  EXPECT_EQ(seen, 3);
  grid::Field<double> wrong(e, 2, 1);
  EXPECT_THROW(r.read_field("called", wrong, 0, 2), core::InputError);  // 3 components stored
}

TEST(Checkpoint, MissingFileIsAnInputError) {
  grid::Decomposition d(MPI_COMM_WORLD, {4, 4, 4}, {false, false, false});
  EXPECT_THROW(io::CheckpointReader(d, "/nonexistent/ckpt.h5"), core::InputError);
}

TEST(OutputStep, WritesGlobalDatasetsAndIndexFiles) {
  const grid::Index3 n{6, 5, 4};
  grid::Decomposition d(MPI_COMM_WORLD, n, {false, false, false});
  const std::string dir = tmp_dir();
  io::OutputStep out(d, dir, "unit", 7, 0.5, 0.1, {0, 0, 0}, "a = 1\n", "SI");
  const auto m = d.local_cells();
  const auto lo = d.local_box().lo;
  std::vector<double> s, v;
  for (int k = 0; k < m.z; ++k)
    for (int j = 0; j < m.y; ++j)
      for (int i = 0; i < m.x; ++i) {
        s.push_back(value({lo.x + i, lo.y + j, lo.z + k}, 0));
        for (int c = 0; c < 3; ++c) v.push_back(c);
      }
  out.add_scalar("s", s, "-");
  out.add_vector("v", v, "m/s");
  out.write();
  MPI_Barrier(MPI_COMM_WORLD);
  EXPECT_TRUE(std::filesystem::exists(dir + "/unit_000007.xmf"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/unit.pvd"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/vtk/unit_000007.pvti"));
  // Read the whole scalar dataset back on every rank and check a few cells.
  hid_t f = io::h5::open_parallel(out.h5_path(), MPI_COMM_WORLD);
  ASSERT_GE(f, 0);
  std::vector<double> all(n.product());
  io::h5::read_block(f, "/fields/s", {0, 0, 0}, {hsize_t(n.z), hsize_t(n.y), hsize_t(n.x)},
                     all.data());
  EXPECT_EQ(io::h5::read_string_attribute(f, "config"), "a = 1\n");
  EXPECT_EQ(io::h5::read_int_attribute(f, "step"), 7);
  H5Fclose(f);
  for (int k = 0; k < n.z; ++k)
    for (int j = 0; j < n.y; ++j)
      for (int i = 0; i < n.x; ++i) ASSERT_EQ(all[(k * n.y + j) * n.x + i], value({i, j, k}, 0));
}
