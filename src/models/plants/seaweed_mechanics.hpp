#pragma once
/// \file seaweed_mechanics.hpp
/// \brief Rigid-sphere seaweed bodies (paper section 4): spheres at buds and along stems, joints
/// with a stiff stretch spring at the shared anchor plus a 3-DOF rotational spring-damper, tearing
/// by eq. (8), buoyancy eq. (9), gravity, drag eq. (10) with the relative velocity, and
/// sphere-sphere contacts with Coulomb-capped viscous friction. Explicit symplectic sub-steps.
///
/// Parallel: spheres live in a particles::ParticleSet; a joint is stored on its child sphere (the
/// parent's global id and the rest anchor; these travel with ghosts). Every joint and
/// contact touching an owned sphere is evaluated by each rank owning one of its two spheres, with
/// identical inputs, and each rank adds it only to its own spheres, summing the interactions of a
/// sphere in a fixed order: body forces, its joints, then its contacts, each group by partner
/// global id. Nothing is scattered back, so forces, and
/// hence trajectories, are bitwise the same on any rank count (docs/seaweed.md). A break is
/// decided by the child's owner; the parent's side sees it at the next ghost refresh (the next
/// sub-step), the same sub-step in which the child stops applying it.
///
/// Neighbour lists (Verlet, with `skin`) are rebuilt when any sphere moved more than skin/2 since
/// the last build (checked every sub-step, collectively); a rebuild migrates first. Between full
/// ghost refreshes at the start and end of a step, sub-steps refresh only the changing state.
#include <functional>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/config.hpp"
#include "models/plants/seaweed_contact_law.hpp"
#include "models/plants/seaweed_joint_block.hpp"
#include "models/plants/ulva_growth.hpp"
#include "particles/particle_comm.hpp"
#include "particles/particle_set.hpp"

namespace biota::models::plants {

/// \brief Mechanical parameters (SI). Defaults and their reasoning: docs/seaweed.md.
struct MechanicsParams {
  Real radius = 0.005, spacing = 0.01, plant_density = 1200, water_density = 998, gravity = 9.8;
  Real drag_cd = 1.0;
  Real joint_k = 50, joint_c = 0.01;             ///< stretch spring [N/m], damper [N s/m]
  Real bend_k = 1e-4, bend_c = 2e-7;             ///< rotational spring [N m/rad], damper [N m s]
  Real force_limit = 1000, torque_limit = 1000;  ///< F_c [N], T_c [N m] (eq. 8)
  Real contact_k = 50, contact_c = 0.01, friction = 0.5, friction_c = 0.01;
  Real cluster_margin = 0.001;  ///< gap still counted as a contact for entanglement [m]
  Real skin = 0.01;             ///< neighbour-list skin [m]
  /// Skin of the inner contact list filtered from the neighbour list (rank-local, re-filtered
  /// when a sphere moved more than half of it) [m]. Not a deck key: it changes no result, only
  /// how many far pairs a sub-step visits; <= 0 visits the whole neighbour list every sub-step.
  Real inner_skin = 0.002;
  int substeps = 20;
  /// Owned spheres per block of the sub-step (0: the whole rank is one block; -1: blocks of 2048
  /// where a rank owns more than 32768 spheres and the interactions shared between blocks add at
  /// most a tenth). Changes no result, only how a rank's state passes through the caches
  /// (seaweed_sub_step.cpp).
  std::int64_t sub_step_block = -1;
  static void declare_config(core::ConfigSchema& schema);
  static MechanicsParams from_config(const core::Config& cfg);
  Real mass() const;
  Real inertia() const;
  /// \brief Largest angular frequency of the explicit scheme's stiff modes [rad/s].
  Real omega_max() const;
  /// \brief Reach of an interaction (contact range or joint, plus the skin): the particle ghost
  /// layer's width [m].
  Real ghost_cutoff() const;
};

/// \brief Entanglement metrics of one instant (identical on every rank).
struct ClusterMetrics {
  int plants = 0, clusters = 0, largest = 0;
  double largest_share = 0;
  long long contacts = 0;       ///< inter-plant sphere contacts
  long long broken_joints = 0;  ///< cumulative
  long long joints = 0;         ///< intact joints
  /// Joints of owned spheres whose partner was beyond the ghost cutoff at the last list build
  /// (not evaluated until the next build; should be 0, see ghost_cutoff()).
  long long skipped_joints = 0;
};

/// \brief Visit the spheres a population is built of, in global-id order: a sphere on every
/// root bud and `spacing`-spaced spheres along every branch. fn(id, x, plant, parent id or
/// kNoId, parent position).
void for_each_sphere(
    const Population& pop, Real spacing,
    const std::function<void(std::uint64_t, const Vec3&, int, std::uint64_t, const Vec3&)>& fn);

/// \brief The seaweed population as rigid spheres.
class SeaweedBodies {
 public:
  /// \brief Fluid velocity [m/s] at a physical position (prescribed flows, tests).
  using VelocityFn = std::function<Vec3(const Vec3&)>;

