#include "linalg/geometric_multigrid.hpp"

#include <petscsys.h>
// After petscsys.h, which it needs.
#include <petscblaslapack.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "linalg/block_halo.hpp"
#include "linalg/cell_multigrid.hpp"
#include "linalg/multigrid_level.hpp"

namespace biota::linalg {
using multigrid::Level;
namespace {
// The coarsest level is solved densely on every rank.
constexpr long long kMaxCoarseCells = 512;
// Above this many cells (the blocks of many ranks stop the coarsening early) the dense
// pseudo-inverse would cost too much; the coarsest level is then smoothed instead.
constexpr long long kMaxDenseCells = 1000;
constexpr int kCoarseSweeps = 20;

int floor_div(int a, int b) {
  return a >= 0 ? a / b : -((-a + b - 1) / b);
}

/// Centre of coarse cell c in units of the fine level's cells (fine cell i spans [i, i+1)).
double coarse_centre(int c, int n) {
  return 0.5 * (2 * c + std::min(2 * c + 2, n));
}

struct Weight {
  int index = 0;  // local cell index on the other level (ghosts -1 and n allowed)
  double w = 0;
};

/// 1D linear interpolation of fine cell `gf` (global; outside [0, nf) only on a periodic axis)
/// from the coarse cell centres, with the pressure condition at a box face (as
/// linalg::interpolation_weights, but with unwrapped coarse indices, so a periodic image keeps
/// its side). Returns the count of (coarse global index, weight) pairs written.
int interpolate_1d(int gf, int nf, int nc, PressureBC lo, PressureBC hi, bool periodic,
                   int index[2], double weight[2]) {
  if (nc == nf) {  // axis not coarsened
    index[0] = gf;
    weight[0] = 1;
    return 1;
  }
  const int shift = periodic ? floor_div(gf, nf) : 0;
  const int g = gf - shift * nf;
  const int c = g / 2;
  const double xf = g + 0.5, xc = coarse_centre(c, nf);
  int count = 1;
  index[0] = c;
  weight[0] = 1;
  if (xf != xc) {  // else: the only fine cell of a one-cell coarse cell
    const int side = xf > xc ? 1 : -1;
    const int c2 = c + side;
    double x2 = 0;
    bool two = true;
    if (c2 >= 0 && c2 < nc) {
      x2 = coarse_centre(c2, nf);
    } else if (periodic) {
      x2 = coarse_centre(side < 0 ? nc - 1 : 0, nf) + (side < 0 ? -nf : nf);
    } else {
      two = false;
      if ((side < 0 ? lo : hi) == PressureBC::kDirichlet) {  // linear to p = 0 on the face
        const double xface = side < 0 ? 0.0 : nf;
        weight[0] = (xf - xface) / (xc - xface);
      }  // Neumann: the mirror image equals the cell
    }
    if (two) {
      const double t = (xf - xc) / (x2 - xc);
      weight[0] = 1 - t;
      index[1] = c2;
      weight[1] = t;
      count = 2;
    }
  }
  for (int m = 0; m < count; ++m) index[m] += shift * nc;
  return count;
}

}  // namespace

struct GeometricMultigrid::Impl {
  MPI_Comm comm = MPI_COMM_NULL;
  std::vector<Level> L;
  PressureBCs bcs{};
  int sweeps = 1;
  double omega = 1;  // over-relaxation of the red-black sweeps
  // Coarsest level: owned rows of the dense pseudo-inverse, global vector buffer.
  std::vector<double> pinv_rows, coarse_global;
  std::vector<int> coarse_owned_global;  // global index of each owned coarsest cell
  bool hierarchy_of_one_rank = true;     // the levels' cell counts are those of one rank

