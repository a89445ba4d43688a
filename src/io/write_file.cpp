#include "io/write_file.hpp"

#include <fmt/format.h>
#include <vtkXMLWriter.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>

#include "core/revision.hpp"
#include "io/hdf5_util.hpp"

namespace biota::io {
namespace {

namespace fs = std::filesystem;

// Bytes free on the file system holding `path` (its directory), or -1 if unknown.
double free_bytes(const std::string& path) {
  std::error_code ec;
  fs::path dir = fs::path(path).parent_path();
  if (dir.empty()) dir = ".";
  const auto space = fs::space(dir, ec);
  return ec ? -1 : static_cast<double>(space.available);
}

std::string free_space_note(const std::string& path) {
  const double free = free_bytes(path);
  return free < 0 ? "" : fmt::format(" ({:.1f} MB free on its file system)", free / 1e6);
}

// Room left beyond the data for the HDF5 metadata flushed at close (object headers, chunk
// indexes, attributes: kilobytes for Biota's files).
constexpr double kMetadataMargin = 4e6;

}  // namespace

void require_free_space(MPI_Comm comm, const std::string& path, double bytes,
                        const std::string& what, const std::string& target) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  double free = 0;
  if (rank == 0) free = core::fault_injected("disk_full", 0) ? 0 : free_bytes(path);
  MPI_Bcast(&free, 1, MPI_DOUBLE, 0, comm);
  if (free < 0 || free >= bytes + kMetadataMargin) return;  // unknown: let the write try
  const char* hint = what == "checkpoint"
                         ? "free space, or set checkpoint.dir to a larger file system"
                         : "free space, or write less (output.interval, output.stride, "
                           "output.region, output.compression)";
  throw std::runtime_error(fmt::format(
      "{}: the file system of {} has {:.1f} MB free and writing {} takes about {:.1f} MB; {}", what,
      fs::path(path).parent_path().string(), free / 1e6, target, (bytes + kMetadataMargin) / 1e6,
      hint));
}

WriteFile::WriteFile(std::string path, MPI_Comm comm, std::string what)
    : path_(std::move(path)), what_(std::move(what)), comm_(comm) {
  MPI_Comm_rank(comm_, &rank_);
  file_ = h5::create_parallel(path_, comm_);
  try {  // every file names the code that wrote it
    h5::write_string_attribute(file_, "biota_revision", core::revision());
  } catch (...) {
    discard();  // the destructor of a half-built object does not run
    throw;
  }
}

WriteFile::~WriteFile() {
  if (file_ >= 0 && !unwind_.unwinding()) discard();
}

void WriteFile::discard() {
  if (file_ >= 0) H5Fclose(file_);
  file_ = -1;
  if (rank_ == 0) {
    std::error_code ec;
    fs::remove(path_, ec);
  }
  MPI_Barrier(comm_);  // no rank looks for the file before it is gone
}

void WriteFile::require_space_for(const std::string& name, const std::vector<hsize_t>& global,
                                  hid_t type, const std::vector<hsize_t>& chunk) {
  // Chunks are stored whole, also where they overhang the dataset's edge (100 cells in chunks of
  // 32: 128); compressed ones take less, so this is an upper bound.
  double bytes = static_cast<double>(H5Tget_size(type));
  for (std::size_t d = 0; d < global.size(); ++d)
    bytes *= static_cast<double>(chunk.empty() ? global[d]
                                               : (global[d] + chunk[d] - 1) / chunk[d] * chunk[d]);
  try {
    require_free_space(comm_, path_, bytes, what_, name + " of " + path_);
  } catch (const std::runtime_error& e) {
    discard();  // every rank is here, and the space left covers the metadata the close writes
    throw std::runtime_error(std::string(e.what()) + "; the partial file was removed");
  }
}

// A failure inside a collective write (an I/O error, or space taken by another process since the
// check) may leave other ranks in it: it is thrown on this rank alone, and the run loop's
// agreement aborts the job after its grace time.
void WriteFile::write_block(const std::string& name, const std::vector<hsize_t>& global,
                            const std::vector<hsize_t>& offset, const std::vector<hsize_t>& count,
                            const double* data, hid_t type, const std::vector<hsize_t>& chunk,
                            int deflate) {
  require_space_for(name, global, type, chunk);
  h5::write_block(file_, name, global, offset, count, data, type, chunk, deflate);
}

