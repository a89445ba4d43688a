#include "solvers/lbm/lbm_solver.hpp"

#include <fmt/format.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include <limits>
#include "core/error.hpp"

#include "io/checkpoint.hpp"
#include "solvers/lbm/aa_sweep.hpp"
#include "solvers/lbm/lattice.hpp"

namespace biota::solvers::lbm {
namespace {

template <class L>
void copy_lattice(std::vector<std::array<int, 3>>& c, std::vector<double>& w,
                  std::vector<int>& opp) {
  c.assign(L::c.begin(), L::c.end());
  w.assign(L::w.begin(), L::w.end());
  opp.assign(L::opp.begin(), L::opp.end());
}

using SweepFn = void (*)(const AaSweepArgs&);

template <class L, bool T, ForceMode F, bool P>
SweepFn pick4(bool macro, bool solids) {
  if (macro)
    return solids ? aa_stream_collide<L, T, F, true, true, P>
                  : aa_stream_collide<L, T, F, true, false, P>;
  return solids ? aa_stream_collide<L, T, F, false, true, P>
                : aa_stream_collide<L, T, F, false, false, P>;
}
template <class L, bool T, ForceMode F>
SweepFn pick3(bool from_post, bool macro, bool solids) {
  return from_post ? pick4<L, T, F, true>(macro, solids) : pick4<L, T, F, false>(macro, solids);
}
template <class L, bool T>
SweepFn pick2(ForceMode f, bool from_post, bool macro, bool solids) {
  switch (f) {
    case ForceMode::kNone:
      return pick3<L, T, ForceMode::kNone>(from_post, macro, solids);
    case ForceMode::kUniform:
      return pick3<L, T, ForceMode::kUniform>(from_post, macro, solids);
    default:
      return pick3<L, T, ForceMode::kField>(from_post, macro, solids);
  }
}
template <class L>
SweepFn pick1(bool trt, ForceMode f, bool from_post, bool macro, bool solids) {
  return trt ? pick2<L, true>(f, from_post, macro, solids)
             : pick2<L, false>(f, from_post, macro, solids);
}

// Density and physical velocity of the owned cells from the post-collision populations post[q][c]
// (solid cells at rest, as a two-grid sweep leaves them). Lattice constants known at compile time
// so that the row loop vectorises; same operations in the same order as the scalar loop it
// replaced.
template <class L>
void macroscopic_fields(const grid::Field<Real>& layout, const double* const* post,
                        const std::uint8_t* solid, const double* const* force, const double* gl,
                        double* const* out) {
  const Index3 n = layout.cells();
  for (int k = 0; k < n.z; ++k)
    for (int j = 0; j < n.y; ++j) {
      const std::ptrdiff_t row = layout.index(0, j, k);
      for (std::ptrdiff_t c = row; c < row + n.x; ++c) {
        double m = 0, jx = 0, jy = 0, jz = 0;
        const bool s = solid[c];
#pragma GCC unroll 32
        for (int q = 0; q < L::Q; ++q) {
          const double v = s ? L::w[q] : post[q][c];
          m += v;
          jx += L::c[q][0] * v;
          jy += L::c[q][1] * v;
          jz += L::c[q][2] * v;
        }
        // Post-collision momentum carries the full force; the physical velocity is half-way.
        double fx = gl[0], fy = gl[1], fz = gl[2];
        if (force[0]) {
          fx += force[0][c];
          fy += force[1][c];
          fz += force[2][c];
        }
        out[0][c] = m;
        out[1][c] = (jx - 0.5 * fx) / m;
        out[2][c] = (jy - 0.5 * fy) / m;
        out[3][c] = (jz - 0.5 * fz) / m;
      }
    }
}

}  // namespace

LbmSolver::LbmSolver(const grid::Decomposition& decomp, const LbmParams& params)
    : decomp_(decomp),
      params_(params),
      units_(params.dx, params.dt, params.density, params.viscosity, params.reference_velocity) {
  if (params_.lattice == "D3Q15")
    copy_lattice<D3Q15>(c_, w_, opp_);
  else
    copy_lattice<D3Q19>(c_, w_, opp_);
  nq_ = static_cast<int>(c_.size());
  const Index3 n = decomp.local_cells();
  f_ = grid::Field<Real>(n, nq_, 1);
  for (int q = 0; q < nq_; ++q)
    offset_.push_back(c_[q][0] + c_[q][1] * f_.stride_y() + c_[q][2] * f_.stride_z());
  force_ = grid::Field<Real>(n, 3, 1);
  rho_ = grid::Field<Real>(n, 1, 1, 1.0);
  u_ = grid::Field<Real>(n, 3, 1);
  solid_.assign(f_.plane_size(), 0);
  // Only the populations that stream into the neighbour cross a face. Before a neighbour step the
  // low ghost layer of axis a needs those with c_a = +1, the high one those with c_a = -1; in the
  // post state population q sits in slot opp(q). After it, the populations with c_a = -1 that
  // were streamed into my low ghosts (c_a = +1: high ghosts) go to the neighbour, slot q.
  grid::FaceComponents pull, push;
  for (int a = 0; a < 3; ++a)
    for (int q = 0; q < nq_; ++q) {
      if (c_[q][a] == 1) pull[a][0].push_back(opp_[q]), push[a][1].push_back(q);
      if (c_[q][a] == -1) pull[a][1].push_back(opp_[q]), push[a][0].push_back(q);
    }
  halo_ = std::make_unique<grid::HaloExchange>(decomp, f_, pull);
  fold_ = std::make_unique<grid::GhostFold>(decomp, f_, push);
  halo_u_ = std::make_unique<grid::HaloExchange>(decomp, u_);
  // The neighbour step's exchange and fold overlap the sweep when one axis alone has neighbours
  // (then both are a single pass along it) and it is y or z (whole rows; an x split would cut
  // every row).
  int active = 0;
  for (int a = 0; a < 3; ++a)
    if (decomp.neighbor(a, 0) != MPI_PROC_NULL || decomp.neighbor(a, 1) != MPI_PROC_NULL) {
      ++active;
      overlap_axis_ = a;
    }
  if (active != 1 || overlap_axis_ == 0 || !params.overlap_halo) overlap_axis_ = -1;
  initialize([](const Index3&, double& rho, Vec3& u) {
    rho = 1.0;
    u = {};
  });
  build_links();
}

LbmSolver::~LbmSolver() = default;

void LbmSolver::initialize(const std::function<void(const Index3&, double&, Vec3&)>& init) {
  const Index3 n = decomp_.local_cells(), lo = decomp_.local_box().lo;
  for (int k = 0; k < n.z; ++k)
    for (int j = 0; j < n.y; ++j)
      for (int i = 0; i < n.x; ++i) {
        double rho = 1.0;
        Vec3 u{};
        init({lo.x + i, lo.y + j, lo.z + k}, rho, u);
        const double uu = dot(u, u);
        for (int q = 0; q < nq_; ++q) {
          const double cu = c_[q][0] * u.x + c_[q][1] * u.y + c_[q][2] * u.z;
          f_(i, j, k, opp_[q]) = w_[q] * rho * (1.0 + 3.0 * cu + 4.5 * cu * cu - 1.5 * uu);
        }
      }
  streamed_ = false;  // the post state: population q of x in slot opp(q) of x
  update_macroscopic();
}

void LbmSolver::post_view(const double* post[32]) const {
  for (int q = 0; q < nq_; ++q)
    post[q] = streamed_ ? f_.component(q) + offset_[q] : f_.component(opp_[q]);
}

grid::Field<Real> LbmSolver::natural_populations() const {
  const Index3 n = decomp_.local_cells();
  grid::Field<Real> out(n, nq_, 1);
  const double* post[32];
  post_view(post);
  for (int q = 0; q < nq_; ++q)
    for (int k = 0; k < n.z; ++k)
      for (int j = 0; j < n.y; ++j)
        for (int i = 0; i < n.x; ++i) {
          const std::ptrdiff_t c = f_.index(i, j, k);
          out(i, j, k, q) = solid_[c] ? w_[q] : post[q][c];
        }
  return out;
}

void LbmSolver::update_macroscopic() {
  const double* post[32];
  post_view(post);
  const Vec3& g = params_.body_force;
  const double gl[3] = {units_.force_density_to_lattice(g.x), units_.force_density_to_lattice(g.y),
                        units_.force_density_to_lattice(g.z)};
  const double* force[3] = {nullptr, nullptr, nullptr};
  if (use_force_field_)
    for (int a = 0; a < 3; ++a) force[a] = force_.component(a);
  double* out[4] = {rho_.component(0), u_.component(0), u_.component(1), u_.component(2)};
  if (params_.lattice == "D3Q15")
    macroscopic_fields<D3Q15>(f_, post, solid_.data(), force, gl, out);
  else
    macroscopic_fields<D3Q19>(f_, post, solid_.data(), force, gl, out);
  halo_u_->exchange();
}

void LbmSolver::set_solid(const std::function<bool(const Index3&)>& is_solid) {
  const Index3 n = decomp_.local_cells(), lo = decomp_.local_box().lo;
  const int g = f_.ghosts();
  has_solids_ = false;
  for (int k = -g; k < n.z + g; ++k)
    for (int j = -g; j < n.y + g; ++j)
      for (int i = -g; i < n.x + g; ++i) {
        Index3 gc = decomp_.wrap({lo.x + i, lo.y + j, lo.z + k});
        bool s = is_solid(gc);
        solid_[f_.index(i, j, k)] = s;
        if (s && i >= 0 && j >= 0 && k >= 0 && i < n.x && j < n.y && k < n.z) has_solids_ = true;
      }
  // has_solids_ picks the sweep variant for this rank's owned cells only; the boundary links
  // (built from the ghosted mask) handle solids next to the rank boundary.
  build_links();
}

void LbmSolver::build_links() {
  links_.clear();
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
                links_.push_back(l);
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
          links_.push_back(l);
        }
      }
  build_plans();
}

