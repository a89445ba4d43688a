#include "grid/halo_exchange.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "core/error.hpp"

namespace biota::grid {

FaceComponents all_components(int ncomp) {
  FaceComponents f;
  std::vector<int> all(ncomp);
  for (int c = 0; c < ncomp; ++c) all[c] = c;
  for (auto& axis : f) axis = {all, all};
  return f;
}

void HaloExchange::pass_range(int pass_axis, int a, int& lo, int& hi) const {
  const int g = field_->ghosts(), n = field_->cells()[a];
  if (a < pass_axis) {  // already exchanged: include its ghosts
    lo = -g;
    hi = n + g;
  } else {
    lo = 0;
    hi = n;
  }
}

long long HaloExchange::slab_cells(int axis) const {
  long long cells = field_->ghosts();
  for (int a = 0; a < 3; ++a) {
    if (a == axis) continue;
    int lo, hi;
    pass_range(axis, a, lo, hi);
    cells *= (hi - lo);
  }
  return cells;
}

template <class F>
void HaloExchange::for_slab(int axis, int start, const std::vector<int>& comps, F&& f) {
  int lo[3], hi[3];
  for (int a = 0; a < 3; ++a) pass_range(axis, a, lo[a], hi[a]);
  lo[axis] = start;
  hi[axis] = start + field_->ghosts();
  for (int c : comps) {
    core::Real* base = field_->component(c);
    for (int k = lo[2]; k < hi[2]; ++k)
      for (int j = lo[1]; j < hi[1]; ++j) {
        core::Real* row = base + field_->index(0, j, k);
        for (int i = lo[0]; i < hi[0]; ++i) f(row[i]);
      }
  }
}

void check_halo_width(const Decomposition& decomp, int ghosts, const GridKeys& keys) {
  for (int d = 0; d < 3; ++d) {
    const int n = decomp.global_cells()[d], dims = decomp.dims()[d];
    // One rank along a periodic axis exchanges with itself: its 2D (1-cell) cases are uniform
    // along that axis, which the self-copy keeps; only distinct neighbours are checked.
    const int thinnest = decomp.thinnest(d);
    if (dims == 1 || thinnest >= ghosts) continue;
    const std::string key =
        keys.cells[d].empty() ? fmt::format("cells along {}", "xyz"[d]) : keys.cells[d];
    throw core::InputError(fmt::format(
        "{}{} = {} over {} ranks along axis {} ({} ranks in all) gives {}-cell rank blocks, "
        "thinner than the {}-cell halo; use at least {} cells per rank along that axis (at most "
        "{} ranks) or more cells",
        keys.source.empty() ? "" : keys.source + ": ", key, n, dims, d, decomp.size(), thinnest,
        ghosts, ghosts, std::max(1, n / ghosts)));
  }
}

HaloExchange::HaloExchange(const Decomposition& decomp, Field<core::Real>& field,
                           FaceComponents faces)
    : decomp_(decomp), field_(&field), faces_(std::move(faces)) {
  check_halo_width(decomp, field.ghosts());
  for (int c = 0; c < field.ncomp(); ++c) all_components_.push_back(c);
  for (int axis = 0; axis < 3; ++axis) {
    Pass& p = passes_[axis];
    const long long layer = slab_cells(axis);
    for (int side = 0; side < 2; ++side) {
      // Ghosts at my side `side` are filled from the neighbour there with the components listed
      // for that side; what I send across side s feeds the neighbour's ghosts at side 1-s. A side
      // without a neighbour has no buffers (its requests carry 0 values to MPI_PROC_NULL).
      if (decomp.neighbor(axis, side) == MPI_PROC_NULL) continue;
      p.recv[side].resize(layer * faces_[axis][side].size());
      p.send[side].resize(layer * faces_[axis][1 - side].size());
    }
    if (decomp.neighbor(axis, 0) != MPI_PROC_NULL || decomp.neighbor(axis, 1) != MPI_PROC_NULL)
      overlap_axis_ = axis;
    init_requests(axis, p.send, p.recv, 100 + axis * 4, p.requests);
  }
}

void HaloExchange::init_requests(int axis, Buffers& send, Buffers& recv, int tag,
                                 std::array<MPI_Request, 4>& requests) {
  // [side] receives, then [2 + side] sends; a message crossing side s carries tag + s.
  for (int side = 0; side < 2; ++side) {
    const int nb = decomp_.neighbor(axis, side);
    MPI_Recv_init(recv[side].data(), static_cast<int>(recv[side].size()), MPI_DOUBLE, nb,
                  tag + (1 - side), decomp_.comm(), &requests[side]);
    MPI_Send_init(send[side].data(), static_cast<int>(send[side].size()), MPI_DOUBLE, nb,
                  tag + side, decomp_.comm(), &requests[2 + side]);
  }
}

void HaloExchange::init_reverse() {
  // Made on the first reverse_sum: most fields never fold their ghosts back, and these buffers
  // carry every component (an LBM's 19 populations, not the 5 that cross a face).
  reverse_ready_ = true;
  for (int axis = 0; axis < 3; ++axis) {
    Pass& p = passes_[axis];
    const long long layer = slab_cells(axis);
    for (int side = 0; side < 2; ++side) {
      if (decomp_.neighbor(axis, side) == MPI_PROC_NULL) continue;
      p.rsend[side].resize(layer * field_->ncomp());
      p.rrecv[side].resize(layer * field_->ncomp());
    }
    init_requests(axis, p.rsend, p.rrecv, 100 + axis * 4 + 2, p.rrequests);
  }
}

HaloExchange::~HaloExchange() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (finalized) return;
  for (auto& p : passes_)
    for (auto* reqs : {&p.requests, &p.rrequests})
      for (auto& r : *reqs)
        if (r != MPI_REQUEST_NULL) MPI_Request_free(&r);
}

