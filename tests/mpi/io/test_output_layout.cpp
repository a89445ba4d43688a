// output.region / output.stride / output.chunk / output.compression: the cell selection, its
// checks, and the files OutputStep writes with it (HDF5 values, chunks and filters, VTK index).
#include <gtest/gtest.h>
#include <mpi.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.hpp"
#include "io/hdf5_util.hpp"
#include "io/output_layout.hpp"
#include "io/output_step.hpp"

using namespace biota;

namespace {

core::Config deck(const std::string& text) {
  static core::ConfigSchema schema = [] {
    core::ConfigSchema s;
    io::declare_output_layout_config(s);
    return s;
  }();
  return core::Config::from_string(schema, text, "deck.toml");
}

std::string error_of(const std::string& text, core::Index3 cells, double dx) {
  try {
    io::output_layout(deck(text), cells, dx, {0, 0, 0});
  } catch (const core::InputError& e) {
    return e.what();
  }
  return "";
}

double value(int x, int y, int z) {
  return z * 1e4 + y * 1e2 + x + 0.25;
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

TEST(OutputLayout, RegionSelectsCellsByTheirCentresClippedToTheDomain) {
  // 10 x 4 x 3 cells of 0.1 m: centres 0.05, 0.15, ...
  auto l = io::output_layout(deck("[output]\nregion = [0.05, -1, 0.1, 0.15, 9, 0.26]\n"),
                             {10, 4, 3}, 0.1, {0, 0, 0});
  EXPECT_EQ(l.region.lo, (core::Index3{0, 0, 1}));
  EXPECT_EQ(l.region.hi, (core::Index3{2, 4, 3}));
  EXPECT_EQ(l.out_cells({10, 4, 3}), (core::Index3{2, 4, 2}));
  // Stride 3 over 10 cells: cells 0, 3, 6, 9; the output cell centres sit on them.
  auto s = io::output_layout(deck("[output]\nstride = 3\n"), {10, 4, 3}, 0.1, {1, 0, 0});
  EXPECT_EQ(s.out_cells({10, 4, 3}), (core::Index3{4, 2, 1}));
  EXPECT_NEAR(s.out_origin({10, 4, 3}, 0.1, {1, 0, 0}).x + 1.5 * 0.3, 1 + 3.5 * 0.1, 1e-12);
  // A block [3, 7) holds cells 3 and 6 -> output indices [1, 3); a block [7, 9) holds none.
  auto b = s.out_box({10, 4, 3}, {{3, 0, 0}, {7, 4, 3}});
  EXPECT_EQ(b.lo.x, 1);
  EXPECT_EQ(b.hi.x, 3);
  EXPECT_EQ(s.out_box({10, 4, 3}, {{7, 0, 0}, {9, 4, 3}}).extent().x, 0);
}

TEST(OutputLayout, BadRegionsAreOneLineErrorsNamingKeyAndDomain) {
  const std::string outside = error_of("[output]\nregion = [5, 5, 5, 6, 6, 6]\n", {10, 4, 3}, 0.1);
  EXPECT_NE(outside.find("deck.toml: output.region = [5, 5, 5, 6, 6, 6] selects no cell"),
            std::string::npos)
      << outside;
  EXPECT_NE(outside.find("the domain is [0, 1] x [0, 0.4] x [0, 0.3] m"), std::string::npos)
      << outside;
  EXPECT_EQ(outside.find('\n'), std::string::npos);
  // Between two cell centres: no cell.
  EXPECT_NE(error_of("[output]\nregion = [0.06, 0, 0, 0.14, 1, 1]\n", {10, 4, 3}, 0.1)
                .find("x axis: no cell centre in [0.06, 0.14] m"),
            std::string::npos);
  EXPECT_NE(
      error_of("[output]\nregion = [0.5, 0, 0, 0.1, 1, 1]\n", {10, 4, 3}, 0.1).find("is not a box"),
      std::string::npos);
  EXPECT_NE(error_of("[output]\ncompression = 4\nchunk = 0\n", {10, 4, 3}, 0.1)
                .find("output.compression = 4 needs chunked datasets"),
            std::string::npos);
  EXPECT_THROW(io::output_layout_whole(deck("[output]\nstride = 2\n"), "no grid"),
               core::InputError);
}

// A region that only the first x block holds (3 ranks split x as 2, 2, 2: two ranks write
// nothing), stride 2, deflate: values, dims, chunks, filters and the VTK/XDMF indices.
TEST(OutputLayout, OutputStepWritesTheSelectedCellsOnAnyRankCount) {
  const core::Index3 n{6, 5, 4};
  grid::Decomposition d(MPI_COMM_WORLD, n, {false, false, false});
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const auto dir =
      std::filesystem::temp_directory_path() / ("biota_layout_np" + std::to_string(size));
  if (d.rank() == 0) std::filesystem::create_directories(dir / "vtk");
  MPI_Barrier(MPI_COMM_WORLD);
  // dx 0.1: x centres 0.05, 0.15 -> cells 0, 1; y 0.15..0.45 -> 1..4; z all; stride 2.
  auto layout = io::output_layout(
      deck("[output]\nregion = [0.0, 0.11, 0.0, 0.19, 0.5, 0.4]\nstride = 2\nchunk = 2\n"
           "compression = 6\n"),
      n, 0.1, {0, 0, 0});
  const core::Index3 m = layout.out_cells(n);
  ASSERT_EQ(m, (core::Index3{1, 2, 2}));  // x {0}, y {1, 3}, z {0, 2}
  io::OutputStep out(d, dir.string(), "lay", 3, 0.5, 0.1, {0, 0, 0}, "a = 1\n", "SI", layout);
  const auto e = d.local_cells();
  const auto lo = d.local_box().lo;
  std::vector<double> s, v;
  for (int k = 0; k < e.z; ++k)
    for (int j = 0; j < e.y; ++j)
      for (int i = 0; i < e.x; ++i) {
        s.push_back(value(lo.x + i, lo.y + j, lo.z + k));
        for (int c = 0; c < 3; ++c) v.push_back(c + 10 * value(lo.x + i, lo.y + j, lo.z + k));
      }
  out.add_scalar("s", s, "-");
  out.add_vector("v", v, "m/s");
  out.write();
  MPI_Barrier(MPI_COMM_WORLD);

  hid_t f = io::h5::open_parallel(out.h5_path(), MPI_COMM_WORLD);
  ASSERT_GE(f, 0);
  EXPECT_EQ(io::h5::dims_of(f, "/fields/s"), (std::vector<hsize_t>{2, 2, 1}));
  EXPECT_EQ(io::h5::dims_of(f, "/fields/v"), (std::vector<hsize_t>{2, 2, 1, 3}));
  EXPECT_DOUBLE_EQ(io::h5::read_double_attribute(f, "dx"), 0.2);
  std::vector<double> all(4), vall(12);
  io::h5::read_block(f, "/fields/s", {0, 0, 0}, {2, 2, 1}, all.data());
  io::h5::read_block(f, "/fields/v", {0, 0, 0, 0}, {2, 2, 1, 3}, vall.data());
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j) {
      EXPECT_EQ(all[k * 2 + j], value(0, 1 + 2 * j, 2 * k));
      for (int c = 0; c < 3; ++c)
        EXPECT_EQ(vall[(k * 2 + j) * 3 + c], c + 10 * value(0, 1 + 2 * j, 2 * k));
    }
  hid_t ds = H5Dopen2(f, "/fields/v", H5P_DEFAULT);
  hid_t dcpl = H5Dget_create_plist(ds);
  EXPECT_EQ(H5Pget_layout(dcpl), H5D_CHUNKED);
  hsize_t chunk[4] = {0, 0, 0, 0};
  EXPECT_EQ(H5Pget_chunk(dcpl, 4, chunk), 4);
  EXPECT_EQ(chunk[0], 2u);
  EXPECT_EQ(chunk[2], 1u);  // clipped to the dataset
  EXPECT_EQ(chunk[3], 3u);
  EXPECT_EQ(H5Pget_nfilters(dcpl), 2);  // shuffle, deflate
  EXPECT_EQ(H5Pget_filter2(dcpl, 1, nullptr, nullptr, nullptr, 0, nullptr, nullptr),
            H5Z_FILTER_DEFLATE);
  H5Pclose(dcpl);
  H5Dclose(ds);
  H5Fclose(f);

  if (d.rank() == 0) {
    const std::string pvti = read_text((dir / "vtk" / "lay_000003.pvti").string());
    EXPECT_NE(pvti.find("WholeExtent=\"0 1 0 2 0 2\""), std::string::npos) << pvti;
    EXPECT_NE(pvti.find("Spacing=\"0.2 0.2 0.2\""), std::string::npos) << pvti;
    // Output cell (0, 0, 0) is centred on cell (0, 1, 0): origin = centre - stride dx / 2.
    EXPECT_NE(pvti.find("Origin=\"-0.05 0.05 -0.05\""), std::string::npos) << pvti;
    int pieces = 0;
    for (auto pos = pvti.find("<Piece "); pos != std::string::npos;
         pos = pvti.find("<Piece ", pos + 1))
      ++pieces;
    EXPECT_GE(pieces, 1);
    EXPECT_LE(pieces, size);
    const std::string xmf = read_text((dir / "lay_000003.xmf").string());
    EXPECT_NE(xmf.find("Dimensions=\"3 3 2\""), std::string::npos) << xmf;
    EXPECT_NE(xmf.find("Dimensions=\"2 2 1 3\""), std::string::npos) << xmf;
  }
}
