#pragma once
/// \file csv_series.hpp
/// \brief A CSV time series (one header line, one row per record, the clock in the first column)
/// that a restart continues without duplicated rows. Used by every scenario's diagnostics CSV.
#include <fstream>
#include <string>

namespace biota::io {

/// \brief One CSV time series file, written by the one rank that owns it (the caller decides
/// which).
///
/// The first column is the series' clock (a step number or a time). On restart from a checkpoint
/// the rows written after the checkpoint belong to an abandoned future: `resume` drops them, so a
/// run restarted from step S gives the same file as a run that went through S without stopping.
class CsvSeries {
 public:
  /// \brief Start a fresh file with `header`, replacing an old one.
  void start(const std::string& path, const std::string& header);
  /// \brief Continue an existing file: keep the rows whose clock (first column) is <= keep_up_to,
  /// drop the others, append from there. A missing file, or one with another header, starts fresh
  /// (a row of another layout cannot be continued). The file is rewritten through `<path>.tmp` and
  /// a rename, so a crash here leaves the old file or the trimmed one, never half of it.
  /// \return the number of rows dropped.
  long long resume(const std::string& path, const std::string& header, double keep_up_to);
  bool is_open() const { return out_.is_open(); }
  /// \brief Append one row (without the newline) and flush, so the file is current at any time.
  void row(const std::string& line);
  /// \brief Flush pending output (rows are flushed already; for streams shared with others).
  void flush() { out_.flush(); }

 private:
  std::ofstream out_;
};

}  // namespace biota::io