  void build_fine(const std::vector<char>& solid);
  void build_coarse(int l);
  void build_transfers(int l);
  void finish_operator(Level& v);
  void build_coarse_solve();
  void coarse_solve(Level& v);
  void vcycle(int l);
};

namespace {
std::array<std::array<int, 2>, 3> neighbours(MPI_Comm comm, const core::Index3& coords,
                                             const core::Index3& dims,
                                             const std::array<bool, 3>& periodic) {
  std::array<std::array<int, 2>, 3> nb{};
  for (int a = 0; a < 3; ++a)
    for (int s = 0; s < 2; ++s) {
      int c[3] = {coords.x, coords.y, coords.z};
      c[a] += s ? 1 : -1;
      if (c[a] < 0 || c[a] >= dims[a]) {
        if (!periodic[a]) {
          nb[a][s] = MPI_PROC_NULL;
          continue;
        }
        c[a] = (c[a] + dims[a]) % dims[a];
      }
      MPI_Cart_rank(comm, c, &nb[a][s]);
    }
  return nb;
}
}  // namespace

GeometricMultigrid::GeometricMultigrid(MPI_Comm comm, const core::Index3& cells,
                                       const std::array<std::vector<int>, 3>& starts,
                                       const core::Index3& coords, const PressureBCs& bcs,
                                       const std::vector<char>& solid_ghosted, int sweeps,
                                       double omega, int max_levels)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.comm = comm;
  m.bcs = bcs;
  m.sweeps = std::max(1, sweeps);
  m.omega = omega;
  CellLevel fine;
  fine.cells = cells;
  fine.starts = starts;
  const auto shapes = cell_levels(fine, std::max(1, max_levels), kMaxCoarseCells);
  CellLevel whole;  // the grid as one rank's block
  whole.cells = cells;
  for (int a = 0; a < 3; ++a) whole.starts[a] = {0, cells[a]};
  const auto one_rank = cell_levels(whole, std::max(1, max_levels), kMaxCoarseCells);
  m.hierarchy_of_one_rank = one_rank.size() == shapes.size();
  for (std::size_t l = 0; m.hierarchy_of_one_rank && l < shapes.size(); ++l)
    m.hierarchy_of_one_rank = one_rank[l].cells == shapes[l].cells;
  int dims_arr[3], periods[3], cc[3];
  MPI_Cart_get(comm, 3, dims_arr, periods, cc);
  const core::Index3 dims{dims_arr[0], dims_arr[1], dims_arr[2]};
  m.L.resize(shapes.size());
  for (std::size_t l = 0; l < shapes.size(); ++l) {
    Level& v = m.L[l];
    v.N = shapes[l].cells;
    for (int a = 0; a < 3; ++a) {
      v.lo[a] = shapes[l].starts[a][coords[a]];
      v.n[a] = shapes[l].starts[a][coords[a] + 1] - v.lo[a];
      v.periodic[a] = bcs[a][0] == PressureBC::kPeriodic && v.N[a] > 1;
    }
    v.blk = GhostedBlock(v.n);
    for (auto* a : {&v.diag, &v.inv_diag, &v.x, &v.b, &v.r}) a->assign(v.blk.size, 0.0);
    for (auto& c : v.coef) c.assign(v.blk.size, 0.0);
    v.halo = std::make_unique<BlockHalo>(comm, v.blk, neighbours(comm, coords, dims, v.periodic));
    if (l + 1 < shapes.size()) {  // a level that restricts (every block is >= 2 cells thick)
      v.wide = GhostedBlock(v.n, 2);
      v.r_wide.assign(v.wide.size, 0.0);
      v.wide_halo =
          std::make_unique<BlockHalo>(comm, v.wide, neighbours(comm, coords, dims, v.periodic));
    }
    for (int a = 0; a < 3; ++a) {
      if (l == 0) {
        v.width[a].assign(v.N[a], 1.0);
      } else {
        const auto& wf = m.L[l - 1].width[a];
        const int nf = m.L[l - 1].N[a];
        v.width[a].resize(v.N[a]);
        for (int c = 0; c < v.N[a]; ++c)
          v.width[a][c] = v.N[a] == nf ? wf[c] : wf[2 * c] + (2 * c + 1 < nf ? wf[2 * c + 1] : 0);
      }
    }
  }
  m.build_fine(solid_ghosted);
  for (std::size_t l = 1; l < m.L.size(); ++l) {
    m.build_transfers(static_cast<int>(l) - 1);
    m.build_coarse(static_cast<int>(l));
  }
  m.build_coarse_solve();
}

