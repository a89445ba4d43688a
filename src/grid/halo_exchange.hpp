#pragma once
#include <array>
#include <string>
/// \file halo_exchange.hpp
/// \brief Ghost-layer exchange of a Field with persistent MPI requests.
///
/// Three passes, x then y then z; each later pass also carries the ghost cells filled by the
/// earlier ones, so edges and corners are correct with 6 messages. Which components cross each face
/// is configurable: the LBM sends only the populations that stream into the neighbour.
#include <mpi.h>

#include <array>
#include <vector>

#include "core/comm_counter.hpp"
#include "grid/decomposition.hpp"
#include "grid/field.hpp"

namespace biota::grid {

/// \brief Components to fill, per ghost side: [axis][0 = low ghosts, 1 = high ghosts].
using FaceComponents = std::array<std::array<std::vector<int>, 2>, 3>;

/// \brief All components on every face.
FaceComponents all_components(int ncomp);

/// \brief Throws core::InputError (the same on every rank, so no rank is left in a collective)
/// when some rank's block along an axis with neighbours is thinner than `ghosts` cells: the
/// neighbour would pack its own stale ghosts into our halo. `keys` names the deck and the keys that
/// set the cell counts per axis (for the message).
void check_halo_width(const Decomposition& decomp, int ghosts, const GridKeys& keys = {});

/// \brief Fills the ghost layers of one field from its neighbours (and periodic images).
class HaloExchange {
 public:
  HaloExchange(const Decomposition& decomp, Field<core::Real>& field, FaceComponents faces);
  HaloExchange(const Decomposition& decomp, Field<core::Real>& field)
      : HaloExchange(decomp, field, all_components(field.ncomp())) {}
  ~HaloExchange();
  HaloExchange(const HaloExchange&) = delete;
  HaloExchange& operator=(const HaloExchange&) = delete;

  /// \brief Copy owned boundary layers into the neighbours' ghost layers.
  void exchange() {
    begin();
    end();
  }
  /// \brief The exchange split for overlap with computation: `begin` completes the passes before
  /// the last axis with a neighbour (`overlap_axis`), then packs and starts that one; `end` waits
  /// for it and fills its ghost layers. Between the two, the field's owned cells may be read and
  /// written except the layer next to that axis's faces (packed) and its ghosts (filled by end).
  void begin();
  void end();
  /// \brief The axis whose pass `begin` leaves in flight; -1 when no axis has a neighbour.
  int overlap_axis() const { return overlap_axis_; }
  /// \brief The reverse: add every ghost layer into the owner's cells, then zero the ghosts.
  /// Used when particles spread forces into ghost cells (z, then y, then x pass).
  void reverse_sum();
  /// \brief Point at another field of the same shape (e.g. after swapping LBM buffers).
  void rebind(Field<core::Real>& field) { field_ = &field; }
  /// \brief Messages and bytes this rank has sent (exchange and reverse_sum; none to
  /// MPI_PROC_NULL).
  const core::CommCounter& sent() const { return sent_; }

 private:
  using Buffers = std::array<std::vector<core::Real>, 2>;  ///< [side]
  struct Pass {
    // side s: send buffer holds my layer adjacent to face s; recv buffer fills ghosts at side s.
    Buffers send, recv;
    std::array<MPI_Request, 4> requests{MPI_REQUEST_NULL, MPI_REQUEST_NULL, MPI_REQUEST_NULL,
                                        MPI_REQUEST_NULL};
    Buffers rsend, rrecv;
    std::array<MPI_Request, 4> rrequests{MPI_REQUEST_NULL, MPI_REQUEST_NULL, MPI_REQUEST_NULL,
                                         MPI_REQUEST_NULL};
  };
  // Range of local indices a pass covers on axis a (interior for later axes, ghosts for earlier).
  void pass_range(int pass_axis, int a, int& lo, int& hi) const;
  // Cells of the slab a pass on `axis` carries per side (ghosts x the pass_range of the others).
  long long slab_cells(int axis) const;
  // Visit the slab of `width` layers starting at local index `start` on `axis`, in pass order.
  template <class F>
  void for_slab(int axis, int start, const std::vector<int>& comps, F&& f);
  void start_pass(int axis);
  void finish_pass(int axis);
  // Persistent requests of one pass's buffers (empty on a side without a neighbour).
  void init_requests(int axis, Buffers& send, Buffers& recv, int tag,
                     std::array<MPI_Request, 4>& requests);
  void init_reverse();

  const Decomposition& decomp_;
  Field<core::Real>* field_;
  FaceComponents faces_;
  std::vector<int> all_components_;  ///< 0..ncomp-1, what reverse_sum carries
  std::array<Pass, 3> passes_;
  int overlap_axis_ = -1;
  bool reverse_ready_ = false;  ///< reverse_sum's buffers and requests exist
  core::CommCounter sent_;
};

}  // namespace biota::grid
