#include "models/plants/node_link_tree.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <stdexcept>
#include <tuple>

#include "core/quat.hpp"

namespace biota::models::plants {

namespace {

// Minimal rotation taking unit vector a to unit vector b (identity, bit for bit, when a == b).
core::Quat minimal_rotation(const Vec3& a, const Vec3& b) {
  const double w = 1 + dot(a, b);
  const Vec3 c = cross(a, b);
  if (w < 1e-12) {  // opposite: half turn about any axis normal to a
    Vec3 ax = std::abs(a.x) < 0.9 ? cross(a, Vec3{1, 0, 0}) : cross(a, Vec3{0, 1, 0});
    ax = ax / norm(ax);
    return {0, ax.x, ax.y, ax.z};
  }
  return core::Quat{w, c.x, c.y, c.z}.normalized();
}

}  // namespace

NodeLinkTree::NodeLinkTree(const TurtleGeometry& g, double scale, const Vec3& base,
                           const NodeLinkParams& p)
    : p_(p) {
  // Node k + (roots) is the end of segment k; parentless segments start at a shared root.
  std::map<std::tuple<double, double, double>, std::int64_t> roots;
  std::vector<std::int64_t> node_of_segment(g.segments.size());
  std::vector<double> width;
  for (std::size_t k = 0; k < g.segments.size(); ++k) {
    const auto& s = g.segments[k];
    std::int64_t par;
    if (s.parent < 0) {
      auto key = std::make_tuple(s.start.x, s.start.y, s.start.z);
      auto it = roots.find(key);
      if (it == roots.end()) {
        it = roots.emplace(key, static_cast<std::int64_t>(pos_.size())).first;
        pos_.push_back(base + s.start * scale);
        parent_.push_back(-1);
        width.push_back(s.radius);
      }
      par = it->second;
    } else {
      par = node_of_segment[s.parent];
    }
    node_of_segment[k] = static_cast<std::int64_t>(pos_.size());
    pos_.push_back(base + s.end * scale);
    parent_.push_back(par);
    width.push_back(s.radius);
  }
  const std::size_t n = pos_.size();
  radius_.assign(n, p_.r_max);
  if (p_.pipe_radii) {
    // Pipe model (Shinozaki): r^2 proportional to the number of tips the link carries, mapped
    // affinely in sqrt(tips) so that tips get r_min and the most loaded link r_max.
    std::vector<double> tips(n, 0);
    std::vector<char> has_child(n, 0);
    for (std::size_t i = 0; i < n; ++i)
      if (parent_[i] >= 0) has_child[parent_[i]] = 1;
    for (std::size_t i = n; i-- > 0;) {
      if (!has_child[i]) tips[i] = 1;
      if (parent_[i] >= 0) tips[parent_[i]] += tips[i];
    }
    double most = 1;
    for (std::size_t i = 0; i < n; ++i)
      if (parent_[i] >= 0) most = std::max(most, tips[i]);
    for (std::size_t i = 0; i < n; ++i) {
      const double t = most > 1 ? (std::sqrt(tips[i]) - 1) / (std::sqrt(most) - 1) : 1;
      radius_[i] = p_.r_min + (p_.r_max - p_.r_min) * t;
    }
  } else {
    double wmax = 0;
    for (double w : width) wmax = std::max(wmax, w);
    for (std::size_t i = 0; i < n; ++i) radius_[i] = p_.r_max * width[i] / wmax;
  }
  init();
}

NodeLinkTree::NodeLinkTree(std::vector<Vec3> pos, std::vector<std::int64_t> parent,
                           std::vector<double> radius, const NodeLinkParams& p)
    : p_(p), pos_(std::move(pos)), parent_(std::move(parent)), radius_(std::move(radius)) {
  for (std::size_t i = 0; i < parent_.size(); ++i)
    if (parent_[i] >= static_cast<std::int64_t>(i))
      throw std::invalid_argument("NodeLinkTree: parent index must be below the node's");
  init();
}

void NodeLinkTree::init() {
  const std::size_t n = pos_.size();
  pos0_ = pos_;
  vel_.assign(n, {});
  force_.assign(n, {});
  rest_.assign(n, {});
  dir0_.assign(n, {});
  length_.assign(n, 0);
  mass_.assign(n, 0);
  area_.assign(n, 0);
  k_link_.assign(n, 0);
  for (std::size_t k = 0; k < n; ++k) {
    if (parent_[k] < 0) continue;
    rest_[k] = pos_[k] - pos_[parent_[k]];
    length_[k] = norm(rest_[k]);
    dir0_[k] = rest_[k] / length_[k];
    const double r = radius_[k], l = length_[k];
    mass_[k] = std::numbers::pi * r * r * l * p_.density;      // (1)
    area_[k] = 2 * std::numbers::pi * r * l;                   // (2)
    k_link_[k] = std::numbers::pi * r * r / l * p_.k_restore;  // (5)
  }
}

void NodeLinkTree::step(double dt, const std::vector<Vec3>& wind, std::vector<Vec3>* wind_force,
                        const std::vector<Vec3>* extra) {
  const std::size_t n = pos_.size();
  std::fill(force_.begin(), force_.end(), Vec3{});
  if (wind_force) wind_force->assign(n, {});
  for (std::size_t k = 0; k < n; ++k) {
    const std::int64_t j = parent_[k];
    if (j < 0) continue;
    const Vec3 fw = p_.k_wind * area_[k] * (wind[k] - vel_[k]);  // (3)
    if (wind_force) (*wind_force)[k] = fw;
    const Vec3 link = pos_[k] - pos_[j];
    Vec3 b = rest_[k];
    const std::int64_t i = parent_[j];
    if (i >= 0) {  // rotate the rest vector with the parent link (section 3.4)
      const Vec3 pl = pos_[j] - pos_[i];
      b = minimal_rotation(dir0_[j], pl / norm(pl)).rotate(rest_[k]);
    }
    const Vec3 fr = k_link_[k] * (b - link);  // (5), P' - P = b - (P_k - P_j)
    force_[k] += fw + fr + mass_[k] * p_.gravity;
    if (extra) force_[k] += (*extra)[k];
    if (i >= 0) {  // (6): reaction on the parent j, perpendicular to P_i -> P_k
      const Vec3 ik = pos_[k] - pos_[i];
      const double lik = norm(ik), lij = norm(pos_[j] - pos_[i]);
      const Vec3 e = ik / lik;
      const Vec3 perp = fr - dot(fr, e) * e;
      force_[j] += (-p_.k_react * lik / lij) * perp;
    }
  }
  const double damp = dt == p_.damp_dt ? p_.k_damp : std::pow(p_.k_damp, dt / p_.damp_dt);
  old_ = pos_;
  for (std::size_t k = 0; k < n; ++k) {
    if (parent_[k] < 0) continue;
    vel_[k] = damp * vel_[k] + force_[k] * (dt / mass_[k]);  // (8), (9)
    pos_[k] = pos_[k] + vel_[k] * dt;                        // (10)
  }
  for (std::size_t k = 0; k < n; ++k) {  // (11), root to tips (parents come first)
    const std::int64_t j = parent_[k];
    if (j < 0) continue;
    const Vec3 link = pos_[k] - pos_[j];
    const double len = norm(link);
    if (len != length_[k]) pos_[k] = pos_[j] + link * (length_[k] / len);
    if (pos_[k] != old_[k] || vel_[k] != Vec3{}) vel_[k] = (pos_[k] - old_[k]) / dt;
  }
}

double NodeLinkTree::max_displacement() const {
  double m = 0;
  for (std::size_t k = 0; k < pos_.size(); ++k) m = std::max(m, norm(pos_[k] - pos0_[k]));
  return m;
}

double NodeLinkTree::max_bending_angle() const {
  double m = 0;
  for (std::size_t k = 0; k < pos_.size(); ++k) {
    if (parent_[k] < 0) continue;
    const Vec3 d = pos_[k] - pos_[parent_[k]];
    m = std::max(m, std::acos(std::clamp(dot(d, dir0_[k]) / norm(d), -1.0, 1.0)));
  }
  return m;
}

double NodeLinkTree::height() const {
  double lo = 1e300, hi = -1e300;
  for (std::size_t k = 0; k < pos_.size(); ++k) {
    hi = std::max(hi, pos_[k].y);
    if (parent_[k] < 0) lo = std::min(lo, pos_[k].y);
  }
  return hi - lo;
}

}  // namespace biota::models::plants
