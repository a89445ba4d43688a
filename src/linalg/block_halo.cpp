#include "linalg/block_halo.hpp"

#include <algorithm>

namespace biota::linalg {

BlockHalo::BlockHalo(MPI_Comm comm, const GhostedBlock& block,
                     std::array<std::array<int, 2>, 3> neighbors)
    : comm_(comm), b_(block), nb_(neighbors) {
  const int w = block.width;
  const core::Index3 g{block.n.x + 2 * w, block.n.y + 2 * w, block.n.z + 2 * w};
  const std::size_t largest =
      std::max({std::size_t(g.y) * g.z, std::size_t(g.x) * g.z, std::size_t(g.x) * g.y});
  send_.resize(largest * w);
  recv_.resize(largest * w);
}

void BlockHalo::exchange(std::vector<double>& a) {
  const core::Index3 n = b_.n;
  const int w = b_.width;
  for (int ax = 0; ax < 3; ++ax) {
    // Slab ranges: earlier axes over their ghosts too (edges and corners), later axes owned only.
    int lo[3], hi[3];
    for (int d = 0; d < 3; ++d) {
      lo[d] = d < ax ? -w : 0;
      hi[d] = d < ax ? n[d] + w : n[d];
    }
    for (int side = 0; side < 2; ++side) {
      const int to = nb_[ax][side], from = nb_[ax][1 - side];
      if (to == MPI_PROC_NULL && from == MPI_PROC_NULL) continue;
      // Send the owned layers next to `side` to that neighbour, receive their counterparts from
      // the other side into our ghost layers there.
      const int src_layer = side ? n[ax] - w : 0, dst_layer = side ? -w : n[ax];
      auto slab = [&](int layer, auto&& f) {
        int l[3] = {lo[0], lo[1], lo[2]}, h[3] = {hi[0], hi[1], hi[2]};
        l[ax] = layer;
        h[ax] = layer + w;
        std::size_t q = 0;
        for (int k = l[2]; k < h[2]; ++k)
          for (int j = l[1]; j < h[1]; ++j)
            for (int i = l[0]; i < h[0]; ++i, ++q) f(b_.index(i, j, k), q);
        return q;
      };
      std::size_t count = 0;
      if (to != MPI_PROC_NULL)
        count = slab(src_layer, [&](std::ptrdiff_t c, std::size_t q) { send_[q] = a[c]; });
      else
        count = slab(src_layer, [](std::ptrdiff_t, std::size_t) {});
      MPI_Sendrecv(send_.data(), to == MPI_PROC_NULL ? 0 : int(count), MPI_DOUBLE, to, 71 + side,
                   recv_.data(), from == MPI_PROC_NULL ? 0 : int(count), MPI_DOUBLE, from,
                   71 + side, comm_, MPI_STATUS_IGNORE);
      if (from != MPI_PROC_NULL)
        slab(dst_layer, [&](std::ptrdiff_t c, std::size_t q) { a[c] = recv_[q]; });
    }
  }
}

}  // namespace biota::linalg
