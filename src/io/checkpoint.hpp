#pragma once
/// \file checkpoint.hpp
/// \brief Checkpoint files: parallel HDF5, decomposition-independent (global datasets), written to
/// a temporary name and renamed so a killed job never leaves a half-written checkpoint.
#include <hdf5.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/agreement.hpp"
#include "grid/decomposition.hpp"
#include "grid/field.hpp"
#include "io/write_file.hpp"

namespace biota::io {

/// \brief Format version written into every checkpoint (attribute `biota_checkpoint_format`);
/// a restart refuses a newer one. 1: first versioned format (scenario, config, complete marker).
inline constexpr std::int64_t kCheckpointFormat = 1;

/// \brief What a restart checks before reading any state (read by `read_checkpoint_header`).
struct CheckpointHeader {
  bool opened = false;       ///< an HDF5 file that opened (false: missing, truncated, not HDF5)
  std::int64_t format = -1;  ///< -1: no format attribute (not a biota checkpoint)
  bool complete = false;     ///< commit() reached the end of the write
  std::string scenario, config;
};

/// \brief Open `path` (collective over `comm`; MPI_COMM_SELF for one rank) and read its header.
CheckpointHeader read_checkpoint_header(MPI_Comm comm, const std::string& path);

/// \brief Writes one checkpoint collectively. Finish with `commit()` (the rename).
class CheckpointWriter {
 public:
  CheckpointWriter(const grid::Decomposition& decomp, std::string path);
  ~CheckpointWriter();
  /// \brief Owned cells of components [c0, c0+n) of `field` as a global dataset [n][Z][Y][X].
  void write_field(const std::string& name, const grid::Field<core::Real>& field, int c0, int n);
  /// \brief The same dataset, component by component from `fill(c, block)`, which puts this
  /// rank's owned cells of component c (x fastest, then y, z) into `block`: no copy of the
  /// whole field (the LBM's populations, reordered as they are written).
  void write_components(const std::string& name, int n,
                        const std::function<void(int, double*)>& fill);
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
  /// \brief Mark complete, close, check the close status on every rank, and atomically rename
  /// to the final path. If any rank's close failed (disk full, ...) the temporary file is removed
  /// and every rank throws the same error. Collective.
  void commit();

 private:
  const grid::Decomposition& decomp_;
  std::string path_, tmp_path_;
  std::unique_ptr<WriteFile> file_;  // the .tmp file
};

/// \brief Reads a checkpoint written on any rank count. Collective.
class CheckpointReader {
 public:
  CheckpointReader(const grid::Decomposition& decomp, std::string path);
  ~CheckpointReader();
  /// \brief Fill owned cells of components [c0, c0+n) of `field` from the global dataset.
  void read_field(const std::string& name, grid::Field<core::Real>& field, int c0, int n);
  /// \brief The same dataset, component by component into `use(c, block)` (owned cells of
  /// component c, x fastest): one component's memory, not the field's.
  void read_components(const std::string& name, int n,
                       const std::function<void(int, const double*)>& use);
  /// \brief All rows of a rows-dataset on every rank (callers keep what they own); returns ncols
  /// through `ncols`. For particles prefer read_rows_share + ParticleComm::redistribute.
  std::vector<double> read_all_rows(const std::string& name, int& ncols);
  /// \brief This rank's share of a rows-dataset (rows [r*N/P, (r+1)*N/P), a hyperslab read), so
  /// no rank holds every row; the caller redistributes them to their owners.
  std::vector<double> read_rows_share(const std::string& name, int& ncols);
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
  core::UnwindGuard unwind_;
};

}  // namespace biota::io
