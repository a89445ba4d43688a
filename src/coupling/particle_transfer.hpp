#pragma once
/// \file particle_transfer.hpp
/// \brief Grid <-> particle-set loops over any transfer with the point-wise interface of
/// TrilinearCoupling (collocated, LBM) and MacCoupling (staggered faces):
///   Vec3 interpolate_at(const Field&, const Vec3& p) const;
///   void spread_owned_at(Field&, const Vec3& p, const Vec3& value) const;
///   Real reach() const;
/// so scenarios never write these loops themselves.
///
/// Spreading is rank-count independent bit for bit: every rank spreads its owned and ghost
/// particles in (global id, sample position) order into its owned cells only, so each cell sums
/// the same terms in the same order on any decomposition, with no reverse halo sum. This needs
/// every particle whose stencil reaches an owned cell present as owned or ghost: a ghost cutoff
/// of at least transfer.reach() plus the largest displacement since the ghosts were built, and
/// every position-valued attribute used as sample point shifted for periodic images (declare it
/// with ParticleLayout::add_position).
#include <algorithm>
#include <numeric>
#include <tuple>
#include <vector>

#include "grid/field.hpp"
#include "particles/particle_set.hpp"

namespace biota::coupling {

/// \brief For every owned particle i: attribute a_out(i) = scale * interpolate_at(field,
/// a_at(i)). a_at is a 3-component position-valued attribute (ParticleSet::kPos for the
/// position); field ghosts must be current.
template <class Transfer>
void interpolate_to_particles(const Transfer& t, const grid::Field<core::Real>& field,
                              particles::ParticleSet& set, int a_at, int a_out,
                              core::Real scale = 1) {
  for (std::size_t i = 0; i < set.n_owned(); ++i)
    set.set_vec3(a_out, i, t.interpolate_at(field, set.vec3(a_at, i)) * scale);
}

/// \brief The owned cells that interpolate_to_particles() reads for the owned particles at a_at,
/// as one box per cell row (x-range of the row's cells read, unit extent in y and z; rows with no
/// cell read are left out). `cells` is the owned block's extent. Needs a transfer with
/// `grid::Box stencil_box(const Vec3& p) const` (local cell indices).
template <class Transfer>
std::vector<grid::Box> sampled_cell_rows(const Transfer& t, const particles::ParticleSet& set,
                                         int a_at, core::Index3 cells) {
  std::vector<int> lo(static_cast<std::size_t>(cells.y) * cells.z, cells.x), hi(lo.size(), 0);
  for (std::size_t i = 0; i < set.n_owned(); ++i) {
    const grid::Box b = t.stencil_box(set.vec3(a_at, i));
    const int x0 = std::max(b.lo.x, 0), x1 = std::min(b.hi.x, cells.x);
    for (int k = std::max(b.lo.z, 0); k < std::min(b.hi.z, cells.z); ++k)
      for (int j = std::max(b.lo.y, 0); j < std::min(b.hi.y, cells.y); ++j) {
        const std::size_t r = j + static_cast<std::size_t>(cells.y) * k;
        lo[r] = std::min(lo[r], x0);
        hi[r] = std::max(hi[r], x1);
      }
  }
  std::vector<grid::Box> rows;
  for (int k = 0; k < cells.z; ++k)
    for (int j = 0; j < cells.y; ++j) {
      const std::size_t r = j + static_cast<std::size_t>(cells.y) * k;
      if (lo[r] < hi[r]) rows.push_back({{lo[r], j, k}, {hi[r], j + 1, k + 1}});
    }
  return rows;
}

/// \brief Spread scale * a_value(i) at a_at(i) for every owned and ghost particle into this
/// rank's owned cells of `field` (added to what is there), in the fixed order described above.
template <class Transfer>
void spread_from_particles(const Transfer& t, grid::Field<core::Real>& field,
                           const particles::ParticleSet& set, int a_at, int a_value,
                           core::Real scale = 1) {
  std::vector<std::size_t> order(set.n_total());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (set.id(a) != set.id(b)) return set.id(a) < set.id(b);
    const core::Vec3 xa = set.vec3(a_at, a), xb = set.vec3(a_at, b);
    return std::tie(xa.x, xa.y, xa.z) < std::tie(xb.x, xb.y, xb.z);  // periodic images
  });
  for (std::size_t i : order)
    t.spread_owned_at(field, set.vec3(a_at, i), set.vec3(a_value, i) * scale);
}

}  // namespace biota::coupling