void LbmSolver::build_plans() {
  // The value link (s -> x, q) delivers is what x reads as its streamed population q: slot opp(q)
  // of s before a neighbour step, slot q of x before a local one. The post-collision population p
  // of cell c is in slot opp(p) of c (post state) or slot p of c + c_p (streamed state).
  const auto plane = static_cast<std::int64_t>(f_.plane_size());
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
  std::vector<char> late(links_.size(), 0);
  if (axis >= 0)
    for (std::size_t i = 0; i < links_.size(); ++i) {
      const Link& l = links_[i];
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
    auto post = [&](int p, std::int64_t c) {
      return streamed ? p * plane + c + offset_[p] : opp_[p] * plane + c;
    };
    plans_[streamed] = {};
    for (std::size_t i = 0; i < links_.size(); ++i) {
      const Link& l = links_[i];
      BoundaryPlan& plan = !streamed && overlap_ && late[i] ? late_plan_ : plans_[streamed];
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
    // Walk the targets in memory order (the links come cell by cell, 19 planes apart).
    std::sort(plans_[streamed].copies.begin(), plans_[streamed].copies.end());
  }
  std::sort(late_plan_.copies.begin(), late_plan_.copies.end());
}

void LbmSolver::apply_boundaries(const BoundaryPlan& plan) {
  const double t = time();
  const double u_in = params_.inlet.face >= 0 ? units_.velocity_to_lattice(params_.inlet.speed) *
                                                    params_.inlet.time_factor(t)
                                              : 0.0;
  // Targets and sources never overlap (a target's writer is not a fluid cell), so order is free.
  double* base = f_.component(0);
  // Half-way bounce-back (walls, solids), specular reflection (free slip), zero gradient.
  for (const auto& [dst, src] : plan.copies) base[dst] = base[src];
  // Moving-wall bounce-back with the inlet velocity (Ladd 1994).
  for (std::size_t i = 0; i < plan.inlet.size(); ++i)
    base[plan.inlet[i][0]] = base[plan.inlet[i][1]] + plan.inlet_coef[i] * u_in;
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
    base[l.dst] =
        -base[l.src] + 2.0 * w_[q] * (1.0 + 4.5 * cu * cu - 1.5 * (ux * ux + uy * uy + uz * uz));
  }
}

