/// \file lbm_boundaries.cpp
/// \brief LbmSolver's boundary links: built from the mask and the faces, compiled into index plans
/// per step parity (split into early and late links for the overlapped neighbour step), applied
/// before each sweep. See docs/lbm.md.
#include <algorithm>
#include <cmath>

#include "solvers/lbm/lbm_solver.hpp"

namespace biota::solvers::lbm {

void LbmSolver::build_links() {
  // Only the plans built from the links are kept (the links cost 40 B each, twice the plans').
  std::vector<Link> links;
  const Index3 n = decomp_.local_cells(), lo = decomp_.local_box().lo, N = decomp_.global_cells();
  auto outside_axes = [&](const Index3& gc, int& count, int& face) {
    count = 0;
    for (int a = 0; a < 3; ++a) {
      if (decomp_.periodic(a)) continue;
      if (gc[a] < 0) {
        ++count;
        face = 2 * a;
      }
      if (gc[a] >= N[a]) {
        ++count;
        face = 2 * a + 1;
      }
    }
  };
  auto is_fluid_local = [&](int i, int j, int k) {
    Index3 gc{lo.x + i, lo.y + j, lo.z + k};
    int cnt = 0, face = -1;
    outside_axes(gc, cnt, face);
    return cnt == 0 && !solid_[f_.index(i, j, k)];
  };
  // Tangential coordinates [m] of a fluid cell centre on face `face`.
  auto on_face = [&](int face, const Index3& gc, double& a, double& b) {
    const int axis = face / 2;
    const int t0 = axis == 0 ? 1 : 0, t1 = axis == 2 ? 1 : 2;
    a = (gc[t0] + 0.5) * params_.dx;
    b = (gc[t1] + 0.5) * params_.dx;
  };
  for (int k = 0; k < n.z; ++k)
    for (int j = 0; j < n.y; ++j)
      for (int i = 0; i < n.x; ++i) {
        if (solid_[f_.index(i, j, k)]) continue;
        const Index3 gx{lo.x + i, lo.y + j, lo.z + k};
        for (int q = 1; q < nq_; ++q) {
          const int si = i - c_[q][0], sj = j - c_[q][1], sk = k - c_[q][2];
          const Index3 gs{lo.x + si, lo.y + sj, lo.z + sk};
          int count = 0, face = -1;
          outside_axes(gs, count, face);
          Link l{f_.index(si, sj, sk), f_.index(i, j, k), 0, q, 0, int(FaceType::kWall), 0.0};
          if (count == 0) {
            if (!solid_[l.s]) continue;  // fluid neighbour: plain streaming
          } else if (count == 1) {
            FaceType t = params_.faces[face];
            double a = 0, b = 0;
            on_face(face, gx, a, b);
            const auto& in = params_.inlet;
            const auto& out = params_.outlet;
            if (in.face == face) {
              const double r2 =
                  (a - in.center[0]) * (a - in.center[0]) + (b - in.center[1]) * (b - in.center[1]);
              if (r2 <= in.radius * in.radius) {
                const double profile = in.parabolic ? 1.0 - r2 / (in.radius * in.radius) : 1.0;
                const int axis = face / 2;
                const double normal = (face % 2 == 0) ? 1.0 : -1.0;  // into the domain
                l.type = -1;
                l.coef = 6.0 * w_[q] * c_[q][axis] * normal * profile;
                links.push_back(l);
                continue;
              }
            }
            if (out.face == face) {
              const double r = std::hypot(a - out.center[0], b - out.center[1]);
              if (r >= out.r_min && r <= out.r_max) t = out.type;
            }
            l.type = int(t);
            if (t == FaceType::kFreeSlip) {
              // Specular reflection: the population left x' = x - c_t in the mirrored direction.
              const int axis = face / 2;
              std::array<int, 3> mirrored = c_[q];
              mirrored[axis] = -mirrored[axis];
              int q2 = -1;
              for (int p = 0; p < nq_; ++p)
                if (c_[p] == mirrored) q2 = p;
              int xi = i, xj = j, xk = k;
              if (axis != 0) xi -= c_[q][0];
              if (axis != 1) xj -= c_[q][1];
              if (axis != 2) xk -= c_[q][2];
              if (is_fluid_local(xi, xj, xk)) {
                l.q2 = q2;
                l.x2 = f_.index(xi, xj, xk);
              } else {
                l.type = int(FaceType::kWall);
              }
            }
          }  // count > 1 (edges, corners): bounce-back wall
          links.push_back(l);
        }
      }
  build_plans(links);
}

void LbmSolver::build_plans(const std::vector<Link>& links) {
  // Overlap: a neighbour-step link is late when a cell it writes or reads (s, x, x2; before a
  // neighbour step every location it touches is a slot of one of them) lies in a ghost layer the
  // exchange fills. It runs after the exchange lands; the sweep of cell r touches the cells
  // r-1..r+1 along the axis, so the rows up to one past the late links' cells are swept after it
  // (band_), and the interior rows before, untouched by either.
  const int axis = overlap_axis_;
  const int n = axis >= 0 ? decomp_.local_cells()[axis] : 0;
  auto row = [&](std::int64_t c) {
    const std::int64_t g = f_.ghosts();
    return static_cast<int>(axis == 1 ? (c / f_.stride_y()) % (n + 2 * g) - g
                                      : c / f_.stride_z() - g);
  };
  band_[0] = band_[1] = 1;
  std::vector<char> late(links.size(), 0);
  if (axis >= 0)
    for (std::size_t i = 0; i < links.size(); ++i) {
      const Link& l = links[i];
      int lo = row(l.s), hi = lo;
      for (std::int64_t c : {l.x, l.type == int(FaceType::kFreeSlip) ? l.x2 : l.x}) {
        lo = std::min(lo, row(c));
        hi = std::max(hi, row(c));
      }
      if (lo < 0) band_[0] = std::max(band_[0], hi + 2);
      if (hi >= n) band_[1] = std::max(band_[1], n - lo + 1);
      late[i] = lo < 0 || hi >= n;
    }
  overlap_ = axis >= 0 && band_[0] + band_[1] <= n;
  late_plan_ = {};
  for (int streamed = 0; streamed < 2; ++streamed) {
    plans_[streamed] = {};
    for (std::size_t i = 0; i < links.size(); ++i)
      add_link(!streamed && overlap_ && late[i] ? late_plan_ : plans_[streamed], links[i],
               streamed);
  }
  for (BoundaryPlan* plan : {&plans_[0], &plans_[1], &late_plan_}) compress_copies(*plan);
  build_fused_plans(links);
}

void LbmSolver::add_link(BoundaryPlan& plan, const Link& l, bool streamed) const {
  // The value link (s -> x, q) delivers is what x reads as its streamed population q: slot opp(q)
  // of s before a neighbour step, slot q of x before a local one. The post-collision population p
  // of cell c is in slot opp(p) of c (post state) or slot p of c + c_p (streamed state).
  const auto plane = static_cast<std::int64_t>(f_.plane_size());
  auto post = [&](int p, std::int64_t c) {
    return streamed ? p * plane + c + offset_[p] : opp_[p] * plane + c;
  };
  const int q = l.q;
  const std::int64_t dst = streamed ? q * plane + l.x : opp_[q] * plane + l.s;
  switch (l.type) {
    case -1:
      plan.inlet.push_back({dst, post(opp_[q], l.x)});
      plan.inlet_coef.push_back(l.coef);
      break;
    case int(FaceType::kFreeSlip):
      plan.copies.push_back({dst, post(l.q2, l.x2)});
      break;
    case int(FaceType::kPressure):
      plan.pressure.push_back({dst, post(opp_[q], l.x), l.x, q});
      break;
    case int(FaceType::kZeroGradient):
      plan.copies.push_back({dst, post(q, l.x)});
      break;
    default:
      plan.copies.push_back({dst, post(opp_[q], l.x)});
  }
}

void LbmSolver::compress_copies(BoundaryPlan& plan) {
  // Walk the targets in memory order (the links come cell by cell, 19 planes apart), and join
  // copies whose targets and sources advance by the same step into one run.
  auto& c = plan.copies;
  std::sort(c.begin(), c.end());
  plan.runs.clear();
  for (std::size_t i = 0; i < c.size();) {
    BoundaryPlan::CopyRun r{c[i][0], c[i][1], 1, 1};
    if (i + 1 < c.size() && c[i + 1][0] - c[i][0] == c[i + 1][1] - c[i][1])
      r.stride = c[i + 1][0] - c[i][0];
    while (i + r.count < c.size() && c[i + r.count][0] == r.dst + r.count * r.stride &&
           c[i + r.count][1] == r.src + r.count * r.stride)
      ++r.count;
    plan.runs.push_back(r);
    i += r.count;
  }
  c = {};  // only the runs are applied
}

template <class Store>
void LbmSolver::visit_boundaries(const BoundaryPlan& plan, Store&& store) const {
  const double t = time();
  const double u_in = params_.inlet.face >= 0 ? units_.velocity_to_lattice(params_.inlet.speed) *
                                                    params_.inlet.time_factor(t)
                                              : 0.0;
  // Targets and sources never overlap (a target's writer is not a fluid cell), so order is free.
  const double* base = f_.component(0);
  // Half-way bounce-back (walls, solids), specular reflection (free slip), zero gradient.
  for (const auto& r : plan.runs) {
    if (r.stride == 1)
      for (std::int64_t k = 0; k < r.count; ++k) store(r.dst + k, base[r.src + k]);
    else
      for (std::int64_t k = 0; k < r.count; ++k)
        store(r.dst + k * r.stride, base[r.src + k * r.stride]);
  }
  // Moving-wall bounce-back with the inlet velocity (Ladd 1994).
  for (std::size_t i = 0; i < plan.inlet.size(); ++i)
    store(plan.inlet[i][0], base[plan.inlet[i][1]] + plan.inlet_coef[i] * u_in);
  // Anti-bounce-back at rho = 1 (Ginzburg et al. 2008): only the even (quadratic) part of the
  // equilibrium enters, so the cell's velocity does not feed back linearly. (Plain equilibrium
  // with the cell's velocity grew round-off at outlet/wall corners into a blow-up after ~4e4
  // steps.) The cell's velocity is computed once for its consecutive links.
  const double* f[32];
  post_view(f);
  std::int64_t cell = -1;
  double ux = 0, uy = 0, uz = 0;
  for (const auto& l : plan.pressure) {
    if (l.cell != cell) {
      cell = l.cell;
      double m = 0, jx = 0, jy = 0, jz = 0;
      for (int p = 0; p < nq_; ++p) {
        const double v = f[p][cell];
        m += v;
        jx += c_[p][0] * v;
        jy += c_[p][1] * v;
        jz += c_[p][2] * v;
      }
      ux = jx / m, uy = jy / m, uz = jz / m;
    }
    const int q = l.q;
    const double cu = c_[q][0] * ux + c_[q][1] * uy + c_[q][2] * uz;
    store(l.dst,
          -base[l.src] + 2.0 * w_[q] * (1.0 + 4.5 * cu * cu - 1.5 * (ux * ux + uy * uy + uz * uz)));
  }
}

void LbmSolver::apply_boundaries(const BoundaryPlan& plan) {
  double* base = f_.component(0);
  visit_boundaries(plan, [base](std::int64_t dst, double v) { base[dst] = v; });
}

void LbmSolver::stage_boundaries(const BoundaryPlan& plan,
                                 std::vector<std::pair<std::int64_t, double>>& staged) const {
  visit_boundaries(plan, [&staged](std::int64_t dst, double v) { staged.emplace_back(dst, v); });
}

}  // namespace biota::solvers::lbm
