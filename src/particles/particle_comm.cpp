#include "particles/particle_comm.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace biota::particles {

namespace {
constexpr int kTagMigrate = 7100, kTagGhost = 7200, kTagUpdate = 7300, kTagReverse = 7400,
              kTagPartial = 7500;

// Exchange a vector of doubles with a pair of ranks: send `out` to `dest`, receive from `src`.
std::vector<double> sendrecv(const std::vector<double>& out, int dest, int src, int tag,
                             MPI_Comm comm, core::CommCounter& sent) {
  int me = 0;
  MPI_Comm_rank(comm, &me);
  if (dest != MPI_PROC_NULL && dest != me) {  // a periodic image on this rank is no network traffic
    sent.add(sizeof(long long));
    sent.add(static_cast<long long>(out.size() * sizeof(double)));
  }
  long long nout = static_cast<long long>(out.size()), nin = 0;
  MPI_Sendrecv(&nout, 1, MPI_LONG_LONG, dest, tag, &nin, 1, MPI_LONG_LONG, src, tag, comm,
               MPI_STATUS_IGNORE);
  std::vector<double> in(static_cast<std::size_t>(nin));
  MPI_Sendrecv(out.data(), static_cast<int>(nout), MPI_DOUBLE, dest, tag + 1, in.data(),
               static_cast<int>(nin), MPI_DOUBLE, src, tag + 1, comm, MPI_STATUS_IGNORE);
  return in;
}
}  // namespace

ParticleComm::ParticleComm(const grid::Decomposition& decomp, Real dx, Vec3 origin)
    : decomp_(decomp), dx_(dx), origin_(origin) {
  const auto& b = decomp.local_box();
  for (int d = 0; d < 3; ++d) {
    lo_[d] = origin[d] + b.lo[d] * dx;
    hi_[d] = origin[d] + b.hi[d] * dx;
    glo_[d] = origin[d];
    ghi_[d] = origin[d] + decomp.global_cells()[d] * dx;
    home_cells_[d] = {Real(b.lo[d]), Real(b.hi[d])};
    first_[d] = decomp.coords()[d] == 0;
    last_[d] = decomp.coords()[d] == decomp.dims()[d] - 1;
  }
}

int ParticleComm::block_of_cell(int d, Real t) const {
  const int n = decomp_.global_cells()[d];
  const Real c = std::floor(t);  // clamped as a real first: no overflow far outside
  return decomp_.block_of(d, c < 0 ? 0 : (c >= n ? n - 1 : static_cast<int>(c)));
}

int ParticleComm::owner_of(const Vec3& p) const {
  int c[3];
  for (int d = 0; d < 3; ++d) c[d] = axis_coord(d, wrap(d, p[d]));
  int r = 0;
  MPI_Cart_rank(decomp_.comm(), c, &r);
  return r;
}

void ParticleComm::wrap_particle(ParticleSet& set, std::size_t i, Real* const x[3]) const {
  for (int d = 0; d < 3; ++d) {
    const Real w = wrap(d, x[d][i]);
    if (w == x[d][i]) continue;
    const Real shift = w - x[d][i];
    x[d][i] = w;
    for (int a : set.extra_positions()) set.real(a, d)[i] += shift;
  }
}