GeometricMultigrid::~GeometricMultigrid() = default;

int GeometricMultigrid::levels() const {
  return static_cast<int>(impl_->L.size());
}

bool GeometricMultigrid::hierarchy_of_one_rank() const {
  return impl_->hierarchy_of_one_rank;
}

void GeometricMultigrid::Impl::finish_operator(Level& v) {
  for (auto& c : v.coef) v.halo->exchange(c);
  const auto& n = v.n;
  v.regular_cell.assign(v.blk.size, 0);
  v.regular_row.assign(std::size_t(n.y) * n.z, 0);
  for (int k = 0; k < n.z; ++k)
    for (int j = 0; j < n.y; ++j) {
      bool row_regular = true;
      for (int i = 0; i < n.x; ++i) {
        const auto q = v.blk.index(i, j, k);
        bool regular = true;
        for (int a = 0; a < 3; ++a)
          regular = regular && v.coef[a][q] == v.regular_coef[a] &&
                    v.coef[a][q - v.stride(a)] == v.regular_coef[a];
        v.regular_cell[q] = regular;
        if (i > 0 && i + 1 < n.x) row_regular = row_regular && regular;
      }
      v.regular_row[j + std::size_t(n.y) * k] = row_regular;
    }
  for (int k = 0; k < n.z; ++k)
    for (int j = 0; j < n.y; ++j)
      for (int i = 0; i < n.x; ++i) {
        const auto q = v.blk.index(i, j, k);
        double d = 0;
        for (int a = 0; a < 3; ++a) d += v.coef[a][q] + v.coef[a][q - v.stride(a)];
        v.diag[q] = d;
        v.inv_diag[q] = d > 0 ? 1.0 / d : 0.0;  // solid or closed cell: no correction
      }
}

void GeometricMultigrid::Impl::build_fine(const std::vector<char>& solid) {
  Level& v = L[0];
  auto fluid = [&](std::ptrdiff_t q) { return solid.empty() || !solid[q]; };
  v.solid = solid.empty() ? std::vector<char>(v.blk.size, 0) : solid;
  for (int k = 0; k < v.n.z; ++k)
    for (int j = 0; j < v.n.y; ++j)
      for (int i = 0; i < v.n.x; ++i) {
        const auto q = v.blk.index(i, j, k);
        const int loc[3] = {i, j, k};
        for (int a = 0; a < 3; ++a) {
          if (v.N[a] == 1) continue;
          const int g = v.lo[a] + loc[a];
          const auto s = v.stride(a);
          if (g + 1 == v.N[a] && !v.periodic[a])
            v.coef[a][q] = bcs[a][1] == PressureBC::kDirichlet && fluid(q) ? 2 : 0;
          else
            v.coef[a][q] = fluid(q) && fluid(q + s) ? 1 : 0;
          if (g == 0 && !v.periodic[a])  // the low box face, kept in the ghost cell's entry
            v.coef[a][q - s] = bcs[a][0] == PressureBC::kDirichlet && fluid(q) ? 2 : 0;
        }
      }
  finish_operator(v);
}

