#include "models/plants/ulva_growth.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <unordered_map>

#include "core/rng.hpp"

namespace biota::models::plants {

void GrowthParams::declare_config(core::ConfigSchema& s) {
  s.add_int("growth.seed", 1, 0, 1'000'000'000'000'000'000, "seed of every growth random stream");
  s.add_int("growth.cycles", 5, 0, 20, "growth cycles p_max (paper Table 1 'step size sigma' = 5)");
  s.add_real("growth.p_grow", 0.8, 0.0, 1.0, "-", "P_I: probability a growth unit makes a metamer");
  s.add_int("growth.initial_branches", 10, 0, 63, "growth units created from each seed");
  s.add_int("growth.branches_min", 0, 0, 14, "min lateral growth units per new bud");
  s.add_int("growth.branches_max", 2, 0, 14, "max lateral growth units per new bud");
  s.add_real("growth.length_min", 0.02, 0.0, std::nullopt, "m", "min stem length l", true);
  s.add_real("growth.length_max", 0.04, 0.0, std::nullopt, "m", "max stem length l", true);
  s.add_real("growth.roll_max", 45.0, 0.0, 180.0, "deg", "roll phi drawn in [-max, max]");
  s.add_real("growth.pitch_max", 45.0, 0.0, 180.0, "deg", "pitch theta drawn in [-max, max]");
  s.add_real("growth.yaw_max", 45.0, 0.0, 180.0, "deg", "yaw psi drawn in [-max, max]");
  s.add_real("growth.env_min", 1.0, 0.0, std::nullopt, "-", "environment factor, inner region");
  s.add_real("growth.env_max", 1.5, 0.0, std::nullopt, "-", "environment factor, outer region");
  s.add_int("growth.env_regions", 5, 1, 100, "number of concentric environment regions");
  s.add_real("growth.personal_radius", 0.015, 0.0, std::nullopt, "m",
             "radius of the personal-space (interference) sphere of a bud");
  s.add_bool("growth.interference", true, "avoid other buds' personal space");
  s.add_int("growth.max_retries", 20, 0, 10000,
            "angle redraws before a metamer is given up (the growth unit rests this cycle)");
  s.add_string("growth.model", "ulva", {"ulva", "general"},
               "ulva: the seaweed model (eq. 5-7, paper Table 1); general: growth.general.* "
               "(eq. 1-4 with P_C, P_A, P_I, P_B)");
  ArchitectureParams::declare_config(s);
}

GrowthParams GrowthParams::from_config(const core::Config& c) {
  GrowthParams g;
  g.seed = static_cast<std::uint64_t>(c.get_int("growth.seed"));
  g.cycles = static_cast<int>(c.get_int("growth.cycles"));
  g.p_grow = c.get_real("growth.p_grow");
  g.initial_branches = static_cast<int>(c.get_int("growth.initial_branches"));
  g.branches_min = static_cast<int>(c.get_int("growth.branches_min"));
  g.branches_max = static_cast<int>(c.get_int("growth.branches_max"));
  if (g.branches_max < g.branches_min) c.fail("growth.branches_max", "must be >= branches_min");
  g.length_min = c.get_real("growth.length_min");
  g.length_max = c.get_real("growth.length_max");
  if (g.length_max < g.length_min) c.fail("growth.length_max", "must be >= length_min");
  g.roll_max = c.get_real("growth.roll_max");
  g.pitch_max = c.get_real("growth.pitch_max");
  g.yaw_max = c.get_real("growth.yaw_max");
  g.env_min = c.get_real("growth.env_min");
  g.env_max = c.get_real("growth.env_max");
  g.env_regions = static_cast<int>(c.get_int("growth.env_regions"));
  g.personal_radius = c.get_real("growth.personal_radius");
  g.interference = c.get_bool("growth.interference");
  g.max_retries = static_cast<int>(c.get_int("growth.max_retries"));
  g.general = c.get_string("growth.model") == "general";
  if (g.general) g.arch = ArchitectureParams::from_config(c);
  return g;
}

Real environment_factor(const GrowthParams& gp, const Vec3& p) {
  // Concentric rings in the horizontal plane around the cultivation centre; region k of R gets
  // e = e_min + (e_max - e_min) k / (R - 1); beyond env_radius the outermost value applies.
  if (gp.env_regions <= 1) return gp.env_min;
  const Real r = std::hypot(p.x - gp.env_centre.x, p.y - gp.env_centre.y);
  // The ring in floating point first: far outside a tiny env_radius the quotient exceeds any
  // int (the cast alone was undefined there and gave negative rings).
  const Real ring = std::floor(r / (gp.env_radius / gp.env_regions));
  const int k = ring < gp.env_regions - 1 ? static_cast<int>(ring) : gp.env_regions - 1;
  return gp.env_min + (gp.env_max - gp.env_min) * k / (gp.env_regions - 1);
}

namespace {

struct Tip {
  GlobalId id;   // growth-unit id: bud id * 64 + index at that bud
  GlobalId bud;  // bud the growth unit sits on
  core::Quat frame;
};

// Spatial hash of bud positions with cells of the personal radius.
class BudHash {
 public:
  explicit BudHash(Real h) : h_(h > 0 ? h : 1.0) {}
  void insert(const Vec3& p, std::size_t i) {
    map_[key(cell(p, 0), cell(p, 1), cell(p, 2))].push_back(i);
  }
  template <class F>
  bool any_within(const Vec3& p, Real r, const std::vector<Bud>& buds, F&& skip) const {
    const long long cx = cell(p, 0), cy = cell(p, 1), cz = cell(p, 2);
    for (long long dz = -1; dz <= 1; ++dz)
      for (long long dy = -1; dy <= 1; ++dy)
        for (long long dx = -1; dx <= 1; ++dx) {
          auto it = map_.find(key(cx + dx, cy + dy, cz + dz));
          if (it == map_.end()) continue;
          for (std::size_t i : it->second) {
            if (skip(i)) continue;
            const Vec3 d = buds[i].pos - p;
            if (core::dot(d, d) < r * r) return true;
          }
        }
    return false;
  }

