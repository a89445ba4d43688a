#include "linalg/cell_multigrid.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "linalg/petsc_check.hpp"

namespace biota::linalg {
namespace {
int ceil_half(int v) {
  return (v + 1) / 2;
}

/// Centre of coarse cell c in fine-cell units (fine cell i spans [i, i+1)).
double coarse_centre(int c, int n) {
  return 0.5 * (2 * c + std::min(2 * c + 2, n));
}

/// Global PETSc index of cell `g` on a level: ranks x fastest, each rank's block contiguous and x
/// fastest inside.
struct LevelNumbering {
  const CellLevel* level;
  core::Index3 dims;
  std::vector<PetscInt> offset;  // first index of every PETSc rank

  LevelNumbering(const CellLevel& l, const core::Index3& P) : level(&l), dims(P) {
    offset.assign(static_cast<std::size_t>(P.product()) + 1, 0);
    std::size_t r = 0;
    for (int pz = 0; pz < P.z; ++pz)
      for (int py = 0; py < P.y; ++py)
        for (int px = 0; px < P.x; ++px, ++r)
          offset[r + 1] = offset[r] + PetscInt(extent(0, px)) * extent(1, py) * extent(2, pz);
  }
  int extent(int a, int p) const { return level->starts[a][p + 1] - level->starts[a][p]; }
  PetscInt index(const core::Index3& g) const {
    int p[3], loc[3];
    for (int a = 0; a < 3; ++a) {
      const auto& s = level->starts[a];
      p[a] = static_cast<int>(std::upper_bound(s.begin(), s.end(), g[a]) - s.begin()) - 1;
      loc[a] = g[a] - s[p[a]];
    }
    const std::size_t r = p[0] + dims.x * (p[1] + std::size_t(dims.y) * p[2]);
    return offset[r] + loc[0] +
           PetscInt(extent(0, p[0])) * (loc[1] + PetscInt(extent(1, p[1])) * loc[2]);
  }
};
}  // namespace

std::vector<CellLevel> cell_levels(const CellLevel& fine, int max_levels,
                                   long long max_coarse_cells) {
  std::vector<CellLevel> levels{fine};
  while (static_cast<int>(levels.size()) < max_levels &&
         levels.back().cells.product() > max_coarse_cells) {
    const CellLevel& f = levels.back();
    CellLevel c = f;
    bool any = false;
    for (int a = 0; a < 3; ++a) {
      if (f.cells[a] <= 2) continue;
      std::vector<int> s(f.starts[a].size());
      // Every fine block at least two cells thick (the restriction reads two ghost layers, from
      // the next block only), and every coarse block non-empty.
      bool nonempty = true;
      for (std::size_t p = 0; p < s.size(); ++p) s[p] = ceil_half(f.starts[a][p]);
      for (std::size_t p = 0; p + 1 < s.size(); ++p)
        nonempty &= s[p + 1] > s[p] && f.starts[a][p + 1] - f.starts[a][p] >= 2;
      if (!nonempty) continue;
      c.cells[a] = ceil_half(f.cells[a]);
      c.starts[a] = std::move(s);
      any = true;
    }
    if (!any) break;
    levels.push_back(std::move(c));
  }
  return levels;
}

Weights1D interpolation_weights(int i, int n, int nc, PressureBC lo, PressureBC hi) {
  Weights1D w;
  if (nc == n) {  // axis not coarsened
    w.count = 1;
    w.index[0] = i;
    w.weight[0] = 1;
    return w;
  }
  const int c = i / 2;
  const double xf = i + 0.5, xc = coarse_centre(c, n);
  w.index[0] = c;
  if (xf == xc) {  // the only fine cell of a one-cell coarse cell
    w.count = 1;
    w.weight[0] = 1;
    return w;
  }
  const int side = xf > xc ? 1 : -1;
  int c2 = c + side;
  double x2;
  if (c2 >= 0 && c2 < nc) {
    x2 = coarse_centre(c2, n);
  } else {
    const PressureBC bc = side < 0 ? lo : hi;
    if (bc == PressureBC::kNeumann) {  // mirror image: the neighbour equals the cell
      w.count = 1;
      w.weight[0] = 1;
      return w;
    }
    if (bc == PressureBC::kDirichlet) {  // linear to p = 0 on the face
      const double xface = side < 0 ? 0.0 : n;
      w.count = 1;
      w.weight[0] = (xf - xface) / (xc - xface);
      return w;
    }
    c2 = side < 0 ? nc - 1 : 0;  // periodic image
    x2 = coarse_centre(c2, n) + (side < 0 ? -n : n);
  }
  const double t = (xf - xc) / (x2 - xc);
  w.count = 2;
  w.weight[0] = 1 - t;
  w.index[1] = c2;
  w.weight[1] = t;
  return w;
}

int setup_cell_multigrid(PC pc, MPI_Comm comm, const CellLevel& fine, const core::Index3& dims,
                         const core::Index3& coords, const PressureBCs& bcs, int max_levels) {
  // Coarsest level: a few hundred cells, solved exactly (SVD) on every rank.
  const auto levels = cell_levels(fine, max_levels, 512);
  const int nl = static_cast<int>(levels.size());
  BIOTA_PETSC(PCSetType(pc, PCMG));
  BIOTA_PETSC(PCMGSetLevels(pc, nl, nullptr));
  BIOTA_PETSC(PCMGSetGalerkin(pc, PC_MG_GALERKIN_BOTH));
  for (int l = 0; l + 1 < nl; ++l) {
    const CellLevel &f = levels[l], &c = levels[l + 1];
    const LevelNumbering nf(f, dims), ncn(c, dims);
    core::Index3 flo, fn, cn;
    for (int a = 0; a < 3; ++a) {
      flo[a] = f.starts[a][coords[a]];
      fn[a] = f.starts[a][coords[a] + 1] - flo[a];
      cn[a] = c.starts[a][coords[a] + 1] - c.starts[a][coords[a]];
    }
    Mat P;
    BIOTA_PETSC(MatCreateAIJ(comm, fn.product(), cn.product(), PETSC_DETERMINE, PETSC_DETERMINE, 8,
                             nullptr, 8, nullptr, &P));
    std::array<std::vector<Weights1D>, 3> w;
    for (int a = 0; a < 3; ++a)
      for (int i = 0; i < fn[a]; ++i)
        w[a].push_back(
            interpolation_weights(flo[a] + i, f.cells[a], c.cells[a], bcs[a][0], bcs[a][1]));
    for (int k = 0; k < fn.z; ++k)
      for (int j = 0; j < fn.y; ++j)
        for (int i = 0; i < fn.x; ++i) {
          const PetscInt row = nf.index({flo.x + i, flo.y + j, flo.z + k});
          PetscInt cols[8];
          PetscScalar vals[8];
          int m = 0;
          const Weights1D &wx = w[0][i], &wy = w[1][j], &wz = w[2][k];
          for (int c2 = 0; c2 < wz.count; ++c2)
            for (int c1 = 0; c1 < wy.count; ++c1)
              for (int c0 = 0; c0 < wx.count; ++c0) {
                cols[m] = ncn.index({wx.index[c0], wy.index[c1], wz.index[c2]});
                vals[m++] = wx.weight[c0] * wy.weight[c1] * wz.weight[c2];
              }
          // ADD: a periodic axis of two coarse cells can name the same cell twice.
          BIOTA_PETSC(MatSetValues(P, 1, &row, m, cols, vals, ADD_VALUES));
        }
    BIOTA_PETSC(MatAssemblyBegin(P, MAT_FINAL_ASSEMBLY));
    BIOTA_PETSC(MatAssemblyEnd(P, MAT_FINAL_ASSEMBLY));
    // PCMG numbers levels from the coarsest (0); P maps level nl-2-l to nl-1-l.
    BIOTA_PETSC(PCMGSetInterpolation(pc, nl - 1 - l, P));
    BIOTA_PETSC(MatDestroy(&P));
  }
  // Defaults; -poisson_mg_levels_* and -poisson_mg_coarse_* options override them.
  for (int l = 1; l < nl; ++l) {
    KSP smoother;
    PC spc;
    BIOTA_PETSC(PCMGGetSmoother(pc, l, &smoother));
    BIOTA_PETSC(KSPSetType(smoother, KSPCHEBYSHEV));
    BIOTA_PETSC(KSPGetPC(smoother, &spc));
    BIOTA_PETSC(PCSetType(spc, PCJACOBI));
    BIOTA_PETSC(KSPSetTolerances(smoother, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT, 2));
  }
  KSP coarse;
  PC cpc;
  BIOTA_PETSC(PCMGGetCoarseSolve(pc, &coarse));
  BIOTA_PETSC(KSPSetType(coarse, KSPPREONLY));
  BIOTA_PETSC(KSPGetPC(coarse, &cpc));
  BIOTA_PETSC(PCSetType(cpc, PCREDUNDANT));
  {
    KSP inner;
    PC ipc;
    BIOTA_PETSC(PCRedundantGetKSP(cpc, &inner));
    BIOTA_PETSC(KSPGetPC(inner, &ipc));
    BIOTA_PETSC(PCSetType(ipc, PCSVD));
  }
  return nl;
}

}  // namespace biota::linalg
