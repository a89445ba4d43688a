#include "io/hdf5_util.hpp"

#include <stdexcept>

namespace biota::io::h5 {
namespace {
void check(herr_t status, const std::string& what) {
  if (status < 0) throw std::runtime_error("HDF5: " + what + " failed");
}
hid_t check_id(hid_t id, const std::string& what) {
  if (id < 0) throw std::runtime_error("HDF5: " + what + " failed");
  return id;
}
// Select this rank's block [offset, offset+count) in `fspace`; return the matching memory space.
// A rank with nothing to do still takes part in the collective call with an empty selection.
hid_t select_block(hid_t fspace, const std::vector<hsize_t>& offset,
                   const std::vector<hsize_t>& count) {
  hsize_t n = 1;
  for (auto c : count) n *= c;
  hid_t mspace = H5Screate_simple(static_cast<int>(count.size()), count.data(), nullptr);
  if (n == 0) {
    H5Sselect_none(fspace);
    H5Sselect_none(mspace);
  } else {
    H5Sselect_hyperslab(fspace, H5S_SELECT_SET, offset.data(), nullptr, count.data(), nullptr);
  }
  return mspace;
}

// The dataset's path, for messages.
std::string name_of(hid_t dset) {
  char name[512] = "";
  H5Iget_name(dset, name, sizeof name);
  return name;
}

hid_t collective_transfer() {
  hid_t dxpl = H5Pcreate(H5P_DATASET_XFER);
  H5Pset_dxpl_mpio(dxpl, H5FD_MPIO_COLLECTIVE);
  return dxpl;
}

}  // namespace

hid_t create_parallel(const std::string& path, MPI_Comm comm) {
  hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  H5Pset_fapl_mpio(fapl, comm, MPI_INFO_NULL);
  hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
  H5Pclose(fapl);
  return check_id(file, "create " + path);
}

hid_t open_parallel(const std::string& path, MPI_Comm comm) {
  hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  H5Pset_fapl_mpio(fapl, comm, MPI_INFO_NULL);
  hid_t file = -1;
  H5E_BEGIN_TRY {
    file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, fapl);
  }
  H5E_END_TRY;
  H5Pclose(fapl);
  return file;
}

void ensure_group(hid_t file, const std::string& path) {
  std::string partial;
  size_t pos = 0;
  while (pos != std::string::npos) {
    pos = path.find('/', pos + 1);
    partial = path.substr(0, pos);
    if (partial.empty() || partial == "/") continue;
    if (H5Lexists(file, partial.c_str(), H5P_DEFAULT) <= 0) {
      hid_t g = check_id(H5Gcreate2(file, partial.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                         "create group " + partial);
      H5Gclose(g);
    }
  }
}

Dataset create_dataset(hid_t file, const std::string& name, const std::vector<hsize_t>& global,
                       hid_t type, const std::vector<hsize_t>& chunk, int deflate) {
  auto slash = name.rfind('/');
  if (slash != std::string::npos && slash > 0) ensure_group(file, name.substr(0, slash));
  const int rank = static_cast<int>(global.size());
  hid_t fspace = H5Screate_simple(rank, global.data(), nullptr);
  hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
  if (!chunk.empty()) {
    if (chunk.size() != global.size())
      throw std::logic_error("HDF5: chunk rank differs from dataset rank for " + name);
    check(H5Pset_chunk(dcpl, rank, chunk.data()), "chunk " + name);
    // Every value is written: skip the fill pass (parallel HDF5 would write each chunk twice).
    check(H5Pset_fill_time(dcpl, H5D_FILL_TIME_NEVER), "fill time " + name);
    if (deflate > 0) {
      check(H5Pset_shuffle(dcpl), "shuffle filter " + name);
      check(H5Pset_deflate(dcpl, static_cast<unsigned>(deflate)), "deflate filter " + name);
    }
  } else if (deflate > 0) {
    throw std::logic_error("HDF5: compression without chunks for " + name);
  }
  hid_t dset = H5Dcreate2(file, name.c_str(), type, fspace, H5P_DEFAULT, dcpl, H5P_DEFAULT);
  H5Pclose(dcpl);
  H5Sclose(fspace);
  return Dataset(check_id(dset, "create dataset " + name));
}

Dataset open_dataset(hid_t file, const std::string& name) {
  return Dataset(check_id(H5Dopen2(file, name.c_str(), H5P_DEFAULT), "open dataset " + name));
}

// Collective transfer of this rank's block of `dset`: H5Dwrite or H5Dread.
template <class Transfer>
void transfer_selection(const Dataset& dset, const std::vector<hsize_t>& offset,
                        const std::vector<hsize_t>& count, const char* verb, Transfer transfer) {
  hid_t fspace = H5Dget_space(dset.id());
  hid_t mspace = select_block(fspace, offset, count);
  hid_t dxpl = collective_transfer();
  const herr_t status = transfer(mspace, fspace, dxpl);
  H5Pclose(dxpl);
  H5Sclose(mspace);
  H5Sclose(fspace);
  if (status < 0) check(status, std::string(verb) + " " + name_of(dset.id()));
}

void write_selection(const Dataset& dset, const std::vector<hsize_t>& offset,
                     const std::vector<hsize_t>& count, const void* data, hid_t type) {
  transfer_selection(dset, offset, count, "write", [&](hid_t mspace, hid_t fspace, hid_t dxpl) {
    return H5Dwrite(dset.id(), type, mspace, fspace, dxpl, data);
  });
}

void read_selection(const Dataset& dset, const std::vector<hsize_t>& offset,
                    const std::vector<hsize_t>& count, void* data, hid_t type) {
  transfer_selection(dset, offset, count, "read", [&](hid_t mspace, hid_t fspace, hid_t dxpl) {
    return H5Dread(dset.id(), type, mspace, fspace, dxpl, data);
  });
}

void write_block(hid_t file, const std::string& name, const std::vector<hsize_t>& global,
                 const std::vector<hsize_t>& offset, const std::vector<hsize_t>& count,
                 const double* data, hid_t type, const std::vector<hsize_t>& chunk, int deflate) {
  write_selection(create_dataset(file, name, global, type, chunk, deflate), offset, count, data,
                  type);
}

void read_block(hid_t file, const std::string& name, const std::vector<hsize_t>& offset,
                const std::vector<hsize_t>& count, void* data, hid_t type) {
  read_selection(open_dataset(file, name), offset, count, data, type);
}

std::vector<hsize_t> dims_of(hid_t file, const std::string& name) {
  const Dataset dset = open_dataset(file, name);
  hid_t space = H5Dget_space(dset.id());
  int rank = H5Sget_simple_extent_ndims(space);
  std::vector<hsize_t> dims(rank);
  H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  H5Sclose(space);
  return dims;
}

void write_string_attribute(hid_t obj, const std::string& name, const std::string& value) {
  hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, value.size() + 1);
  hid_t space = H5Screate(H5S_SCALAR);
  hid_t attr = H5Acreate2(obj, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT);
  check(H5Awrite(attr, type, value.c_str()), "write attribute " + name);
  H5Aclose(attr);
  H5Sclose(space);
  H5Tclose(type);
}