void LbmSolver::sweep(bool macro, int begin, int end) {
  const Vec3& bf = params_.body_force;
  AaSweepArgs a{
      &f_,
      &force_,
      &rho_,
      &u_,
      solid_.data(),
      {units_.force_density_to_lattice(bf.x), units_.force_density_to_lattice(bf.y),
       units_.force_density_to_lattice(bf.z)},
      params_.trt ? Relaxation::trt(units_.tau(), params_.magic) : Relaxation::bgk(units_.tau())};
  const Index3 n = decomp_.local_cells();
  a.j_end = n.y;
  a.k_end = n.z;
  if (end >= 0) (overlap_axis_ == 1 ? a.j_begin : a.k_begin) = begin;
  if (end >= 0) (overlap_axis_ == 1 ? a.j_end : a.k_end) = end;
  if (a.j_begin >= a.j_end || a.k_begin >= a.k_end) return;
  ForceMode fm = use_force_field_                        ? ForceMode::kField
                 : (bf.x != 0 || bf.y != 0 || bf.z != 0) ? ForceMode::kUniform
                                                         : ForceMode::kNone;
  const bool from_post = !streamed_;
  SweepFn fn = params_.lattice == "D3Q15"
                   ? pick1<D3Q15>(params_.trt, fm, from_post, macro, has_solids_)
                   : pick1<D3Q19>(params_.trt, fm, from_post, macro, has_solids_);
  fn(a);
}