 private:
  long long cell(const Vec3& p, int d) const {
    return static_cast<long long>(std::floor(p[d] / h_));
  }
  static std::uint64_t key(long long x, long long y, long long z) {
    return (static_cast<std::uint64_t>(x & 0x1FFFFF) << 42) |
           (static_cast<std::uint64_t>(y & 0x1FFFFF) << 21) |
           static_cast<std::uint64_t>(z & 0x1FFFFF);
  }
  Real h_;
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> map_;
};

core::Quat random_rotation(core::Rng& r) {
  // Shoemake's uniform random rotation.
  const Real u1 = r.uniform(), u2 = r.uniform(), u3 = r.uniform();
  const Real a = std::sqrt(1 - u1), b = std::sqrt(u1), tp = 2 * std::numbers::pi;
  return core::Quat{b * std::cos(tp * u3), a * std::sin(tp * u2), a * std::cos(tp * u2),
                    b * std::sin(tp * u3)}
      .normalized();
}

// Elongation G(l, phi, theta, psi) from `from` in `parent_frame`: up to max_retries + 1 angle
// draws keeping l; false when every position lies in another bud's personal space.
bool place(core::Rng& rng, const GrowthParams& gp, const BudHash& hash,
           const std::vector<Bud>& buds, const Vec3& from, const core::Quat& parent_frame, Real l,
           Vec3& pos, core::Quat& frame, CycleStats& st) {
  constexpr Real deg = std::numbers::pi / 180;
  for (int attempt = 0; attempt <= gp.max_retries; ++attempt) {
    const Real roll = rng.uniform(-gp.roll_max, gp.roll_max) * deg;
    const Real pitch = rng.uniform(-gp.pitch_max, gp.pitch_max) * deg;
    const Real yaw = rng.uniform(-gp.yaw_max, gp.yaw_max) * deg;
    // Intrinsic roll (about the growth direction x), then pitch (y), then yaw (z).
    frame = (parent_frame * core::Quat::axis_angle({1, 0, 0}, roll) *
             core::Quat::axis_angle({0, 1, 0}, pitch) * core::Quat::axis_angle({0, 0, 1}, yaw))
                .normalized();
    pos = from + frame.rotate({1, 0, 0}) * l;
    const bool blocked = gp.interference && hash.any_within(pos, gp.personal_radius, buds,
                                                            [](std::size_t) { return false; });
    if (!blocked) return true;
    if (attempt < gp.max_retries) ++st.retries;
  }
  return false;
}

Population grow_general(const GrowthParams& gp, const std::vector<Vec3>& seeds);

// The seeds are the first buds (id = plant = seed index) and occupy personal space too.
void plant_seeds(const std::vector<Vec3>& seeds, Population& pop, BudHash& hash) {
  for (std::size_t j = 0; j < seeds.size(); ++j) {
    Bud b;
    b.id = j;
    b.plant = static_cast<int>(j);
    b.pos = seeds[j];
    pop.buds.push_back(b);
    hash.insert(b.pos, j);
  }
}

}  // namespace

Population grow_population(const GrowthParams& gp, const std::vector<Vec3>& seeds) {
  if (gp.general) return grow_general(gp, seeds);
  Population pop;
  BudHash hash(gp.personal_radius);
  std::vector<Tip> tips;
  plant_seeds(seeds, pop, hash);
  // Step 1: growth units from each seed, each created with probability P_I, random directions.
  for (std::size_t j = 0; j < seeds.size(); ++j) {
    core::Rng rng(gp.seed, j, 0, core::RngPurpose::kPlacement);
    for (int k = 0; k < gp.initial_branches; ++k) {
      const bool keep = rng.bernoulli(gp.p_grow);
      const core::Quat q = random_rotation(rng);
      if (keep) tips.push_back({static_cast<GlobalId>(j) * 64 + k, j, q});
    }
  }
  for (int cycle = 1; cycle <= gp.cycles; ++cycle) {
    CycleStats st;
    st.tips_before = static_cast<long long>(tips.size());
    std::vector<Tip> next;
    // Tips are kept sorted by id, so this loop is the fixed global priority order.
    for (const Tip& t : tips) {
      core::Rng rng(gp.seed, t.id, static_cast<std::uint64_t>(cycle), core::RngPurpose::kGrowth);
      ++st.trials;
      if (!rng.bernoulli(gp.p_grow)) {
        next.push_back(t);  // rests this cycle (probability 1 - P_I)
        continue;
      }
      ++st.successes;
      const Bud& parent = pop.buds[t.bud];
      const Real l = rng.uniform(gp.length_min, gp.length_max) * environment_factor(gp, parent.pos);
      core::Quat frame;
      Vec3 pos;
      if (!place(rng, gp, hash, pop.buds, parent.pos, t.frame, l, pos, frame, st)) {
        // Fallback (the paper has no retry limit): the metamer is not created and the growth
        // unit rests, so it may try again next cycle.
        ++st.blocked;
        next.push_back(t);
        continue;
      }
      Bud b;
      b.id = pop.buds.size();
      b.parent = parent.id;
      b.plant = parent.plant;
      b.cycle = cycle;
      b.pos = pos;
      pop.buds.push_back(b);
      hash.insert(pos, b.id);
      ++st.grown;
      // The new bud carries the continuing apex plus n lateral growth units at the same position
      // (eq. 7, M_I = n + 1), n uniform in [branches_min, branches_max].
      const int n = static_cast<int>(rng.uniform_int(gp.branches_min, gp.branches_max));
      st.laterals += n;
      for (int k = 0; k <= n; ++k) next.push_back({b.id * 64 + k, b.id, frame});
    }
    std::sort(next.begin(), next.end(), [](const Tip& a, const Tip& b) { return a.id < b.id; });
    tips.swap(next);
    pop.stats.push_back(st);
  }
  return pop;
}

namespace {

// The general model (architecture.hpp) with the Ulva geometry: the metamers of a growth unit are
// chained along the axis (each one elongation G from the previous node, environment factor and
// interference as for Ulva; a blocked metamer is not created), lateral buds sit on their metamer's
// node and start a new axis turned by a random (roll, pitch, yaw) from the metamer's frame.
// Apex ids: seed j's k-th apex j*64 + k; an apex continuing from bud b: b*64; the n-th lateral of
// bud b: b*64 + 1 + n. Apices are processed in id order (fixed priority, as for Ulva).
Population grow_general(const GrowthParams& gp, const std::vector<Vec3>& seeds) {
  constexpr Real deg = std::numbers::pi / 180;
  const ArchitectureParams& A = gp.arch;
  A.validate();
  const int n = A.types;
  struct Apex {
    GlobalId id, bud;
    core::Quat frame;
    int type, age;  // 0-based type; growth cycles done in this type
  };
  Population pop;
  BudHash hash(gp.personal_radius);
  std::vector<Apex> apices;
  plant_seeds(seeds, pop, hash);
  for (std::size_t j = 0; j < seeds.size(); ++j) {
    core::Rng rng(gp.seed, j, 0, core::RngPurpose::kPlacement);
    for (int k = 0; k < gp.initial_branches; ++k)
      apices.push_back(
          {static_cast<GlobalId>(j) * 64 + k, j, random_rotation(rng), A.initial_type - 1, 0});
  }
  for (int cycle = 1; cycle <= gp.cycles; ++cycle) {
    CycleStats st;
    st.units_by_type.assign(n, 0), st.metamers_by_type.assign(n, 0);
    st.laterals_by_type.assign(n, 0);
    st.tips_before = static_cast<long long>(apices.size());
    std::vector<Apex> next;
    for (const Apex& t : apices) {
      core::Rng rng(gp.seed, t.id, static_cast<std::uint64_t>(cycle), core::RngPurpose::kGrowth);
      ++st.trials;
      const int p = t.type;
      if (!rng.bernoulli(A.p_c[p])) {  // the apex dies (1 - P_C)
        ++st.died;
        continue;
      }
      if (rng.bernoulli(A.p_a[p])) {  // it rests this cycle (P_A)
        ++st.rested;
        next.push_back(t);
        continue;
      }
      ++st.successes;
      ++st.units_by_type[p];
      GlobalId at = t.bud;
      core::Quat frame = t.frame;
      struct Made {
        GlobalId bud;
        int type;
        core::Quat frame;
      };
      std::vector<Made> made;
      for (int k = 0; k < n; ++k)
        for (int m = 0; m < A.mi(p, k); ++m) {
          if (!rng.bernoulli(A.p_i[k])) continue;  // the metamer does not appear (1 - P_I)
          const Bud& from = pop.buds[at];
          const Real l =
              rng.uniform(gp.length_min, gp.length_max) * environment_factor(gp, from.pos);
          core::Quat f;
          Vec3 pos;
          if (!place(rng, gp, hash, pop.buds, from.pos, frame, l, pos, f, st)) {
            ++st.blocked;
            continue;
          }
          Bud b;
          b.id = pop.buds.size();
          b.parent = at;
          b.plant = from.plant;
          b.cycle = cycle;
          b.type = k + 1;
          b.pos = pos;
          pop.buds.push_back(b);
          hash.insert(pos, b.id);
          ++st.grown;
          ++st.metamers_by_type[k];
          made.push_back({b.id, k, f});
          at = b.id;
          frame = f;
        }
      for (const Made& m : made) {
        int count = 0;
        for (int j = 0; j < n; ++j)
          for (int q = 0; q < A.nb(m.type, j); ++q) {
            if (!rng.bernoulli(A.p_b[j])) continue;  // the lateral bud does not branch
            const Real roll = rng.uniform(-gp.roll_max, gp.roll_max) * deg;
            const Real pitch = rng.uniform(-gp.pitch_max, gp.pitch_max) * deg;
            const Real yaw = rng.uniform(-gp.yaw_max, gp.yaw_max) * deg;
            const core::Quat lf =
                (m.frame * core::Quat::axis_angle({1, 0, 0}, roll) *
                 core::Quat::axis_angle({0, 1, 0}, pitch) * core::Quat::axis_angle({0, 0, 1}, yaw))
                    .normalized();
            next.push_back({m.bud * 64 + 1 + count++, m.bud, lf, j, 0});
            ++st.laterals_by_type[j];
            ++st.laterals;
          }
      }
      // Change of physiological age (M_A, T_A) after this growth cycle.
      Apex c{at == t.bud ? t.id : at * 64, at, frame, p, t.age + 1};
      if (A.m_a[p] > 0 && c.age >= A.m_a[p]) {
        if (A.t_a[p] == 0) continue;  // the apex stops
        c.type = A.t_a[p] - 1;
        c.age = 0;
      }
      next.push_back(c);
    }
    std::sort(next.begin(), next.end(), [](const Apex& a, const Apex& b) { return a.id < b.id; });
    apices.swap(next);
    pop.stats.push_back(st);
  }
  return pop;
}

}  // namespace

}  // namespace biota::models::plants

namespace biota::models::plants {
std::vector<Vec3> place_seeds(std::uint64_t seed, int n, const Vec3& lo, const Vec3& hi,
                              Real min_spacing) {
  std::vector<Vec3> s;
  for (int j = 0; j < n; ++j) {
    Vec3 p;
    for (int attempt = 0;; ++attempt) {
      core::Rng r(seed, static_cast<std::uint64_t>(j), static_cast<std::uint64_t>(attempt),
                  core::RngPurpose::kPlacement);
      for (int d = 0; d < 3; ++d) p[d] = r.uniform(lo[d], hi[d]);
      bool ok = true;
      for (const Vec3& q : s) ok = ok && core::norm(q - p) >= min_spacing;
      if (ok || attempt >= 1000) break;  // after 1000 attempts accept (documented fallback)
    }
    s.push_back(p);
  }
  return s;
}
}  // namespace biota::models::plants
