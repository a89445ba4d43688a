#pragma once
/// \file write_file.hpp
/// \brief The files an output or checkpoint step writes, with one error path for all ranks.
///
/// A full disk is the failure users meet. A parallel HDF5 write that runs out of space in the
/// middle cannot be recovered cleanly: ROMIO returns the error on some ranks while the others
/// wait in the collective write, and a file whose close failed is flushed again by HDF5 inside
/// MPI_Finalize, which crashed in ROMIO (docs/robustness.md). So the space is checked before
/// each dataset and each set of VTK pieces, collectively: when it is short, every rank stops
/// with one message, the partial HDF5 file is closed cleanly and removed, and no rank is left
/// in a collective. Index files (.xmf, .pvti, .pvtp, .pvd) are written through a .tmp, checked,
/// then renamed, so a failure never replaces a good one with a torn one.
#include <hdf5.h>
#include <mpi.h>

#include <exception>
#include <functional>
#include <string>
#include <vector>

#include "core/agreement.hpp"

class vtkXMLWriter;

namespace biota::io {

/// \brief Collective: throws std::runtime_error on every rank unless the file system holding
/// `path` has `bytes` (plus a margin for HDF5 metadata) free, as rank 0 sees it. `what` names
/// the step ("output", "checkpoint") and `target` the data in the message. Test hook:
/// BIOTA_TEST_FAIL=disk_full@0 makes rank 0 see no free space.
void require_free_space(MPI_Comm comm, const std::string& path, double bytes,
                        const std::string& what, const std::string& target);

/// \brief A parallel HDF5 file created (truncated) by every rank of `comm`.
class WriteFile {
 public:
  /// `what` names the step in messages: "output" or "checkpoint".
  WriteFile(std::string path, MPI_Comm comm, std::string what);
  /// Not closed: closed and removed, unless an exception that was not agreed is unwinding on
  /// this rank (H5Fclose is collective and the other ranks may never come: leaked).
  ~WriteFile();
  WriteFile(const WriteFile&) = delete;
  WriteFile& operator=(const WriteFile&) = delete;

  hid_t id() const { return file_; }

  /// \brief Collective write of a global dataset (h5::write_block) after require_free_space
  /// for it; if the space is short every rank closes the file, rank 0 removes it, and every rank
  /// throws.
  void write_block(const std::string& name, const std::vector<hsize_t>& global,
                   const std::vector<hsize_t>& offset, const std::vector<hsize_t>& count,
                   const double* data, hid_t type = H5T_NATIVE_DOUBLE,
                   const std::vector<hsize_t>& chunk = {}, int deflate = 0);
  /// \brief The same for a dataset written slab by slab along its first dimension, every rank
  /// writing every slab (`offset[0]` = 0, `count[0]` = `global[0]`): `fill(s, slab)` puts this
  /// rank's block of slab s (the product of count[1..] values, C order) into one buffer reused
  /// for every slab. The memory taken is one slab's, not the dataset's (a checkpoint of a large
  /// grid would otherwise copy the populations whole).
  void write_slabs(const std::string& name, const std::vector<hsize_t>& global,
                   const std::vector<hsize_t>& offset, const std::vector<hsize_t>& count,
                   const std::function<void(int, double*)>& fill);
  /// \brief Collective close; if it failed on any rank the file is removed and every rank
  /// throws. Returns the file's size in bytes (every rank).
  double close();

 private:
  void discard();  // collective: close if open; rank 0 removes the file
  // require_free_space for dataset `name`; if short, discard and throw (every rank).
  void require_space_for(const std::string& name, const std::vector<hsize_t>& global, hid_t type,
                         const std::vector<hsize_t>& chunk);

  std::string path_, what_;
  MPI_Comm comm_;
  int rank_ = 0;
  hid_t file_ = -1;
  core::UnwindGuard unwind_;
};

/// \brief Write `content` to `path` through `path`.tmp (checked, then renamed over `path`); throws
/// std::runtime_error naming the file and the free space if it cannot. One rank.
void write_text_file(const std::string& path, const std::string& content);

/// \brief Write the input of a VTK XML writer to `path`: appended raw binary, 64-bit headers and
/// ids, zlib at `compression` (1-9; 0: none, not VTK's default zlib). If it fails, remove what it
/// wrote and throw std::runtime_error naming the file and the free space. One rank.
void write_vtk_checked(vtkXMLWriter& writer, const std::string& path, int compression);

/// \brief Collective: throws on every rank, with the message of the lowest rank whose `error` is
/// set, if any rank's is.
void agree_on_error(MPI_Comm comm, std::exception_ptr error);

/// \brief Collective: runs `fn` on the ranks where `here` is true; if it threw on any rank, every
/// rank throws the lowest failing rank's message. For the files each rank or rank 0 writes alone
/// (VTK pieces, index files), which hold no collective.
template <class F>
void run_agreed(MPI_Comm comm, bool here, F&& fn) {
  std::exception_ptr error;
  if (here) {
    try {
      fn();
    } catch (...) {
      error = std::current_exception();
    }
  }
  agree_on_error(comm, error);
}

}  // namespace biota::io