void ParticleComm::migrate(ParticleSet& set, bool keep_order) {
  set.clear_ghosts();
  have_plan_ = false;
  MPI_Comm comm = decomp_.comm();
  const int w = set.pack_width(false);
  Real* x[3] = {set.real(ParticleSet::kPos, 0), set.real(ParticleSet::kPos, 1),
                set.real(ParticleSet::kPos, 2)};
  // Axis by axis (each coordinate wraps on its own): a particle inside the box along d, nearly
  // all of them, costs wrap()'s subtraction and three comparisons.
  for (int d = 0; d < 3; ++d) {
    if (!decomp_.periodic(d)) continue;
    Real* xd = x[d];
    const Real lo = glo_[d], hi = ghi_[d];  // locals: the stores below cannot change them
    for (std::size_t i = 0, n = set.n_owned(); i < n; ++i) {
      const Real v = xd[i], w = wrap_coord(v, lo, hi);
      if (w == v) continue;
      xd[i] = w;
      for (int a : set.extra_positions()) set.real(a, d)[i] += w - v;
    }
  }
  bool split[3];
  for (int d = 0; d < 3; ++d) split[d] = decomp_.dims()[d] > 1;
  for (int round = 0;; ++round) {
    if (round > 64) throw std::runtime_error("ParticleComm::migrate did not converge");
    // Particles not yet home after this round: only arrivals can be (a particle that stays was
    // home along every split axis). An arrival along axis d is tested here along the axes up to
    // d; the later axes of the round test it as they test every particle.
    long long away = 0;
    for (int d = 0; d < 3; ++d) {
      const int dims = decomp_.dims()[d], me = decomp_.coords()[d];
      if (dims == 1) continue;
      std::array<std::vector<double>, 2> out;
      std::vector<char> gone(set.n_owned(), 0);
      bool any_gone = false;
      for (std::size_t i = 0; i < set.n_owned(); ++i) {
        int delta = axis_coord(d, set.real(ParticleSet::kPos, d)[i]) - me;
        if (delta == 0) continue;
        if (decomp_.periodic(d)) {  // shortest way round
          if (delta > dims / 2) delta -= dims;
          if (delta < -dims / 2) delta += dims;
        }
        const int side = delta < 0 ? 0 : 1;
        if (decomp_.neighbor(d, side) == MPI_PROC_NULL) continue;
        set.pack(i, false, out[side]);
        gone[i] = 1;
        any_gone = true;
      }
      if (any_gone) set.remove_owned(gone, keep_order);
      for (int side = 0; side < 2; ++side) {
        auto in = sendrecv(out[side], decomp_.neighbor(d, side), decomp_.neighbor(d, 1 - side),
                           kTagMigrate + 2 * side, comm, sent_);
        const std::size_t n = in.size() / w, first = set.n_owned();
        set.resize(first + n, first + n);
        for (std::size_t k = 0; k < n; ++k) {
          const std::size_t i = first + k;
          set.unpack(i, false, in.data() + k * w);
          for (int e = 0; e <= d; ++e)
            if (split[e] && !is_home(e, set.real(ParticleSet::kPos, e)[i])) {
              ++away;
              break;
            }
        }
      }
    }
    // Done when every particle is home (at most a few rounds when a move spans several ranks).
    long long total = 0;
    MPI_Allreduce(&away, &total, 1, MPI_LONG_LONG, MPI_SUM, comm);
    if (total == 0) break;
  }
}

void ParticleComm::redistribute(ParticleSet& set) {
  set.clear_ghosts();
  have_plan_ = false;
  MPI_Comm comm = decomp_.comm();
  const int P = decomp_.size(), w = set.pack_width(false);
  std::vector<std::vector<double>> out(P);
  std::vector<char> gone(set.n_owned(), 0);
  Real* x[3] = {set.real(ParticleSet::kPos, 0), set.real(ParticleSet::kPos, 1),
                set.real(ParticleSet::kPos, 2)};
  for (std::size_t i = 0; i < set.n_owned(); ++i) {
    wrap_particle(set, i, x);
    const int r = owner_of(set.pos(i));
    if (r == decomp_.rank()) continue;
    set.pack(i, false, out[r]);
    gone[i] = 1;
  }
  set.remove_owned(gone);
  std::vector<int> scount(P), rcount(P), sdisp(P), rdisp(P);
  for (int r = 0; r < P; ++r) scount[r] = static_cast<int>(out[r].size());
  MPI_Alltoall(scount.data(), 1, MPI_INT, rcount.data(), 1, MPI_INT, comm);
  std::vector<double> sbuf, rbuf;
  for (int r = 0; r < P; ++r) {
    sdisp[r] = static_cast<int>(sbuf.size());
    sbuf.insert(sbuf.end(), out[r].begin(), out[r].end());
  }
  int rtotal = 0;
  for (int r = 0; r < P; ++r) {
    rdisp[r] = rtotal;
    rtotal += rcount[r];
  }
  rbuf.resize(rtotal);
  for (int r = 0; r < P; ++r)
    if (r != decomp_.rank() && scount[r] > 0) sent_.add(scount[r] * sizeof(double));
  MPI_Alltoallv(sbuf.data(), scount.data(), sdisp.data(), MPI_DOUBLE, rbuf.data(), rcount.data(),
                rdisp.data(), MPI_DOUBLE, comm);
  const std::size_t n = rbuf.size() / w, first = set.n_owned();
  set.resize(first + n, first + n);
  for (std::size_t k = 0; k < n; ++k) set.unpack(first + k, false, rbuf.data() + k * w);
}