  SeaweedBodies(particles::ParticleComm& comm, MechanicsParams params);
  /// \brief Build spheres and joints of `pop` (replicated on all ranks; each keeps what it owns).
  void build(const Population& pop, int n_plants);
  particles::ParticleSet& set() { return set_; }
  const particles::ParticleSet& set() const { return set_; }
  /// \brief Start of a physics step: migrate + ghosts + neighbour lists when the skin is used up
  /// (or a sub-step rebuilt without migrating), else a ghost refresh. Collective.
  void begin_step();
  /// \brief Number of neighbour-list rebuilds so far (tests, timing).
  long long rebuilds() const { return rebuilds_; }
  /// \brief Number of inner contact-list filters so far (timing).
  long long filters() const { return filters_; }
  /// \brief Ghost cutoff used for the particle halo [m]: covers contacts and joints stretched
  /// up to twice seaweed.spacing, plus the skin.
  Real ghost_cutoff() const;
  /// \brief Longest joint (child-parent distance) at build() [m]. Collective.
  Real longest_bond() const;
  /// \brief Cumulative broken joints counted on this rank (restored from checkpoints).
  long long& broken_local() { return broken_local_; }
  /// \brief Set the fluid velocity of every owned sphere from `u` (call after begin_step).
  void sample_fluid(const VelocityFn& u);
  /// \brief Advance `dt` with params.substeps sub-steps. The fluid velocity is held fixed over the
  /// step; the drag impulse per sphere is accumulated in attribute "drag_impulse". Collective.
  void advance(Real dt);
  /// \brief Clusters of plants connected by contacts (union-find over gathered pairs). Collective.
  ClusterMetrics clusters();
  long long global_count() const;
  const MechanicsParams& params() const { return p_; }

  // Attribute handles.
  int a_vel, a_quat, a_omega, a_force, a_torque, a_uf, a_imp, a_anchor_c, a_jforce, a_jtorque,
      a_radius, a_xs;
  int u_plant, u_parent;

 private:
  /// What the contacts and the joints' parents read of a sphere, in one record (begin_sub_step).
  using Hot = SphereHot;
  std::vector<Hot> hot_;
  std::unique_ptr<JointBlock> joint_block_ = std::make_unique<JointBlock>();  // 2.7 kB scratch
  void rebuild_lists();
  void store_by_plant();  // owned spheres by (plant, id), for blocks; after a migration
  bool max_displacement_exceeded() const;    // collective
  bool local_displacement_exceeded() const;  // this rank's owned spheres only
  // The slot of `id` nearest to `near` (SIZE_MAX if none); `guess`: a place in slots_ tried as
  // the first entry of `id` before a binary search (any value, also out of range).
  std::size_t find_near(GlobalId id, const Vec3& near, std::size_t guess) const;

