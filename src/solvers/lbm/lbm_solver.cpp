#include "solvers/lbm/lbm_solver.hpp"

#include <fmt/format.h>
#include <mpi.h>

#include <algorithm>
#include <bit>
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
void macroscopic_fields(const grid::Field<Real>& layout, const grid::Box& cells,
                        const double* const* post, const std::uint8_t* solid,
                        const double* const* force, const double* gl, double* const* out) {
  for (int k = cells.lo.z; k < cells.hi.z; ++k)
    for (int j = cells.lo.y; j < cells.hi.y; ++j) {
      const std::ptrdiff_t row = layout.index(cells.lo.x, j, k);
      for (std::ptrdiff_t c = row; c < row + (cells.hi.x - cells.lo.x); ++c) {
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

void LbmSolver::update_macroscopic() {
  const grid::Box all{{0, 0, 0}, decomp_.local_cells()};
  update_macroscopic(std::span<const grid::Box>(&all, 1));
}

void LbmSolver::update_macroscopic(std::span<const grid::Box> regions) {
  const double* post[32];
  post_view(post);
  const Vec3& g = params_.body_force;
  const double gl[3] = {units_.force_density_to_lattice(g.x), units_.force_density_to_lattice(g.y),
                        units_.force_density_to_lattice(g.z)};
  const double* force[3] = {nullptr, nullptr, nullptr};
  if (use_force_field_)
    for (int a = 0; a < 3; ++a) force[a] = force_.component(a);
  double* out[4] = {rho_.component(0), u_.component(0), u_.component(1), u_.component(2)};
  const Index3 n = decomp_.local_cells();
  for (const grid::Box& r : regions) {
    const grid::Box cells{{std::max(r.lo.x, 0), std::max(r.lo.y, 0), std::max(r.lo.z, 0)},
                          {std::min(r.hi.x, n.x), std::min(r.hi.y, n.y), std::min(r.hi.z, n.z)}};
    if (cells.lo.x >= cells.hi.x || cells.lo.y >= cells.hi.y || cells.lo.z >= cells.hi.z) continue;
    if (params_.lattice == "D3Q15")
      macroscopic_fields<D3Q15>(f_, cells, post, solid_.data(), force, gl, out);
    else
      macroscopic_fields<D3Q19>(f_, cells, post, solid_.data(), force, gl, out);
  }
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

void LbmSolver::sweep(bool macro, int begin, int end) {
  const Index3 n = decomp_.local_cells();
  int j0 = 0, j1 = n.y, k0 = 0, k1 = n.z;
  if (end >= 0) (overlap_axis_ == 1 ? j0 : k0) = begin;
  if (end >= 0) (overlap_axis_ == 1 ? j1 : k1) = end;
  sweep_rows(macro, !streamed_, j0, j1, k0, k1);
}

void LbmSolver::sweep_rows(bool macro, bool from_post, int j0, int j1, int k0, int k1) {
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
  a.j_begin = j0, a.j_end = j1, a.k_begin = k0, a.k_end = k1;
  if (a.j_begin >= a.j_end || a.k_begin >= a.k_end) return;
  if (use_force_field_) {
    if (force_spans_stale_) update_force_spans();
    a.force_lo = force_lo_.data();
    a.force_hi = force_hi_.data();
  }
  ForceMode fm = use_force_field_                        ? ForceMode::kField
                 : (bf.x != 0 || bf.y != 0 || bf.z != 0) ? ForceMode::kUniform
                                                         : ForceMode::kNone;
  SweepFn fn = params_.lattice == "D3Q15"
                   ? pick1<D3Q15>(params_.trt, fm, from_post, macro, has_solids_)
                   : pick1<D3Q19>(params_.trt, fm, from_post, macro, has_solids_);
  fn(a);
}

void LbmSolver::update_force_spans() {
  // A bit test, not `!= 0`: a -0 component must be loaded (uniform + (-0) and uniform + 0.0
  // differ when the uniform part is -0).
  const Index3 n = decomp_.local_cells();
  force_lo_.assign(static_cast<std::size_t>(n.y) * n.z, n.x);
  force_hi_.assign(force_lo_.size(), n.x);
  const double* fc[3] = {force_.component(0), force_.component(1), force_.component(2)};
  for (int k = 0; k < n.z; ++k)
    for (int j = 0; j < n.y; ++j) {
      const std::ptrdiff_t row = f_.index(0, j, k);
      auto carries = [&](int i) {
        return std::bit_cast<std::uint64_t>(fc[0][row + i]) != 0 ||
               std::bit_cast<std::uint64_t>(fc[1][row + i]) != 0 ||
               std::bit_cast<std::uint64_t>(fc[2][row + i]) != 0;
      };
      int lo = 0, hi = n.x;
      while (lo < n.x && !carries(lo)) ++lo;
      while (hi > lo && !carries(hi - 1)) --hi;
      const std::size_t r = j + static_cast<std::size_t>(n.y) * k;
      if (lo < hi) force_lo_[r] = lo, force_hi_[r] = hi;
    }
  force_spans_stale_ = false;
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
  // Whether to overlap is a timed choice (overlap_choice_), made on the neighbour steps without
  // the update. Its decision is collective, so every rank of a grid with one cut axis times and
  // records the way asked for, also a rank whose bands do not allow the overlap (overlap_ is
  // per rank; it steps plainly either way).
  const bool timed = neighbour_step && overlap_axis_ >= 0 && !update_macro;
  const bool want_overlap = timed ? overlap_choice_.pick() : overlap_choice_.chosen();
  const bool overlapped = neighbour_step && overlap_ && want_overlap;
  const double ts = timed ? MPI_Wtime() : 0;
  if (overlapped) {
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
    if (neighbour_step) apply_boundaries(late_plan_);  // empty unless overlap_ (all links then)
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
  if (timed && overlap_choice_.record(want_overlap, MPI_Wtime() - ts, decomp_.comm()))
    report_choice(overlap_choice_, "neighbour steps", "overlap their halo exchange",
                  "exchange before the sweep", "overlapped", "not");
}

void LbmSolver::report_choice(const TimedChoice& c, const char* what, const char* if_true,
                              const char* if_false, const char* true_is,
                              const char* false_is) const {
  if (!params_.report_choices || decomp_.rank() != 0) return;
  fmt::print("lbm: {} {} ({:.2f} ms {}, {:.2f} ms {}, best of {} each)\n", what,
             c.chosen() ? if_true : if_false, 1e3 * c.best(true), true_is, 1e3 * c.best(false),
             false_is, c.trials());
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
  // Natural order on either parity, so a restart onto any rank count continues bitwise; one
  // direction at a time, so the checkpoint takes one direction's memory, not a second copy.
  const Index3 n = decomp_.local_cells();
  const double* post[32];
  post_view(post);
  w.write_components("lbm_populations", nq_, [&](int q, double* block) {
    for (int k = 0; k < n.z; ++k)
      for (int j = 0; j < n.y; ++j)
        for (int i = 0; i < n.x; ++i) {
          const std::ptrdiff_t c = f_.index(i, j, k);
          *block++ = solid_[c] ? w_[q] : post[q][c];
        }
  });
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
  r.read_components("lbm_populations", nq_, [&](int q, const double* block) {
    for (int k = 0; k < n.z; ++k)
      for (int j = 0; j < n.y; ++j)
        for (int i = 0; i < n.x; ++i) f_(i, j, k, opp_[q]) = *block++;
  });
  streamed_ = false;
  step_ = r.read_attribute_int("lbm_step");
  update_macroscopic();
}

}  // namespace biota::solvers::lbm