void WriteFile::write_slabs(const std::string& name, const std::vector<hsize_t>& global,
                            const std::vector<hsize_t>& offset, const std::vector<hsize_t>& count,
                            const std::function<void(int, double*)>& fill) {
  if (global.empty() || offset[0] != 0 || count[0] != global[0])
    throw std::logic_error("WriteFile::write_slabs: every rank writes every slab of " + name);
  require_space_for(name, global, H5T_NATIVE_DOUBLE, {});
  hsize_t per_slab = 1;
  for (std::size_t d = 1; d < count.size(); ++d) per_slab *= count[d];
  std::vector<double> slab(per_slab);
  std::vector<hsize_t> slab_offset = offset, slab_count = count;
  slab_count[0] = 1;
  const auto dset = h5::create_dataset(file_, name, global, H5T_NATIVE_DOUBLE, {}, 0);
  for (hsize_t s = 0; s < global[0]; ++s) {
    fill(static_cast<int>(s), slab.data());
    slab_offset[0] = s;
    h5::write_selection(dset, slab_offset, slab_count, slab.data(), H5T_NATIVE_DOUBLE);
  }
}

double WriteFile::close() {
  int status = H5Fclose(file_) < 0 ? 1 : 0, any = 0;
  file_ = -1;
  if (core::fault_injected(what_ + "_close", rank_)) status = 1;
  MPI_Allreduce(&status, &any, 1, MPI_INT, MPI_MAX, comm_);
  if (any) {
    discard();
    throw std::runtime_error(
        fmt::format("{}: writing {} failed (HDF5 close reported an error: disk full or I/O "
                    "error){}; the partial file was removed",
                    what_, path_, free_space_note(path_)));
  }
  double size = 0;
  if (rank_ == 0) {
    std::error_code ec;
    size = static_cast<double>(fs::file_size(path_, ec));
  }
  MPI_Bcast(&size, 1, MPI_DOUBLE, 0, comm_);
  return size;
}

void write_text_file(const std::string& path, const std::string& content) {
  const std::string tmp = path + ".tmp";
  bool ok = false;
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << content;
    out.flush();
    ok = static_cast<bool>(out);
  }
  std::error_code ec;
  if (ok) fs::rename(tmp, path, ec);
  if (!ok || ec) {
    fs::remove(tmp, ec);
    throw std::runtime_error(fmt::format("output: writing {} failed{}; the previous one is kept",
                                         path, free_space_note(path)));
  }
}

void agree_on_error(MPI_Comm comm, std::exception_ptr error) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  int first = error ? rank : std::numeric_limits<int>::max();
  MPI_Allreduce(MPI_IN_PLACE, &first, 1, MPI_INT, MPI_MIN, comm);
  if (first == std::numeric_limits<int>::max()) return;
  std::string message;
  if (rank == first) {
    try {
      std::rethrow_exception(error);
    } catch (const std::exception& e) {
      message = e.what();
    } catch (...) {
      message = "unknown error";
    }
  }
  int length = static_cast<int>(message.size());
  MPI_Bcast(&length, 1, MPI_INT, first, comm);
  message.resize(length);
  MPI_Bcast(message.data(), length, MPI_CHAR, first, comm);
  throw std::runtime_error(message);
}

void write_vtk_checked(vtkXMLWriter& writer, const std::string& path, int compression) {
  writer.SetFileName(path.c_str());
  writer.SetDataModeToAppended();
  writer.EncodeAppendedDataOff();
  writer.SetHeaderTypeToUInt64();  // 32-bit headers cap an appended array at 4 GiB
  writer.SetIdTypeToInt64();
  if (compression > 0) {
    writer.SetCompressorTypeToZLib();
    writer.SetCompressionLevel(compression);
  } else {
    writer.SetCompressorTypeToNone();
  }
  if (writer.Write()) return;
  std::error_code ec;
  fs::remove(path, ec);
  throw std::runtime_error(fmt::format("output: writing {} failed{}; the partial file was removed",
                                       path, free_space_note(path)));
}

}  // namespace biota::io
