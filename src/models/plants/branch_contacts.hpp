#pragma once
/// \file branch_contacts.hpp
/// \brief Branch collisions (the tree paper's future work, section 7): every link is a capsule
/// (the segment from its parent node to its node, the link's radius); two capsules that overlap
/// push apart with a linear penalty k_c (overlap) along the line of the closest points and rub
/// with a regularised Coulomb friction min(c_t |v_t|, mu |F_n|) against the tangential relative
/// velocity v_t there. Links of one tree that share a node are never in contact (the joint).
/// The force at the contact point is split onto the link's two nodes with the closest point's
/// parameter s along the link: (1 - s) to the parent node, s to the node.
///
/// Pure model code (no MPI). Deterministic: the candidate pairs of a capsule are visited in the
/// order of the capsule list, so a list in (tree, node) order gives the same sums on any rank.
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "core/types.hpp"

namespace biota::models::plants {

using core::Vec3;

/// \brief One link as a capsule: ends a (parent node) and b (node), their velocities, radius.
struct Capsule {
  Vec3 a, b, va, vb;
  double radius = 0;
  std::uint64_t tree = 0;
  std::int64_t node_a = -1, node_b = -1;  ///< tree-local node indices (adjacency test)
};

/// \brief Contact law constants.
struct ContactParams {
  double stiffness = 100;  ///< k_c (N/m of overlap)
  double friction = 0.5;   ///< Coulomb coefficient mu
  double viscous = 10;     ///< c_t (N s/m): friction below mu |F_n| is c_t |v_t|
};

/// \brief Closest points of segments p0-p1 and q0-q1: parameters s, t in [0, 1] (Ericson 5.1.9).
void closest_points(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1, double& s,
                    double& t);

/// \brief True for a pair that must not be in contact (besides links sharing a node).
using ContactFilter = std::function<bool(const Capsule&, const Capsule&)>;

/// \brief Contact forces on the capsules `mine` (indices into `all`) from every capsule of `all`:
/// fa[m], fb[m] are the forces on the two nodes of capsule mine[m]. Pairs for which `skip`
/// returns true are left out. Returns the number of contacts found (pairs counted from the side
/// of `mine`).
long long capsule_forces(const std::vector<Capsule>& all, const std::vector<std::size_t>& mine,
                         const ContactParams& p, std::vector<Vec3>& fa, std::vector<Vec3>& fb,
                         const ContactFilter& skip = {});

/// \brief Pairs (node_b, node_b; smaller first) of capsules of `caps` that share no node and
/// overlap already: in a tree's rest shape these links grew together at a joint (e.g. a link and
/// its sibling's child at a 20 degree fork), so they are not a collision.
std::vector<std::pair<std::int64_t, std::int64_t>> overlapping_pairs(
    const std::vector<Capsule>& caps);

}  // namespace biota::models::plants