void GeometricMultigrid::Impl::build_coarse(int l) {
  const Level& f = L[l - 1];
  Level& v = L[l];
  for (int a = 0; a < 3; ++a) {  // interior face: summed over the transverse children
    double r = f.regular_coef[a] * (v.N[a] == f.N[a] ? 1.0 : 0.5);
    for (int b = 0; b < 3; ++b)
      if (b != a && v.N[b] != f.N[b]) r *= 2;
    v.regular_coef[a] = r;
  }
  // Fine children of a coarse global index along axis a (local fine indices).
  auto children = [&](int a, int gc, int out[2]) {
    if (v.N[a] == f.N[a]) {
      out[0] = gc - f.lo[a];
      return 1;
    }
    out[0] = 2 * gc - f.lo[a];
    if (2 * gc + 1 < f.N[a]) {
      out[1] = 2 * gc + 1 - f.lo[a];
      return 2;
    }
    return 1;
  };
  for (int k = 0; k < v.n.z; ++k)
    for (int j = 0; j < v.n.y; ++j)
      for (int i = 0; i < v.n.x; ++i) {
        const auto q = v.blk.index(i, j, k);
        const int g[3] = {v.lo.x + i, v.lo.y + j, v.lo.z + k};
        int ch[3][2], nch[3];
        for (int a = 0; a < 3; ++a) nch[a] = children(a, g[a], ch[a]);
        for (int a = 0; a < 3; ++a) {
          // Sum of the fine face coefficients on the coarse cell's high (and low box) face.
          auto face_sum = [&](int fine_along) {
            double s = 0;
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            for (int mb = 0; mb < nch[b]; ++mb)
              for (int mc = 0; mc < nch[c]; ++mc) {
                int fl[3];
                fl[a] = fine_along;
                fl[b] = ch[b][mb];
                fl[c] = ch[c][mc];
                s += f.coef[a][f.blk.index(fl[0], fl[1], fl[2])];
              }
            return s;
          };
          const int last = ch[a][nch[a] - 1], glast = f.lo[a] + last;
          v.coef[a][q] = face_sum(last) * f.high_distance(a, glast) / v.high_distance(a, g[a]);
          if (g[a] == 0 && !v.periodic[a] && v.N[a] > 1)
            v.coef[a][q - v.stride(a)] =
                face_sum(ch[a][0] - 1) * f.width[a][0] / v.width[a][0];  // half widths
        }
      }
  finish_operator(v);
}

void GeometricMultigrid::Impl::build_transfers(int l) {
  Level& f = L[l];
  const Level& c = L[l + 1];
  for (int a = 0; a < 3; ++a) {
    std::vector<std::vector<Weight>> prolong(f.n[a]), restrict_w(c.n[a]);
    for (int i = -2; i <= f.n[a] + 1; ++i) {
      const int gf = f.lo[a] + i;
      if ((gf < 0 || gf >= f.N[a]) && !f.periodic[a]) continue;
      int idx[2];
      double w[2];
      const int cnt =
          interpolate_1d(gf, f.N[a], c.N[a], bcs[a][0], bcs[a][1], f.periodic[a], idx, w);
      for (int m = 0; m < cnt; ++m) {
        const int lc = idx[m] - c.lo[a];
        if (i >= 0 && i < f.n[a]) {
          if (lc < -1 || lc > c.n[a])
            throw std::logic_error("GeometricMultigrid: interpolation reaches beyond the ghosts");
          prolong[i].push_back({lc, w[m]});
        }
        if (lc >= 0 && lc < c.n[a]) restrict_w[lc].push_back({i, w[m]});
      }
    }
    // Fixed counts (2 and 4) with zero weights, so the transfer loops have no inner branches.
    for (int m = 0; m < 2; ++m) {
      f.p_index[a][m].assign(f.n[a], 0);
      f.p_weight[a][m].assign(f.n[a], 0.0);
    }
    for (int i = 0; i < f.n[a]; ++i)
      for (std::size_t m = 0; m < prolong[i].size(); ++m) {
        f.p_index[a][m][i] = prolong[i][m].index;
        f.p_weight[a][m][i] = prolong[i][m].w;
      }
    for (int i = 0; i < f.n[a]; ++i)
      if (prolong[i].size() == 1) f.p_index[a][1][i] = prolong[i][0].index;
    for (int m = 0; m < 4; ++m) {
      f.r_index[a][m].assign(c.n[a], 0);
      f.r_weight[a][m].assign(c.n[a], 0.0);
    }
    for (int I = 0; I < c.n[a]; ++I) {
      if (restrict_w[I].size() > 4)
        throw std::logic_error("GeometricMultigrid: more than four fine cells restrict to one");
      for (std::size_t m = 0; m < 4; ++m) {
        const Weight& w = m < restrict_w[I].size() ? restrict_w[I][m] : restrict_w[I][0];
        f.r_index[a][m][I] = w.index;
        f.r_weight[a][m][I] = m < restrict_w[I].size() ? w.w : 0.0;
      }
    }
  }
  f.work_x.assign(std::size_t(c.n.x) * (f.n.y + 4) * (f.n.z + 4), 0.0);
  f.work_y.assign(std::size_t(c.n.x) * c.n.y * (f.n.z + 4), 0.0);
}

