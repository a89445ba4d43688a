#pragma once
/// \file remote_samples.hpp
/// \brief Grid <-> point transfer for points owned by a rank other than the one whose box holds
/// them (e.g. the nodes of a tree owned whole by one rank but spanning several ranks' boxes).
///
/// The owner hands its points (global id, position) over; they travel as particles of a
/// particles::ParticleSet to the rank whose box holds them (ParticleComm::redistribute), are
/// interpolated or spread there with any transfer of the particle_transfer.hpp interface
/// (TrilinearCoupling, MacCoupling), and interpolated values travel back to the owner the same
/// way (the particle's position is swapped for the centre of the owner's box); points already in
/// the owner's box are interpolated in place. Spreading uses
/// coupling::spread_from_particles on the spatial owners' owned and ghost particles, so each
/// cell sums the same terms in the same order on any rank count: bitwise rank-count independent
/// like the rest of the coupling.
///
/// Cost per call: one (interpolate: two) all-to-all redistributions, plus a ghost build within
/// transfer.reach() for spreading.
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "coupling/particle_transfer.hpp"
#include "particles/particle_comm.hpp"

namespace biota::coupling {

/// \brief Interpolation and spreading at points owned anywhere; see the file comment.
class RemoteSamples {
 public:
  explicit RemoteSamples(particles::ParticleComm& comm)
      : comm_(comm), set_(make_layout(a_home_, a_value_, u_slot_)) {}

  /// \brief out[n] = scale * t.interpolate_at(field, at[n]) for this rank's points (any
  /// position in or outside its box). Collective; field ghosts must be current.
  template <class Transfer>
  std::vector<core::Vec3> interpolate(const Transfer& t, const grid::Field<core::Real>& field,
                                      const std::vector<core::GlobalId>& ids,
                                      const std::vector<core::Vec3>& at, core::Real scale = 1) {
    // Points inside this rank's box are interpolated here (a pure function of the point, so
    // the same value as on any other rank); only the others travel.
    std::vector<core::Vec3> out(ids.size());
    std::vector<core::GlobalId> rid;
    std::vector<core::Vec3> rat;
    std::vector<std::size_t> rslot;
    const core::Vec3 lo = comm_.lo(), hi = comm_.hi();
    for (std::size_t n = 0; n < ids.size(); ++n) {
      const core::Vec3& p = at[n];
      if (p.x >= lo.x && p.x < hi.x && p.y >= lo.y && p.y < hi.y && p.z >= lo.z && p.z < hi.z) {
        out[n] = t.interpolate_at(field, p) * scale;
      } else {
        rid.push_back(ids[n]);
        rat.push_back(p);
        rslot.push_back(n);
      }
    }
    load(rid, rat);
    const core::Vec3 home = 0.5 * (lo + hi);
    for (std::size_t i = 0; i < set_.n_owned(); ++i) set_.set_vec3(a_home_, i, home);
    comm_.redistribute(set_);  // to the rank whose box holds the point
    interpolate_to_particles(t, field, set_, particles::ParticleSet::kPos, a_value_, scale);
    for (std::size_t i = 0; i < set_.n_owned(); ++i) {  // back to the owner
      const core::Vec3 p = set_.pos(i);
      set_.set_pos(i, set_.vec3(a_home_, i));
      set_.set_vec3(a_home_, i, p);
    }
    comm_.redistribute(set_);
    if (set_.n_owned() != rid.size())
      throw std::logic_error("RemoteSamples: points lost on the way back to their owner");
    for (std::size_t i = 0; i < set_.n_owned(); ++i)
      out[rslot[set_.u64(u_slot_)[i]]] = set_.vec3(a_value_, i);
    return out;
  }

  /// \brief Add scale * values[n] at at[n] into `field` with t.spread_owned_at on the ranks
  /// whose owned cells the stencil touches (no reverse halo sum needed). Collective.
  template <class Transfer>
  void spread(const Transfer& t, grid::Field<core::Real>& field,
              const std::vector<core::GlobalId>& ids, const std::vector<core::Vec3>& at,
              const std::vector<core::Vec3>& values, core::Real scale = 1) {
    load(ids, at);
    for (std::size_t i = 0; i < set_.n_owned(); ++i) set_.set_vec3(a_value_, i, values[i]);
    comm_.redistribute(set_);
    comm_.build_ghosts(set_, t.reach());
    spread_from_particles(t, field, set_, particles::ParticleSet::kPos, a_value_, scale);
  }

  const core::CommCounter& sent() const { return comm_.sent(); }

 private:
  static particles::ParticleLayout make_layout(int& home, int& value, int& slot) {
    particles::ParticleLayout l;
    home = l.add_real("home", 3, true, false);
    value = l.add_real("value", 3, true, true);
    slot = l.add_u64("slot", 1, true, false);
    return l;
  }
  void load(const std::vector<core::GlobalId>& ids, const std::vector<core::Vec3>& at) {
    if (ids.size() != at.size()) throw std::invalid_argument("RemoteSamples: ids/at sizes");
    set_.resize(0, 0);  // drop everything, then one resize (zeroed columns)
    set_.resize(ids.size(), ids.size());
    std::uint64_t* id = set_.u64(particles::ParticleSet::kId);
    std::uint64_t* slot = set_.u64(u_slot_);
    for (std::size_t n = 0; n < ids.size(); ++n) {
      id[n] = ids[n];
      slot[n] = n;
      set_.set_pos(n, at[n]);
    }
  }

  particles::ParticleComm& comm_;
  int a_home_ = 0, a_value_ = 0, u_slot_ = 0;
  particles::ParticleSet set_;
};

}  // namespace biota::coupling
