#include "models/plants/seaweed_mechanics.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>

#include "core/quat.hpp"
#include "particles/cell_list.hpp"

namespace biota::models::plants {

using particles::kNoId;
using particles::ParticleSet;

SeaweedBodies::SeaweedBodies(particles::ParticleComm& comm, MechanicsParams params)
    : comm_(comm), p_(params), set_(seaweed_layout()) {
  const auto& L = set_.layout();
  a_vel = L.find_real("v"), a_quat = L.find_real("q"), a_omega = L.find_real("omega");
  a_force = L.find_real("force"), a_torque = L.find_real("torque"), a_uf = L.find_real("u_fluid");
  a_imp = L.find_real("drag_impulse"), a_anchor_c = L.find_real("anchor_child");
  a_jforce = L.find_real("joint_force"), a_jtorque = L.find_real("joint_torque");
  a_radius = L.find_real("radius");
  a_xs = L.find_real("x_sample");
  u_plant = L.find_u64("plant"), u_parent = L.find_u64("parent");
}

namespace {
/// \brief Stable counting sort of `in` into `out` (of the same size) by key(e) in [0, n_keys);
/// `start` is scratch.
template <class Pair, class Key>
void counting_sort(const std::vector<Pair>& in, std::vector<Pair>& out, std::size_t n_keys,
                   std::vector<std::uint32_t>& start, Key key) {
  start.assign(n_keys + 1, 0);
  for (const Pair& e : in) ++start[key(e) + 1];
  for (std::size_t k = 0; k < n_keys; ++k) start[k + 1] += start[k];
  for (const Pair& e : in) out[start[key(e)]++] = e;
}

/// \brief True if beyond(d2) for the squared displacement d2 of any of the first n spheres of
/// `set` from its reference position ref[i]. Run every sub-step (the skin and inner-list checks):
/// chunks are tested without a branch, in vector lanes, with an exit after each (0.55-0.72 of
/// the time of a branch or a max per sphere, docs/performance-seaweed.md, session 28).
template <class Beyond>
bool any_moved(const ParticleSet& set, const Vec3* ref, std::size_t n, Beyond beyond) {
  const Real *px = set.real(ParticleSet::kPos, 0), *py = set.real(ParticleSet::kPos, 1),
             *pz = set.real(ParticleSet::kPos, 2);
  constexpr std::size_t kChunk = 512;
  for (std::size_t k0 = 0; k0 < n; k0 += kChunk) {
    const std::size_t k1 = std::min(n, k0 + kChunk);
    int moved = 0;
    for (std::size_t k = k0; k < k1; ++k) {
      const Real dx = px[k] - ref[k].x, dy = py[k] - ref[k].y, dz = pz[k] - ref[k].z;
      moved |= beyond(dx * dx + dy * dy + dz * dz) ? 1 : 0;
    }
    if (moved != 0) return true;
  }
  return false;
}

void set_q(ParticleSet& s, int a, std::size_t i, const core::Quat& q) {
  s.real(a, 0)[i] = q.w, s.real(a, 1)[i] = q.x, s.real(a, 2)[i] = q.y, s.real(a, 3)[i] = q.z;
}
}  // namespace

void for_each_sphere(
    const Population& pop, Real spacing,
    const std::function<void(std::uint64_t, const Vec3&, int, std::uint64_t, const Vec3&)>& fn) {
  std::vector<GlobalId> bud_sphere(pop.buds.size(), kNoId);
  GlobalId next = 0;
  for (const Bud& b : pop.buds) {
    if (b.parent == ~GlobalId{0}) {
      bud_sphere[b.id] = next;
      fn(next++, b.pos, b.plant, kNoId, {});
      continue;
    }
    const Vec3 a = pop.buds[b.parent].pos, d = b.pos - a;
    const int segments = std::max(1, static_cast<int>(std::ceil(core::norm(d) / spacing - 1e-9)));
    GlobalId prev = bud_sphere[b.parent];
    Vec3 prev_x = a;
    for (int k = 1; k <= segments; ++k) {
      const Vec3 x = a + d * (static_cast<Real>(k) / segments);
      fn(next, x, b.plant, prev, prev_x);
      prev = next++;
      prev_x = x;
    }
    bud_sphere[b.id] = prev;
  }
}

void SeaweedBodies::build(const Population& pop, int n_plants) {
  n_plants_ = n_plants;
  const int me = comm_.decomposition().rank();
  for_each_sphere(
      pop, p_.spacing,
      [&](GlobalId id, const Vec3& x, int plant, GlobalId parent, const Vec3& parent_x) {
        if (comm_.owner_of(x) != me) return;
        const std::size_t i = set_.add_owned(id, x);
        set_q(set_, a_quat, i, {});
        set_.real(a_radius)[i] = p_.radius;
        set_.u64(u_plant)[i] = static_cast<std::uint64_t>(plant);
        set_.u64(u_parent)[i] = parent;
        if (parent != kNoId) {
          longest_bond_local_ = std::max(longest_bond_local_, core::norm(x - parent_x));
          // Joint anchor at the midpoint; all spheres start with the identity orientation, so
          // the rest relative orientation is the identity and the parent's anchor, (x -
          // parent_x) * 0.5, is 0 - anchor_child bit for bit (seaweed_joint_block.hpp).
          set_.set_vec3(a_anchor_c, i, (parent_x - x) * 0.5);
        }
      });
}

long long SeaweedBodies::global_count() const {
  long long n = static_cast<long long>(set_.n_owned());
  MPI_Allreduce(MPI_IN_PLACE, &n, 1, MPI_LONG_LONG, MPI_SUM, comm_.decomposition().comm());
  return n;
}

Real SeaweedBodies::ghost_cutoff() const {
  return p_.ghost_cutoff();
}

Real SeaweedBodies::longest_bond() const {
  Real m = longest_bond_local_;
  MPI_Allreduce(MPI_IN_PLACE, &m, 1, MPI_DOUBLE, MPI_MAX, comm_.decomposition().comm());
  return m;
}

void SeaweedBodies::begin_step() {
  // Full rebuild (migrate + ghosts + lists) when a sphere moved more than half the skin since the
  // last build, after a rebuild inside advance() (which did not migrate), and at the start.
  if (!built_ || need_migrate_ || max_displacement_exceeded()) {
    comm_.migrate(set_);
    rebuild_lists();
    need_migrate_ = false;
    built_ = true;
  } else {
    comm_.update_ghosts(set_);
  }
}

bool SeaweedBodies::local_displacement_exceeded() const {
  const Real lim2 = 0.25 * p_.skin * p_.skin;
  return any_moved(set_, x_build_.data(), std::min(set_.n_owned(), x_build_.size()),
                   [lim2](Real d2) { return d2 > lim2; });
}

bool SeaweedBodies::filter_due() const {
  // A contact dropped by the filter was at least r_i + r_j + inner_skin apart; while no sphere
  // (owned or ghost: both are refreshed each sub-step and keep their slots between list builds)
  // moved half the inner skin, it is still more than r_i + r_j apart and adds nothing. The
  // (1 - 1e-6) keeps that margin ~1e-9 m, far above round-off. Rank-local: the filter changes no
  // result, so ranks need not agree on when they filter.
  if (need_filter_ || p_.inner_skin <= 0) return true;
  const Real lim = 0.5 * p_.inner_skin * (1 - 1e-6), lim2 = lim * lim;
  return any_moved(set_, x_filter_.data(), set_.n_total(), [lim2](Real d2) { return d2 >= lim2; });
}

bool SeaweedBodies::max_displacement_exceeded() const {
  int flag = local_displacement_exceeded();
  MPI_Allreduce(MPI_IN_PLACE, &flag, 1, MPI_INT, MPI_MAX, comm_.decomposition().comm());
  return flag != 0;
}

void SeaweedBodies::store_by_plant() {
  // Ids alone interleave the plants: every growth cycle numbers its new spheres after all older
  // ones, so a branch's first joint has its parent thousands of slots away in id order, very
  // likely in another block of the sub-step (seaweed_sub_step.cpp), which must then evaluate it
  // too: 20-21% more joint evaluations with blocks of 1024-4096 in the 10x weak-scaling case.
  // Stored plant by plant (by id within a plant), a plant's spheres are together (0.7% more), and
  // the joints are walked in that order (rebuild_lists). The storage order changes no result: every
  // sum follows global ids.
  const std::size_t no = set_.n_owned();
  const std::uint64_t* plant = set_.u64(u_plant);
  const GlobalId* ids = set_.u64(ParticleSet::kId);
  const auto before = [&](std::size_t a, std::size_t b) {
    return plant[a] != plant[b] ? plant[a] < plant[b] : ids[a] < ids[b];
  };
  // A migration keeps the staying spheres' order and appends the arrivals: merge those in.
  std::size_t in_order = 1;
  while (in_order < no && !before(in_order, in_order - 1)) ++in_order;
  if (in_order >= no) return;
  std::vector<std::size_t> order(no);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin() + static_cast<std::ptrdiff_t>(in_order), order.end(), before);
  std::inplace_merge(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(in_order),
                     order.end(), before);
  set_.reorder_owned(order);
}

