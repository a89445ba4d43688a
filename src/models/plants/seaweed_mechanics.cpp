#include "models/plants/seaweed_mechanics.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <numeric>
#include <type_traits>
#include <utility>

#include "core/quat.hpp"
#include "models/plants/seaweed_body_forces.hpp"
#include "models/plants/seaweed_contact_block.hpp"
#include "models/plants/seaweed_contact_law.hpp"
#include "models/plants/seaweed_integrate.hpp"
#include "models/plants/seaweed_joint_block.hpp"
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
  a_anchor_p = L.find_real("anchor_parent"), a_qrest = L.find_real("q_rest");
  a_jforce = L.find_real("joint_force"), a_jtorque = L.find_real("joint_torque");
  a_radius = L.find_real("radius");
  a_xs = L.find_real("x_sample");
  u_plant = L.find_u64("plant"), u_parent = L.find_u64("parent");
}

namespace {
void set_q(ParticleSet& s, int a, std::size_t i, const core::Quat& q) {
  s.real(a, 0)[i] = q.w, s.real(a, 1)[i] = q.x, s.real(a, 2)[i] = q.y, s.real(a, 3)[i] = q.z;
}
/// The three columns of a 3-component attribute, read without the set's indirections.
struct Col3 {
  const Real *c0, *c1, *c2;
  Vec3 at(std::size_t i) const { return {c0[i], c1[i], c2[i]}; }
};
Col3 cols3(const ParticleSet& s, int a) {
  return {s.real(a, 0), s.real(a, 1), s.real(a, 2)};
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
        set_q(set_, a_qrest, i, {});
        set_.real(a_radius)[i] = p_.radius;
        set_.u64(u_plant)[i] = static_cast<std::uint64_t>(plant);
        set_.u64(u_parent)[i] = parent;
        if (parent != kNoId) {
          longest_bond_local_ = std::max(longest_bond_local_, core::norm(x - parent_x));
          // Joint anchor at the midpoint; all spheres start with the identity
          // orientation.
          set_.set_vec3(a_anchor_c, i, (parent_x - x) * 0.5);
          set_.set_vec3(a_anchor_p, i, (x - parent_x) * 0.5);
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
  Real m2 = 0;
  for (std::size_t i = 0; i < set_.n_owned() && i < x_build_.size(); ++i) {
    const Vec3 d = set_.pos(i) - x_build_[i];
    m2 = std::max(m2, core::dot(d, d));
  }
  return m2 > 0.25 * p_.skin * p_.skin;
}

bool SeaweedBodies::filter_due() const {
  // A contact dropped by the filter was at least r_i + r_j + inner_skin apart; while no sphere
  // (owned or ghost: both are refreshed each sub-step and keep their slots between list builds)
  // moved half the inner skin, it is still more than r_i + r_j apart and adds nothing. The
  // (1 - 1e-6) keeps that margin ~1e-9 m, far above round-off. Rank-local: the filter changes no
  // result, so ranks need not agree on when they filter.
  if (need_filter_ || p_.inner_skin <= 0) return true;
  const std::size_t nt = set_.n_total();
  const Real *px = set_.real(ParticleSet::kPos, 0), *py = set_.real(ParticleSet::kPos, 1),
             *pz = set_.real(ParticleSet::kPos, 2);
  const Real lim = 0.5 * p_.inner_skin * (1 - 1e-6), lim2 = lim * lim;
  for (std::size_t k = 0; k < nt; ++k) {
    const Real dx = px[k] - x_filter_[k].x, dy = py[k] - x_filter_[k].y,
               dz = pz[k] - x_filter_[k].z;
    if (dx * dx + dy * dy + dz * dz >= lim2) return true;
  }
  return false;
}

bool SeaweedBodies::max_displacement_exceeded() const {
  int flag = local_displacement_exceeded();
  MPI_Allreduce(MPI_IN_PLACE, &flag, 1, MPI_INT, MPI_MAX, comm_.decomposition().comm());
  return flag != 0;
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
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;  // (lower id, higher id)
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
    pairs.emplace_back(lo, hi);
  });
  joints_.clear();
  long long skipped = 0;
  // Joints in the order of their child's global id (slots_ is sorted by id): a sphere's parent
  // has a lower id than the sphere and its children higher ones (for_each_sphere numbers a
  // parent first), so adding each joint's result to its owned spheres in this order sums a
  // sphere's joints by partner id -- the joint as child first, then those as parent by child id
  // -- without a slot per result.
  for (const auto& [child_id, c] : slots_) {
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
  joint_parent_id_.resize(joints_.size());
  for (std::size_t m = 0; m < joints_.size(); ++m) joint_parent_id_[m] = ids[joints_[m].second];
  // Contacts once per pair, ordered by (lower id, higher id): a sphere s meets its pairs (p, s),
  // p < s, by increasing p, all before its pairs (s, q) by increasing q -- its contacts by partner
  // id, the fixed summation order after the joints. Built as a CSR by lower sphere (counted,
  // filled, each short segment sorted by partner id), read out in id order through slots_.
  std::vector<std::uint32_t> begin(nt + 1, 0), upper(pairs.size());
  for (const auto& pr : pairs) ++begin[pr.first + 1];
  for (std::size_t i = 0; i < nt; ++i) begin[i + 1] += begin[i];
  std::vector<std::uint32_t> fill(begin.begin(), begin.end() - 1);
  for (const auto& [i, j] : pairs) upper[fill[i]++] = j;
  const auto by_id = [&](std::uint32_t x, std::uint32_t y) {
    return ids[x] != ids[y] ? ids[x] < ids[y] : x < y;
  };
  contact_pairs_.clear();
  contact_pairs_.reserve(pairs.size());
  for (const auto& [id, lower] : slots_) {
    std::uint32_t* seg = upper.data() + begin[lower];
    std::uint32_t* seg_end = upper.data() + begin[lower + 1];
    std::sort(seg, seg_end, by_id);
    for (; seg != seg_end; ++seg)
      contact_pairs_.push_back({static_cast<std::uint32_t>(lower), *seg});
  }
}

void SeaweedBodies::sample_fluid(const VelocityFn& u) {
  for (std::size_t i = 0; i < set_.n_owned(); ++i) set_.set_vec3(a_uf, i, u(set_.pos(i)));
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

void SeaweedBodies::compute_forces(Real dt_sub) {
  const std::size_t no = set_.n_owned();
  const Real V = 4.0 / 3.0 * std::numbers::pi * p_.radius * p_.radius * p_.radius;
  const Real area = std::numbers::pi * p_.radius * p_.radius;
  const Vec3 weight{0, 0,
                    (p_.water_density - p_.plant_density) * V * p_.gravity};  // eq. 9 + gravity
  // Column pointers hoisted out of the loops (the accessors go through two indirections each);
  // the arithmetic is the same expression for expression, so the results are bitwise unchanged.
  const ParticleSet& cs = set_;
  const Col3 x = cols3(cs, ParticleSet::kPos), v = cols3(cs, a_vel), w = cols3(cs, a_omega),
             ac = cols3(cs, a_anchor_c), ap = cols3(cs, a_anchor_p), uf = cols3(cs, a_uf);
  Real *fx = set_.real(a_force, 0), *fy = set_.real(a_force, 1), *fz = set_.real(a_force, 2);
  Real *tx = set_.real(a_torque, 0), *ty = set_.real(a_torque, 1), *tz = set_.real(a_torque, 2);
  Real *ix = set_.real(a_imp, 0), *iy = set_.real(a_imp, 1), *iz = set_.real(a_imp, 2);
  const Real *qw = set_.real(a_quat, 0), *qx = set_.real(a_quat, 1), *qy = set_.real(a_quat, 2),
             *qz = set_.real(a_quat, 3);
  const Real *rw = set_.real(a_qrest, 0), *rx = set_.real(a_qrest, 1), *ry = set_.real(a_qrest, 2),
             *rz = set_.real(a_qrest, 3);
  const Real* rad = set_.real(a_radius);
  const std::uint64_t* parent = set_.u64(u_parent);
  Real *jforce = set_.real(a_jforce), *jtorque = set_.real(a_jtorque);
  // The sum on each owned sphere: body forces, then its joints, then its contacts, each group
  // by partner id (an order of global ids only, so the same on any rank count). Each phase runs
  // over all spheres at once, adding into the force columns in that order: no loop per sphere
  // whose varying length the core mispredicts at every exit.
  BodyForceLaw body{
      weight.z, 0.5 * p_.drag_cd * p_.water_density * area, dt_sub, p_.contact_k, p_.contact_c, {},
      {}};
  for (int d = 0; d < 3; ++d) {
    const bool periodic = comm_.decomposition().periodic(d);
    body.wall_lo[d] = periodic ? -INFINITY : comm_.domain_lo()[d] + p_.radius;
    body.wall_hi[d] = periodic ? INFINITY : comm_.domain_hi()[d] - p_.radius;
  }
  body_forces(body,
              {{x.c0, x.c1, x.c2},
               {v.c0, v.c1, v.c2},
               {uf.c0, uf.c1, uf.c2},
               {fx, fy, fz},
               {tx, ty, tz},
               {ix, iy, iz}},
              no);
  // Joint results are added to their owned spheres as they come, in joints_'s order (child id),
  // which is each sphere's joint order by partner id (rebuild_lists).
  const std::size_t nj = joints_.size();
  const GlobalId* joint_parent_id = joint_parent_id_.data();
  const auto add = [&](std::size_t i, const Vec3& f, const Vec3& t) {
    fx[i] = fx[i] + f.x, fy[i] = fy[i] + f.y, fz[i] = fz[i] + f.z;
    tx[i] = tx[i] + t.x, ty[i] = ty[i] + t.y, tz[i] = tz[i] + t.z;
  };
  // Joints: evaluated by the owner of either sphere with the child's (ghost-refreshed) data, in
  // blocks of kJointBlock (gathered into SoA lanes, evaluated with vector instructions, bitwise
  // the scalar law: seaweed_joint_block.hpp). Padding lanes repeat the block's first joint and
  // are discarded.
  JointBlock& jb = *joint_block_;
  // The joints' parents and the contacts' partners are read in no particular order: position,
  // velocity, angular velocity, radius and orientation are copied into one record per sphere
  // first (two cache lines per partner instead of fourteen columns).
  const std::size_t nt = set_.n_total();
  hot_.resize(nt);
  for (std::size_t i = 0; i < nt; ++i)
    hot_[i] = {x.at(i), v.at(i), w.at(i), rad[i], {qw[i], qx[i], qy[i], qz[i]}, {0, 0}};
  const Hot* hot = hot_.data();
  // The child inputs of a block: the lane each is copied to, and its column. The gather copies
  // them; the joint loop prefetches the columns ahead of it.
  const std::pair<Real*, const Real*> child_inputs[] = {
      {jb.qc.w, qw},    {jb.qc.x, qx},    {jb.qc.y, qy},    {jb.qc.z, qz},    {jb.qr.w, rw},
      {jb.qr.x, rx},    {jb.qr.y, ry},    {jb.qr.z, rz},    {jb.ac.x, ac.c0}, {jb.ac.y, ac.c1},
      {jb.ac.z, ac.c2}, {jb.ap.x, ap.c0}, {jb.ap.y, ap.c1}, {jb.ap.z, ap.c2}, {jb.xc.x, x.c0},
      {jb.xc.y, x.c1},  {jb.xc.z, x.c2},  {jb.vc.x, v.c0},  {jb.vc.y, v.c1},  {jb.vc.z, v.c2},
      {jb.wc.x, w.c0},  {jb.wc.y, w.c1},  {jb.wc.z, w.c2}};
  // Lanes are filled one input at a time by gather_lane (one vector gather and store, so the
  // law's vector loads find whole stores). A parent's inputs come from its record: `hot_reals`
  // is the offset of the record of slot pj[l], and the field's offset in it is added to the
  // base. Where a block's children are consecutive slots (joints are listed in child order; 86%
  // of the blocks at t = 8 s) a child input is one 64-byte copy from its column.
  const auto gather = [&](auto ci, const std::size_t* hot_reals) {
    for (const auto& [dst, src] : child_inputs) {
      if constexpr (std::is_integral_v<decltype(ci)>)  // lanes ci, ci + 1, ...
        std::memcpy(dst, src + ci, sizeof(JointBlock::Lane));
      else
        gather_lane(dst, src, ci);
    }
    const auto parent = [&](Real* dst, const Real& field) {
      gather_lane(dst, &field, hot_reals);  // field: a member of hot[0]
    };
    const Hot& h = hot[0];
    parent(jb.qp.w, h.q[0]), parent(jb.qp.x, h.q[1]), parent(jb.qp.y, h.q[2]);
    parent(jb.qp.z, h.q[3]);
    parent(jb.xp.x, h.x.x), parent(jb.xp.y, h.x.y), parent(jb.xp.z, h.x.z);
    parent(jb.vp.x, h.v.x), parent(jb.vp.y, h.v.y), parent(jb.vp.z, h.v.z);
    parent(jb.wp.x, h.w.x), parent(jb.wp.y, h.w.y), parent(jb.wp.z, h.w.z);
  };
  constexpr std::size_t kHotReals = sizeof(Hot) / sizeof(Real);
  static_assert(sizeof(Hot) % sizeof(Real) == 0);
  // The 23 child columns are prefetched kPrefetchJoints joints ahead: the hardware prefetchers
  // do not keep that many streams ahead, and the gather stalled on their loads
  // (docs/performance-seaweed.md, session 24: the particle step 0.82-0.88x in one process).
  constexpr std::size_t kPrefetchJoints = 4 * kJointBlock;
  for (std::size_t m0 = 0; m0 < nj; m0 += kJointBlock) {
    const int lanes = static_cast<int>(std::min<std::size_t>(kJointBlock, nj - m0));
    std::size_t ci[kJointBlock], pj_reals[kJointBlock];
    bool runs = lanes == kJointBlock;
    for (int l = 0; l < kJointBlock; ++l) {
      const auto [c, p] = joints_[m0 + (l < lanes ? l : 0)];
      ci[l] = c, pj_reals[l] = p * kHotReals;
      runs = runs && c == ci[0] + l;
    }
    if (m0 + kPrefetchJoints < nj) {
      // The line of the ahead block's last child: its first child's line is that of the slot
      // before, prefetched a block earlier, when the blocks run on consecutive slots (most do).
      // Written in the loop: GCC drops a prefetch in a helper that does nothing else.
      const auto [c, p] = joints_[m0 + kPrefetchJoints];
      const std::size_t last = std::min(c + kJointBlock - 1, nt - 1);
      for (const auto& input : child_inputs) __builtin_prefetch(input.second + last, 0, 3);
      __builtin_prefetch(hot + p, 0, 3);
      __builtin_prefetch(reinterpret_cast<const char*>(hot + p) + 64, 0, 3);
    }
    if (runs)
      gather(ci[0], pj_reals);
    else
      gather(+ci, pj_reals);
    evaluate_joint_block(jb, p_.joint_k, p_.joint_c, p_.bend_k, p_.bend_c);
    for (int l = 0; l < lanes; ++l) {
      const std::size_t m = m0 + l;
      const auto [i, j] = joints_[m];
      if (parent[i] != joint_parent_id[m]) continue;  // broken since the list was built
      const Vec3 F{jb.F.x[l], jb.F.y[l], jb.F.z[l]};
      if (j < no) add(j, -F, {jb.tp.x[l], jb.tp.y[l], jb.tp.z[l]});
      if (i < no) {
        add(i, F, {jb.tc.x[l], jb.tc.y[l], jb.tc.z[l]});  // the child's owner records the joint
                                                          // state and decides the break (eq. 8)
        const Real fm = jb.fm[l], tm = jb.tm[l];
        jforce[i] = fm;
        jtorque[i] = tm;
        if (fm > p_.force_limit || tm > p_.torque_limit) broken_now_.push_back(i);
      }
    }
  }
  // Contacts: each pair once, both results added as they come (rebuild_lists), the partners read
  // from their records (hot_).
  const ContactLaw law{p_.contact_k, p_.contact_c, p_.friction, p_.friction_c};
  // The inner list (see filter_due): on a filter sub-step the whole neighbour list is walked and
  // the contacts that can still touch are copied, in order; otherwise only those are walked.
  // Dropping a pair that cannot overlap drops an exact no-op, so the sums are unchanged.
  if (filter_due()) {
    ++filters_;
    need_filter_ = false;
    x_filter_.resize(nt);
    for (std::size_t k = 0; k < nt; ++k) x_filter_[k] = hot[k].x;
    near_.clear();
    const Real s_in = p_.inner_skin;
    for (const ContactPair& pr : contact_pairs_) {
      const Hot &ha = hot[pr.a], &hb = hot[pr.b];
      const Vec3 d = ha.x - hb.x;
      const Real rr = ha.r + hb.r, reach = rr + s_in, d2 = core::dot(d, d);
      // Beyond the reach and failing the law's first test: cannot touch before the next filter.
      if (d2 >= reach * reach && clearly_apart(d2, rr)) continue;
      near_.push_back(pr);
    }
  }
  // Touching contacts compacted first without a branch on the test, then their laws: a branch
  // per candidate ("touches?", ~50%) and per orientation mispredicts, and each miss discards
  // the next contacts' work in flight.
  touch_.resize(near_.size());
  std::uint32_t* touch = touch_.data();
  std::size_t n_touch = 0;
  for (std::size_t k = 0; k < near_.size(); ++k) {
    const ContactPair e = near_[k];
    const Hot &ha = hot[e.a], &hb = hot[e.b];
    const Vec3 d = ha.x - hb.x;
    touch[n_touch] = static_cast<std::uint32_t>(k);
    n_touch += clearly_apart(core::dot(d, d), ha.r + hb.r) ? 0 : 1;
  }
  // The laws in vector blocks of kContactBlock pairs (the last block padded with its first
  // pair, whose copies are not added); a block's results are added in list order, each pair's
  // to those of its two spheres this rank owns (b gets -f: x + (-f) is x - f, bit for bit).
  ContactBlockOut r;
  std::uint32_t a[kContactBlock], b[kContactBlock];
  for (std::size_t c0 = 0; c0 < n_touch; c0 += kContactBlock) {
    const int lanes = static_cast<int>(std::min<std::size_t>(kContactBlock, n_touch - c0));
    for (int l = 0; l < kContactBlock; ++l) {
      const ContactPair e = near_[touch[c0 + (l < lanes ? l : 0)]];
      a[l] = e.a, b[l] = e.b;
    }
    evaluate_contact_block(hot, a, b, law, r);
    // A lane that does not touch after all adds +0 (and -0 to b): exact, the sums are never -0.
    for (int l = 0; l < lanes; ++l) {
      const Vec3 f{r.fx[l], r.fy[l], r.fz[l]};
      if (a[l] < no) add(a[l], f, {r.tax[l], r.tay[l], r.taz[l]});
      if (b[l] < no) add(b[l], -f, {r.tbx[l], r.tby[l], r.tbz[l]});
    }
  }
  // Breaks take effect after the step's forces are in (ghost copies see them at the next refresh).
  for (std::size_t i : broken_now_) {
    set_.u64(u_parent)[i] = kNoId;
    ++broken_local_;
  }
  broken_now_.clear();
}

void SeaweedBodies::advance(Real dt) {
  const int ns = p_.substeps;
  const Real h = dt / ns, m = p_.mass(), I = p_.inertia();
  set_.zero_real(a_imp);
  for (int s = 0; s < ns; ++s) {
    if (s > 0) {
      // The skin check's reduction runs while the ghosts are refreshed (one synchronisation per
      // sub-step instead of two). A rebuild replaces the ghosts from owned data, so the refresh
      // it makes redundant changes nothing.
      int flag = local_displacement_exceeded();
      MPI_Request req;
      MPI_Iallreduce(MPI_IN_PLACE, &flag, 1, MPI_INT, MPI_MAX, comm_.decomposition().comm(), &req);
      // Only the state that changes inside a step travels: position, velocity, orientation,
      // angular velocity and the parent id (a break). Joint rest data, radius, plant never change
      // and the drag impulse and sampling point are needed on ghosts only after the step (the
      // full refresh at its end).
      comm_.update_ghosts(set_, {ParticleSet::kPos, a_vel, a_quat, a_omega}, {u_parent});
      MPI_Wait(&req, MPI_STATUS_IGNORE);
      if (flag != 0) {  // skin used up inside the step: migrate, new ghosts and lists
        // Everything a sphere carries through the step (velocity, drag impulse so far, sampled
        // fluid velocity, sampling point) migrates with it, and no sum depends on which rank
        // owns a sphere, so migrating here changes no result; it saves begin_step a second
        // rebuild (the former mid-step rebuild without migration forced one).
        comm_.migrate(set_);
        rebuild_lists();
      }
    }
    compute_forces(h);
    // Symplectic Euler: velocities first, then positions with the new velocities.
    const auto col = [&](int a, int c) { return set_.real(a, c); };
    const SphereColumns cols{col(a_force, 0),
                             col(a_force, 1),
                             col(a_force, 2),
                             col(a_torque, 0),
                             col(a_torque, 1),
                             col(a_torque, 2),
                             col(a_vel, 0),
                             col(a_vel, 1),
                             col(a_vel, 2),
                             col(a_omega, 0),
                             col(a_omega, 1),
                             col(a_omega, 2),
                             col(ParticleSet::kPos, 0),
                             col(ParticleSet::kPos, 1),
                             col(ParticleSet::kPos, 2),
                             col(a_quat, 0),
                             col(a_quat, 1),
                             col(a_quat, 2),
                             col(a_quat, 3)};
    integrate_spheres(cols, set_.n_owned(), h, h / m, h / I);
  }
  comm_.update_ghosts(set_);  // ghosts carry the step's final state and drag impulse
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