void write_double_attribute(hid_t obj, const std::string& name, double value) {
  hid_t space = H5Screate(H5S_SCALAR);
  hid_t attr = H5Acreate2(obj, name.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT);
  check(H5Awrite(attr, H5T_NATIVE_DOUBLE, &value), "write attribute " + name);
  H5Aclose(attr);
  H5Sclose(space);
}

void write_int_attribute(hid_t obj, const std::string& name, long long value) {
  hid_t space = H5Screate(H5S_SCALAR);
  hid_t attr = H5Acreate2(obj, name.c_str(), H5T_NATIVE_LLONG, space, H5P_DEFAULT, H5P_DEFAULT);
  check(H5Awrite(attr, H5T_NATIVE_LLONG, &value), "write attribute " + name);
  H5Aclose(attr);
  H5Sclose(space);
}

void write_double_list_attribute(hid_t obj, const std::string& name,
                                 const std::vector<double>& values) {
  const hsize_t n = values.size();
  hid_t space = H5Screate_simple(1, &n, nullptr);
  hid_t attr = H5Acreate2(obj, name.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT);
  check(H5Awrite(attr, H5T_NATIVE_DOUBLE, values.data()), "write attribute " + name);
  H5Aclose(attr);
  H5Sclose(space);
}

std::string read_string_attribute(hid_t obj, const std::string& name) {
  hid_t attr = check_id(H5Aopen(obj, name.c_str(), H5P_DEFAULT), "open attribute " + name);
  hid_t type = H5Aget_type(attr);
  size_t size = H5Tget_size(type);
  std::string value(size, '\0');
  hid_t mem = H5Tcopy(H5T_C_S1);
  H5Tset_size(mem, size);
  check(H5Aread(attr, mem, value.data()), "read attribute " + name);
  H5Tclose(mem);
  H5Tclose(type);
  H5Aclose(attr);
  value.resize(value.find('\0') == std::string::npos ? size : value.find('\0'));
  return value;
}

double read_double_attribute(hid_t obj, const std::string& name) {
  hid_t attr = check_id(H5Aopen(obj, name.c_str(), H5P_DEFAULT), "open attribute " + name);
  double v = 0;
  check(H5Aread(attr, H5T_NATIVE_DOUBLE, &v), "read attribute " + name);
  H5Aclose(attr);
  return v;
}

long long read_int_attribute(hid_t obj, const std::string& name) {
  hid_t attr = check_id(H5Aopen(obj, name.c_str(), H5P_DEFAULT), "open attribute " + name);
  long long v = 0;
  check(H5Aread(attr, H5T_NATIVE_LLONG, &v), "read attribute " + name);
  H5Aclose(attr);
  return v;
}

}  // namespace biota::io::h5