void SeaweedBodies::rebuild_lists() {
  const bool by_plant = n_blocks() > 1;
  if (by_plant) store_by_plant();
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
  place_.resize(nt);  // slot -> place in slots_
  for (std::size_t k = 0; k < nt; ++k) place_[slots_[k].second] = static_cast<std::uint32_t>(k);
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
  cl.for_each_pair([&](std::size_t i, std::size_t j, Real) {
    if (i >= no && j >= no) return;
    // Joined neighbours and siblings on one parent do not collide.
    const GlobalId pi = parent[i], pj = parent[j];
    if (pi == ids[j] || pj == ids[i] || (pi == pj && pi != kNoId)) return;
    const auto lo = static_cast<std::uint32_t>(ids[i] < ids[j] ? i : j);
    const auto hi = static_cast<std::uint32_t>(ids[i] < ids[j] ? j : i);
    pairs_.push_back({lo, hi});
  });
  joints_.clear();
  long long skipped = 0;
  // Joints in the order of their child's global id, plant by plant where the spheres are stored
  // so: a sphere's parent has a lower id than the sphere and its children higher ones
  // (for_each_sphere numbers a parent first), and a joint never leaves its plant, so adding each
  // joint's result to its owned spheres in either order sums a sphere's joints by partner id --
  // the joint as child first, then those as parent by child id -- without a slot per result.
  // Walked in the storage order, the children come as runs of consecutive slots.
  std::vector<std::size_t> walk(nt);
  if (by_plant) {  // slots_ bucketed by plant
    std::uint64_t n_plant_keys = 0;
    const std::uint64_t* plant = set_.u64(u_plant);
    for (std::size_t i = 0; i < nt; ++i) n_plant_keys = std::max(n_plant_keys, plant[i] + 1);
    std::vector<std::size_t> plant_begin(n_plant_keys + 1, 0);
    for (std::size_t i = 0; i < nt; ++i) ++plant_begin[plant[i] + 1];
    std::partial_sum(plant_begin.begin(), plant_begin.end(), plant_begin.begin());
    for (const auto& [id, slot] : slots_) walk[plant_begin[plant[slot]]++] = slot;
  } else {
    for (std::size_t k = 0; k < nt; ++k) walk[k] = slots_[k].second;
  }
  // A parent is most often its child's predecessor in id order (a chain grown in one cycle):
  // that place is tried before a binary search (0.35 of the walk's time, session 28).
  for (const std::size_t c : walk) {
    const GlobalId pid = parent[c];
    if (pid == kNoId) continue;
    const std::size_t p = find_near(pid, set_.pos(c), std::size_t{place_[c]} - 1);
    // Partner out of range: expected for a ghost child (its owner evaluates the joint); for an
    // owned child the joint is lost for this list's lifetime -- counted, reported in metrics.
    if (p == SIZE_MAX) {
      skipped += c < no ? 1 : 0;
      continue;
    }
    if (c < no || p < no) joints_.emplace_back(c, p);
  }
  skipped_joints_ = skipped;
  joint_parent_id_.resize(joints_.size());
  for (std::size_t m = 0; m < joints_.size(); ++m) joint_parent_id_[m] = ids[joints_[m].second];
  split_joints_by_block();
  // Contacts once per pair, ordered by (lower id, higher id): a sphere s meets its pairs (p, s),
  // p < s, by increasing p, all before its pairs (s, q) by increasing q -- its contacts by partner
  // id, the fixed summation order after the joints. Two stable counting sorts on the spheres'
  // places in id order (slots_, ties by slot), by the higher sphere and then by the lower one:
  // 0.38 of the time of a sort per lower sphere by id (docs/performance-seaweed.md, session 28).
  const std::uint32_t* place = place_.data();
  pair_scratch_.resize(pairs_.size());
  contact_pairs_.resize(pairs_.size());
  counting_sort(pairs_, pair_scratch_, nt, place_start_,
                [place](const ContactPair& e) { return place[e.b]; });
  counting_sort(pair_scratch_, contact_pairs_, nt, place_start_,
                [place](const ContactPair& e) { return place[e.a]; });
}

