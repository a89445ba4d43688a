#include "grid/decomposition.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace biota::grid {

Decomposition::Decomposition(MPI_Comm comm, Index3 global_cells, std::array<bool, 3> periodic,
                             Index3 dims)
    : global_(global_cells), dims_(dims), periodic_(periodic) {
  int size = 0;
  MPI_Comm_size(comm, &size);
  int d[3] = {dims.x, dims.y, dims.z};
  MPI_Dims_create(size, 3, d);
  dims_ = {d[0], d[1], d[2]};
  for (int a = 0; a < 3; ++a)
    if (dims_[a] > global_[a])
      throw std::invalid_argument("decomposition: " + std::to_string(dims_[a]) +
                                  " ranks along axis " + std::to_string(a) + " but only " +
                                  std::to_string(global_[a]) + " cells");
  int per[3] = {periodic[0], periodic[1], periodic[2]};
  // reorder = 0: the rank order of the input communicator is kept, so rank 0 stays rank 0.
  MPI_Cart_create(comm, 3, d, per, 0, &cart_);
  MPI_Comm_rank(cart_, &rank_);
  MPI_Comm_size(cart_, &size_);
  int c[3];
  MPI_Cart_coords(cart_, rank_, 3, c);
  coords_ = {c[0], c[1], c[2]};
  box_ = box_of(coords_);
  for (int a = 0; a < 3; ++a) MPI_Cart_shift(cart_, a, 1, &neighbors_[a][0], &neighbors_[a][1]);
}

Decomposition::~Decomposition() {
  if (cart_ != MPI_COMM_NULL) {
    int finalized = 0;
    MPI_Finalized(&finalized);
    if (!finalized) MPI_Comm_free(&cart_);
  }
}

Box Decomposition::box_of(const Index3& c) const {
  Box b;
  for (int a = 0; a < 3; ++a) {
    b.lo[a] = block_start(global_[a], dims_[a], c[a]);
    b.hi[a] = block_start(global_[a], dims_[a], c[a] + 1);
  }
  return b;
}

Index3 Decomposition::wrap(Index3 c) const {
  for (int a = 0; a < 3; ++a)
    if (periodic_[a]) c[a] = ((c[a] % global_[a]) + global_[a]) % global_[a];
  return c;
}

int Decomposition::owner_of_cell(Index3 cell) const {
  cell = wrap(cell);
  int c[3];
  for (int a = 0; a < 3; ++a) {
    int i = cell[a] < 0 ? 0 : (cell[a] >= global_[a] ? global_[a] - 1 : cell[a]);
    // Invert block_start: blocks of size base+1 first, then base.
    const int base = global_[a] / dims_[a], rem = global_[a] % dims_[a];
    const int big = rem * (base + 1);
    c[a] = i < big ? i / (base + 1) : rem + (i - big) / base;
  }
  int r = 0;
  MPI_Cart_rank(cart_, c, &r);
  return r;
}

int Decomposition::owner_of_point(const core::Vec3& p) const {
  return owner_of_cell({static_cast<int>(std::floor(p.x)), static_cast<int>(std::floor(p.y)),
                        static_cast<int>(std::floor(p.z))});
}

}  // namespace biota::grid
