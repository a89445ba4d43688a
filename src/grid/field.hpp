#pragma once
/// \file field.hpp
/// \brief Ghosted, multi-component cell field in structure-of-arrays layout.
#include <cstddef>
#include <memory>
#include <new>
#include <span>
#include <vector>

#include "core/types.hpp"

namespace biota::grid {

using core::Index3;

/// \brief madvise(MADV_HUGEPAGE) on a block (a hint: ignored where THP is off or unsupported).
void advise_huge_pages(void* p, std::size_t bytes);

/// \brief 64-byte aligned allocator so component planes start on cache lines (vector loads).
/// Blocks of 8 MiB and more (LBM populations, force and macroscopic fields) are 2 MiB aligned and
/// advised as transparent huge pages: the sweep walks 19-38 streams of such a block at once, and
/// with 4 KiB pages (THP is `madvise` on Debian) each stream crosses a page every 512 doubles.
template <class T>
struct AlignedAllocator {
  using value_type = T;
  static constexpr std::size_t kHugeFrom = std::size_t{8} << 20, kHugePage = std::size_t{2} << 20;
  AlignedAllocator() = default;
  template <class U>
  AlignedAllocator(const AlignedAllocator<U>&) {}
  static std::align_val_t alignment(std::size_t n) {
    return std::align_val_t{n * sizeof(T) >= kHugeFrom ? kHugePage : 64};
  }
  T* allocate(std::size_t n) {
    void* p = ::operator new(n * sizeof(T), alignment(n));
    if (n * sizeof(T) >= kHugeFrom) advise_huge_pages(p, n * sizeof(T));
    return static_cast<T*>(p);
  }
  void deallocate(T* p, std::size_t n) { ::operator delete(p, alignment(n)); }
  template <class U>
  bool operator==(const AlignedAllocator<U>&) const {
    return true;
  }
};

/// \brief `ncomp` components over a local block of `cells` with `ghosts` layers on every side.
///
/// Layout: component-major (SoA), then z, y, x with x fastest. Local indices run from -ghosts to
/// cells+ghosts-1 on each axis; 0..cells-1 are the owned cells.
template <class T>
class Field {
 public:
  Field() = default;
  Field(Index3 cells, int ncomp, int ghosts, T init = T{})
      : cells_(cells), ncomp_(ncomp), ghosts_(ghosts) {
    sx_ = cells.x + 2 * ghosts;
    sy_ = cells.y + 2 * ghosts;
    sz_ = cells.z + 2 * ghosts;
    // Pad each component plane to a multiple of 8 values to keep planes 64-byte aligned.
    plane_ = (static_cast<std::size_t>(sx_) * sy_ * sz_ + 7) / 8 * 8;
    data_.assign(plane_ * ncomp, init);
  }

  const Index3& cells() const { return cells_; }
  int ncomp() const { return ncomp_; }
  int ghosts() const { return ghosts_; }
  /// \brief Strides of the linear index in y and z (x stride is 1).
  std::ptrdiff_t stride_y() const { return sx_; }
  std::ptrdiff_t stride_z() const { return static_cast<std::ptrdiff_t>(sx_) * sy_; }
  std::size_t plane_size() const { return plane_; }

  /// \brief Linear index of local cell (i, j, k) within one component plane.
  std::ptrdiff_t index(int i, int j, int k) const {
    return (static_cast<std::ptrdiff_t>(k + ghosts_) * sy_ + (j + ghosts_)) * sx_ + (i + ghosts_);
  }
  T& operator()(int i, int j, int k, int c = 0) { return data_[c * plane_ + index(i, j, k)]; }
  const T& operator()(int i, int j, int k, int c = 0) const {
    return data_[c * plane_ + index(i, j, k)];
  }
  T* component(int c) { return data_.data() + c * plane_; }
  const T* component(int c) const { return data_.data() + c * plane_; }
  T* data() { return data_.data(); }
  const T* data() const { return data_.data(); }
  void fill(T v) { std::fill(data_.begin(), data_.end(), v); }
  void swap(Field& o) noexcept {
    std::swap(cells_, o.cells_);
    std::swap(ncomp_, o.ncomp_);
    std::swap(ghosts_, o.ghosts_);
    std::swap(sx_, o.sx_);
    std::swap(sy_, o.sy_);
    std::swap(sz_, o.sz_);
    std::swap(plane_, o.plane_);
    data_.swap(o.data_);
  }

 private:
  Index3 cells_{};
  int ncomp_ = 0, ghosts_ = 0;
  int sx_ = 0, sy_ = 0, sz_ = 0;
  std::size_t plane_ = 0;
  std::vector<T, AlignedAllocator<T>> data_;
};

}  // namespace biota::grid
