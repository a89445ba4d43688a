#include "particles/particle_set.hpp"

#include <algorithm>
#include <bit>
#include <cstring>
#include <stdexcept>

namespace biota::particles {

ParticleLayout::ParticleLayout() {
  reals_.push_back({"x", 3, true, true, true});
  u64s_.push_back({"id", 1, true, true});
}

int ParticleLayout::add_real(const std::string& name, int ncomp, bool migrate, bool ghost) {
  if (find_real(name) >= 0) throw std::logic_error("particle attribute declared twice: " + name);
  reals_.push_back({name, ncomp, migrate, ghost});
  return static_cast<int>(reals_.size()) - 1;
}

int ParticleLayout::add_position(const std::string& name, bool migrate, bool ghost) {
  const int a = add_real(name, 3, migrate, ghost);
  reals_[a].position = true;
  return a;
}

int ParticleLayout::add_u64(const std::string& name, int ncomp, bool migrate, bool ghost) {
  if (find_u64(name) >= 0) throw std::logic_error("particle attribute declared twice: " + name);
  u64s_.push_back({name, ncomp, migrate, ghost});
  return static_cast<int>(u64s_.size()) - 1;
}

int ParticleLayout::find_real(const std::string& name) const {
  for (std::size_t a = 0; a < reals_.size(); ++a)
    if (reals_[a].name == name) return static_cast<int>(a);
  return -1;
}

int ParticleLayout::find_u64(const std::string& name) const {
  for (std::size_t a = 0; a < u64s_.size(); ++a)
    if (u64s_[a].name == name) return static_cast<int>(a);
  return -1;
}

ParticleSet::ParticleSet(ParticleLayout layout) : layout_(std::move(layout)) {
  for (const auto& a : layout_.reals()) {
    rfirst_.push_back(rcol_.size());
    for (int c = 0; c < a.ncomp; ++c) {
      rcol_.emplace_back();
      rmig_.push_back(a.migrate);
      rghost_.push_back(a.ghost);
    }
  }
  for (std::size_t a = 0; a < layout_.reals().size(); ++a) {
    if (layout_.reals()[a].position && a != kPos) extra_pos_.push_back(static_cast<int>(a));
    if (layout_.reals()[a].ghost) ghost_reals_.push_back(static_cast<int>(a));
  }
  for (std::size_t a = 0; a < layout_.u64s().size(); ++a)
    if (layout_.u64s()[a].ghost) ghost_u64s_.push_back(static_cast<int>(a));
  for (const auto& a : layout_.u64s()) {
    ufirst_.push_back(ucol_.size());
    for (int c = 0; c < a.ncomp; ++c) {
      ucol_.emplace_back();
      umig_.push_back(a.migrate);
      ughost_.push_back(a.ghost);
    }
  }
}

void ParticleSet::resize(std::size_t n_owned, std::size_t n_total) {
  for (auto& c : rcol_) c.resize(n_total, 0.0);
  for (auto& c : ucol_) c.resize(n_total, 0);
  n_owned_ = n_owned;
  n_total_ = n_total;
}

std::size_t ParticleSet::add_owned(GlobalId id, const Vec3& p) {
  const std::size_t i = n_owned_;
  resize(n_owned_, n_owned_);
  resize(i + 1, i + 1);
  for (auto& c : rcol_) c[i] = 0.0;
  for (auto& c : ucol_) c[i] = 0;
  ucol_[0][i] = id;
  set_pos(i, p);
  return i;
}

void ParticleSet::remove_owned(const std::vector<char>& remove, bool keep_order) {
  if (!keep_order) {
    // [lo, hi) still to settle: the first hole from below takes the last kept particle.
    std::size_t lo = 0, hi = n_owned_;
    for (;;) {
      while (lo < hi && !remove[lo]) ++lo;
      while (hi > lo && remove[hi - 1]) --hi;
      if (lo >= hi) break;
      --hi;
      for (auto& c : rcol_) c[lo] = c[hi];
      for (auto& c : ucol_) c[lo] = c[hi];
      ++lo;
    }
    resize(lo, lo);
    return;
  }
  // Removals are few (the particles that left the rank this step): the runs of kept particles
  // between them move down column by column, one memmove each (a row-by-row copy through every
  // column took 1.6% of a 2-rank flock profile at 1e6 boids, the memmoves 0.7%).
  std::vector<std::size_t> gone;
  for (std::size_t i = 0; i < n_owned_; ++i)
    if (remove[i]) gone.push_back(i);
  gone.push_back(n_owned_);  // sentinel: the last run ends at n_owned
  const std::size_t kept = n_owned_ - (gone.size() - 1);
  const auto compact = [&](auto* c) {
    std::size_t w = gone[0];
    for (std::size_t k = 0; k + 1 < gone.size(); ++k) {
      const std::size_t run = gone[k + 1] - gone[k] - 1;
      if (run > 0) std::memmove(c + w, c + gone[k] + 1, run * sizeof(*c));
      w += run;
    }
  };
  for (auto& c : rcol_) compact(c.data());
  for (auto& c : ucol_) compact(c.data());
  resize(kept, kept);
}

void ParticleSet::reorder_owned(const std::vector<std::size_t>& order) {
  if (order.size() != n_owned_) throw std::invalid_argument("reorder_owned: order size != n_owned");
  resize(n_owned_, n_owned_);
  // Each column is gathered into a spare one, which then takes its place (no copy back); the
  // column it replaces becomes the spare for the next, so the capacities stay in the set.
  const auto permute = [&](auto& columns, auto& spare) {
    for (auto& c : columns) {
      spare.resize(n_owned_);
      for (std::size_t m = 0; m < n_owned_; ++m) spare[m] = c[order[m]];
      c.swap(spare);
    }
  };
  permute(rcol_, spare_real_);
  permute(ucol_, spare_u64_);
}

void ParticleSet::zero_real(int a) {
  for (int c = 0; c < layout_.reals()[a].ncomp; ++c)
    std::fill(rcol_[rfirst_[a] + c].begin(), rcol_[rfirst_[a] + c].end(), 0.0);
}

int ParticleSet::pack_width(bool ghost_only) const {
  int w = 0;
  for (std::size_t c = 0; c < rcol_.size(); ++c) w += ghost_only ? rghost_[c] : rmig_[c];
  for (std::size_t c = 0; c < ucol_.size(); ++c) w += ghost_only ? ughost_[c] : umig_[c];
  return w;
}

void ParticleSet::pack(std::size_t i, bool ghost_only, std::vector<double>& buf) const {
  for (std::size_t c = 0; c < rcol_.size(); ++c)
    if (ghost_only ? rghost_[c] : rmig_[c]) buf.push_back(rcol_[c][i]);
  // 64-bit integers travel bit-exactly inside doubles (one MPI datatype for the whole message).
  for (std::size_t c = 0; c < ucol_.size(); ++c)
    if (ghost_only ? ughost_[c] : umig_[c]) buf.push_back(std::bit_cast<double>(ucol_[c][i]));
}

void ParticleSet::unpack(std::size_t i, bool ghost_only, const double* in) {
  for (std::size_t c = 0; c < rcol_.size(); ++c)
    if (ghost_only ? rghost_[c] : rmig_[c]) rcol_[c][i] = *in++;
  for (std::size_t c = 0; c < ucol_.size(); ++c)
    if (ghost_only ? ughost_[c] : umig_[c]) ucol_[c][i] = std::bit_cast<std::uint64_t>(*in++);
}

std::size_t ParticleSet::row_width(const std::vector<int>& reals,
                                   const std::vector<int>& u64s) const {
  std::size_t w = 0;
  for (int a : reals) w += static_cast<std::size_t>(layout_.reals()[a].ncomp);
  for (int a : u64s) w += static_cast<std::size_t>(layout_.u64s()[a].ncomp);
  return w;
}

void ParticleSet::pack_rows(const std::vector<std::size_t>& rows, const std::vector<int>& reals,
                            const std::vector<int>& u64s, int axis, Real shift,
                            std::vector<double>& buf) const {
  const std::size_t w = row_width(reals, u64s);
  const std::size_t n = rows.size(), at = buf.size();
  buf.resize(at + n * w);
  double* out = buf.data() + at;
  std::size_t off = 0;  // the column's place within a row
  for (int a : reals) {
    const auto& spec = layout_.reals()[a];
    for (int c = 0; c < spec.ncomp; ++c, ++off) {
      const Real* col = real(a, c);
      if (spec.position && c == axis)
        for (std::size_t k = 0; k < n; ++k) out[k * w + off] = col[rows[k]] + shift;
      else
        for (std::size_t k = 0; k < n; ++k) out[k * w + off] = col[rows[k]];
    }
  }
  for (int a : u64s)
    for (int c = 0; c < layout_.u64s()[a].ncomp; ++c, ++off) {
      const std::uint64_t* col = u64(a, c);
      for (std::size_t k = 0; k < n; ++k) out[k * w + off] = std::bit_cast<double>(col[rows[k]]);
    }
}

void ParticleSet::unpack_rows(std::size_t first, std::size_t count, const std::vector<int>& reals,
                              const std::vector<int>& u64s, const double* in) {
  const std::size_t w = row_width(reals, u64s);
  std::size_t off = 0;
  for (int a : reals)
    for (int c = 0; c < layout_.reals()[a].ncomp; ++c, ++off) {
      Real* col = real(a, c) + first;
      for (std::size_t k = 0; k < count; ++k) col[k] = in[k * w + off];
    }
  for (int a : u64s)
    for (int c = 0; c < layout_.u64s()[a].ncomp; ++c, ++off) {
      std::uint64_t* col = u64(a, c) + first;
      for (std::size_t k = 0; k < count; ++k)
        col[k] = std::bit_cast<std::uint64_t>(in[k * w + off]);
    }
}

void ParticleSet::append_ghost_copies(const std::vector<std::size_t>& from, int axis, Real shift) {
  const std::size_t first = n_total_, n = from.size();
  resize(n_owned_, first + n);
  for (std::size_t a = 0; a < layout_.reals().size(); ++a) {
    const auto& spec = layout_.reals()[a];
    if (!spec.ghost) continue;
    for (int c = 0; c < spec.ncomp; ++c) {
      Real* col = rcol_[rfirst_[a] + c].data();
      if (spec.position && c == axis)  // as the packed path: the shift is added even when 0
        for (std::size_t k = 0; k < n; ++k) col[first + k] = col[from[k]] + shift;
      else
        for (std::size_t k = 0; k < n; ++k) col[first + k] = col[from[k]];
    }
  }
  for (std::size_t c = 0; c < ucol_.size(); ++c) {
    if (!ughost_[c]) continue;
    std::uint64_t* col = ucol_[c].data();
    for (std::size_t k = 0; k < n; ++k) col[first + k] = col[from[k]];
  }
}

void ParticleSet::swap_slots(std::size_t i, std::size_t j) {
  for (auto& c : rcol_) std::swap(c[i], c[j]);
  for (auto& c : ucol_) std::swap(c[i], c[j]);
}

}  // namespace biota::particles
