/// \file seaweed_sub_step.cpp
/// \brief The seaweed sub-step (split from seaweed_mechanics.cpp, which builds the spheres and
/// their lists): forces and symplectic Euler, block by block of owned spheres.
///
/// A block is a range of owned slots; its body forces, the joints and contacts touching it, and
/// its integration run one after the other while its columns are in cache. This is what each
/// rank already does for the interactions that cross the rank boundary: an interaction between
/// two blocks is evaluated by both, with the same inputs (the sub-step's start state), and each
/// adds it to its own spheres only. Each block walks its subsequence of the rank's joint and
/// contact lists, so every sphere's sum keeps its order and the bits do not depend on the
/// blocks. What a block reads of other spheres comes from the hot records built at the
/// sub-step's start, never from the columns an earlier block has already integrated.
///
/// Blocks pay only where a rank's spheres overflow the caches (block_spheres). With blocks the
/// spheres are stored plant by plant (store_by_plant), so a parent's slot comes before its
/// children's: a joint that crosses blocks has its child in a later block, whose columns still
/// hold the start state.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <type_traits>
#include <utility>

#include "models/plants/seaweed_body_forces.hpp"
#include "models/plants/seaweed_contact_block.hpp"
#include "models/plants/seaweed_contact_law.hpp"
#include "models/plants/seaweed_integrate.hpp"
#include "models/plants/seaweed_joint_block.hpp"
#include "models/plants/seaweed_mechanics.hpp"

namespace biota::models::plants {

using particles::kNoId;
using particles::ParticleSet;

namespace {
/// The three columns of a 3-component attribute, read without the set's indirections.
struct Col3 {
  const Real *c0, *c1, *c2;
  Vec3 at(std::size_t i) const { return {c0[i], c1[i], c2[i]}; }
};
Col3 cols3(const ParticleSet& s, int a) {
  return {s.real(a, 0), s.real(a, 1), s.real(a, 2)};
}

/// The blocks' subsequences of a list of n interactions, as a CSR of positions in the list:
/// interaction k goes to the block of each of its owned spheres (once if both are in one block),
/// in list order. `spheres(k)` gives its two slots. count() gives the offsets, so a caller can
/// decide from the total before fill() copies the positions out.
template <class Spheres>
struct BlockSplit {
  std::size_t n, n_owned, block, n_blocks;
  Spheres spheres;

