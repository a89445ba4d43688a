// The output files' error path (io/write_file.hpp): one message on every rank, no partial file.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "io/write_file.hpp"

using namespace biota;

namespace {
int rank_of_world() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}
int size_of_world() {
  int s = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &s);
  return s;
}
std::string tmp_dir() {
  auto dir = std::filesystem::temp_directory_path() /
             ("biota_write_file_np" + std::to_string(size_of_world()));
  if (rank_of_world() == 0) std::filesystem::create_directories(dir);
  MPI_Barrier(MPI_COMM_WORLD);
  return dir.string();
}
// The message every rank threw, or "" if none threw.
template <class F>
std::string message_of(F&& fn) {
  try {
    fn();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(WriteFile, AFailureOnOneRankReachesEveryRankWithItsMessage) {
  const int last = size_of_world() - 1;
  const std::string got = message_of([&] {
    io::run_agreed(MPI_COMM_WORLD, rank_of_world() == last,
                   [&] { throw std::runtime_error("piece of rank " + std::to_string(last)); });
  });
  EXPECT_EQ(got, "piece of rank " + std::to_string(last));
  // The lowest failing rank's message wins; nothing thrown where nothing failed.
  EXPECT_EQ(message_of([] {
              io::run_agreed(MPI_COMM_WORLD, true, [] {
                throw std::runtime_error("rank " + std::to_string(rank_of_world()));
              });
            }),
            "rank 0");
  EXPECT_EQ(message_of([] { io::run_agreed(MPI_COMM_WORLD, true, [] {}); }), "");
}

TEST(WriteFile, ShortSpaceStopsEveryRankAndRemovesThePartialFile) {
  const std::string path = tmp_dir() + "/short.h5";
  const double values[4] = {1, 2, 3, 4};
  const hsize_t n = static_cast<hsize_t>(size_of_world()) * 4, at = 4 * rank_of_world();
  std::string got;
  {
    io::WriteFile file(path, MPI_COMM_WORLD, "output");
    file.write_block("/a", {n}, {at}, {4}, values);  // fits
    setenv("BIOTA_TEST_FAIL", "disk_full@0", 1);     // then rank 0 sees no free space
    got = message_of([&] { file.write_block("/b", {n}, {at}, {4}, values); });
    unsetenv("BIOTA_TEST_FAIL");
  }
  EXPECT_NE(got.find("0.0 MB free and writing /b of " + path), std::string::npos) << got;
  EXPECT_NE(got.find("the partial file was removed"), std::string::npos) << got;
  MPI_Barrier(MPI_COMM_WORLD);
  EXPECT_FALSE(std::filesystem::exists(path));
}

TEST(WriteFile, AFailedTextWriteKeepsThePreviousFile) {
  const std::string path = tmp_dir() + "/index.pvd";  // collective
  if (rank_of_world() != 0) return;
  io::write_text_file(path, "good\n");
  // A directory where the .tmp should go: the write fails and the good file stays.
  std::filesystem::create_directories(path + ".tmp");
  const std::string got = message_of([&] { io::write_text_file(path, "torn"); });
  EXPECT_NE(got.find("writing " + path + " failed"), std::string::npos) << got;
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "good");
  std::filesystem::remove_all(path + ".tmp");
}
