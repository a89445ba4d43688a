/// \file sandpile.cpp
/// \brief Relaxation of the 3D BTW sandpile (spec boids.md 2.3, eqs. 3.1–3.2).
#include "models/flock/sandpile.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

#include "core/rng.hpp"

namespace biota::models::flock {

namespace {
// Far below any threshold, so a ghost never topples; half of INT32_MIN leaves room for ~1e9
// received grains before rearm_ghosts() has to reset it.
constexpr std::int32_t kGhost = std::numeric_limits<std::int32_t>::min() / 2;
constexpr std::int64_t kRearmAfter = std::int64_t{1} << 29;
}  // namespace

Sandpile::Sandpile(int lx, int ly, int lz, std::uint64_t seed, int threshold)
    : lx_(lx), ly_(ly), lz_(lz), zc_(threshold), seed_(seed) {
  if (lx < 1 || ly < 1 || lz < 1)
    throw std::invalid_argument("Sandpile: lattice extents must be >= 1, got " +
                                std::to_string(lx) + "x" + std::to_string(ly) + "x" +
                                std::to_string(lz));
  if (threshold < 5)
    throw std::invalid_argument("Sandpile: threshold must be >= 5 (6 neighbours), got " +
                                std::to_string(threshold));
  px_ = lx + 2;
  py_ = ly + 2;
  pz_ = lz + 2;
  const std::int64_t padded = std::int64_t{px_} * py_ * pz_;
  if (padded > std::numeric_limits<std::int32_t>::max())
    throw std::invalid_argument("Sandpile: lattice too large for 32-bit site indices");
  n_ = std::int64_t{lx} * ly * lz;
  const std::int32_t sx = 1, sy = px_, sz = px_ * py_;
  const std::int32_t offs[6] = {-sx, sx, -sy, sy, -sz, sz};
  std::copy(offs, offs + 6, off_);

  h_.assign(padded, kGhost);
  sink_.assign(padded, 0);
  site_of_.assign(padded, -1);
  padded_.resize(n_);
  avl_mark_.assign(padded, 0);
  wave_mark_.assign(padded, 0);
  const int bulk_loss = zc_ + 1 - 6;
  for (int z = 0; z < lz; ++z)
    for (int y = 0; y < ly; ++y)
      for (int x = 0; x < lx; ++x) {
        const std::int64_t s = site(x, y, z);
        const std::int32_t p = (x + 1) + px_ * ((y + 1) + py_ * (z + 1));
        padded_[s] = p;
        site_of_[p] = static_cast<std::int32_t>(s);
        const int open_faces =
            (x == 0) + (x == lx - 1) + (y == 0) + (y == ly - 1) + (z == 0) + (z == lz - 1);
        sink_[p] = static_cast<std::uint8_t>(open_faces + bulk_loss);
        core::Rng rng(seed, static_cast<std::uint64_t>(s), 0, core::RngPurpose::kSandpile);
        h_[p] = static_cast<std::int32_t>(rng.uniform_int(0, zc_));
        initial_grains_ += h_[p];
      }
  work_a_.reserve(n_);
  work_b_.reserve(n_);
  toppled_.reserve(n_);
  toppled_ids_.reserve(n_);
}

std::int64_t Sandpile::random_site(std::uint64_t drive) const {
  core::Rng rng(seed_, std::numeric_limits<std::uint64_t>::max(), drive,
                core::RngPurpose::kSandpile);
  return rng.uniform_int(0, n_ - 1);
}

void Sandpile::deposit(std::int64_t site, std::int32_t count) {
  if (count < 0) throw std::invalid_argument("Sandpile::deposit: negative grain count");
  h_[padded_[site]] += count;
  grains_added_ += count;
}

Avalanche Sandpile::add_grain(std::int64_t site, ToppleOrder order) {
  const std::int32_t p = padded_[site];
  ++h_[p];
  ++grains_added_;
  work_a_.clear();
  if (h_[p] > zc_) work_a_.push_back(p);
  Avalanche a = order == ToppleOrder::kWaves ? relax_waves({}) : relax_stack({});
  finish(a);
  return a;
}

Avalanche Sandpile::relax(ToppleOrder order) {
  work_a_.clear();
  for (std::int64_t s = 0; s < n_; ++s)
    if (h_[padded_[s]] > zc_) work_a_.push_back(padded_[s]);
  Avalanche a = order == ToppleOrder::kWaves ? relax_waves({}) : relax_stack({});
  finish(a);
  return a;
}

void Sandpile::note_toppled(std::int32_t p) {
  if (avl_mark_[p] != avl_serial_) {
    avl_mark_[p] = avl_serial_;
    toppled_.push_back(p);
  }
}

// Each site sits on the stack at most once: it is pushed only when it crosses from stable to
// unstable, and popping it topples it back to stable in one go (h -> h mod (z_c + 1)), which is a
// legal sequence of single topplings because the model is abelian.
Avalanche Sandpile::relax_stack(Avalanche a) {
  toppled_.clear();
  if (++avl_serial_ == 0) {
    std::fill(avl_mark_.begin(), avl_mark_.end(), 0u);
    avl_serial_ = 1;
  }
  const std::int32_t q = zc_ + 1;
  auto& st = work_a_;
  while (!st.empty()) {
    const std::int32_t p = st.back();
    st.pop_back();
    const std::int32_t k = h_[p] / q;
    h_[p] -= k * q;
    a.size += k;
    a.lost += std::int64_t{k} * sink_[p];
    note_toppled(p);
    for (int d = 0; d < 6; ++d) {
      const std::int32_t nb = p + off_[d];
      const std::int32_t old = h_[nb];
      h_[nb] = old + k;
      if (old <= zc_ && old + k > zc_) st.push_back(nb);
    }
  }
  return a;
}

// Synchronous update: the list `cur` holds exactly the sites unstable at the start of the wave.
// Candidates for the next wave are the toppled sites and the sites that received grains; they are
// deduplicated with a per-wave stamp and filtered at the end of the wave, because a site queued
// before its own toppling in this wave may have become stable again.
Avalanche Sandpile::relax_waves(Avalanche a) {
  toppled_.clear();
  if (++avl_serial_ == 0) {
    std::fill(avl_mark_.begin(), avl_mark_.end(), 0u);
    avl_serial_ = 1;
  }
  const std::int32_t q = zc_ + 1;
  auto* cur = &work_a_;
  auto* next = &work_b_;
  while (!cur->empty()) {
    if (++wave_serial_ == 0) {
      std::fill(wave_mark_.begin(), wave_mark_.end(), 0u);
      wave_serial_ = 1;
    }
    const std::uint32_t ws = wave_serial_;
    next->clear();
    ++a.duration;
    for (const std::int32_t p : *cur) {
      h_[p] -= q;
      ++a.size;
      a.lost += sink_[p];
      note_toppled(p);
      if (h_[p] > zc_ && wave_mark_[p] != ws) {
        wave_mark_[p] = ws;
        next->push_back(p);
      }
      for (int d = 0; d < 6; ++d) {
        const std::int32_t nb = p + off_[d];
        if (++h_[nb] > zc_ && wave_mark_[nb] != ws) {
          wave_mark_[nb] = ws;
          next->push_back(nb);
        }
      }
    }
    std::erase_if(*next, [&](std::int32_t p) { return h_[p] <= zc_; });
    std::swap(cur, next);
  }
  return a;
}

void Sandpile::finish(Avalanche& a) {
  a.area = static_cast<std::int64_t>(toppled_.size());
  toppled_ids_.resize(toppled_.size());
  for (std::size_t i = 0; i < toppled_.size(); ++i) toppled_ids_[i] = site_of_[toppled_[i]];
  grains_lost_ += a.lost;
  topplings_ += a.size;
  ++relaxations_;
  lost_since_rearm_ += a.lost;
  if (lost_since_rearm_ > kRearmAfter) rearm_ghosts();
}

void Sandpile::rearm_ghosts() {
  for (std::size_t p = 0; p < h_.size(); ++p)
    if (site_of_[p] < 0) h_[p] = kGhost;
  lost_since_rearm_ = 0;
}

std::vector<std::int32_t> Sandpile::heights() const {
  std::vector<std::int32_t> out(n_);
  for (std::int64_t s = 0; s < n_; ++s) out[s] = h_[padded_[s]];
  return out;
}

std::int64_t Sandpile::sum_heights() const {
  std::int64_t sum = 0;
  for (std::int64_t s = 0; s < n_; ++s) sum += h_[padded_[s]];
  return sum;
}

SandpileState Sandpile::state() const {
  return {heights(), initial_grains_, grains_added_, grains_lost_, topplings_, relaxations_};
}

void Sandpile::restore(const SandpileState& s) {
  if (static_cast<std::int64_t>(s.heights.size()) != n_)
    throw std::invalid_argument("Sandpile::restore: state has " + std::to_string(s.heights.size()) +
                                " sites, lattice has " + std::to_string(n_));
  for (std::int64_t i = 0; i < n_; ++i) h_[padded_[i]] = s.heights[i];
  initial_grains_ = s.initial_grains;
  grains_added_ = s.grains_added;
  grains_lost_ = s.grains_lost;
  topplings_ = s.topplings;
  relaxations_ = s.relaxations;
  toppled_.clear();
  toppled_ids_.clear();
  rearm_ghosts();
}

}  // namespace biota::models::flock
