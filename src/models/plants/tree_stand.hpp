#pragma once
/// \file tree_stand.hpp
/// \brief A stand of node-link trees in the world frame of the wind (x downwind, y across, z up):
/// where each tree stands, which species (L-system file, seed, height) it is, and its node-link
/// model built from the derived L-string. Pure model code (no MPI): every rank can plan the same
/// stand and build any tree of it, bit for bit.
#include <cstdint>
#include <string>
#include <vector>

#include "models/plants/lsystem.hpp"
#include "models/plants/node_link_tree.hpp"

namespace biota::models::plants {

/// \brief One species: an L-system grown with its seed to a given height.
struct TreeSpecies {
  LSystem lsystem;
  std::uint64_t seed = 1;
  int derivations = -1;  ///< < 0: the file's `derivations:`
  double height = 6.67;  ///< m, the turtle geometry's height (max - min along the heading) scaled
};

/// \brief One tree of the stand.
struct TreeSite {
  std::uint64_t id = 0;  ///< global tree id (its index in the stand); keys the L-system draws
  int species = 0;       ///< index into the species list
  Vec3 base;             ///< ground point of the root (m)
  double height = 0;     ///< m
};

/// \brief Global node id of node `k` of tree `tree` (ids are unique over the stand).
inline std::uint64_t tree_node_id(std::uint64_t tree, std::uint64_t k) {
  return tree << 32 | k;
}

/// \brief The node-link tree of `site`: the species' L-system derived with (species seed, tree
/// id), interpreted by the turtle, scaled to the site's height and turned from the turtle frame
/// (heading +y) into the world frame (up +z): world = (x_t, -z_t, y_t), a proper rotation about
/// +x. `p.gravity` is taken in the world frame.
NodeLinkTree build_tree(const TreeSpecies& sp, const TreeSite& site, const NodeLinkParams& p,
                        std::size_t max_modules);

/// \brief Sites at random in the rectangle [lo, hi] (x, y) on the ground z = ground, at least
/// min_spacing apart (place_seeds: Philox keyed by (seed, tree, attempt); after 1000 attempts a
/// tree is accepted as drawn), species t mod n_species, the species' height.
std::vector<TreeSite> random_sites(std::uint64_t seed, int n, double lo_x, double lo_y, double hi_x,
                                   double hi_y, double ground, double min_spacing,
                                   const std::vector<TreeSpecies>& species);

}  // namespace biota::models::plants
