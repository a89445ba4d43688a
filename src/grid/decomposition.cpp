#include "grid/decomposition.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "core/error.hpp"

namespace biota::grid {

namespace {

bool fits(const Index3& dims, const Index3& cells) {
  return dims.x <= cells.x && dims.y <= cells.y && dims.z <= cells.z;
}

// The rank grid with the fewest cut faces among those that fit the cells and keep the given
// (non-zero) dims; {0, 0, 0} if none fits.
Index3 compact_fitting_dims(int size, const Index3& cells, const Index3& given) {
  Index3 best{0, 0, 0};
  double best_cut = 0;
  for (int a = 1; a <= size; ++a) {
    if (size % a) continue;
    for (int b = 1; b <= size / a; ++b) {
      if ((size / a) % b) continue;
      const Index3 d{a, b, size / a / b};
      bool keeps = true;
      for (int k = 0; k < 3; ++k) keeps = keeps && (given[k] == 0 || given[k] == d[k]);
      if (!keeps || !fits(d, cells)) continue;
      const double cut = double(d.x - 1) * cells.y * cells.z + double(d.y - 1) * cells.x * cells.z +
                         double(d.z - 1) * cells.x * cells.y;
      if (best.x == 0 || cut < best_cut) best = d, best_cut = cut;
    }
  }
  return best;
}

// MPI_Dims_create's counts (non-increasing, x first) permuted over the axes the caller left free
// (zero in `given`) to the fewest cut faces. Ties keep the fewest ranks on z, then on x:
//  - z is the vertical (seaweed and trees rooted on the floor, settled spheres, the tank's
//    jet), so a horizontal cut balances the particle work a z cut would leave on the lowest rank;
//  - the fields are x-fastest, so an x cut packs one value per row while a y cut packs whole
//    contiguous rows (a 100^3 LBM split 2 x 1 x 1 spent 17% of its step in the halo).
// Never more cut faces than MPI's own order, which is one of the permutations.
Index3 prefer_row_cuts(const Index3& dims, const Index3& cells, const Index3& given) {
  auto cut = [&](const Index3& d) {
    return double(d.x - 1) * cells.y * cells.z + double(d.y - 1) * cells.x * cells.z +
           double(d.z - 1) * cells.x * cells.y;
  };
  auto better_tie = [](const Index3& a, const Index3& b) {
    return a.z != b.z ? a.z < b.z : a.x < b.x;
  };
  std::array<int, 3> perm{0, 1, 2};
  Index3 best = dims;
  do {
    Index3 d;
    bool keeps = true;
    for (int a = 0; a < 3; ++a) {
      d[a] = dims[perm[a]];
      keeps = keeps && (given[a] == 0 ? given[perm[a]] == 0 : perm[a] == a);
    }
    if (!keeps || !fits(d, cells)) continue;
    const double c = cut(d), b = cut(best);
    if (c < b || (c == b && better_tie(d, best))) best = d;
  } while (std::next_permutation(perm.begin(), perm.end()));
  return best;
}

}  // namespace

Index3 Decomposition::rank_grid(int size, Index3 cells, Index3 dims, const GridKeys& keys) {
  int d[3] = {dims.x, dims.y, dims.z};
  MPI_Dims_create(size, 3, d);
  const Index3 mpi{d[0], d[1], d[2]};
  if (fits(mpi, cells)) return prefer_row_cuts(mpi, cells, dims);
  // MPI_Dims_create ignores the cells (8 ranks on 64 x 64 x 1 gives 2 x 2 x 2).
  const Index3 alt = compact_fitting_dims(size, cells, dims);
  if (alt.x != 0) return alt;
  // Every rank reaches this with the same numbers; only rank 0 prints InputErrors.
  std::string names;
  for (int a = 0; a < 3; ++a)
    names +=
        (a ? ", " : "") + (keys.cells[a].empty() ? std::string("xyz").substr(a, 1) : keys.cells[a]);
  // One option for all three axes (a benchmark's --size): named once.
  if (!keys.cells[0].empty() && keys.cells[0] == keys.cells[1] && keys.cells[1] == keys.cells[2])
    names = keys.cells[0];
  throw core::InputError((keys.source.empty() ? std::string("decomposition") : keys.source) + ": " +
                         names + " = " + std::to_string(cells.x) + " x " + std::to_string(cells.y) +
                         " x " + std::to_string(cells.z) + " cells cannot be split over " +
                         std::to_string(size) + " MPI ranks (every rank grid of " +
                         std::to_string(size) + " ranks, e.g. " + std::to_string(mpi.x) + " x " +
                         std::to_string(mpi.y) + " x " + std::to_string(mpi.z) +
                         ", puts more ranks than cells on an axis); use fewer ranks or more cells");
}

Decomposition::Decomposition(MPI_Comm comm, Index3 global_cells, std::array<bool, 3> periodic,
                             Index3 dims, const GridKeys& keys,
                             const std::array<std::vector<int>, 3>& starts)
    : global_(global_cells), periodic_(periodic) {
  int size = 0;
  MPI_Comm_size(comm, &size);
  dims_ = rank_grid(size, global_, dims, keys);
  int d[3] = {dims_.x, dims_.y, dims_.z};
  int per[3] = {periodic[0], periodic[1], periodic[2]};
  // reorder = 0: the rank order of the input communicator is kept, so rank 0 stays rank 0.
  MPI_Cart_create(comm, 3, d, per, 0, &cart_);
  MPI_Comm_rank(cart_, &rank_);
  MPI_Comm_size(cart_, &size_);
  int c[3];
  MPI_Cart_coords(cart_, rank_, 3, c);
  coords_ = {c[0], c[1], c[2]};
  for (int a = 0; a < 3; ++a) {
    const auto& given = starts[a];
    bool ok = given.empty();
    if (!ok && static_cast<int>(given.size()) == dims_[a] + 1 && given.front() == 0 &&
        given.back() == global_[a]) {
      ok = true;
      for (int i = 0; i < dims_[a]; ++i) ok = ok && given[i] < given[i + 1];
    }
    if (!ok)
      throw std::logic_error("Decomposition: block starts along axis " + std::to_string(a) +
                             " do not fit the rank grid");
    if (given.empty())
      for (int i = 0; i <= dims_[a]; ++i)
        starts_[a].push_back(block_start(global_[a], dims_[a], i));
    else
      starts_[a] = given;
  }
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

std::vector<int> weighted_block_starts(const std::vector<double>& plane_weight, int parts,
                                       int min_cells) {
  return weighted_block_starts(plane_weight, std::vector<double>(parts, 1.0), min_cells);
}

std::vector<int> weighted_block_starts(const std::vector<double>& plane_weight,
                                       const std::vector<double>& capacity, int min_cells) {
  const int n = static_cast<int>(plane_weight.size());
  const int parts = static_cast<int>(capacity.size());
  min_cells = std::clamp(min_cells, 1, std::max(1, n / parts));
  std::vector<double> prefix(n + 1, 0.0);
  for (int k = 0; k < n; ++k) prefix[k + 1] = prefix[k] + plane_weight[k];
  double total_capacity = 0;
  for (double c : capacity) total_capacity += c;
  std::vector<int> starts(parts + 1, 0);
  starts[parts] = n;
  double capacity_before = 0;  // of the blocks before cut i
  for (int i = 1; i < parts; ++i) {
    capacity_before += capacity[i - 1];
    const double share = prefix[n] * capacity_before / total_capacity;
    int k =
        static_cast<int>(std::lower_bound(prefix.begin(), prefix.end(), share) - prefix.begin());
    // Room for the blocks before (at least min_cells each) and after.
    starts[i] = std::clamp(k, starts[i - 1] + min_cells, n - (parts - i) * min_cells);
  }
  return starts;
}

std::array<std::vector<double>, 3> block_capacities(const Index3& dims,
                                                    const std::vector<double>& rank_speed) {
  std::array<std::vector<double>, 3> capacity;
  for (int a = 0; a < 3; ++a)
    if (dims[a] > 1) capacity[a].assign(dims[a], std::numeric_limits<double>::infinity());
  for (int r = 0; r < static_cast<int>(rank_speed.size()); ++r) {
    // MPI_Cart_create without reorder numbers ranks row-major (the last axis fastest).
    const int c[3] = {r / (dims.y * dims.z), (r / dims.z) % dims.y, r % dims.z};
    for (int a = 0; a < 3; ++a)
      if (!capacity[a].empty()) capacity[a][c[a]] = std::min(capacity[a][c[a]], rank_speed[r]);
  }
  return capacity;
}

std::array<std::vector<int>, 3> balanced_block_starts(
    const Index3& dims, const Index3& cells, const std::array<std::vector<double>, 3>& plane_weight,
    const std::vector<double>& rank_speed, int min_cells) {
  const auto capacity = block_capacities(
      dims, rank_speed.empty() ? std::vector<double>(dims.product(), 1.0) : rank_speed);
  std::array<std::vector<int>, 3> starts;
  for (int a = 0; a < 3; ++a)
    if (dims[a] > 1)
      starts[a] = weighted_block_starts(
          plane_weight[a].empty() ? std::vector<double>(cells[a], 1.0) : plane_weight[a],
          capacity[a], std::max(min_cells, cells[a] / dims[a] / 2));
  return starts;
}

Box Decomposition::box_of(const Index3& c) const {
  Box b;
  for (int a = 0; a < 3; ++a) {
    b.lo[a] = starts_[a][c[a]];
    b.hi[a] = starts_[a][c[a] + 1];
  }
  return b;
}

int Decomposition::block_start_of(int axis, int index) const {
  return starts_[axis][index];
}

int Decomposition::block_of(int axis, int cell) const {
  const auto& s = starts_[axis];
  const int i = std::clamp(cell, 0, global_[axis] - 1);
  return static_cast<int>(std::upper_bound(s.begin(), s.end(), i) - s.begin()) - 1;
}

int Decomposition::thinnest(int axis) const {
  int t = global_[axis];
  for (int i = 0; i < dims_[axis]; ++i) t = std::min(t, starts_[axis][i + 1] - starts_[axis][i]);
  return t;
}

int Decomposition::widest(int axis) const {
  int w = 0;
  for (int i = 0; i < dims_[axis]; ++i) w = std::max(w, starts_[axis][i + 1] - starts_[axis][i]);
  return w;
}

Index3 Decomposition::wrap(Index3 c) const {
  for (int a = 0; a < 3; ++a)
    if (periodic_[a]) c[a] = ((c[a] % global_[a]) + global_[a]) % global_[a];
  return c;
}

int Decomposition::owner_of_cell(Index3 cell) const {
  cell = wrap(cell);
  int c[3];
  for (int a = 0; a < 3; ++a) c[a] = block_of(a, cell[a]);
  int r = 0;
  MPI_Cart_rank(cart_, c, &r);
  return r;
}

int Decomposition::owner_of_point(const core::Vec3& p) const {
  return owner_of_cell({static_cast<int>(std::floor(p.x)), static_cast<int>(std::floor(p.y)),
                        static_cast<int>(std::floor(p.z))});
}

}  // namespace biota::grid