void GeometricMultigrid::Impl::build_coarse_solve() {
  Level& v = L.back();
  const core::Index3 N = v.N;
  const int total = N.product();
  if (total > kMaxDenseCells) return;  // smoothed instead (coarse_solve)
  std::vector<double> A(std::size_t(total) * total, 0.0);
  auto gindex = [&](int gi, int gj, int gk) { return gi + N.x * (gj + N.y * gk); };
  coarse_owned_global.clear();
  for (int k = 0; k < v.n.z; ++k)
    for (int j = 0; j < v.n.y; ++j)
      for (int i = 0; i < v.n.x; ++i) {
        const auto q = v.blk.index(i, j, k);
        const int g[3] = {v.lo.x + i, v.lo.y + j, v.lo.z + k};
        const int row = gindex(g[0], g[1], g[2]);
        coarse_owned_global.push_back(row);
        A[std::size_t(row) * total + row] += v.diag[q];
        for (int a = 0; a < 3; ++a)
          for (int s = 0; s < 2; ++s) {
            const double t = s ? v.coef[a][q] : v.coef[a][q - v.stride(a)];
            if (t == 0) continue;
            int h[3] = {g[0], g[1], g[2]};
            h[a] += s ? 1 : -1;
            if (h[a] < 0 || h[a] >= N[a]) {
              if (!v.periodic[a]) continue;  // Dirichlet face: in the diagonal only
              h[a] = (h[a] + N[a]) % N[a];
            }
            A[std::size_t(row) * total + gindex(h[0], h[1], h[2])] -= t;
          }
      }
  // Every row comes from its one owner, the other ranks add zeros: exact in any order, so the
  // same matrix (and pseudo-inverse) on any rank count.
  MPI_Allreduce(MPI_IN_PLACE, A.data(), static_cast<int>(A.size()), MPI_DOUBLE, MPI_SUM, comm);
  // Pseudo-inverse from the eigen-decomposition (LAPACK through PETSc): drops the constant null
  // vector of the Neumann problem and the empty rows of solid cells alike.
  std::vector<double> lambda(total);
  PetscBLASInt nn = total, lwork = -1, info = 0;
  double wq = 0;
  LAPACKsyev_("V", "U", &nn, A.data(), &nn, lambda.data(), &wq, &lwork, &info);
  lwork = static_cast<PetscBLASInt>(wq);
  std::vector<double> work(std::max<PetscBLASInt>(lwork, 1));
  LAPACKsyev_("V", "U", &nn, A.data(), &nn, lambda.data(), work.data(), &lwork, &info);
  if (info != 0) throw std::runtime_error("GeometricMultigrid: coarse eigen-decomposition failed");
  const double lmax = *std::max_element(lambda.begin(), lambda.end());
  // Column e of A (column-major) is eigenvector e.
  pinv_rows.assign(coarse_owned_global.size() * std::size_t(total), 0.0);
  for (int e = 0; e < total; ++e) {
    if (lambda[e] <= 1e-10 * lmax) continue;
    const double* ve = A.data() + std::size_t(e) * total;
    const double inv = 1.0 / lambda[e];
    for (std::size_t r = 0; r < coarse_owned_global.size(); ++r) {
      const double s = ve[coarse_owned_global[r]] * inv;
      double* row = pinv_rows.data() + r * total;
      for (int col = 0; col < total; ++col) row[col] += s * ve[col];
    }
  }
  coarse_global.assign(total, 0.0);
}