void SeaweedBodies::sample_fluid(const VelocityFn& u) {
  for (std::size_t i = 0; i < set_.n_owned(); ++i) set_.set_vec3(a_uf, i, u(set_.pos(i)));
}

std::size_t SeaweedBodies::find_near(GlobalId id, const Vec3& near, std::size_t guess) const {
  const bool first_at_guess = guess < slots_.size() && slots_[guess].first == id &&
                              (guess == 0 || slots_[guess - 1].first != id);
  auto it = first_at_guess ? slots_.begin() + static_cast<std::ptrdiff_t>(guess)
                           : std::lower_bound(slots_.begin(), slots_.end(),
                                              std::pair<GlobalId, std::size_t>{id, 0});
  std::size_t best = SIZE_MAX;
  Real bd = 1e300;
  for (; it != slots_.end() && it->first == id; ++it) {
    const Vec3 d = set_.pos(it->second) - near;
    const Real r2 = core::dot(d, d);
    if (r2 < bd) bd = r2, best = it->second;
  }
  return best;
}

ClusterMetrics SeaweedBodies::clusters() {
  MPI_Comm comm = comm_.decomposition().comm();
  // Plant pairs in contact, gathered on every rank; union-find in a fixed order, so every rank
  // and every rank count gets the same labels.
  std::vector<std::uint64_t> local;
  long long contacts = 0;
  for (const auto [i, j] : contact_pairs_) {
    if (i >= set_.n_owned()) continue;  // counted by the owner of the lower-id sphere
    const auto a = set_.u64(u_plant)[i], b = set_.u64(u_plant)[j];
    if (a == b) continue;
    const Real gap =
        core::norm(set_.pos(i) - set_.pos(j)) - set_.real(a_radius)[i] - set_.real(a_radius)[j];
    if (gap > p_.cluster_margin) continue;
    ++contacts;
    local.push_back(std::min(a, b) * static_cast<std::uint64_t>(n_plants_) + std::max(a, b));
  }
  std::sort(local.begin(), local.end());
  local.erase(std::unique(local.begin(), local.end()), local.end());
  int P = 0;
  MPI_Comm_size(comm, &P);
  int n = static_cast<int>(local.size());
  std::vector<int> counts(P), disp(P);
  MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
  int total = 0;
  for (int r = 0; r < P; ++r) disp[r] = total, total += counts[r];
  std::vector<std::uint64_t> all(total);
  MPI_Allgatherv(local.data(), n, MPI_UINT64_T, all.data(), counts.data(), disp.data(),
                 MPI_UINT64_T, comm);
  std::sort(all.begin(), all.end());
  std::vector<int> parent(n_plants_);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (auto key : all) {
    const int a = find(static_cast<int>(key / n_plants_)),
              b = find(static_cast<int>(key % n_plants_));
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
  std::vector<int> size(n_plants_, 0);
  for (int k = 0; k < n_plants_; ++k) ++size[find(k)];
  ClusterMetrics cm;
  cm.plants = n_plants_;
  for (int k = 0; k < n_plants_; ++k)
    if (size[k] > 0) ++cm.clusters, cm.largest = std::max(cm.largest, size[k]);
  cm.largest_share = n_plants_ > 0 ? static_cast<double>(cm.largest) / n_plants_ : 0;
  long long joints = 0;
  for (std::size_t i = 0; i < set_.n_owned(); ++i) joints += set_.u64(u_parent)[i] != kNoId;
  long long v[4] = {contacts, broken_local_, joints, skipped_joints_};
  MPI_Allreduce(MPI_IN_PLACE, v, 4, MPI_LONG_LONG, MPI_SUM, comm);
  cm.contacts = v[0], cm.broken_joints = v[1], cm.joints = v[2], cm.skipped_joints = v[3];
  return cm;
}

}  // namespace biota::models::plants
