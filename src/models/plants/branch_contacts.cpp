#include "models/plants/branch_contacts.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace biota::models::plants {

void closest_points(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1, double& s,
                    double& t) {
  const Vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = dot(d1, d1), e = dot(d2, d2), f = dot(d2, r);
  if (a <= 1e-300 && e <= 1e-300) {
    s = t = 0;
    return;
  }
  if (a <= 1e-300) {
    s = 0;
    t = std::clamp(f / e, 0.0, 1.0);
    return;
  }
  const double c = dot(d1, r);
  if (e <= 1e-300) {
    t = 0;
    s = std::clamp(-c / a, 0.0, 1.0);
    return;
  }
  const double b = dot(d1, d2), den = a * e - b * b;
  if (den <= 1e-12 * a * e) {
    // Parallel: the middle of the overlap of q's projection onto p (an end if none), so that
    // both sides of a pair pick the same contact point and side-by-side links push at their
    // middles, not at an end.
    const double s0 = -c / a, s1 = (b - c) / a;
    const double lo = std::max(0.0, std::min(s0, s1)), hi = std::min(1.0, std::max(s0, s1));
    s = lo <= hi ? 0.5 * (lo + hi) : (std::max(s0, s1) < 0 ? 0.0 : 1.0);
    t = std::clamp((b * s + f) / e, 0.0, 1.0);
    return;
  }
  s = std::clamp((b * f - c * e) / den, 0.0, 1.0);
  t = (b * s + f) / e;
  if (t < 0) {
    t = 0;
    s = std::clamp(-c / a, 0.0, 1.0);
  } else if (t > 1) {
    t = 1;
    s = std::clamp((b - c) / a, 0.0, 1.0);
  }
}

namespace {

// Calls f(m, n, s, t, d, overlap) for every overlapping pair (mine[m], n), n in list order.
template <class F>
void for_each_overlap(const std::vector<Capsule>& all, const std::vector<std::size_t>& mine,
                      const ContactFilter& skip, F&& f) {
  if (all.empty() || mine.empty()) return;
  // Bins of size h (the largest capsule extent) by midpoint: a pair in contact has midpoints
  // less than h apart, so the 27 bins around a capsule's hold every partner.
  double h = 0;
  for (const auto& c : all) h = std::max(h, norm(c.b - c.a) + 2 * c.radius);
  h = std::max(h, 1e-9);
  auto key = [h](const Vec3& x) {
    const auto i = static_cast<std::int64_t>(std::floor(x.x / h)) & 0x1fffff;
    const auto j = static_cast<std::int64_t>(std::floor(x.y / h)) & 0x1fffff;
    const auto k = static_cast<std::int64_t>(std::floor(x.z / h)) & 0x1fffff;
    return static_cast<std::uint64_t>(i) | static_cast<std::uint64_t>(j) << 21 |
           static_cast<std::uint64_t>(k) << 42;
  };
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> bins;
  for (std::size_t n = 0; n < all.size(); ++n) bins[key(0.5 * (all[n].a + all[n].b))].push_back(n);
  std::vector<std::size_t> cand;
  for (std::size_t m = 0; m < mine.size(); ++m) {
    const Capsule& ci = all[mine[m]];
    const Vec3 mid = 0.5 * (ci.a + ci.b);
    cand.clear();
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          auto it = bins.find(key(mid + Vec3{dx * h, dy * h, dz * h}));
          if (it != bins.end()) cand.insert(cand.end(), it->second.begin(), it->second.end());
        }
    std::sort(cand.begin(), cand.end());  // list order, whatever the bins
    cand.erase(std::unique(cand.begin(), cand.end()), cand.end());
    for (std::size_t n : cand) {
      if (n == mine[m]) continue;
      const Capsule& cj = all[n];
      if (ci.tree == cj.tree && (ci.node_a == cj.node_a || ci.node_a == cj.node_b ||
                                 ci.node_b == cj.node_a || ci.node_b == cj.node_b))
        continue;  // links sharing a node: the joint, not a contact
      if (skip && skip(ci, cj)) continue;
      double s, t;
      closest_points(ci.a, ci.b, cj.a, cj.b, s, t);
      const Vec3 pi = ci.a + s * (ci.b - ci.a), pj = cj.a + t * (cj.b - cj.a);
      const Vec3 d = pi - pj;
      const double dist = norm(d), overlap = ci.radius + cj.radius - dist;
      if (overlap <= 0 || dist <= 0) continue;
      f(m, n, s, t, d / dist, overlap);
    }
  }
}

}  // namespace

long long capsule_forces(const std::vector<Capsule>& all, const std::vector<std::size_t>& mine,
                         const ContactParams& p, std::vector<Vec3>& fa, std::vector<Vec3>& fb,
                         const ContactFilter& skip) {
  fa.assign(mine.size(), {});
  fb.assign(mine.size(), {});
  long long contacts = 0;
  for_each_overlap(
      all, mine, skip,
      [&](std::size_t m, std::size_t n, double s, double t, const Vec3& nrm, double overlap) {
        const Capsule &ci = all[mine[m]], &cj = all[n];
        ++contacts;
        const double fn = p.stiffness * overlap;
        const Vec3 vrel = (1 - s) * ci.va + s * ci.vb - ((1 - t) * cj.va + t * cj.vb);
        const Vec3 vt = vrel - dot(vrel, nrm) * nrm;
        const double vtn = norm(vt);
        Vec3 f = fn * nrm;
        if (vtn > 0) f += (-std::min(p.viscous, p.friction * fn / vtn)) * vt;
        fa[m] += (1 - s) * f;
        fb[m] += s * f;
      });
  return contacts;
}

std::vector<std::pair<std::int64_t, std::int64_t>> overlapping_pairs(
    const std::vector<Capsule>& caps) {
  std::vector<std::size_t> all(caps.size());
  for (std::size_t i = 0; i < caps.size(); ++i) all[i] = i;
  std::vector<std::pair<std::int64_t, std::int64_t>> out;
  for_each_overlap(caps, all, {},
                   [&](std::size_t m, std::size_t n, double, double, const Vec3&, double) {
                     if (caps[m].tree == caps[n].tree && caps[m].node_b < caps[n].node_b)
                       out.emplace_back(caps[m].node_b, caps[n].node_b);
                   });
  return out;
}

}  // namespace biota::models::plants
