#pragma once
/// \file checkpoint.hpp
/// \brief Checkpoint files: parallel HDF5, decomposition-independent (global datasets), written to
/// a temporary name and renamed so a killed job never leaves a half-written checkpoint.
#include <hdf5.h>

#include <cstdint>
#include <string>
#include <vector>

#include "grid/decomposition.hpp"
#include "grid/field.hpp"

namespace biota::io {

/// \brief Writes one checkpoint collectively. Finish with `commit()` (the rename).
class CheckpointWriter {
 public:
  CheckpointWriter(const grid::Decomposition& decomp, std::string path);
  ~CheckpointWriter();
  /// \brief Owned cells of components [c0, c0+n) of `field` as a global dataset [n][Z][Y][X].
  void write_field(const std::string& name, const grid::Field<core::Real>& field, int c0, int n);
  /// \brief Rows of `ncols` values owned by this rank, concatenated over ranks in rank order into
  /// a global [rows][ncols] dataset (particles: order does not matter, ids travel in a column).
  void write_rows(const std::string& name, const std::vector<double>& local_rows, int ncols);
  /// \brief Same for 64-bit integers (global ids, bond lists).
  void write_rows_u64(const std::string& name, const std::vector<std::uint64_t>& local_rows,
                      int ncols);
  /// \brief Replicated data (same on every rank; rank 0's copy is stored).
  void write_attribute(const std::string& name, double value);
  void write_attribute(const std::string& name, std::int64_t value);
  void write_attribute(const std::string& name, const std::string& value);
  void write_replicated(const std::string& name, const std::vector<double>& values);
  /// \brief Close and atomically rename to the final path. Collective.
  void commit();

 private:
  const grid::Decomposition& decomp_;
  std::string path_, tmp_path_;
  hid_t file_ = -1;
};

/// \brief Reads a checkpoint written on any rank count. Collective.
class CheckpointReader {
 public:
  CheckpointReader(const grid::Decomposition& decomp, std::string path);
  ~CheckpointReader();
  /// \brief Fill owned cells of components [c0, c0+n) of `field` from the global dataset.
  void read_field(const std::string& name, grid::Field<core::Real>& field, int c0, int n);
  /// \brief All rows of a rows-dataset on every rank (callers keep what they own); returns ncols
  /// through `ncols`.
  std::vector<double> read_all_rows(const std::string& name, int& ncols);
  std::vector<std::uint64_t> read_all_rows_u64(const std::string& name, int& ncols);
  double read_attribute_real(const std::string& name);
  std::int64_t read_attribute_int(const std::string& name);
  std::string read_attribute_string(const std::string& name);
  std::vector<double> read_replicated(const std::string& name);
  bool has(const std::string& name) const;

 private:
  const grid::Decomposition& decomp_;
  std::string path_;
  hid_t file_ = -1;
};

}  // namespace biota::io