void LbmSolver::overlapped_neighbour_step(bool macro) {
  // Bitwise the sequential step: every cell writes exactly the locations it read, so the order of
  // the cells is free as long as each finds its inputs in place. The exchange fills only the
  // ghost layers of overlap_axis_, which the interior rows do not touch; the late links write and
  // read only cells of the bands; the fold lands in slots no owned cell of this step touches.
  const int n = decomp_.local_cells()[overlap_axis_];
  const int inner = n - band_[1];
  const int mid = band_[0] + (inner - band_[0]) / 2;
  const double t0 = MPI_Wtime();
  halo_->begin();
  const double t1 = MPI_Wtime();
  apply_boundaries(plans_[0]);
  const double t2 = MPI_Wtime();
  sweep(macro, band_[0], mid);
  const double t3 = MPI_Wtime();
  halo_->end();
  const double t4 = MPI_Wtime();
  apply_boundaries(late_plan_);
  const double t5 = MPI_Wtime();
  sweep(macro, 0, band_[0]);
  sweep(macro, inner, n);
  const double t6 = MPI_Wtime();
  fold_->begin();
  const double t7 = MPI_Wtime();
  sweep(macro, mid, inner);
  const double t8 = MPI_Wtime();
  fold_->end();
  const double t9 = MPI_Wtime();
  t_halo_ += (t1 - t0) + (t4 - t3) + (t7 - t6) + (t9 - t8);
  t_boundary_ += (t2 - t1) + (t5 - t4);
  t_collide_ += (t3 - t2) + (t6 - t5) + (t8 - t7);
}

void LbmSolver::step(bool update_macro) {
  // Neighbour step: the crossing populations come in through the ghosts before the sweep and the
  // ones streamed out into the ghosts go to their owners after it. Local step: no communication.
  const bool neighbour_step = !streamed_;
  if (neighbour_step && overlap_) {
    overlapped_neighbour_step(update_macro);
    streamed_ = true;
    const double t0 = MPI_Wtime();
    if (update_macro) halo_u_->exchange();
    t_halo_ += MPI_Wtime() - t0;
  } else {
    double t0 = MPI_Wtime();
    if (neighbour_step) halo_->exchange();
    double t1 = MPI_Wtime();
    apply_boundaries(plans_[streamed_]);
    if (neighbour_step) apply_boundaries(late_plan_);  // empty unless overlap_
    double t2 = MPI_Wtime();
    sweep(update_macro);
    double t3 = MPI_Wtime();
    if (neighbour_step) fold_->fold();
    streamed_ = neighbour_step;
    if (update_macro) halo_u_->exchange();
    double t4 = MPI_Wtime();
    t_halo_ += (t1 - t0) + (t4 - t3);
    t_boundary_ += t2 - t1;
    t_collide_ += t3 - t2;
  }
  ++step_;
  updates_ += static_cast<double>(decomp_.local_cells().product());
}

