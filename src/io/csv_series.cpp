#include "io/csv_series.hpp"

#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include "io/write_file.hpp"

namespace biota::io {
namespace {

void open_or_throw(std::ofstream& out, const std::string& path, std::ios::openmode mode) {
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  out.open(path, std::ios::out | mode);
  if (!out) throw std::runtime_error(path + ": cannot open the CSV series for writing");
}

}  // namespace

void CsvSeries::start(const std::string& path, const std::string& header) {
  if (out_.is_open()) out_.close();
  open_or_throw(out_, path, std::ios::trunc);
  out_ << header << "\n" << std::flush;
}

long long CsvSeries::resume(const std::string& path, const std::string& header, double keep_up_to) {
  std::vector<std::string> keep;
  long long dropped = 0;
  {
    std::ifstream in(path);
    std::string line;
    if (!in || !std::getline(in, line) || line != header) {
      start(path, header);
      return 0;
    }
    while (std::getline(in, line)) {
      if (line.empty()) continue;
      // A row whose clock does not parse (a torn last line) is dropped like a future one.
      const char* begin = line.c_str();
      char* end = nullptr;
      const double clock = std::strtod(begin, &end);
      if (end != begin && (*end == ',' || *end == '\0') && clock <= keep_up_to)
        keep.push_back(line);
      else
        ++dropped;
    }
  }
  std::string trimmed = header + "\n";
  for (const auto& l : keep) trimmed += l + "\n";
  write_text_file(path, trimmed);
  if (out_.is_open()) out_.close();
  open_or_throw(out_, path, std::ios::app);
  return dropped;
}

void CsvSeries::row(const std::string& line) {
  out_ << line << "\n" << std::flush;
}

}  // namespace biota::io
