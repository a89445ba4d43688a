#include "models/plants/tree_stand.hpp"

#include <stdexcept>

#include "models/plants/turtle.hpp"
#include "models/plants/ulva_growth.hpp"

namespace biota::models::plants {

NodeLinkTree build_tree(const TreeSpecies& sp, const TreeSite& site, const NodeLinkParams& p,
                        std::size_t max_modules) {
  DeriveOptions opt;
  opt.derivations = sp.derivations;
  opt.seed = sp.seed;
  opt.tree_id = site.id;
  opt.max_modules = max_modules;
  TurtleGeometry g = interpret(sp.lsystem, derive(sp.lsystem, opt));
  if (g.segments.empty())
    throw std::invalid_argument("tree " + std::to_string(site.id) + ": the L-system draws nothing");
  const double h = g.hi.y - g.lo.y;
  if (!(h > 0))
    throw std::invalid_argument("tree " + std::to_string(site.id) +
                                ": the L-system geometry has no height along the heading");
  // Turtle frame (heading +y, up +z) -> world (up +z): (x, y, z) -> (x, -z, y).
  for (auto& s : g.segments) {
    s.start = {s.start.x, -s.start.z, s.start.y};
    s.end = {s.end.x, -s.end.z, s.end.y};
  }
  return NodeLinkTree(g, site.height / h, site.base, p);
}

std::vector<TreeSite> random_sites(std::uint64_t seed, int n, double lo_x, double lo_y, double hi_x,
                                   double hi_y, double ground, double min_spacing,
                                   const std::vector<TreeSpecies>& species) {
  const auto pts = place_seeds(seed, n, {lo_x, lo_y, ground}, {hi_x, hi_y, ground}, min_spacing);
  std::vector<TreeSite> sites(pts.size());
  for (std::size_t t = 0; t < pts.size(); ++t) {
    sites[t].id = t;
    sites[t].species = static_cast<int>(t % species.size());
    sites[t].base = {pts[t].x, pts[t].y, ground};
    sites[t].height = species[sites[t].species].height;
  }
  return sites;
}

}  // namespace biota::models::plants
