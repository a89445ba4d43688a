/// \file seaweed_lists.cpp
/// \brief SeaweedBodies' neighbour lists: the list build (ghosts, contact pairs, joints, each owned
/// sphere's interactions in summation order, the first inner contact list) and the per-sphere
/// re-filter marking of the inner list (see seaweed_mechanics.hpp).
#include <algorithm>
#include <vector>

#include "models/plants/seaweed_mechanics.hpp"
#include "particles/cell_list.hpp"

namespace biota::models::plants {

using particles::kNoId;
using particles::ParticleSet;

void SeaweedBodies::mark_refilter() {
  // A contact dropped by the filter had reference positions at least r_i + r_j + inner_skin
  // apart; while neither sphere (owned or ghost: both are refreshed each sub-step and keep their
  // slots between list builds) is half the inner skin from its reference, it is still more than
  // r_i + r_j apart and adds nothing. The (1 - 1e-6) keeps that margin ~1e-9 m, far above
  // round-off. A sphere that moved that far gets its current position as reference, and the
  // segments of all owned spheres listing a contact with it (and its own) are filtered again.
  // Rank-local: the filter changes no result, so ranks need not agree on when they filter.
  const std::size_t no = set_.n_owned(), nt = set_.n_total();
  const Real *px = set_.real(ParticleSet::kPos, 0), *py = set_.real(ParticleSet::kPos, 1),
             *pz = set_.real(ParticleSet::kPos, 2);
  if (need_filter_ || p_.inner_skin <= 0) {
    // After a list build (which made the inner list from the same positions) only the references
    // are set; with inner_skin <= 0 every sub-step filters every sphere.
    need_filter_ = false;
    const Real* rad = set_.real(a_radius);
    refs_.resize(nt);
    for (std::size_t k = 0; k < nt; ++k) refs_[k] = {{px[k], py[k], pz[k]}, rad[k]};
    refilter_.assign(no, p_.inner_skin <= 0 ? 1 : 0);
    return;
  }
  const Real lim = 0.5 * p_.inner_skin * (1 - 1e-6), lim2 = lim * lim;
  std::uint8_t* mark = refilter_.data();
  for (std::size_t k = 0; k < nt; ++k) {
    Vec3& ref = refs_[k].x;
    const Real dx = px[k] - ref.x, dy = py[k] - ref.y, dz = pz[k] - ref.z;
    if (dx * dx + dy * dy + dz * dz < lim2) continue;
    ref = {px[k], py[k], pz[k]};
    if (k < no) {  // itself and its owned contact partners
      mark[k] = 1;
      for (std::size_t e = adj_begin_[k]; e < adj_begin_[k + 1]; ++e)
        if (entries_[e].kind() == 2 && entries_[e].index < no) mark[entries_[e].index] = 1;
    } else {
      for (std::size_t t = touch_begin_[k - no]; t < touch_begin_[k - no + 1]; ++t)
        mark[touch_[t]] = 1;
    }
  }
}

void SeaweedBodies::rebuild_lists() {
  comm_.build_ghosts(set_, ghost_cutoff());
  ++rebuilds_;
  need_filter_ = true;
  const std::size_t no = set_.n_owned(), nt = set_.n_total();
  x_build_.resize(no);
  for (std::size_t i = 0; i < no; ++i) x_build_[i] = set_.pos(i);
  // (id, slot) of every owned and ghost sphere sorted by id: find_near's lookup (one flat sort
  // instead of a node-based hash map rebuilt each time).
  slots_.resize(nt);
  for (std::size_t i = 0; i < nt; ++i) slots_[i] = {set_.id(i), i};
  std::sort(slots_.begin(), slots_.end());
  // Every interaction touching an owned sphere is listed here, also when the other sphere is a
  // ghost: both owners evaluate it with identical inputs and each adds it to its own sphere only,
  // so nothing is scattered back and the sum on a sphere never depends on the decomposition.
  // Pairs are oriented (lower id, higher id); the list covers pairs closer than the contact range
  // plus the skin.
  pairs_.clear();
  const Real contact_range = 2 * p_.radius + p_.cluster_margin + p_.skin;
  particles::CellList cl(set_.real(ParticleSet::kPos, 0), set_.real(ParticleSet::kPos, 1),
                         set_.real(ParticleSet::kPos, 2), nt, contact_range);
  const GlobalId* ids = set_.u64(ParticleSet::kId);
  const std::uint64_t* parent = set_.u64(u_parent);
  // The pairs closer than twice the largest radius plus the inner skin are also flagged for the
  // first inner list (see mark_refilter; the positions now are the filter's references). With
  // equal radii that is the filter's own bound, else a superset of it.
  const Real* rad = set_.real(a_radius);
  Real rmax = 0;
  for (std::size_t k = 0; k < nt; ++k) rmax = std::max(rmax, rad[k]);
  const Real reach = 2 * rmax + p_.inner_skin, reach2 = reach * reach;
  pair_near_.clear();
  cl.for_each_pair([&](std::size_t i, std::size_t j, Real r2) {
    if (i >= no && j >= no) return;
    // Joined neighbours and siblings on one parent do not collide.
    const GlobalId pi = parent[i], pj = parent[j];
    if (pi == ids[j] || pj == ids[i] || (pi == pj && pi != kNoId)) return;
    pairs_.emplace_back(ids[i] < ids[j] ? i : j, ids[i] < ids[j] ? j : i);
    pair_near_.push_back(r2 < reach2);
  });
  joints_.clear();
  long long skipped = 0;
  for (std::size_t c = 0; c < nt; ++c) {
    const GlobalId pid = set_.u64(u_parent)[c];
    if (pid == kNoId) continue;
    const std::size_t p = find_near(pid, set_.pos(c));
    // Partner out of range: expected for a ghost child (its owner evaluates the joint); for an
    // owned child the joint is lost for this list's lifetime -- counted, reported in metrics.
    if (p == SIZE_MAX) {
      skipped += c < no ? 1 : 0;
      continue;
    }
    if (c < no || p < no) joints_.emplace_back(c, p);
  }
  skipped_joints_ = skipped;
  // Per owned sphere: its interactions sorted by (partner id, kind) -- the fixed summation order.
  // Flat CSR of the entries (counted, then filled), each sphere's segment then sorted.
  adj_begin_.assign(no + 1, 0);
  for (const auto& [c, p] : joints_) {
    if (c < no) ++adj_begin_[c + 1];
    if (p < no) ++adj_begin_[p + 1];
  }
  // Per ghost g (slot no + g), the owned spheres listing a contact with it (a pair has at least one
  // owned sphere), for the re-filter (see mark_refilter; an owned sphere's segment lists them).
  const std::size_t ng = nt - no;
  touch_begin_.assign(ng + 1, 0);
  for (const auto& [i, j] : pairs_) {
    ++(i < no ? adj_begin_[i + 1] : touch_begin_[i - no + 1]);
    ++(j < no ? adj_begin_[j + 1] : touch_begin_[j - no + 1]);
  }
  for (std::size_t i = 0; i < no; ++i) adj_begin_[i + 1] += adj_begin_[i];
  for (std::size_t g = 0; g < ng; ++g) touch_begin_[g + 1] += touch_begin_[g];
  touch_.resize(touch_begin_[ng]);
  std::vector<std::size_t> touch_fill(touch_begin_.begin(), touch_begin_.end() - 1);
  entries_.resize(adj_begin_[no]);
  std::vector<std::size_t> fill(adj_begin_.begin(), adj_begin_.end() - 1);
  const auto key = [&](std::size_t partner, std::uint64_t kind) {
    return ids[partner] << 2 | kind;
  };
  for (std::size_t m = 0; m < joints_.size(); ++m) {
    const auto [c, p] = joints_[m];
    if (c < no) entries_[fill[c]++] = {key(p, 0), static_cast<std::uint32_t>(m), 0};
    if (p < no) entries_[fill[p]++] = {key(c, 1), static_cast<std::uint32_t>(m), 1};
  }
  for (std::size_t m = 0; m < pairs_.size(); ++m) {
    const auto [i, j] = pairs_[m];
    // A contact entry keeps the partner's slot (the pair is re-oriented from `side` in the sum).
    const std::uint32_t near = pair_near_[m] ? Entry::kNear : 0;
    if (i < no)
      entries_[fill[i]++] = {key(j, 2), static_cast<std::uint32_t>(j), 0 | near};
    else
      touch_[touch_fill[i - no]++] = static_cast<std::uint32_t>(j);
    if (j < no)
      entries_[fill[j]++] = {key(i, 2), static_cast<std::uint32_t>(i), 1 | near};
    else
      touch_[touch_fill[j - no]++] = static_cast<std::uint32_t>(i);
  }
  // Joint results are stored densely in summation order: slot_[2 m + side] is the position of
  // joint m's result on that side's sphere among all joint entries.
  // The first inner list (every joint and the flagged contacts) is copied in the same pass.
  slot_.assign(2 * joints_.size(), kNoSlot);
  near_.resize(entries_.size());
  near_end_.resize(no);
  std::uint32_t nslots = 0;
  for (std::size_t i = 0; i < no; ++i) {
    const auto b = entries_.begin() + adj_begin_[i], e = entries_.begin() + adj_begin_[i + 1];
    std::sort(b, e, [](const Entry& x, const Entry& y) { return x.key < y.key; });
    Near* kept = near_.data() + adj_begin_[i];
    for (auto it = b; it != e; ++it) {
      const std::uint32_t kind = it->kind(), side = it->side & 1u;
      if (kind != 2) slot_[2 * it->index + side] = nslots++;
      if (kind != 2 || it->side & Entry::kNear) *kept++ = {it->index, kind | side << 2};
    }
    near_end_[i] = static_cast<std::size_t>(kept - near_.data());
  }
  contrib_.resize(nslots);
}

std::size_t SeaweedBodies::find_near(GlobalId id, const Vec3& near) const {
  auto it = std::lower_bound(slots_.begin(), slots_.end(), std::pair<GlobalId, std::size_t>{id, 0});
  std::size_t best = SIZE_MAX;
  Real bd = 1e300;
  for (; it != slots_.end() && it->first == id; ++it) {
    const Vec3 d = set_.pos(it->second) - near;
    const Real r2 = core::dot(d, d);
    if (r2 < bd) bd = r2, best = it->second;
  }
  return best;
}

}  // namespace biota::models::plants
