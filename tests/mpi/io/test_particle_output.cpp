/// \file test_particle_output.cpp
/// \brief io::ParticleOutput on 1, 2, 3 ranks: the HDF5 file read back holds every owned particle
/// once (count, id set, positions and attributes by id), lines with their end ids and geometry;
/// the VTK / XDMF / .pvd files exist.
#include <gtest/gtest.h>
#include <mpi.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "io/hdf5_util.hpp"
#include "io/particle_output.hpp"

using namespace biota;

namespace {
constexpr std::uint64_t kN = 57;
double coord(std::uint64_t id, int c) {
  return 0.001 * id + 10.0 * c + 0.125;
}
}  // namespace

TEST(ParticleOutput, HdfReadBackHasEveryParticleOnce) {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const auto dir =
      std::filesystem::temp_directory_path() / ("biota_particle_output_np" + std::to_string(size));
  if (rank == 0) std::filesystem::remove_all(dir);
  MPI_Barrier(MPI_COMM_WORLD);

  // Rank r owns ids with id % size == r (uneven counts); line id -> id - 1 for every owned id > 0,
  // the partner appended as a ghost copy when another rank owns it.
  io::ParticleData d;
  std::vector<std::uint64_t> mine;
  for (std::uint64_t id = 0; id < kN; ++id)
    if (static_cast<int>(id % size) == rank) mine.push_back(id);
  std::vector<std::uint64_t> pts = mine;
  d.owned = mine.size();
  for (std::size_t k = 0; k < mine.size(); ++k) {
    if (mine[k] == 0) continue;
    const std::uint64_t partner = mine[k] - 1;
    std::size_t j = 0;
    if (static_cast<int>(partner % size) == rank) {
      j = k - 1;  // ids ascend in `mine`, partner is the previous owned one
    } else {
      pts.push_back(partner);
      j = pts.size() - 1;
    }
    d.lines.push_back({static_cast<std::uint32_t>(k), static_cast<std::uint32_t>(j)});
  }
  std::vector<double> mass, vel, lscal;
  for (auto id : pts) {
    for (int c = 0; c < 3; ++c) d.positions.push_back(coord(id, c));
    d.ids.push_back(id);
    mass.push_back(2.0 * id);
    vel.insert(vel.end(), {1.0 * id, -1.0 * id, 0.5});
  }
  for (const auto& l : d.lines) lscal.push_back(static_cast<double>(pts[l[0]]));
  d.scalars = {{"mass", mass}};
  d.vectors = {{"velocity", vel}};
  d.line_scalars = {{"child", lscal}};
  io::ParticleOutput(MPI_COMM_WORLD, dir.string(), "parts", 7, 0.5, "a = 1", 0).write(d);

  // Read back (every rank reads everything).
  hid_t f = io::h5::open_parallel((dir / "parts_000007.h5").string(), MPI_COMM_WORLD);
  ASSERT_GE(f, 0);
  EXPECT_EQ(io::h5::read_int_attribute(f, "points"), static_cast<long long>(kN));
  EXPECT_DOUBLE_EQ(io::h5::read_double_attribute(f, "time"), 0.5);
  const auto n = io::h5::dims_of(f, "/points/id");
  ASSERT_EQ(n.size(), 1u);
  ASSERT_EQ(n[0], kN);
  std::vector<std::uint64_t> ids(kN);
  std::vector<double> pos(3 * kN), m(kN), v(3 * kN);
  io::h5::read_block(f, "/points/id", {0}, {kN}, ids.data(), H5T_NATIVE_UINT64);
  io::h5::read_block(f, "/points/position", {0, 0}, {kN, 3}, pos.data());
  io::h5::read_block(f, "/points/mass", {0}, {kN}, m.data());
  io::h5::read_block(f, "/points/velocity", {0, 0}, {kN, 3}, v.data());
  std::set<std::uint64_t> seen(ids.begin(), ids.end());
  EXPECT_EQ(seen.size(), kN);
  EXPECT_EQ(*seen.rbegin(), kN - 1);
  for (std::size_t k = 0; k < kN; ++k) {
    for (int c = 0; c < 3; ++c) EXPECT_EQ(pos[3 * k + c], coord(ids[k], c));
    EXPECT_EQ(m[k], 2.0 * ids[k]);
    EXPECT_EQ(v[3 * k + 1], -1.0 * ids[k]);
  }
  const std::uint64_t nl = kN - 1;
  ASSERT_EQ(io::h5::dims_of(f, "/lines/id")[0], nl);
  std::vector<std::uint64_t> lid(2 * nl), conn(2 * nl);
  std::vector<double> lpos(6 * nl), child(nl);
  io::h5::read_block(f, "/lines/id", {0, 0}, {nl, 2}, lid.data(), H5T_NATIVE_UINT64);
  io::h5::read_block(f, "/lines/connectivity", {0, 0}, {nl, 2}, conn.data(), H5T_NATIVE_UINT64);
  io::h5::read_block(f, "/lines/position", {0, 0}, {2 * nl, 3}, lpos.data());
  io::h5::read_block(f, "/lines/child", {0}, {nl}, child.data());
  H5Fclose(f);
  std::set<std::uint64_t> children;
  for (std::size_t k = 0; k < nl; ++k) {
    EXPECT_EQ(lid[2 * k + 1] + 1, lid[2 * k]);
    EXPECT_EQ(child[k], static_cast<double>(lid[2 * k]));
    children.insert(lid[2 * k]);
    for (int e = 0; e < 2; ++e) {
      EXPECT_EQ(conn[2 * k + e], 2 * k + e);
      for (int c = 0; c < 3; ++c) EXPECT_EQ(lpos[3 * (2 * k + e) + c], coord(lid[2 * k + e], c));
    }
  }
  EXPECT_EQ(children.size(), nl);

  if (rank == 0) {
    EXPECT_TRUE(std::filesystem::exists(dir / "parts_000007.xmf"));
    EXPECT_TRUE(std::filesystem::exists(dir / "vtk" / "parts_000007.pvtp"));
    for (int r = 0; r < size; ++r)
      EXPECT_TRUE(std::filesystem::exists(
          dir / "vtk" /
          ("parts_000007_" + std::string(r < 10 ? "000" : "00") + std::to_string(r) + ".vtp")));
    std::ifstream pvd(dir / "parts.pvd");
    std::stringstream ss;
    ss << pvd.rdbuf();
    EXPECT_NE(ss.str().find("vtk/parts_000007.pvtp"), std::string::npos);
    std::ifstream xmf(dir / "parts_000007.xmf");
    std::stringstream xs;
    xs << xmf.rdbuf();
    EXPECT_NE(xs.str().find("Polyvertex"), std::string::npos);
    EXPECT_NE(xs.str().find("Polyline"), std::string::npos);
  }
}