void HaloExchange::start_pass(int axis) {
  const int g = field_->ghosts(), n = field_->cells()[axis];
  Pass& p = passes_[axis];
  MPI_Startall(2, p.requests.data());
  for (int side = 0; side < 2; ++side) {
    if (decomp_.neighbor(axis, side) == MPI_PROC_NULL) continue;
    core::Real* out = p.send[side].data();
    for_slab(axis, side == 0 ? 0 : n - g, faces_[axis][1 - side],
             [&](core::Real& v) { *out++ = v; });
    if (decomp_.neighbor(axis, side) != decomp_.rank())  // periodic image on this rank: no network
      sent_.add(static_cast<long long>(p.send[side].size() * sizeof(core::Real)));
  }
  MPI_Startall(2, p.requests.data() + 2);
}

void HaloExchange::finish_pass(int axis) {
  const int g = field_->ghosts(), n = field_->cells()[axis];
  Pass& p = passes_[axis];
  MPI_Waitall(4, p.requests.data(), MPI_STATUSES_IGNORE);
  for (int side = 0; side < 2; ++side) {
    if (decomp_.neighbor(axis, side) == MPI_PROC_NULL) continue;
    const core::Real* in = p.recv[side].data();
    for_slab(axis, side == 0 ? -g : n, faces_[axis][side], [&](core::Real& v) { v = *in++; });
  }
}

void HaloExchange::begin() {
  // Passes after the overlapped one have no neighbour on either side: nothing to carry.
  for (int axis = 0; axis < overlap_axis_; ++axis) {
    start_pass(axis);
    finish_pass(axis);
  }
  if (overlap_axis_ >= 0) start_pass(overlap_axis_);
}

void HaloExchange::end() {
  if (overlap_axis_ >= 0) finish_pass(overlap_axis_);
}

void HaloExchange::reverse_sum() {
  if (!reverse_ready_) init_reverse();
  const int g = field_->ghosts();
  const std::vector<int>& all = all_components_;
  for (int axis = 2; axis >= 0; --axis) {
    Pass& p = passes_[axis];
    const int n = field_->cells()[axis];
    MPI_Startall(2, p.rrequests.data());
    for (int side = 0; side < 2; ++side) {
      if (decomp_.neighbor(axis, side) == MPI_PROC_NULL) continue;
      core::Real* out = p.rsend[side].data();
      for_slab(axis, side == 0 ? -g : n, all, [&](core::Real& v) {
        *out++ = v;
        v = 0;
      });
      if (decomp_.neighbor(axis, side) != decomp_.rank())
        sent_.add(static_cast<long long>(p.rsend[side].size() * sizeof(core::Real)));
    }
    MPI_Startall(2, p.rrequests.data() + 2);
    MPI_Waitall(4, p.rrequests.data(), MPI_STATUSES_IGNORE);
    for (int side = 0; side < 2; ++side) {
      if (decomp_.neighbor(axis, side) == MPI_PROC_NULL) continue;
      const core::Real* in = p.rrecv[side].data();
      for_slab(axis, side == 0 ? 0 : n - g, all, [&](core::Real& v) { v += *in++; });
    }
  }
}

}  // namespace biota::grid
