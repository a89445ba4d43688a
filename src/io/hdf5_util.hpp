#pragma once
/// \file hdf5_util.hpp
/// \brief Small RAII and helper layer over the parallel HDF5 C API (internal to src/io).
#include <hdf5.h>
#include <mpi.h>

#include <string>
#include <vector>

#include "core/agreement.hpp"

namespace biota::io::h5 {

/// \brief Create (truncate) a file for collective parallel access.
hid_t create_parallel(const std::string& path, MPI_Comm comm);
/// \brief Open a file read-only for collective parallel access; -1 if it cannot be opened.
hid_t open_parallel(const std::string& path, MPI_Comm comm);
/// \brief Create the group path (like mkdir -p), return nothing.
void ensure_group(hid_t file, const std::string& path);
/// \brief Collective write of a global double dataset: `global` dims, this rank's block at
/// `offset` with `count`; `data` holds the block in C order. A non-empty `chunk` (same rank as
/// `global`) stores the dataset in chunks; `deflate` > 0 adds the shuffle and deflate filters
/// (needs chunks; parallel HDF5 >= 1.10.2 writes filtered datasets collectively).
void write_block(hid_t file, const std::string& name, const std::vector<hsize_t>& global,
                 const std::vector<hsize_t>& offset, const std::vector<hsize_t>& count,
                 const double* data, hid_t type = H5T_NATIVE_DOUBLE,
                 const std::vector<hsize_t>& chunk = {}, int deflate = 0);
/// \brief An open dataset, closed when it goes out of scope, except while an exception unwinds
/// (H5Dclose may be collective and the other ranks may not come: leaked, as the file is).
class Dataset {
 public:
  explicit Dataset(hid_t id) : id_(id) {}
  ~Dataset() {
    if (!unwind_.unwinding()) H5Dclose(id_);
  }
  Dataset(const Dataset&) = delete;
  Dataset& operator=(const Dataset&) = delete;
  hid_t id() const { return id_; }

 private:
  hid_t id_;
  core::UnwindGuard unwind_;
};
/// \brief Create a dataset of dims `global` without writing it (`chunk` and `deflate` as for
/// write_block).
Dataset create_dataset(hid_t file, const std::string& name, const std::vector<hsize_t>& global,
                       hid_t type, const std::vector<hsize_t>& chunk, int deflate);
/// \brief Open a dataset; throws if it cannot.
Dataset open_dataset(hid_t file, const std::string& name);
/// \brief Collective write of this rank's block (`offset`, `count`) of an open dataset.
void write_selection(const Dataset& dset, const std::vector<hsize_t>& offset,
                     const std::vector<hsize_t>& count, const void* data, hid_t type);
/// \brief Collective read of this rank's block (`offset`, `count`) of an open dataset.
void read_selection(const Dataset& dset, const std::vector<hsize_t>& offset,
                    const std::vector<hsize_t>& count, void* data, hid_t type);
/// \brief Collective read of a block of a global dataset.
void read_block(hid_t file, const std::string& name, const std::vector<hsize_t>& offset,
                const std::vector<hsize_t>& count, void* data, hid_t type = H5T_NATIVE_DOUBLE);
/// \brief Dimensions of a dataset.
std::vector<hsize_t> dims_of(hid_t file, const std::string& name);
void write_string_attribute(hid_t obj, const std::string& name, const std::string& value);
void write_double_attribute(hid_t obj, const std::string& name, double value);
void write_int_attribute(hid_t obj, const std::string& name, long long value);
/// \brief A 1-D double array attribute (e.g. an origin).
void write_double_list_attribute(hid_t obj, const std::string& name,
                                 const std::vector<double>& values);
std::string read_string_attribute(hid_t obj, const std::string& name);
double read_double_attribute(hid_t obj, const std::string& name);
long long read_int_attribute(hid_t obj, const std::string& name);

}  // namespace biota::io::h5
