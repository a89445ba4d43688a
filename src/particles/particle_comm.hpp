#pragma once
/// \file particle_comm.hpp
/// \brief Particle communication over a grid::Decomposition: migration to face neighbours, global
/// redistribution, ghost build/refresh within a cutoff, and the reverse scatter (sum) of values
/// accumulated on ghosts back to their owners.
///
/// Positions are physical (m); the decomposition's cells have size `dx` and the grid starts at
/// `origin`. A rank owns the particles whose position lies in its box; on a non-periodic axis
/// particles outside the domain stay with the boundary rank. Exchanges run axis by axis (x, y, z)
/// with face neighbours only (LAMMPS comm_brick), so diagonal moves and corner ghosts need no
/// extra messages: ghosts received in pass x are forwarded in passes y and z. Periodic images and
/// wraps shift every position-valued attribute (AttributeSpec::position), not only "x".
#include <mpi.h>

#include <array>
#include <cmath>
#include <vector>

#include "core/comm_counter.hpp"
#include "grid/decomposition.hpp"
#include "particles/particle_set.hpp"

namespace biota::particles {

/// \brief Communication plan and routines for particle sets on one decomposition.
class ParticleComm {
 public:
  ParticleComm(const grid::Decomposition& decomp, Real dx, Vec3 origin = {});

  /// \brief Send owned particles that left this rank's box to their owner through face
  /// neighbours (repeated passes until every particle is home; diagonal moves take one round).
  /// Wraps positions on periodic axes. Drops ghosts. Collective. With keep_order the staying
  /// particles keep their order and the arrivals follow them; without it (for a caller that
  /// reorders its storage anyway) the removal costs only as much as the particles that left.
  void migrate(ParticleSet& set, bool keep_order = true);
  /// \brief Send every owned particle straight to its owner (all-to-all; after setup/restart).
  void redistribute(ParticleSet& set);
  /// \brief Build ghosts: every image of a particle within `cutoff` of this rank's box (periodic
  /// images shifted). Must follow migrate(). Records the plan for update_ghosts/reverse_sum.
  void build_ghosts(ParticleSet& set, Real cutoff);
  /// \brief Refresh the ghost attributes (those flagged `ghost`) from the owners with the plan of
  /// the last build_ghosts (positions shifted for periodic images). Collective.
  void update_ghosts(ParticleSet& set);
  /// \brief Refresh only the listed real and u64 attributes on the ghosts (e.g. the state that
  /// changes between two full refreshes), with the plan of the last build_ghosts. Packs column by
  /// column and sends one message per pass and side (the counts are known from the plan);
  /// position-valued attributes among `reals` are shifted for periodic images. Collective.
  void update_ghosts(ParticleSet& set, const std::vector<int>& reals, const std::vector<int>& u64s);
  /// \brief Add the values of real attributes `attrs` held on ghosts to the owners' values and
  /// zero them on the ghosts (forces computed on ghosts). Collective.
  void reverse_sum(ParticleSet& set, const std::vector<int>& attrs);

  /// \brief Physical box of this rank [lo, hi) and of the whole domain.
  const Vec3& lo() const { return lo_; }
  const Vec3& hi() const { return hi_; }
  const Vec3& domain_lo() const { return glo_; }
  const Vec3& domain_hi() const { return ghi_; }
  const grid::Decomposition& decomposition() const { return decomp_; }
  /// \brief Rank owning the physical point p (clamped on walls, wrapped on periodic axes).
  int owner_of(const Vec3& p) const;
  /// \brief Messages and bytes this rank has sent (face-neighbour passes: one count message and
  /// one payload message per pass and side; redistribute's all-to-all counts one per peer).
  const core::CommCounter& sent() const { return sent_; }
  /// \brief Edge of the decomposition's cells (m).
  Real cell_size() const { return dx_; }

 private:
  // Rank coordinate along axis d of the physical coordinate v. Inline for the common answer
  // "this rank" (migrate asks it per particle): the cell coordinate t = (v - origin) / dx against
  // this rank's cells [a, b), open below on the first rank and above on the last (the block
  // search clamps there), gives the same answer as the block search without its divisions.
  int axis_coord(int d, Real v) const {
    return is_home(d, v) ? decomp_.coords()[d] : block_of_cell(d, (v - origin_[d]) / dx_);
  }
  // Whether v lies in this rank's cells along d (axis_coord's common answer).
  bool is_home(int d, Real v) const {
    const Real t = (v - origin_[d]) / dx_;
    return (t >= home_cells_[d][0] || first_[d]) && (t < home_cells_[d][1] || last_[d]);
  }
  // The block search of axis_coord from the cell coordinate t.
  int block_of_cell(int d, Real t) const;
  Real wrap(int d, Real v) const;
  // wrap() on a periodic axis with box [lo, hi) (static: callers keep the bounds in registers).
  static Real wrap_coord(Real v, Real lo, Real hi);
  // Wrap particle i's position onto the periodic domain, moving its other position-valued
  // attributes by the same shift.
  void wrap_particle(ParticleSet& set, std::size_t i, Real* const x[3]) const;

  struct GhostPass {
    std::vector<std::size_t> send;  // local indices sent
    Real shift = 0;                 // added to coordinate d of what is sent
    std::size_t recv_begin = 0, recv_count = 0;
  };
  const grid::Decomposition& decomp_;
  Real dx_;
  Vec3 origin_, lo_, hi_, glo_, ghi_;
  std::array<std::array<Real, 2>, 3> home_cells_{};  // this rank's first and end cell, per axis
  std::array<bool, 3> first_{}, last_{};             // first / last rank along the axis
  std::array<std::array<GhostPass, 2>, 3> plan_{};   // [axis][side sent to]
  bool have_plan_ = false;
  core::CommCounter sent_;
};

// Inline: migrate() calls it per particle and axis (a call cost as much as the test).
inline Real ParticleComm::wrap_coord(Real v, Real lo, Real hi) {
  const Real L = hi - lo;
  // Inside the box (nearly always): 0 < t < L makes t / L round into [0, 1), so the formula
  // below gives v - L * (+0) = v exactly; skip its division.
  const Real t = v - lo;
  if (t > 0 && t < L && v < hi) return v;
  Real w = v - L * std::floor((v - lo) / L);
  if (w >= hi) w = lo;  // round-off at the top edge
  return w;
}

inline Real ParticleComm::wrap(int d, Real v) const {
  return decomp_.periodic(d) ? wrap_coord(v, glo_[d], ghi_[d]) : v;
}

/// \brief The narrowest rank block (m, cells of `dx`) along the axes the rank grid splits, and
/// its axis; {infinity, -1} if none is split. ParticleComm::build_ghosts needs the ghost cutoff
/// no wider (ghosts come from the neighbouring block only); scenarios compare their cutoff with
/// it at set-up, so their error names the deck keys that set it.
struct SplitBlock {
  double width;
  int axis;
};
SplitBlock thinnest_split_block(const grid::Decomposition& decomp, double dx);

}  // namespace biota::particles
