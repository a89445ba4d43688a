#include "io/checkpoint.hpp"

#include <cstdio>
#include <stdexcept>

#include "core/error.hpp"
#include "io/hdf5_util.hpp"
#include "io/write_file.hpp"

namespace biota::io {
namespace {

// Global [n][Z][Y][X] selection of this rank's owned block.
void field_block(const grid::Decomposition& d, int n, std::vector<hsize_t>& global,
                 std::vector<hsize_t>& offset, std::vector<hsize_t>& count) {
  const auto& g = d.global_cells();
  const auto& b = d.local_box();
  const auto e = b.extent();
  global = {hsize_t(n), hsize_t(g.z), hsize_t(g.y), hsize_t(g.x)};
  offset = {0, hsize_t(b.lo.z), hsize_t(b.lo.y), hsize_t(b.lo.x)};
  count = {hsize_t(n), hsize_t(e.z), hsize_t(e.y), hsize_t(e.x)};
}

// Exclusive prefix sum of `rows` over ranks, and the total.
void row_offsets(MPI_Comm comm, unsigned long long rows, unsigned long long& offset,
                 unsigned long long& total) {
  MPI_Exscan(&rows, &offset, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm);
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  if (rank == 0) offset = 0;
  MPI_Allreduce(&rows, &total, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm);
}

}  // namespace

CheckpointWriter::CheckpointWriter(const grid::Decomposition& decomp, std::string path)
    : decomp_(decomp), path_(std::move(path)), tmp_path_(path_ + ".tmp") {
  file_ = std::make_unique<WriteFile>(tmp_path_, decomp_.comm(), "checkpoint");
  h5::write_int_attribute(file_->id(), "biota_checkpoint_format", kCheckpointFormat);
}

// Not committed: the .tmp file is removed (WriteFile), the old checkpoint is intact.
CheckpointWriter::~CheckpointWriter() = default;

void CheckpointWriter::write_field(const std::string& name, const grid::Field<core::Real>& field,
                                   int c0, int n) {
  const auto e = field.cells();
  write_components(name, n, [&](int c, double* block) {
    for (int k = 0; k < e.z; ++k)
      for (int j = 0; j < e.y; ++j)
        for (int i = 0; i < e.x; ++i) *block++ = field(i, j, k, c0 + c);
  });
}

void CheckpointWriter::write_components(const std::string& name, int n,
                                        const std::function<void(int, double*)>& fill) {
  std::vector<hsize_t> global, offset, count;
  field_block(decomp_, n, global, offset, count);
  file_->write_slabs("/fields/" + name, global, offset, count, fill);
}

void CheckpointWriter::write_rows(const std::string& name, const std::vector<double>& local_rows,
                                  int ncols) {
  unsigned long long rows = local_rows.size() / ncols, offset = 0, total = 0;
  row_offsets(decomp_.comm(), rows, offset, total);
  file_->write_block("/rows/" + name, {total, hsize_t(ncols)}, {offset, 0}, {rows, hsize_t(ncols)},
                     local_rows.data());
}

void CheckpointWriter::write_rows_u64(const std::string& name,
                                      const std::vector<std::uint64_t>& local_rows, int ncols) {
  unsigned long long rows = local_rows.size() / ncols, offset = 0, total = 0;
  row_offsets(decomp_.comm(), rows, offset, total);
  file_->write_block("/rows/" + name, {total, hsize_t(ncols)}, {offset, 0}, {rows, hsize_t(ncols)},
                     reinterpret_cast<const double*>(local_rows.data()), H5T_NATIVE_UINT64);
}

void CheckpointWriter::write_attribute(const std::string& name, double value) {
  h5::write_double_attribute(file_->id(), name, value);
}
void CheckpointWriter::write_attribute(const std::string& name, std::int64_t value) {
  h5::write_int_attribute(file_->id(), name, value);
}
void CheckpointWriter::write_attribute(const std::string& name, const std::string& value) {
  h5::write_string_attribute(file_->id(), name, value);
}

void CheckpointWriter::write_replicated(const std::string& name,
                                        const std::vector<double>& values) {
  const bool root = decomp_.rank() == 0;
  file_->write_block("/replicated/" + name, {hsize_t(values.size())}, {0},
                     {root ? hsize_t(values.size()) : 0}, values.data());
}

void CheckpointWriter::commit() {
  h5::write_int_attribute(file_->id(), "complete", 1);
  file_->close();  // on failure on any rank: removed, every rank throws
  int renamed = 1;
  if (decomp_.rank() == 0) renamed = std::rename(tmp_path_.c_str(), path_.c_str()) == 0;
  MPI_Bcast(&renamed, 1, MPI_INT, 0, decomp_.comm());
  if (!renamed) throw std::runtime_error("checkpoint: cannot rename " + tmp_path_ + " to " + path_);
}

CheckpointHeader read_checkpoint_header(MPI_Comm comm, const std::string& path) {
  CheckpointHeader h;
  hid_t file = h5::open_parallel(path, comm);
  if (file < 0) return h;
  h.opened = true;
  auto attr_exists = [&](const char* name) { return H5Aexists(file, name) > 0; };
  if (attr_exists("biota_checkpoint_format"))
    h.format = h5::read_int_attribute(file, "biota_checkpoint_format");
  h.complete = attr_exists("complete") && h5::read_int_attribute(file, "complete") == 1;
  if (attr_exists("scenario")) h.scenario = h5::read_string_attribute(file, "scenario");
  if (attr_exists("config")) h.config = h5::read_string_attribute(file, "config");
  H5Fclose(file);
  return h;
}

CheckpointReader::CheckpointReader(const grid::Decomposition& decomp, std::string path)
    : decomp_(decomp), path_(std::move(path)) {
  file_ = h5::open_parallel(path_, decomp_.comm());
  if (file_ < 0)
    throw core::InputError(path_ +
                           ": cannot open checkpoint (missing, truncated or not an HDF5 file)");
}

CheckpointReader::~CheckpointReader() {
  if (file_ >= 0 && !unwind_.unwinding()) H5Fclose(file_);  // collective: not while unwinding
}

bool CheckpointReader::has(const std::string& name) const {
  if (name.empty()) return false;
  if (H5Aexists(file_, name.c_str()) > 0) return true;
  // Check each level so a missing group is not an HDF5 error.
  std::string path;
  size_t pos = 0;
  while (pos != std::string::npos) {
    pos = name.find('/', pos + 1);
    path = name.substr(0, pos);
    if (path.empty() || path == "/") continue;
    if (H5Lexists(file_, path.c_str(), H5P_DEFAULT) <= 0) return false;
  }
  return true;
}

void CheckpointReader::read_field(const std::string& name, grid::Field<core::Real>& field, int c0,
                                  int n) {
  const auto e = field.cells();
  read_components(name, n, [&](int c, const double* block) {
    for (int k = 0; k < e.z; ++k)
      for (int j = 0; j < e.y; ++j)
        for (int i = 0; i < e.x; ++i) field(i, j, k, c0 + c) = *block++;
  });
}

void CheckpointReader::read_components(const std::string& name, int n,
                                       const std::function<void(int, const double*)>& use) {
  const std::string ds = "/fields/" + name;
  if (!has(ds)) throw core::InputError(path_ + ": checkpoint has no field '" + name + "'");
  auto dims = h5::dims_of(file_, ds);
  const auto& g = decomp_.global_cells();
  if (dims.size() != 4 || dims[0] != hsize_t(n) || dims[1] != hsize_t(g.z) ||
      dims[2] != hsize_t(g.y) || dims[3] != hsize_t(g.x))
    throw core::InputError(path_ + ": field '" + name +
                           "' has a different grid size than this run's deck");
  std::vector<hsize_t> global, offset, count;
  field_block(decomp_, n, global, offset, count);
  count[0] = 1;
  std::vector<double> block(count[1] * count[2] * count[3]);
  const auto dset = h5::open_dataset(file_, ds);
  for (int c = 0; c < n; ++c) {
    offset[0] = hsize_t(c);
    h5::read_selection(dset, offset, count, block.data(), H5T_NATIVE_DOUBLE);
    use(c, block.data());
  }
}

std::vector<double> CheckpointReader::read_all_rows(const std::string& name, int& ncols) {
  auto dims = h5::dims_of(file_, "/rows/" + name);
  ncols = static_cast<int>(dims[1]);
  std::vector<double> out(dims[0] * dims[1]);
  h5::read_block(file_, "/rows/" + name, {0, 0}, dims, out.data());
  return out;
}

std::vector<double> CheckpointReader::read_rows_share(const std::string& name, int& ncols) {
  auto dims = h5::dims_of(file_, "/rows/" + name);
  ncols = static_cast<int>(dims[1]);
  const hsize_t P = decomp_.size(), r = decomp_.rank();
  const hsize_t lo = dims[0] * r / P, hi = dims[0] * (r + 1) / P;
  std::vector<double> out((hi - lo) * dims[1]);
  h5::read_block(file_, "/rows/" + name, {lo, 0}, {hi - lo, dims[1]}, out.data());
  return out;
}

std::vector<std::uint64_t> CheckpointReader::read_all_rows_u64(const std::string& name,
                                                               int& ncols) {
  auto dims = h5::dims_of(file_, "/rows/" + name);
  ncols = static_cast<int>(dims[1]);
  std::vector<std::uint64_t> out(dims[0] * dims[1]);
  h5::read_block(file_, "/rows/" + name, {0, 0}, dims, out.data(), H5T_NATIVE_UINT64);
  return out;
}

double CheckpointReader::read_attribute_real(const std::string& name) {
  return h5::read_double_attribute(file_, name);
}
std::int64_t CheckpointReader::read_attribute_int(const std::string& name) {
  return h5::read_int_attribute(file_, name);
}
std::string CheckpointReader::read_attribute_string(const std::string& name) {
  return h5::read_string_attribute(file_, name);
}
std::vector<double> CheckpointReader::read_replicated(const std::string& name) {
  auto dims = h5::dims_of(file_, "/replicated/" + name);
  std::vector<double> out(dims[0]);
  h5::read_block(file_, "/replicated/" + name, {0}, dims, out.data());
  return out;
}

}  // namespace biota::io