  particles::ParticleComm& comm_;
  MechanicsParams p_;
  particles::ParticleSet set_;
  // (child, parent) local slots by the child's global id, plant by plant where the spheres are
  // stored so (each sphere's summation order either way, rebuild_lists).
  std::vector<std::pair<std::size_t, std::size_t>> joints_;
  std::vector<GlobalId> joint_parent_id_;  // per joint: the parent's id at the list build
  std::vector<std::size_t> broken_now_;
  std::vector<Vec3> x_build_;  // owned positions at the last list build
  bool built_ = false, need_migrate_ = false;
  long long rebuilds_ = 0;
  std::vector<std::pair<GlobalId, std::size_t>> slots_;  // (global id, local slot), sorted
  // Contacts: each listed pair (slots a, b; id a < id b) once, in the order of (id a, id b),
  // which is every sphere's contact order by partner id (rebuild_lists), so both results of one
  // evaluation are added to their owned spheres as they come.
  struct ContactPair {
    std::uint32_t a, b;
  };
  std::vector<ContactPair> contact_pairs_;
  // The list build's scratch, kept between builds: the pairs as found (lower id first) and sorted
  // halfway; each slot's place in slots_ (the counting sorts' key, the parent lookup's first
  // guess) and the counting sorts' bucket starts.
  std::vector<ContactPair> pairs_, pair_scratch_;
  std::vector<std::uint32_t> place_, place_start_;
  // Inner list: the pairs of contact_pairs_ that can still touch (closer than the radii plus
  // inner_skin at the last filter), in the same order.
  std::vector<ContactPair> near_;
  std::vector<ContactPair> filter_out_;  // the filter's scratch: every pair written, kept counted
  std::vector<std::uint32_t> touch_;     // scratch: positions in near_ of the touching contacts
  std::vector<Vec3> x_filter_;           // owned and ghost positions at the last filter
  bool need_filter_ = true;
  long long filters_ = 0;
  bool filter_due() const;

  // The sub-step, block by block of owned spheres (seaweed_sub_step.cpp).
  /// Owned slots [lo, hi) and the joints and contacts touching them: subsequences of joints_
  /// (with joint_parent_id_) and near_, in their order.
  struct SphereBlock {
    std::size_t lo, hi;
    const std::pair<std::size_t, std::size_t>* joints;
    const GlobalId* joint_parent_id;
    std::size_t n_joints;
    const ContactPair* contacts;
    std::size_t n_contacts;
  };
  std::size_t block_spheres() const;    // 0: no blocks
  std::size_t n_blocks() const;         // planned: lists split, spheres stored by plant
  std::size_t n_blocks_in_use() const;  // the sub-step's: 1 where blocks do not pay
  bool blocks_pay_ = true;              // set at each split of the contacts
  SphereBlock sphere_block(std::size_t k) const;
  void split_joints_by_block();    // after each list build
  void split_contacts_by_block();  // after each filter
  void sub_step(Real h);
  void begin_sub_step();  // hot records, the inner list's filter when due
  void block_forces(const SphereBlock& blk, Real dt_sub);
  // The blocks' subsequences when there is more than one block (CSR by block).
  std::vector<std::size_t> block_joint_begin_, block_contact_begin_;
  std::vector<std::pair<std::size_t, std::size_t>> block_joints_;
  std::vector<GlobalId> block_joint_parent_id_;
  std::vector<ContactPair> block_contacts_;
  int n_plants_ = 0;
  long long broken_local_ = 0;
  long long skipped_joints_ = 0;  // at the last list build, owned children only
  Real longest_bond_local_ = 0;
};

/// \brief Build the layout of a seaweed sphere set (shared with output/checkpoint code).
particles::ParticleLayout seaweed_layout();

/// \brief Checkpoint rows (migrating columns, `width` values each, this rank's share) in the
/// layout of seaweed_layout(). Rows of the layout before the parent anchor and the rest
/// orientation left it (issue 11, session 31: 7 values more, after anchor_child) are converted in
/// place and `width` set. Every rank throws core::InputError naming `path` for any other width,
/// or (collective over `comm`) if a dropped value is not the one the model implies (0 -
/// anchor_child, the identity).
void to_current_seaweed_rows(std::vector<double>& rows, int& width, const std::string& path,
                             MPI_Comm comm);

}  // namespace biota::models::plants