  template <class Visit>
  void blocks_of(std::size_t k, Visit&& visit) const {
    const auto [s0, s1] = spheres(k);
    const std::size_t b0 = s0 < n_owned ? s0 / block : n_blocks;
    const std::size_t b1 = s1 < n_owned ? s1 / block : n_blocks;
    if (b0 < n_blocks) visit(b0);
    if (b1 < n_blocks && b1 != b0) visit(b1);
  }
  /// Block b's entries are [begin[b], begin[b + 1]); returns the total.
  std::size_t count(std::vector<std::size_t>& begin) const {
    begin.assign(n_blocks + 1, 0);
    for (std::size_t k = 0; k < n; ++k) blocks_of(k, [&](std::size_t b) { ++begin[b + 1]; });
    for (std::size_t b = 0; b < n_blocks; ++b) begin[b + 1] += begin[b];
    return begin[n_blocks];
  }
  /// The positions, by the offsets of count().
  void fill(const std::vector<std::size_t>& begin, std::vector<std::size_t>& at) const {
    at.resize(begin[n_blocks]);
    std::vector<std::size_t> next(begin.begin(), begin.end() - 1);
    for (std::size_t k = 0; k < n; ++k) blocks_of(k, [&](std::size_t b) { at[next[b]++] = k; });
  }
};
}  // namespace

std::size_t SeaweedBodies::block_spheres() const {
  if (p_.sub_step_block >= 0) return static_cast<std::size_t>(p_.sub_step_block);
  // Automatic: blocks pay where a rank's spheres (about 600 bytes each with their records and
  // lists) overflow its share of the last-level cache, and cost where they do not, through the
  // interactions between blocks evaluated twice (docs/performance-seaweed.md, session 26: 0.90-0.97
  // of the time with 45k spheres per rank, 1.13-1.15 with 17k in the cycle-5 mat); see also
  // blocks_pay_.
  constexpr std::size_t kBlockFrom = 32768, kBlock = 2048;
  return set_.n_owned() > kBlockFrom ? kBlock : 0;
}

std::size_t SeaweedBodies::n_blocks() const {
  const std::size_t no = set_.n_owned(), per = block_spheres();
  return per == 0 || no <= per ? 1 : (no + per - 1) / per;
}

std::size_t SeaweedBodies::n_blocks_in_use() const {
  return blocks_pay_ ? n_blocks() : 1;
}

void SeaweedBodies::split_joints_by_block() {
  if (n_blocks() == 1) return;
  const BlockSplit split{joints_.size(), set_.n_owned(), block_spheres(), n_blocks(),
                         [&](std::size_t m) { return joints_[m]; }};
  std::vector<std::size_t> at;
  split.count(block_joint_begin_);
  split.fill(block_joint_begin_, at);
  block_joints_.resize(at.size());
  block_joint_parent_id_.resize(at.size());
  for (std::size_t k = 0; k < at.size(); ++k)
    block_joints_[k] = joints_[at[k]], block_joint_parent_id_[k] = joint_parent_id_[at[k]];
}

void SeaweedBodies::split_contacts_by_block() {
  if (n_blocks() == 1) return;
  const BlockSplit split{near_.size(), set_.n_owned(), block_spheres(), n_blocks(),
                         [&](std::size_t k) {
                           return std::pair<std::size_t, std::size_t>{near_[k].a, near_[k].b};
                         }};
  // Automatic blocks only while the interactions they share add at most a tenth to the work:
  // many contacts join two plants in a dense mat, and a block is a few plants. Where they do not
  // pay, the contacts are not copied out.
  const std::size_t whole = joints_.size() + near_.size(),
                    in_blocks = block_joints_.size() + split.count(block_contact_begin_);
  blocks_pay_ = p_.sub_step_block >= 0 || in_blocks * 10 <= whole * 11;
  if (!blocks_pay_) return;
  std::vector<std::size_t> at;
  split.fill(block_contact_begin_, at);
  block_contacts_.resize(at.size());
  for (std::size_t k = 0; k < at.size(); ++k) block_contacts_[k] = near_[at[k]];
}

SeaweedBodies::SphereBlock SeaweedBodies::sphere_block(std::size_t k) const {
  const std::size_t no = set_.n_owned();
  if (n_blocks_in_use() == 1)
    return {0,           no, joints_.data(), joint_parent_id_.data(), joints_.size(), near_.data(),
            near_.size()};
  const std::size_t per = block_spheres(), j0 = block_joint_begin_[k], c0 = block_contact_begin_[k];
  return {k * per,
          std::min(no, (k + 1) * per),
          block_joints_.data() + j0,
          block_joint_parent_id_.data() + j0,
          block_joint_begin_[k + 1] - j0,
          block_contacts_.data() + c0,
          block_contact_begin_[k + 1] - c0};
}

void SeaweedBodies::begin_sub_step() {
  // The joints' parents and the contacts' partners are read in no particular order: position,
  // velocity, angular velocity, radius and orientation are copied into one record per sphere
  // first (two cache lines per partner instead of fourteen columns). They also hold the
  // sub-step's start state while earlier blocks are integrated.
  const std::size_t nt = set_.n_total();
  const ParticleSet& cs = set_;
  const Col3 x = cols3(cs, ParticleSet::kPos), v = cols3(cs, a_vel), w = cols3(cs, a_omega);
  const Real *qw = cs.real(a_quat, 0), *qx = cs.real(a_quat, 1), *qy = cs.real(a_quat, 2),
             *qz = cs.real(a_quat, 3), *rad = cs.real(a_radius);
  hot_.resize(nt);
  for (std::size_t i = 0; i < nt; ++i)
    hot_[i] = {x.at(i), v.at(i), w.at(i), rad[i], {qw[i], qx[i], qy[i], qz[i]}, {0, 0}};
  // The inner list (see filter_due): on a filter sub-step the whole neighbour list is walked and
  // the contacts that can still touch are copied, in order; otherwise only those are walked.
  // Dropping a pair that cannot overlap drops an exact no-op, so the sums are unchanged.
  if (!filter_due()) return;
  ++filters_;
  need_filter_ = false;
  const Hot* hot = hot_.data();
  x_filter_.resize(nt);
  for (std::size_t k = 0; k < nt; ++k) x_filter_[k] = hot[k].x;
  // The pairs read the dense copies, x_filter_ and the radius column (32 bytes a sphere, in L2,
  // where a record is two lines), and the test does not branch: every pair is written and the
  // count advances over those kept (about one in seven in the cycle-5 mat), whose pattern the
  // branch mispredicted. 0.57-0.59 of the filter's time (docs/performance-seaweed.md, session 27).
  if (filter_out_.size() < contact_pairs_.size()) filter_out_.resize(contact_pairs_.size());
  ContactPair* kept = filter_out_.data();
  std::size_t n_kept = 0;
  const Vec3* xf = x_filter_.data();
  const Real s_in = p_.inner_skin;
  for (const ContactPair& pr : contact_pairs_) {
    const Vec3 d = xf[pr.a] - xf[pr.b];
    const Real rr = rad[pr.a] + rad[pr.b], reach = rr + s_in, d2 = core::dot(d, d);
    // Beyond the reach and failing the law's first test: cannot touch before the next filter.
    const bool apart = (d2 >= reach * reach) & clearly_apart(d2, rr);
    kept[n_kept] = pr;
    n_kept += apart ? 0 : 1;
  }
  near_.assign(kept, kept + n_kept);
  split_contacts_by_block();
}

void SeaweedBodies::block_forces(const SphereBlock& blk, Real dt_sub) {
  const std::size_t lo = blk.lo, span = blk.hi - blk.lo;
  // Whether slot i is one of this block's spheres, the only ones it adds to.
  const auto mine = [lo, span](std::size_t i) { return i - lo < span; };
  const Real V = 4.0 / 3.0 * std::numbers::pi * p_.radius * p_.radius * p_.radius;
  const Real area = std::numbers::pi * p_.radius * p_.radius;
  const Vec3 weight{0, 0,
                    (p_.water_density - p_.plant_density) * V * p_.gravity};  // eq. 9 + gravity
  // Column pointers hoisted out of the loops (the accessors go through two indirections each);
  // the arithmetic is the same expression for expression, so the results are bitwise unchanged.
  const ParticleSet& cs = set_;
  const Col3 x = cols3(cs, ParticleSet::kPos), v = cols3(cs, a_vel), w = cols3(cs, a_omega),
             ac = cols3(cs, a_anchor_c), uf = cols3(cs, a_uf);
  Real *fx = set_.real(a_force, 0), *fy = set_.real(a_force, 1), *fz = set_.real(a_force, 2);
  Real *tx = set_.real(a_torque, 0), *ty = set_.real(a_torque, 1), *tz = set_.real(a_torque, 2);
  Real *ix = set_.real(a_imp, 0), *iy = set_.real(a_imp, 1), *iz = set_.real(a_imp, 2);
  const Real *qw = set_.real(a_quat, 0), *qx = set_.real(a_quat, 1), *qy = set_.real(a_quat, 2),
             *qz = set_.real(a_quat, 3);
  const std::uint64_t* parent = set_.u64(u_parent);
  Real *jforce = set_.real(a_jforce), *jtorque = set_.real(a_jtorque);
  // The sum on each owned sphere: body forces, then its joints, then its contacts, each group
  // by partner id (an order of global ids only, so the same on any rank count). Each phase runs
  // over all the block's spheres at once, adding into the force columns in that order: no loop
  // per sphere whose varying length the core mispredicts at every exit.
  BodyForceLaw body{
      weight.z, 0.5 * p_.drag_cd * p_.water_density * area, dt_sub, p_.contact_k, p_.contact_c, {},
      {}};
  for (int d = 0; d < 3; ++d) {
    const bool periodic = comm_.decomposition().periodic(d);
    body.wall_lo[d] = periodic ? -INFINITY : comm_.domain_lo()[d] + p_.radius;
    body.wall_hi[d] = periodic ? INFINITY : comm_.domain_hi()[d] - p_.radius;
  }
  body_forces(body,
              {{x.c0 + lo, x.c1 + lo, x.c2 + lo},
               {v.c0 + lo, v.c1 + lo, v.c2 + lo},
               {uf.c0 + lo, uf.c1 + lo, uf.c2 + lo},
               {fx + lo, fy + lo, fz + lo},
               {tx + lo, ty + lo, tz + lo},
               {ix + lo, iy + lo, iz + lo}},
              span);
  // Joint results are added to the block's spheres as they come, in the joint list's order
  // (child id), which is each sphere's joint order by partner id (rebuild_lists).
  const std::size_t nj = blk.n_joints;
  const auto* joints = blk.joints;
  const GlobalId* joint_parent_id = blk.joint_parent_id;
  const auto add = [&](std::size_t i, const Vec3& f, const Vec3& t) {
    fx[i] = fx[i] + f.x, fy[i] = fy[i] + f.y, fz[i] = fz[i] + f.z;
    tx[i] = tx[i] + t.x, ty[i] = ty[i] + t.y, tz[i] = tz[i] + t.z;
  };
  // Joints: evaluated by the owner of either sphere with the child's (ghost-refreshed) data, in
  // blocks of kJointBlock (gathered into SoA lanes, evaluated with vector instructions, bitwise
  // the scalar law: seaweed_joint_block.hpp). Padding lanes repeat the block's first joint and
  // are discarded.
  JointBlock& jb = *joint_block_;
  const std::size_t nt = set_.n_total();
  const Hot* hot = hot_.data();
  // The child inputs of a block: the lane each is copied to, and its column. The gather copies
  // them; the joint loop prefetches the columns ahead of it.
  const std::pair<Real*, const Real*> child_inputs[] = {
      {jb.qc.w, qw},    {jb.qc.x, qx},    {jb.qc.y, qy},    {jb.qc.z, qz},
      {jb.ac.x, ac.c0}, {jb.ac.y, ac.c1}, {jb.ac.z, ac.c2}, {jb.xc.x, x.c0},
      {jb.xc.y, x.c1},  {jb.xc.z, x.c2},  {jb.vc.x, v.c0},  {jb.vc.y, v.c1},
      {jb.vc.z, v.c2},  {jb.wc.x, w.c0},  {jb.wc.y, w.c1},  {jb.wc.z, w.c2}};
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
  // The 16 child columns are prefetched kPrefetchJoints joints ahead: the hardware prefetchers
  // do not keep that many streams ahead, and the gather stalled on their loads
  // (docs/performance-seaweed.md, session 24: the particle step 0.82-0.88x in one process).
  constexpr std::size_t kPrefetchJoints = 4 * kJointBlock;
  for (std::size_t m0 = 0; m0 < nj; m0 += kJointBlock) {
    const int lanes = static_cast<int>(std::min<std::size_t>(kJointBlock, nj - m0));
    std::size_t ci[kJointBlock], pj_reals[kJointBlock];
    bool runs = lanes == kJointBlock;
    for (int l = 0; l < kJointBlock; ++l) {
      const auto [c, p] = joints[m0 + (l < lanes ? l : 0)];
      ci[l] = c, pj_reals[l] = p * kHotReals;
      runs = runs && c == ci[0] + l;
    }
    if (m0 + kPrefetchJoints < nj) {
      // The line of the ahead block's last child: its first child's line is that of the slot
      // before, prefetched a block earlier, when the blocks run on consecutive slots (most do).
      // Written in the loop: GCC drops a prefetch in a helper that does nothing else.
      const auto [c, p] = joints[m0 + kPrefetchJoints];
      const std::size_t last = std::min(c + kJointBlock - 1, nt - 1);
      for (const auto& input : child_inputs) __builtin_prefetch(input.second + last, 0, 3);
      __builtin_prefetch(hot + p, 0, 3);
      __builtin_prefetch(reinterpret_cast<const char*>(hot + p) + 64, 0, 3);
    }
    // A child is never in an earlier block, whose columns hold the sub-step's end state (see
    // the file comment).
    if (runs)
      gather(ci[0], pj_reals);
    else
      gather(+ci, pj_reals);
    evaluate_joint_block(jb, p_.joint_k, p_.joint_c, p_.bend_k, p_.bend_c);
    for (int l = 0; l < lanes; ++l) {
      const std::size_t m = m0 + l;
      const auto [i, j] = joints[m];
      if (parent[i] != joint_parent_id[m]) continue;  // broken since the list was built
      const Vec3 F{jb.F.x[l], jb.F.y[l], jb.F.z[l]};
      if (mine(j)) add(j, -F, {jb.tp.x[l], jb.tp.y[l], jb.tp.z[l]});
      if (mine(i)) {
        add(i, F, {jb.tc.x[l], jb.tc.y[l], jb.tc.z[l]});  // the child's owner records the joint
                                                          // state and decides the break (eq. 8)
        const Real fm = jb.fm[l], tm = jb.tm[l];
        jforce[i] = fm;
        jtorque[i] = tm;
        if (fm > p_.force_limit || tm > p_.torque_limit) broken_now_.push_back(i);
      }
    }
  }
  // Contacts: each pair once per block, both results added as they come (rebuild_lists), the
  // partners read from their records (hot_). Touching contacts compacted first without a branch
  // on the test, then their laws: a branch per candidate ("touches?", ~50%) and per orientation
  // mispredicts, and each miss discards the next contacts' work in flight.
  const ContactLaw law{p_.contact_k, p_.contact_c, p_.friction, p_.friction_c};
  const ContactPair* near = blk.contacts;
  touch_.resize(blk.n_contacts);
  std::uint32_t* touch = touch_.data();
  std::size_t n_touch = 0;
  for (std::size_t k = 0; k < blk.n_contacts; ++k) {
    const ContactPair e = near[k];
    const Hot &ha = hot[e.a], &hb = hot[e.b];
    const Vec3 d = ha.x - hb.x;
    touch[n_touch] = static_cast<std::uint32_t>(k);
    n_touch += clearly_apart(core::dot(d, d), ha.r + hb.r) ? 0 : 1;
  }
  // The laws in vector blocks of kContactBlock pairs (the last block padded with its first
  // pair, whose copies are not added); a block's results are added in list order, each pair's
  // to those of its two spheres this block owns (b gets -f: x + (-f) is x - f, bit for bit).
  ContactBlockOut r;
  std::uint32_t a[kContactBlock], b[kContactBlock];
  for (std::size_t c0 = 0; c0 < n_touch; c0 += kContactBlock) {
    const int lanes = static_cast<int>(std::min<std::size_t>(kContactBlock, n_touch - c0));
    for (int l = 0; l < kContactBlock; ++l) {
      const ContactPair e = near[touch[c0 + (l < lanes ? l : 0)]];
      a[l] = e.a, b[l] = e.b;
    }
    evaluate_contact_block(hot, a, b, law, r);
    // A lane that does not touch after all adds +0 (and -0 to b): exact, the sums are never -0.
    for (int l = 0; l < lanes; ++l) {
      const Vec3 f{r.fx[l], r.fy[l], r.fz[l]};
      if (mine(a[l])) add(a[l], f, {r.tax[l], r.tay[l], r.taz[l]});
      if (mine(b[l])) add(b[l], -f, {r.tbx[l], r.tby[l], r.tbz[l]});
    }
  }
}

void SeaweedBodies::sub_step(Real h) {
  begin_sub_step();
  const Real m = p_.mass(), I = p_.inertia();
  const auto col = [&](int a, int c) { return set_.real(a, c); };
  for (std::size_t k = 0, nb = n_blocks_in_use(); k < nb; ++k) {
    const SphereBlock blk = sphere_block(k);
    block_forces(blk, h);
    // Symplectic Euler: velocities first, then positions with the new velocities.
    const auto at = [&](int a, int c) { return col(a, c) + blk.lo; };
    const SphereColumns cols{at(a_force, 0),
                             at(a_force, 1),
                             at(a_force, 2),
                             at(a_torque, 0),
                             at(a_torque, 1),
                             at(a_torque, 2),
                             at(a_vel, 0),
                             at(a_vel, 1),
                             at(a_vel, 2),
                             at(a_omega, 0),
                             at(a_omega, 1),
                             at(a_omega, 2),
                             at(ParticleSet::kPos, 0),
                             at(ParticleSet::kPos, 1),
                             at(ParticleSet::kPos, 2),
                             at(a_quat, 0),
                             at(a_quat, 1),
                             at(a_quat, 2),
                             at(a_quat, 3)};
    integrate_spheres(cols, blk.hi - blk.lo, h, h / m, h / I);
  }
  // Breaks take effect after the sub-step's forces are in, in every block (ghost copies see them
  // at the next refresh).
  for (std::size_t i : broken_now_) {
    set_.u64(u_parent)[i] = kNoId;
    ++broken_local_;
  }
  broken_now_.clear();
}

void SeaweedBodies::advance(Real dt) {
  const int ns = p_.substeps;
  const Real h = dt / ns;
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
    sub_step(h);
  }
  comm_.update_ghosts(set_);  // ghosts carry the step's final state and drag impulse
}

}  // namespace biota::models::plants
