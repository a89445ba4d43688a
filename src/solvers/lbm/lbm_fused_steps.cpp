/// \file lbm_fused_steps.cpp
/// \brief Two AA steps fused plane by plane (temporal blocking of a neighbour step and the local
/// step after it). See advance() and docs/lbm.md.
#include <fmt/format.h>

#include <algorithm>

#include "solvers/lbm/lbm_solver.hpp"

namespace biota::solvers::lbm {

void LbmSolver::advance(int steps, PairMode mode) {
  int s = 0;
  if (streamed_ && s < steps) step(false), ++s;  // reach the post state: pairs start there
  for (; s + 2 <= steps; s += 2) {
    // Pairs are timed for the choice only while the single steps are not in their own trial of
    // the halo overlap (a single pair would then mix both ways); during that trial the pairs run
    // as single steps, so that it ends. Every rank times and records the way asked for, also a
    // rank that cannot fuse (its local size or boundary links; it steps singly either way): the
    // decision is collective, and the group's time under each request is what counts.
    const bool timed = mode == PairMode::kAuto && !overlap_choice_.deciding();
    const bool want_fused = mode == PairMode::kFused || (timed && fuse_choice_.pick());
    const double t0 = MPI_Wtime();
    if (fused_ && want_fused)
      fused_step_pair();
    else
      step(false), step(false);
    if (timed && fuse_choice_.record(want_fused, MPI_Wtime() - t0, decomp_.comm()) && fused_)
      report_choice(fuse_choice_, "step pairs", "fused plane by plane", "as single steps", "fused",
                    "single per pair");
  }
  if (s < steps) step(false);
}

void LbmSolver::build_fused_plans(const std::vector<Link>& links) {
  // Why the order of fused_step_pair() gives the bits of two sequential steps (k: z plane):
  //  - the neighbour step of plane k reads and writes only planes k-1..k+1, so once it has passed
  //    plane k+1, no later neighbour-step cell touches plane k;
  //  - a local-step link (s -> x, q) writes slot q of the fluid cell x; its value comes from slots
  //    the neighbour step of x or of a fluid cell next to x wrote (the wall value: x itself; zero
  //    gradient, pressure: x's populations in the cells around it; free slip: x's mirror
  //    neighbour), not from the ghost fold (except free slip whose mirror cell is a ghost: those
  //    links are evaluated after the fold), and those slots change again only in the local step
  //    of the cell holding them (planes k-1..k+1). So the links of plane k are evaluated once the
  //    neighbour step has passed plane k+1 and before the local step of plane k-1;
  //  - the local step of a cell reads and writes only that cell's slots;
  //  - the ghost fold writes slots of the first/last layer along an axis with neighbours only (an
  //    x neighbour would cut every row: no fusion then), and may overwrite a link's target there:
  //    those cells take their local step after the fold, and their links' values, evaluated in
  //    the wavefront, are stored after it.
  const Index3 n = decomp_.local_cells();
  auto has_neighbour = [&](int a) {
    return decomp_.neighbor(a, 0) != MPI_PROC_NULL || decomp_.neighbor(a, 1) != MPI_PROC_NULL;
  };
  deferred_y_ = has_neighbour(1);
  deferred_z_ = has_neighbour(2);
  fused_ = !has_neighbour(0) && n.z >= 3 && (!deferred_y_ || n.y >= 3);
  local_plan_by_z_.assign(fused_ ? n.z : 0, {});
  local_plan_deferred_by_z_.assign(fused_ ? n.z : 0, {});
  if (!fused_) return;
  const std::int64_t g = f_.ghosts(), sy = f_.stride_y(), sz = f_.stride_z();
  auto coords = [&](std::int64_t cell) {  // local cell indices of a field offset
    return Index3{static_cast<int>(cell % sy - g),
                  static_cast<int>((cell / sy) % (n.y + 2 * g) - g),
                  static_cast<int>(cell / sz - g)};
  };
  auto deferred = [&](const Index3& c) {
    return (deferred_y_ && (c.y == 0 || c.y == n.y - 1)) ||
           (deferred_z_ && (c.z == 0 || c.z == n.z - 1));
  };
  local_plan_after_fold_ = {};
  // The same entries as plans_[1], split by their target cell x (links come cell by cell, so each
  // part keeps the pressure links of a cell consecutive).
  for (const Link& l : links) {
    const Index3 x = coords(l.x);
    const bool later = deferred(x);
    // Free slip whose mirror cell is a ghost: its value arrives with the fold.
    const bool after_fold =
        l.type == int(FaceType::kFreeSlip) && !grid::Box{{0, 0, 0}, n}.contains(coords(l.x2));
    if (after_fold && !later) {  // cannot happen with y/z neighbours only; stay sequential
      fused_ = false;
      return;
    }
    add_link(after_fold ? local_plan_after_fold_
             : later    ? local_plan_deferred_by_z_[x.z]
                        : local_plan_by_z_[x.z],
             l, true);
  }
  for (auto& p : local_plan_by_z_) compress_copies(p);
  for (auto& p : local_plan_deferred_by_z_) compress_copies(p);
  compress_copies(local_plan_after_fold_);
}

void LbmSolver::fused_step_pair() {
  const Index3 n = decomp_.local_cells();
  const int jy0 = deferred_y_ ? 1 : 0, jy1 = deferred_y_ ? n.y - 1 : n.y;
  const int kz0 = deferred_z_ ? 1 : 0, kz1 = deferred_z_ ? n.z - 1 : n.z;
  double t0 = MPI_Wtime();
  halo_->exchange();
  double t1 = MPI_Wtime();
  apply_boundaries(plans_[0]);
  apply_boundaries(late_plan_);  // empty unless overlap_
  // From here on the local step's view: its links see the second step's time, and the pressure
  // links read the post-collision populations in the streamed state.
  ++step_;
  streamed_ = true;
  staged_.clear();
  double t2 = MPI_Wtime();
  t_halo_ += t1 - t0;
  t_boundary_ += t2 - t1;
  auto links_of_plane = [&](int k) {
    const double b0 = MPI_Wtime();
    apply_boundaries(local_plan_by_z_[k]);
    stage_boundaries(local_plan_deferred_by_z_[k], staged_);
    t_boundary_ += MPI_Wtime() - b0;
  };
  auto local_step_of_plane = [&](int k) {
    const double c0 = MPI_Wtime();
    if (k >= kz0 && k < kz1) sweep_rows(false, false, jy0, jy1, k, k + 1);
    t_collide_ += MPI_Wtime() - c0;
  };
  for (int k = 0; k < n.z; ++k) {
    const double c0 = MPI_Wtime();
    sweep_rows(false, true, 0, n.y, k, k + 1);
    t_collide_ += MPI_Wtime() - c0;
    if (k >= 1) links_of_plane(k - 1);
    if (k >= 2) local_step_of_plane(k - 2);
  }
  links_of_plane(n.z - 1);
  local_step_of_plane(n.z - 2);
  local_step_of_plane(n.z - 1);
  t0 = MPI_Wtime();
  fold_->fold();
  t1 = MPI_Wtime();
  double* base = f_.component(0);
  for (const auto& [dst, v] : staged_) base[dst] = v;
  apply_boundaries(local_plan_after_fold_);
  t2 = MPI_Wtime();
  if (deferred_y_)
    for (int j : {0, n.y - 1}) sweep_rows(false, false, j, j + 1, kz0, kz1);
  if (deferred_z_)
    for (int k : {0, n.z - 1}) sweep_rows(false, false, 0, n.y, k, k + 1);
  t_halo_ += t1 - t0;
  t_boundary_ += t2 - t1;
  t_collide_ += MPI_Wtime() - t2;
  streamed_ = false;
  ++step_;
  updates_ += 2.0 * static_cast<double>(n.product());
}

}  // namespace biota::solvers::lbm