void ParticleComm::build_ghosts(ParticleSet& set, Real cutoff) {
  set.clear_ghosts();
  MPI_Comm comm = decomp_.comm();
  const int w = set.pack_width(true);
  for (int d = 0; d < 3; ++d) {
    const Real width = hi_[d] - lo_[d];
    if (cutoff > width && decomp_.neighbor(d, 0) != MPI_PROC_NULL)
      throw std::runtime_error("particle ghost cutoff " + std::to_string(cutoff) +
                               " m exceeds the rank's width " + std::to_string(width) +
                               " m on axis " + std::to_string(d) + "; use fewer ranks");
  }
  for (int d = 0; d < 3; ++d) {
    const int dims = decomp_.dims()[d], me = decomp_.coords()[d];
    const Real L = ghi_[d] - glo_[d];
    const std::size_t n_candidates = set.n_total();  // owned + ghosts of earlier passes
    for (int side = 0; side < 2; ++side) {
      GhostPass& p = plan_[d][side];
      p.send.clear();
      p.shift = 0;
      if (side == 0 && me == 0) p.shift = L;
      if (side == 1 && me == dims - 1) p.shift = -L;
      const int dest = decomp_.neighbor(d, side), src = decomp_.neighbor(d, 1 - side);
      if (dest != MPI_PROC_NULL) {  // the particles within the cutoff of this side's face
        const Real* x = set.real(ParticleSet::kPos, d);
        const Real edge = side == 0 ? lo_[d] + cutoff : hi_[d] - cutoff;
        for (std::size_t i = 0; i < n_candidates; ++i)
          if (side == 0 ? x[i] < edge : x[i] >= edge) p.send.push_back(i);
      }
      if (dest == decomp_.rank() && src == dest) {
        // A periodic axis not split over ranks: the images are this rank's own particles, so the
        // columns are copied directly (no pack, message or unpack; the same values and order).
        p.recv_begin = set.n_total();
        p.recv_count = p.send.size();
        set.append_ghost_copies(p.send, d, p.shift);
        continue;
      }
      std::vector<double> out;
      set.pack_rows(p.send, set.ghost_reals(), set.ghost_u64s(), d, p.shift, out);
      auto in = sendrecv(out, dest, src, kTagGhost + 2 * side, comm, sent_);
      const std::size_t n = in.size() / w, first = set.n_total();
      set.resize(set.n_owned(), first + n);
      set.unpack_rows(first, n, set.ghost_reals(), set.ghost_u64s(), in.data());
      p.recv_begin = first;
      p.recv_count = n;
    }
  }
  have_plan_ = true;
}