double LbmSolver::total_mass() const {
  const Index3 n = decomp_.local_cells();
  const double* post[32];
  post_view(post);
  double local = 0;
  for (int q = 0; q < nq_; ++q)
    for (int k = 0; k < n.z; ++k)
      for (int j = 0; j < n.y; ++j)
        for (int i = 0; i < n.x; ++i) {
          const std::ptrdiff_t c = f_.index(i, j, k);
          local += solid_[c] ? w_[q] : post[q][c];
        }
  double global = 0;
  MPI_Allreduce(&local, &global, 1, MPI_DOUBLE, MPI_SUM, decomp_.comm());
  return global;
}

void LbmSolver::check_health(double rho_min, double rho_max) const {
  const Index3 n = decomp_.local_cells(), lo = decomp_.local_box().lo;
  const double* post[32];
  post_view(post);
  long long bad = -1;
  double bad_rho = 0;
  for (int k = 0; k < n.z && bad < 0; ++k)
    for (int j = 0; j < n.y && bad < 0; ++j)
      for (int i = 0; i < n.x; ++i) {
        const std::ptrdiff_t c = f_.index(i, j, k);
        if (solid_[c]) continue;
        double m = 0;
        for (int q = 0; q < nq_; ++q) m += post[q][c];
        if (!std::isfinite(m) || m < rho_min || m > rho_max) {
          const Index3 gc{lo.x + i, lo.y + j, lo.z + k};
          bad = (static_cast<long long>(gc.z) * decomp_.global_cells().y + gc.y) *
                    decomp_.global_cells().x +
                gc.x;
          bad_rho = m;
          break;
        }
      }
  long long first = bad < 0 ? LLONG_MAX : bad, global_first = 0;
  MPI_Allreduce(&first, &global_first, 1, MPI_LONG_LONG, MPI_MIN, decomp_.comm());
  if (global_first == LLONG_MAX) return;
  double rho_bad = first == global_first ? bad_rho : 0.0, rho_report = 0;
  MPI_Allreduce(&rho_bad, &rho_report, 1, MPI_DOUBLE, MPI_SUM, decomp_.comm());
  const auto& N = decomp_.global_cells();
  const long long x = global_first % N.x, y = (global_first / N.x) % N.y,
                  z = global_first / (1LL * N.x * N.y);
  throw core::UnstableError(fmt::format(
      "LBM unstable at step {}: density {} outside [{}, {}] or not finite in cell ({}, {}, {}) = "
      "({:.4g}, {:.4g}, {:.4g}) m",
      step_, rho_report, rho_min, rho_max, x, y, z, (x + 0.5) * params_.dx, (y + 0.5) * params_.dx,
      (z + 0.5) * params_.dx));
}

void LbmSolver::poison_for_test() {
  const Index3 n = decomp_.local_cells();
  for (int k = 0; k < n.z; ++k)
    for (int j = 0; j < n.y; ++j)
      for (int i = 0; i < n.x; ++i)
        if (!solid_[f_.index(i, j, k)]) {
          f_(i, j, k, 0) = std::numeric_limits<double>::quiet_NaN();
          return;
        }
}

void LbmSolver::write_checkpoint(io::CheckpointWriter& w) const {
  // Natural order on either parity, so a restart onto any rank count continues bitwise.
  w.write_field("lbm_populations", natural_populations(), 0, nq_);
  w.write_attribute("lbm_step", static_cast<std::int64_t>(step_));
  w.write_attribute("lbm_lattice", params_.lattice);
}

void LbmSolver::read_checkpoint(io::CheckpointReader& r) {
  const std::string lattice = r.read_attribute_string("lbm_lattice");
  if (lattice != params_.lattice)
    throw core::InputError(
        fmt::format("checkpoint uses lattice {} but the deck says lbm.lattice = "
                    "{}",
                    lattice, params_.lattice));
  const Index3 n = decomp_.local_cells();
  grid::Field<Real> natural(n, nq_, 1);
  r.read_field("lbm_populations", natural, 0, nq_);
  for (int q = 0; q < nq_; ++q)
    for (int k = 0; k < n.z; ++k)
      for (int j = 0; j < n.y; ++j)
        for (int i = 0; i < n.x; ++i) f_(i, j, k, opp_[q]) = natural(i, j, k, q);
  streamed_ = false;
  step_ = r.read_attribute_int("lbm_step");
  update_macroscopic();
}

}  // namespace biota::solvers::lbm
