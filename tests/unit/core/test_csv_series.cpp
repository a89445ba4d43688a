// io::CsvSeries: a restart keeps the rows up to the checkpoint and drops the abandoned future.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/csv_series.hpp"

using biota::io::CsvSeries;

namespace {
std::string read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}
}  // namespace

TEST(CsvSeries, ResumeDropsRowsAfterTheCheckpoint) {
  const std::string dir = "csv_series_test";
  std::filesystem::remove_all(dir);
  const std::string path = dir + "/series.csv";
  {
    CsvSeries s;
    s.start(path, "step,value");
    for (int k = 0; k < 10; ++k) s.row(std::to_string(k) + "," + std::to_string(k * k));
  }
  {
    CsvSeries s;  // restart at step 4: rows 0..3 are the past
    EXPECT_EQ(s.resume(path, "step,value", 3.5), 6);
    for (int k = 4; k < 10; ++k) s.row(std::to_string(k) + "," + std::to_string(k * k));
  }
  std::string expect = "step,value\n";
  for (int k = 0; k < 10; ++k) expect += std::to_string(k) + "," + std::to_string(k * k) + "\n";
  EXPECT_EQ(read(path), expect);
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
}

TEST(CsvSeries, ResumeOfAnotherLayoutOrATornRowStartsCleanly) {
  const std::string dir = "csv_series_test2";
  std::filesystem::remove_all(dir);
  const std::string path = dir + "/series.csv";
  {
    std::filesystem::create_directories(dir);
    std::ofstream f(path);
    f << "step,value\n0,1\n1,2\n2,";  // torn last row of an interrupted writer: "2," parses,
    f << "\nx7,3\n";                  // but a row without a numeric clock is dropped
  }
  CsvSeries s;
  EXPECT_EQ(s.resume(path, "step,value", 1.5), 2);
  s.row("2,5");
  EXPECT_EQ(read(path), "step,value\n0,1\n1,2\n2,5\n");
  CsvSeries t;
  EXPECT_EQ(t.resume(path, "step,other", 10), 0);  // another header: fresh file
  EXPECT_EQ(read(path), "step,other\n");
}