void ParticleComm::update_ghosts(ParticleSet& set) {
  if (!have_plan_) throw std::logic_error("update_ghosts without build_ghosts");
  MPI_Comm comm = decomp_.comm();
  const int w = set.pack_width(true);
  for (int d = 0; d < 3; ++d)
    for (int side = 0; side < 2; ++side) {
      GhostPass& p = plan_[d][side];
      std::vector<double> out;
      set.pack_rows(p.send, set.ghost_reals(), set.ghost_u64s(), d, p.shift, out);
      auto in = sendrecv(out, decomp_.neighbor(d, side), decomp_.neighbor(d, 1 - side),
                         kTagUpdate + 2 * side, comm, sent_);
      if (in.size() != p.recv_count * w) throw std::logic_error("ghost plan out of date");
      set.unpack_rows(p.recv_begin, p.recv_count, set.ghost_reals(), set.ghost_u64s(), in.data());
    }
}

void ParticleComm::update_ghosts(ParticleSet& set, const std::vector<int>& reals,
                                 const std::vector<int>& u64s) {
  if (!have_plan_) throw std::logic_error("update_ghosts without build_ghosts");
  MPI_Comm comm = decomp_.comm();
  int me = 0;
  MPI_Comm_rank(comm, &me);
  const std::size_t w = set.row_width(reals, u64s);
  std::vector<double> out, in;
  for (int d = 0; d < 3; ++d)
    for (int side = 0; side < 2; ++side) {
      const GhostPass& p = plan_[d][side];
      out.clear();
      set.pack_rows(p.send, reals, u64s, d, p.shift, out);
      in.resize(p.recv_count * w);
      const int dest = decomp_.neighbor(d, side), src = decomp_.neighbor(d, 1 - side);
      if (dest != MPI_PROC_NULL && dest != me)
        sent_.add(static_cast<long long>(out.size() * sizeof(double)));
      MPI_Sendrecv(out.data(), static_cast<int>(out.size()), MPI_DOUBLE, dest, kTagPartial + side,
                   in.data(), static_cast<int>(in.size()), MPI_DOUBLE, src, kTagPartial + side,
                   comm, MPI_STATUS_IGNORE);
      set.unpack_rows(p.recv_begin, p.recv_count, reals, u64s, in.data());
    }
}

void ParticleComm::reverse_sum(ParticleSet& set, const std::vector<int>& attrs) {
  if (!have_plan_) throw std::logic_error("reverse_sum without build_ghosts");
  MPI_Comm comm = decomp_.comm();
  std::vector<Real*> cols;
  for (int a : attrs)
    for (int c = 0; c < set.layout().reals()[a].ncomp; ++c) cols.push_back(set.real(a, c));
  const std::size_t w = cols.size();
  // Undo the passes in reverse order: a ghost forwarded in a later pass first receives what its
  // own copies accumulated, then sends the total one hop back.
  for (int d = 2; d >= 0; --d)
    for (int side = 1; side >= 0; --side) {
      GhostPass& p = plan_[d][side];
      std::vector<double> out;
      out.reserve(p.recv_count * w);
      for (std::size_t k = 0; k < p.recv_count; ++k)
        for (Real* c : cols) {
          out.push_back(c[p.recv_begin + k]);
          c[p.recv_begin + k] = 0;
        }
      // Ghosts of pass (d, side) came from neighbor(d, 1-side); send their sums back there.
      auto in = sendrecv(out, decomp_.neighbor(d, 1 - side), decomp_.neighbor(d, side),
                         kTagReverse + 2 * side, comm, sent_);
      if (in.size() != p.send.size() * w) throw std::logic_error("reverse plan mismatch");
      for (std::size_t k = 0; k < p.send.size(); ++k)
        for (std::size_t c = 0; c < w; ++c) cols[c][p.send[k]] += in[k * w + c];
    }
}

SplitBlock thinnest_split_block(const grid::Decomposition& decomp, double dx) {
  SplitBlock t{std::numeric_limits<double>::infinity(), -1};
  for (int d = 0; d < 3; ++d)
    if (decomp.dims()[d] > 1 && decomp.thinnest(d) * dx < t.width) t = {decomp.thinnest(d) * dx, d};
  return t;
}

}  // namespace biota::particles
