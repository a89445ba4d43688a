#include "grid/ghost_fold.hpp"

namespace biota::grid {

template <class F>
void GhostFold::for_slab(int axis, int start, const std::vector<int>& comps, F&& f) {
  const int g = field_->ghosts();
  int lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = -g;
    hi[a] = field_->cells()[a] + g;
  }
  lo[axis] = start;
  hi[axis] = start + g;
  for (int c : comps) {
    core::Real* base = field_->component(c);
    for (int k = lo[2]; k < hi[2]; ++k)
      for (int j = lo[1]; j < hi[1]; ++j) {
        core::Real* row = base + field_->index(0, j, k);
        for (int i = lo[0]; i < hi[0]; ++i) f(row[i]);
      }
  }
}

GhostFold::GhostFold(const Decomposition& decomp, Field<core::Real>& field, FaceComponents faces)
    : decomp_(decomp), field_(&field), faces_(std::move(faces)) {
  const int g = field.ghosts();
  for (int axis = 0; axis < 3; ++axis) {
    Pass& p = passes_[axis];
    long long layer = g;
    for (int a = 0; a < 3; ++a)
      if (a != axis) layer *= field.cells()[a] + 2 * g;
    for (int side = 0; side < 2; ++side) {
      // I send my ghosts at side s; the neighbour there receives them into its owned layer at
      // its side 1-s, so what I receive at side s are the neighbour's ghosts of side 1-s. A side
      // without a neighbour has no buffers (its requests carry 0 values to MPI_PROC_NULL).
      if (decomp.neighbor(axis, side) == MPI_PROC_NULL) continue;
      p.send[side].resize(layer * faces_[axis][side].size());
      p.recv[side].resize(layer * faces_[axis][1 - side].size());
    }
    const int tag = 200 + axis * 2;
    MPI_Comm comm = decomp.comm();
    if (overlap_axis_ < 0 &&
        (decomp.neighbor(axis, 0) != MPI_PROC_NULL || decomp.neighbor(axis, 1) != MPI_PROC_NULL))
      overlap_axis_ = axis;
    for (int side = 0; side < 2; ++side) {
      const int nb = decomp.neighbor(axis, side);
      MPI_Recv_init(p.recv[side].data(), static_cast<int>(p.recv[side].size()), MPI_DOUBLE, nb,
                    tag + (1 - side), comm, &p.requests[side]);
      MPI_Send_init(p.send[side].data(), static_cast<int>(p.send[side].size()), MPI_DOUBLE, nb,
                    tag + side, comm, &p.requests[2 + side]);
    }
  }
}

GhostFold::~GhostFold() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (finalized) return;
  for (auto& p : passes_)
    for (auto& r : p.requests)
      if (r != MPI_REQUEST_NULL) MPI_Request_free(&r);
}

void GhostFold::start_pass(int axis) {
  const int g = field_->ghosts(), n = field_->cells()[axis];
  Pass& p = passes_[axis];
  MPI_Startall(2, p.requests.data());
  for (int side = 0; side < 2; ++side) {
    if (decomp_.neighbor(axis, side) == MPI_PROC_NULL) continue;
    core::Real* out = p.send[side].data();
    for_slab(axis, side == 0 ? -g : n, faces_[axis][side], [&](core::Real& v) { *out++ = v; });
  }
  MPI_Startall(2, p.requests.data() + 2);
}

void GhostFold::finish_pass(int axis) {
  const int g = field_->ghosts(), n = field_->cells()[axis];
  Pass& p = passes_[axis];
  MPI_Waitall(4, p.requests.data(), MPI_STATUSES_IGNORE);
  for (int side = 0; side < 2; ++side) {
    if (decomp_.neighbor(axis, side) == MPI_PROC_NULL) continue;
    const core::Real* in = p.recv[side].data();
    for_slab(axis, side == 0 ? 0 : n - g, faces_[axis][1 - side],
             [&](core::Real& v) { v = *in++; });
  }
}

// Passes run z, then y, then x; those before the overlapped one (the lowest axis with a
// neighbour) have to land first, as later passes carry what they wrote.
void GhostFold::begin() {
  for (int axis = 2; axis > overlap_axis_; --axis) {
    start_pass(axis);
    finish_pass(axis);
  }
  if (overlap_axis_ >= 0) start_pass(overlap_axis_);
}

void GhostFold::end() {
  if (overlap_axis_ >= 0) finish_pass(overlap_axis_);
}

}  // namespace biota::grid
