#include "solvers/mac/mac_solver.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "core/reproducible_sum.hpp"
#include "solvers/mac/kernels.hpp"

namespace biota::solvers::mac {
namespace {

bool is_outflow(BoundaryType t) {
  return t == BoundaryType::kOutflow || t == BoundaryType::kConvectiveOutflow;
}
bool is_wall(BoundaryType t) {
  return t == BoundaryType::kNoSlip || t == BoundaryType::kFreeSlip || t == BoundaryType::kGround;
}

linalg::PressureBCs pressure_bcs(const Boundaries& b) {
  linalg::PressureBCs out;
  for (int a = 0; a < 3; ++a)
    for (int s = 0; s < 2; ++s)
      out[a][s] = b[a][s].type == BoundaryType::kPeriodic ? linalg::PressureBC::kPeriodic
                  : is_outflow(b[a][s].type)              ? linalg::PressureBC::kDirichlet
                                                          : linalg::PressureBC::kNeumann;
  return out;
}

double allreduce(double v, MPI_Op op, MPI_Comm comm) {
  double g = 0;
  MPI_Allreduce(&v, &g, 1, MPI_DOUBLE, op, comm);
  return g;
}
}  // namespace

MacSolver::MacSolver(const grid::Decomposition& decomp, MacParams params, core::Timers& timers)
    : d_(decomp), p_(std::move(params)), timers_(timers), n_(decomp.local_cells()) {
  validate(p_.boundaries, "wind.boundary.");
  for (int a = 0; a < 3; ++a)
    if (d_.periodic(a) != (type(a, 0) == BoundaryType::kPeriodic))
      throw std::logic_error("MacSolver: decomposition periodicity differs from the boundaries");
  u_ = grid::Field<Real>(n_, 3, MacSolver::kGhosts);
  ustar_ = grid::Field<Real>(n_, 3, MacSolver::kGhosts);
  rhs_ = grid::Field<Real>(n_, 3, MacSolver::kGhosts);
  force_ = grid::Field<Real>(n_, 3, MacSolver::kGhosts);
  phi_ = grid::Field<Real>(n_, 1, MacSolver::kGhosts);
  psi_ = grid::Field<Real>(n_, 1, MacSolver::kGhosts);
  div_ = grid::Field<Real>(n_, 1, MacSolver::kGhosts);
  solid_ = grid::Field<Real>(n_, 1, MacSolver::kGhosts);
  halo_u_ = std::make_unique<grid::HaloExchange>(d_, u_);
  halo_ustar_ = std::make_unique<grid::HaloExchange>(d_, ustar_);
  halo_psi_ = std::make_unique<grid::HaloExchange>(d_, psi_);

  // Solid mask: owned cells from the predicate, ghosts from neighbours, outside the box fluid.
  bool any_solid = false;
  const auto lo = d_.local_box().lo;
  if (p_.solid)
    for (int k = 0; k < n_.z; ++k)
      for (int j = 0; j < n_.y; ++j)
        for (int i = 0; i < n_.x; ++i)
          if (p_.solid({lo.x + i, lo.y + j, lo.z + k})) solid_(i, j, k) = 1, any_solid = true;
  int any = any_solid, any_global = 0;
  MPI_Allreduce(&any, &any_global, 1, MPI_INT, MPI_MAX, d_.comm());
  {
    grid::HaloExchange h(d_, solid_);
    h.exchange();
  }
  open_.assign(u_.plane_size(), {1, 1, 1});
  const std::ptrdiff_t st[3] = {1, u_.stride_y(), u_.stride_z()};
  const Real* sm = solid_.component(0);
  for (int k = -1; k <= n_.z; ++k)
    for (int j = -1; j <= n_.y; ++j)
      for (int i = -1; i <= n_.x; ++i) {
        const auto q = u_.index(i, j, k);
        for (int c = 0; c < 3; ++c) open_[q][c] = !(sm[q] > 0.5 || sm[q - st[c]] > 0.5);
      }

  poisson_ = std::make_unique<linalg::PoissonSolver>(d_, p_.dx, pressure_bcs(p_.boundaries),
                                                     any_global ? &solid_ : nullptr,
                                                     p_.poisson_options, p_.poisson_options_key);

  // Initial velocity: the inflow profile along the inflow axis, else the given uniform value.
  for (int c = 0; c < 3; ++c) {
    int inflow_side = -1;
    for (int s = 0; s < 2; ++s)
      if (type(c, s) == BoundaryType::kInflow) inflow_side = s;
    for (int k = 0; k <= n_.z; ++k)
      for (int j = 0; j <= n_.y; ++j)
        for (int i = 0; i <= n_.x; ++i)
          u_(i, j, k, c) = (p_.initial_from_inflow && inflow_side >= 0)
                               ? inflow_normal(c, inflow_side, i, j, k)
                               : p_.initial_velocity[c];
  }
  refresh();
}

MacSolver::~MacSolver() = default;

Real MacSolver::inflow_normal(int axis, int side, int i, int j, int k) const {
  const int v = p_.vertical_axis;
  const int loc[3] = {i, j, k};
  Real speed = p_.inflow.speed;
  if (p_.inflow.kind == InflowProfile::kLog && v != axis) {
    const Real h = (d_.local_box().lo[v] + loc[v] + 0.5) * p_.dx;
    speed = log_profile(h, p_.inflow.speed, p_.inflow.reference_height, p_.inflow.roughness_length);
  }
  return side == 0 ? speed : -speed;
}

void MacSolver::exchange_velocity(grid::Field<Real>& u) {
  {
    auto t = timers_.scope("wind.halo");
    (&u == &u_ ? halo_u_ : halo_ustar_)->exchange();
  }
  apply_velocity_bc(u);
}

void MacSolver::refresh() {
  // Blocked faces carry no flow.
  for (int c = 0; c < 3; ++c) {
    Real* U = u_.component(c);
    for (int k = 0; k <= n_.z; ++k)
      for (int j = 0; j <= n_.y; ++j)
        for (int i = 0; i <= n_.x; ++i) {
          const auto q = u_.index(i, j, k);
          if (!open_[q][c]) U[q] = 0;
        }
  }
  exchange_velocity(u_);
}

void MacSolver::project_initial() {
  project(u_, 1.0);
  phi_.fill(0);
}

// Ghost layers (and prescribed boundary faces) of bounded axes. Axis by axis over the full
// ghosted range of the other axes, after the halo exchange, so edges and corners are consistent.
template <class F>
void MacSolver::for_each_face_line(const grid::Field<Real>& field, int a, F&& f) const {
  const int b1 = (a + 1) % 3, b2 = (a + 2) % 3;
  for (int y = -MacSolver::kGhosts; y < n_[b2] + MacSolver::kGhosts; ++y)
    for (int x = -MacSolver::kGhosts; x < n_[b1] + MacSolver::kGhosts; ++x) {
      int loc[3];
      loc[a] = 0;
      loc[b1] = x;
      loc[b2] = y;
      f(loc, field.index(loc[0], loc[1], loc[2]));
    }
}

void MacSolver::apply_velocity_bc(grid::Field<Real>& u) {
  auto t = timers_.scope("wind.boundary");
  const std::ptrdiff_t st[3] = {1, u.stride_y(), u.stride_z()};
  for (int a = 0; a < 3; ++a) {
    for (int s = 0; s < 2; ++s) {
      if (!(s == 0 ? bounded_low(a) : bounded_high(a))) continue;
      const BoundaryType bt = type(a, s);
      const Vec3 w = p_.boundaries[a][s].wall_velocity;
      const std::ptrdiff_t sa = st[a];
      const int na = n_[a];
      for_each_face_line(u, a, [&](int* loc, std::ptrdiff_t q0) {
        for (int c = 0; c < 3; ++c) {
          Real* L = u.component(c) + q0;  // L[t * sa] = value at index t along a
          if (c == a) {                   // normal component: boundary face, then beyond
            const std::ptrdiff_t f = s == 0 ? 0 : na * sa;  // boundary face
            if (bt == BoundaryType::kInflow) {
              loc[a] = s == 0 ? 0 : na;
              L[f] = inflow_normal(a, s, loc[0], loc[1], loc[2]);
            } else if (is_wall(bt)) {
              L[f] = 0;
            }
            const std::ptrdiff_t dir = s == 0 ? -sa : sa;  // outward
            if (is_outflow(bt)) {
              L[f + dir] = L[f];
              if (s == 0) L[f + 2 * dir] = L[f];
            } else {
              L[f + dir] = 2 * L[f] - L[f - dir];
              if (s == 0) L[f + 2 * dir] = 2 * L[f] - L[f - 2 * dir];
            }
          } else {  // tangential: ghosts mirror the first interior layers
            const std::ptrdiff_t in0 = s == 0 ? 0 : (na - 1) * sa;
            const std::ptrdiff_t in1 = s == 0 ? sa : (na - 2) * sa;
            const std::ptrdiff_t gh0 = s == 0 ? -sa : na * sa;
            const std::ptrdiff_t gh1 = s == 0 ? -2 * sa : (na + 1) * sa;
            switch (bt) {
              case BoundaryType::kNoSlip:
                L[gh0] = 2 * w[c] - L[in0];
                L[gh1] = 2 * w[c] - L[in1];
                break;
              case BoundaryType::kInflow:
                L[gh0] = -L[in0];
                L[gh1] = -L[in1];
                break;
              case BoundaryType::kFreeSlip:
              case BoundaryType::kGround:  // stress from the wall model, see compute_rhs
                L[gh0] = L[in0];
                L[gh1] = L[in1];
                break;
              default:  // outflow: zero gradient
                L[gh0] = L[in0];
                L[gh1] = L[in0];
            }
          }
        }
      });
    }
  }
}

void MacSolver::apply_pressure_bc(grid::Field<Real>& p) {
  const std::ptrdiff_t st[3] = {1, p.stride_y(), p.stride_z()};
  for (int a = 0; a < 3; ++a)
    for (int s = 0; s < 2; ++s) {
      if (!(s == 0 ? bounded_low(a) : bounded_high(a))) continue;
      const Real sign = is_outflow(type(a, s)) ? -1.0 : 1.0;  // p = 0 on the face, or dp/dn = 0
      const std::ptrdiff_t sa = st[a];
      const int na = n_[a];
      for_each_face_line(p, a, [&](int*, std::ptrdiff_t q0) {
        Real* L = p.component(0) + q0;
        if (s == 0) {
          L[-sa] = sign * L[0];
          L[-2 * sa] = sign * L[sa];
        } else {
          L[na * sa] = sign * L[(na - 1) * sa];
          L[(na + 1) * sa] = sign * L[(na - 2) * sa];
        }
      });
    }
}

void MacSolver::compute_rhs(const grid::Field<Real>& u, grid::Field<Real>& rhs) {
  const std::ptrdiff_t st[3] = {1, u.stride_y(), u.stride_z()};
  const Real inv2dx = 1 / (2 * p_.dx), nu_dx2 = p_.viscosity / (p_.dx * p_.dx);
  {
    auto t = timers_.scope("wind.advection");
    for (int c = 0; c < 3; ++c) {
      const Real* U[3] = {u.component(0), u.component(1), u.component(2)};
      Real* R = rhs.component(c);
      const Real* F = force_.component(c);
      const Real fb = p_.body_force[c];
      const int o1 = (c + 1) % 3, o2 = (c + 2) % 3;
      const std::ptrdiff_t sc = st[c], s1 = st[o1], s2 = st[o2];
      int lo[3] = {0, 0, 0};
      if (bounded_low(c)) lo[c] = 1;
      for (int k = lo[2]; k < n_.z; ++k)
        for (int j = lo[1]; j < n_.y; ++j) {
          const auto q0 = u.index(0, j, k);
          for (int i = lo[0]; i < n_.x; ++i) {
            const auto q = q0 + i;
            const Real* P = U[c] + q;
            const Real a1 = 0.25 * (U[o1][q] + U[o1][q - sc] + U[o1][q + s1] + U[o1][q - sc + s1]);
            const Real a2 = 0.25 * (U[o2][q] + U[o2][q - sc] + U[o2][q + s2] + U[o2][q - sc + s2]);
            const Real adv = upwind2(P[0], P[-2 * sc], P[-sc], P[0], P[sc], P[2 * sc]) +
                             upwind2(a1, P[-2 * s1], P[-s1], P[0], P[s1], P[2 * s1]) +
                             upwind2(a2, P[-2 * s2], P[-s2], P[0], P[s2], P[2 * s2]);
            R[q] = -adv * inv2dx + F[q] + fb;
          }
        }
    }
  }
  {
    auto t = timers_.scope("wind.diffusion");
    for (int c = 0; c < 3; ++c) {
      const Real* P = u.component(c);
      Real* R = rhs.component(c);
      int lo[3] = {0, 0, 0};
      if (bounded_low(c)) lo[c] = 1;
      const std::ptrdiff_t sy = st[1], sz = st[2];
      for (int k = lo[2]; k < n_.z; ++k)
        for (int j = lo[1]; j < n_.y; ++j) {
          const auto q0 = u.index(0, j, k);
          for (int i = lo[0]; i < n_.x; ++i) {
            const auto q = q0 + i;
            R[q] += nu_dx2 * (P[q - 1] + P[q + 1] + P[q - sy] + P[q + sy] + P[q - sz] + P[q + sz] -
                              6 * P[q]);
          }
        }
    }
    // Rough-wall (log-law) stress on the first cell layer next to "ground" faces.
    for (int a = 0; a < 3; ++a)
      for (int s = 0; s < 2; ++s) {
        if (type(a, s) != BoundaryType::kGround || !(s == 0 ? bounded_low(a) : bounded_high(a)))
          continue;
        const Real cd = wall_drag_coefficient(0.5 * p_.dx, p_.ground_roughness) / p_.dx;
        for (int c = 0; c < 3; ++c) {
          if (c == a) continue;
          const int o = 3 - a - c;
          const Real *U = u.component(c), *V = u.component(o);
          Real* R = rhs.component(c);
          int lo[3] = {0, 0, 0}, hi[3] = {n_.x, n_.y, n_.z};
          if (bounded_low(c)) lo[c] = 1;
          lo[a] = s == 0 ? 0 : n_[a] - 1;
          hi[a] = lo[a] + 1;
          for (int k = lo[2]; k < hi[2]; ++k)
            for (int j = lo[1]; j < hi[1]; ++j)
              for (int i = lo[0]; i < hi[0]; ++i) {
                const auto q = u.index(i, j, k);
                const Real vo = 0.25 * (V[q] + V[q - st[c]] + V[q + st[o]] + V[q - st[c] + st[o]]);
                R[q] -= cd * std::sqrt(U[q] * U[q] + vo * vo) * U[q];
              }
        }
      }
  }
}

void MacSolver::predict(const grid::Field<Real>& u, const grid::Field<Real>& u_old, Real a_old,
                        Real dt, grid::Field<Real>& out) {
  compute_rhs(u, rhs_);
  auto t = timers_.scope("wind.advection");
  const Real b = 1 - a_old;
  const std::ptrdiff_t st[3] = {1, u.stride_y(), u.stride_z()};
  for (int c = 0; c < 3; ++c) {
    const Real *U = u.component(c), *U0 = u_old.component(c), *R = rhs_.component(c);
    Real* O = out.component(c);
    int lo[3] = {0, 0, 0};
    if (bounded_low(c)) lo[c] = 1;
    for (int k = lo[2]; k < n_.z; ++k)
      for (int j = lo[1]; j < n_.y; ++j) {
        const auto q0 = u.index(0, j, k);
        for (int i = lo[0]; i < n_.x; ++i) {
          const auto q = q0 + i;
          O[q] = open_[q][c] ? a_old * U0[q] + b * (U[q] + dt * R[q]) : 0.0;
        }
      }
    // Outflow boundary faces of this component (inflow and wall faces are set by the BCs).
    for (int s = 0; s < 2; ++s) {
      if (!is_outflow(type(c, s))) continue;
      const bool here = s == 0 ? bounded_low(c) : bounded_high(c);
      const std::ptrdiff_t f = s == 0 ? 0 : n_[c] * st[c];
      const std::ptrdiff_t in = s == 0 ? st[c] : -st[c];  // inward
      const int o1 = (c + 1) % 3, o2 = (c + 2) % 3;
      // Convection speed: mean outward normal velocity on this face (every rank takes part),
      // summed reproducibly, so the same on any decomposition.
      Real uc = 0;
      if (type(c, s) == BoundaryType::kConvectiveOutflow) {
        std::vector<double> face;
        if (here) {
          int loc[3];
          loc[c] = 0;
          for (int y = 0; y < n_[o2]; ++y)
            for (int x = 0; x < n_[o1]; ++x) {
              loc[o1] = x, loc[o2] = y;
              face.push_back(U[u.index(loc[0], loc[1], loc[2]) + f]);
            }
        }
        const double sum = core::reproducible_sum(face.data(), face.size(), d_.comm());
        const double cells = double(d_.global_cells()[o1]) * double(d_.global_cells()[o2]);
        uc = std::max(0.0, (s == 0 ? -1.0 : 1.0) * sum / cells);
      }
      if (!here) continue;
      int loc[3];
      loc[c] = 0;
      for (int y = 0; y < n_[o2]; ++y)
        for (int x = 0; x < n_[o1]; ++x) {
          loc[o1] = x, loc[o2] = y;
          const auto q = u.index(loc[0], loc[1], loc[2]) + f;
          if (type(c, s) == BoundaryType::kOutflow)
            O[q] = O[q + in];
          else
            O[q] = a_old * U0[q] + b * (U[q] - dt * uc * (U[q] - U[q + in]) / p_.dx);
          if (!open_[q][c]) O[q] = 0;
        }
    }
  }
}

void MacSolver::project(grid::Field<Real>& u, Real dts) {
  exchange_velocity(u);
  const std::ptrdiff_t st[3] = {1, u.stride_y(), u.stride_z()};
  const Real inv_dx = 1 / p_.dx;
  {
    auto t = timers_.scope("wind.poisson");
    Real umax = 0;  // over the low faces of owned cells: the scale of the divergence target
    for (int k = 0; k < n_.z; ++k)
      for (int j = 0; j < n_.y; ++j)
        for (int i = 0; i < n_.x; ++i) {
          const auto q = u.index(i, j, k);
          Real dv = 0;
          for (int c = 0; c < 3; ++c) {
            dv += u.component(c)[q + st[c]] - u.component(c)[q];
            umax = std::max(umax, std::fabs(u.component(c)[q]));
          }
          div_.component(0)[q] = dv * inv_dx;
          psi_.component(0)[q] = phi_.component(0)[q] * dts;
        }
    // The correction leaves div u = rhs - L psi per cell, so max |div u| dx / max|u| <= target
    // once max |rhs - L psi| <= target umax / dx. The factor 2 covers a fall of max|u| by the
    // correction itself of up to half (in a developing flow it changes by far less than 1%).
    constexpr Real kDivergenceSafety = 2;
    umax = allreduce(umax, MPI_MAX, d_.comm());
    const Real max_residual = p_.divergence_target * umax * inv_dx / kDivergenceSafety;
    auto s = poisson_->solve(div_, psi_, max_residual);
    stats_.poisson_iterations += s.iterations;
    stats_.poisson_seconds += s.seconds;
  }
  {
    auto t = timers_.scope("wind.halo");
    halo_psi_->exchange();
  }
  apply_pressure_bc(psi_);
  {
    auto t = timers_.scope("wind.correction");
    const Real* P = psi_.component(0);
    for (int c = 0; c < 3; ++c) {
      Real* U = u.component(c);
      int lo[3] = {0, 0, 0}, hi[3] = {n_.x, n_.y, n_.z};
      if (bounded_low(c) && !is_outflow(type(c, 0))) lo[c] = 1;
      if (bounded_high(c) && is_outflow(type(c, 1))) hi[c] = n_[c] + 1;
      for (int k = lo[2]; k < hi[2]; ++k)
        for (int j = lo[1]; j < hi[1]; ++j) {
          const auto q0 = u.index(0, j, k);
          for (int i = lo[0]; i < hi[0]; ++i) {
            const auto q = q0 + i;
            if (open_[q][c]) U[q] -= (P[q] - P[q - st[c]]) * inv_dx;
          }
        }
    }
    const Real inv_dts = 1 / dts;
    for (int k = 0; k < n_.z; ++k)
      for (int j = 0; j < n_.y; ++j)
        for (int i = 0; i < n_.x; ++i) phi_(i, j, k) = psi_(i, j, k) * inv_dts;
  }
  exchange_velocity(u);
}

StepStats MacSolver::next_dt() const {
  StepStats s;
  const Vec3 m = max_speed();
  const Real sum = m.x + m.y + m.z;
  s.dt_cfl = sum > 0 ? p_.cfl * p_.dx / sum : 1e30;
  s.dt_viscous = p_.viscosity > 0 ? p_.diffusion_number * p_.dx * p_.dx / p_.viscosity : 1e30;
  // Harmonic combination: advection moves the RK2 amplification factor off the real axis, where
  // the stable interval on the negative real axis (diffusion) is shorter; min() alone is not
  // enough (seen as a lid-corner instability in the cavity at dt = min of the two limits).
  s.dt = std::min(1 / (1 / s.dt_cfl + 1 / s.dt_viscous), p_.dt_max);
  if (p_.fixed_dt > 0) s.dt = p_.fixed_dt;
  return s;
}

void MacSolver::step(Real dt_limit) {
  stats_ = next_dt();
  stats_.dt = std::min(stats_.dt, dt_limit);
  const Real dt = stats_.dt;
  if (p_.scheme == TimeScheme::kEuler) {
    predict(u_, u_, 0.0, dt, ustar_);
    project(ustar_, dt);
    std::copy(ustar_.data(), ustar_.data() + 3 * ustar_.plane_size(), u_.data());
  } else {
    predict(u_, u_, 0.0, dt, ustar_);
    project(ustar_, dt);
    predict(ustar_, u_, 0.5, dt, u_);
    project(u_, 0.5 * dt);
  }
  time_ += dt;
  ++step_;
  stats_.max_divergence = relative_divergence();
}

Vec3 MacSolver::max_speed() const {
  double m[3] = {0, 0, 0}, g[3];
  for (int c = 0; c < 3; ++c) {
    const Real* U = u_.component(c);
    for (int k = 0; k < n_.z; ++k)
      for (int j = 0; j < n_.y; ++j)
        for (int i = 0; i <= n_.x; ++i) m[c] = std::max(m[c], std::fabs(U[u_.index(i, j, k)]));
  }
  MPI_Allreduce(m, g, 3, MPI_DOUBLE, MPI_MAX, d_.comm());
  return {g[0], g[1], g[2]};
}

template <class Visit>
void MacSolver::for_each_cell_divergence(Visit&& visit) const {
  const std::ptrdiff_t st[3] = {1, u_.stride_y(), u_.stride_z()};
  for (int k = 0; k < n_.z; ++k)
    for (int j = 0; j < n_.y; ++j)
      for (int i = 0; i < n_.x; ++i) {
        const auto q = u_.index(i, j, k);
        Real dv = 0;
        for (int c = 0; c < 3; ++c) dv += u_.component(c)[q + st[c]] - u_.component(c)[q];
        visit(dv / p_.dx);
      }
}

std::vector<double> MacSolver::divergence() const {
  std::vector<double> out;
  out.reserve(n_.product());
  for_each_cell_divergence([&](Real div) { out.push_back(div); });
  return out;
}

Real MacSolver::relative_divergence() const {
  double m = 0;  // no per-cell vector: this runs after every step
  for_each_cell_divergence([&](Real div) { m = std::max(m, std::fabs(div)); });
  m = allreduce(m, MPI_MAX, d_.comm());
  const Vec3 s = max_speed();
  const Real umax = std::max({s.x, s.y, s.z});
  return umax > 0 ? m * p_.dx / umax : m;
}

std::vector<double> MacSolver::cell_velocity() const {
  std::vector<double> out;
  out.reserve(3 * n_.product());
  const std::ptrdiff_t st[3] = {1, u_.stride_y(), u_.stride_z()};
  for (int k = 0; k < n_.z; ++k)
    for (int j = 0; j < n_.y; ++j)
      for (int i = 0; i < n_.x; ++i) {
        const auto q = u_.index(i, j, k);
        for (int c = 0; c < 3; ++c)
          out.push_back(0.5 * (u_.component(c)[q] + u_.component(c)[q + st[c]]));
      }
  return out;
}

std::vector<double> MacSolver::vorticity_magnitude() const {
  std::vector<double> out;
  out.reserve(n_.product());
  const std::ptrdiff_t st[3] = {1, u_.stride_y(), u_.stride_z()};
  auto uc = [&](int c, std::ptrdiff_t q) {
    return 0.5 * (u_.component(c)[q] + u_.component(c)[q + st[c]]);
  };
  // d(u_c)/d(x_a) by central differences of cell-centred velocities (an axis of one cell: 0).
  auto der = [&](int c, int a, std::ptrdiff_t q) {
    if (d_.global_cells()[a] == 1) return 0.0;
    return (uc(c, q + st[a]) - uc(c, q - st[a])) / (2 * p_.dx);
  };
  for (int k = 0; k < n_.z; ++k)
    for (int j = 0; j < n_.y; ++j)
      for (int i = 0; i < n_.x; ++i) {
        const auto q = u_.index(i, j, k);
        const Real wx = der(2, 1, q) - der(1, 2, q);
        const Real wy = der(0, 2, q) - der(2, 0, q);
        const Real wz = der(1, 0, q) - der(0, 1, q);
        out.push_back(std::sqrt(wx * wx + wy * wy + wz * wz));
      }
  return out;
}

std::vector<double> MacSolver::cell_pressure() const {
  std::vector<double> out;
  out.reserve(n_.product());
  for (int k = 0; k < n_.z; ++k)
    for (int j = 0; j < n_.y; ++j)
      for (int i = 0; i < n_.x; ++i) out.push_back(phi_(i, j, k));
  return out;
}

Real MacSolver::kinetic_energy() const {
  double e = 0;
  const auto v = cell_velocity();
  for (double x : v) e += 0.5 * x * x;
  return allreduce(e * p_.dx * p_.dx * p_.dx, MPI_SUM, d_.comm());
}

bool MacSolver::finite() const {
  int ok = 1;
  for (int c = 0; c < 3 && ok; ++c)
    for (int k = 0; k < n_.z && ok; ++k)
      for (int j = 0; j < n_.y && ok; ++j)
        for (int i = 0; i < n_.x; ++i)
          if (!std::isfinite(u_(i, j, k, c))) {
            ok = 0;
            break;
          }
  int g = 0;
  MPI_Allreduce(&ok, &g, 1, MPI_INT, MPI_MIN, d_.comm());
  return g == 1;
}

std::vector<double> MacSolver::boundary_face_rows() const {
  std::vector<double> rows;
  const auto lo = d_.local_box().lo;
  for (int a = 0; a < 3; ++a) {
    if (!bounded_high(a)) continue;
    int l[3] = {0, 0, 0}, h[3] = {n_.x, n_.y, n_.z};
    l[a] = n_[a];
    h[a] = n_[a] + 1;
    for (int k = l[2]; k < h[2]; ++k)
      for (int j = l[1]; j < h[1]; ++j)
        for (int i = l[0]; i < h[0]; ++i)
          rows.insert(rows.end(), {double(a), double(lo.x + i), double(lo.y + j), double(lo.z + k),
                                   u_(i, j, k, a)});
  }
  return rows;
}

void MacSolver::set_boundary_face_rows(const std::vector<double>& rows) {
  const auto& box = d_.local_box();
  for (std::size_t r = 0; r + 5 <= rows.size(); r += 5) {
    const int a = static_cast<int>(rows[r]);
    const int g[3] = {static_cast<int>(rows[r + 1]), static_cast<int>(rows[r + 2]),
                      static_cast<int>(rows[r + 3])};
    if (!bounded_high(a) || g[a] != box.hi[a]) continue;
    bool mine = true;
    for (int b = 0; b < 3; ++b)
      if (b != a && (g[b] < box.lo[b] || g[b] >= box.hi[b])) mine = false;
    if (mine) u_(g[0] - box.lo.x, g[1] - box.lo.y, g[2] - box.lo.z, a) = rows[r + 4];
  }
}

}  // namespace biota::solvers::mac