TEST(ParticleOutput, SurfaceFromRankZeroInTheSameStep) {
  // A replicated triangle surface (two triangles of a unit square, a cell scalar): rank 0's copy
  // goes to /surface of the step's HDF5 file, a "surface" grid of its XDMF and a VTK PolyData in
  // <prefix>_surface.pvd; the other ranks pass it empty.
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const std::filesystem::path dir = "particle_surface_np" + std::to_string(size);
  io::ParticleData d;
  d.positions = {0.5 + rank, 0.5, 0.5};
  d.ids = {static_cast<std::uint64_t>(rank)};
  d.owned = 1;
  if (rank == 0) {
    d.surface.positions = {0, 0, 0, 1, 0, 0, 1, 0, 1, 0, 0, 1};
    d.surface.triangles = {0, 2, 1, 0, 3, 2};
    d.surface.cell_scalars = {{"S", {10.0, 20.0}}};
  } else {
    d.surface.cell_scalars = {{"S", {}}};
  }
  io::ParticleOutput out(MPI_COMM_WORLD, dir.string(), "surf", 3, 1.5, "cfg", 0);
  out.write(d);
  MPI_Barrier(MPI_COMM_WORLD);
  hid_t f = io::h5::open_parallel((dir / "surf_000003.h5").string(), MPI_COMM_WORLD);
  ASSERT_GE(f, 0);
  EXPECT_EQ(io::h5::dims_of(f, "/points/id")[0], static_cast<hsize_t>(size));
  ASSERT_EQ(io::h5::dims_of(f, "/surface/triangles")[0], 2u);
  ASSERT_EQ(io::h5::dims_of(f, "/surface/position")[0], 4u);
  std::vector<std::uint64_t> tri(6);
  std::vector<double> s(2), pos(12);
  io::h5::read_block(f, "/surface/triangles", {0, 0}, {2, 3}, tri.data(), H5T_NATIVE_UINT64);
  io::h5::read_block(f, "/surface/S", {0}, {2}, s.data());
  io::h5::read_block(f, "/surface/position", {0, 0}, {4, 3}, pos.data());
  H5Fclose(f);
  EXPECT_EQ(tri, (std::vector<std::uint64_t>{0, 2, 1, 0, 3, 2}));
  EXPECT_EQ(s, (std::vector<double>{10.0, 20.0}));
  EXPECT_EQ(pos[6], 1.0);
  EXPECT_EQ(pos[8], 1.0);
  if (rank == 0) {
    EXPECT_TRUE(std::filesystem::exists(dir / "vtk" / "surf_000003_surface.vtp"));
    std::ifstream pvd(dir / "surf_surface.pvd");
    std::stringstream ps;
    ps << pvd.rdbuf();
    EXPECT_NE(ps.str().find("vtk/surf_000003_surface.vtp"), std::string::npos);
    std::ifstream xmf(dir / "surf_000003.xmf");
    std::stringstream xs;
    xs << xmf.rdbuf();
    EXPECT_NE(xs.str().find("TopologyType=\"Triangle\" NumberOfElements=\"2\""), std::string::npos);
    EXPECT_NE(xs.str().find(":/surface/S"), std::string::npos);
  }
}