void GeometricMultigrid::Impl::coarse_solve(Level& v) {
  if (pinv_rows.empty()) {  // symmetric red-black sweeps from zero: still an SPD operator
    multigrid::smooth_from_zero(v, omega);
    for (int s = 0; s < kCoarseSweeps; ++s) {
      if (s > 0) {
        v.halo->exchange(v.x);
        multigrid::smooth(v, 0, omega);
      }
      v.halo->exchange(v.x);
      multigrid::smooth(v, 1, omega);
    }
    for (int s = 0; s < kCoarseSweeps; ++s) {
      v.halo->exchange(v.x);
      multigrid::smooth(v, 1, omega);
      v.halo->exchange(v.x);
      multigrid::smooth(v, 0, omega);
    }
    return;
  }
  std::fill(coarse_global.begin(), coarse_global.end(), 0.0);
  std::size_t r = 0;
  for (int k = 0; k < v.n.z; ++k)
    for (int j = 0; j < v.n.y; ++j)
      for (int i = 0; i < v.n.x; ++i, ++r)
        coarse_global[coarse_owned_global[r]] = v.b[v.blk.index(i, j, k)];
  MPI_Allreduce(MPI_IN_PLACE, coarse_global.data(), static_cast<int>(coarse_global.size()),
                MPI_DOUBLE, MPI_SUM, comm);  // one owner per entry, as A's rows: exact
  const std::size_t total = coarse_global.size();
  r = 0;
  for (int k = 0; k < v.n.z; ++k)
    for (int j = 0; j < v.n.y; ++j)
      for (int i = 0; i < v.n.x; ++i, ++r) {
        const double* row = pinv_rows.data() + r * total;
        double s = 0;
        for (std::size_t c = 0; c < total; ++c) s += row[c] * coarse_global[c];
        v.x[v.blk.index(i, j, k)] = s;
      }
}

void GeometricMultigrid::Impl::vcycle(int l) {
  Level& v = L[l];
  if (l + 1 == static_cast<int>(L.size())) {
    coarse_solve(v);
    return;
  }
  for (int s = 0; s < sweeps; ++s) {
    if (s > 0) {
      v.halo->exchange(v.x);
      multigrid::smooth(v, 0, omega);
    } else {
      multigrid::smooth_from_zero(v, omega);
    }
    v.halo->exchange(v.x);
    multigrid::smooth(v, 1, omega);
  }
  v.halo->exchange(v.x);
  multigrid::residual(v);
  v.wide_halo->exchange(v.r_wide);
  Level& c = L[l + 1];
  multigrid::restrict_to(v, c);
  vcycle(l + 1);
  c.halo->exchange(c.x);
  multigrid::prolong_add(c, v);
  for (int s = 0; s < sweeps; ++s) {  // the reverse order: the cycle stays symmetric
    v.halo->exchange(v.x);
    multigrid::smooth(v, 1, omega);
    v.halo->exchange(v.x);
    multigrid::smooth(v, 0, omega);
  }
}

void GeometricMultigrid::multiply(const double* x, double* y) {
  multigrid::multiply(impl_->L[0], x, y);
}

void GeometricMultigrid::apply(const double* r, double* z) {
  Impl& m = *impl_;
  Level& v = m.L[0];
  std::size_t p = 0;
  for (int k = 0; k < v.n.z; ++k)
    for (int j = 0; j < v.n.y; ++j)
      for (int i = 0; i < v.n.x; ++i, ++p) v.b[v.blk.index(i, j, k)] = r[p];
  m.vcycle(0);
  p = 0;
  for (int k = 0; k < v.n.z; ++k)
    for (int j = 0; j < v.n.y; ++j)
      for (int i = 0; i < v.n.x; ++i, ++p) z[p] = v.x[v.blk.index(i, j, k)];
}

}  // namespace biota::linalg
