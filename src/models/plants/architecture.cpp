#include "models/plants/architecture.hpp"

#include <fmt/format.h>

#include <map>
#include <stdexcept>

namespace biota::models::plants {

ArchitectureParams ArchitectureParams::kang_example() {
  ArchitectureParams a;
  a.types = 3;
  a.m_i = {0, 2, 1, 0, 0, 2, 0, 0, 1};  // eq. 1
  a.n_b = {0, 1, 1, 0, 0, 1, 0, 0, 0};  // eq. 2
  a.m_a = {5, 3, 1};                    // eq. 3
  a.t_a = {2, 3, 0};                    // eq. 4
  a.p_c = a.p_i = a.p_b = {1, 1, 1};
  a.p_a = {0, 0, 0};
  a.initial_type = 1;
  return a;
}

void ArchitectureParams::validate() const {
  const std::size_t n = static_cast<std::size_t>(types);
  auto need = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument(what);
  };
  need(types >= 1, "types must be >= 1");
  need(m_i.size() == n * n, fmt::format("m_i needs {} entries (types^2)", n * n));
  need(n_b.size() == n * n, fmt::format("n_b needs {} entries (types^2)", n * n));
  for (const auto* v : {&m_i, &n_b})
    for (double x : *v) need(x >= 0 && x <= 62 && x == static_cast<int>(x), "counts are 0..62");
  need(m_a.size() == n && t_a.size() == n, fmt::format("m_a and t_a need {} entries", n));
  for (int t : t_a) need(t >= 0 && t <= types, "t_a entries are 0 (stop) or a type 1..types");
  for (int m : m_a) need(m >= 0, "m_a entries are >= 0 (0: never changes)");
  for (const auto* v : {&p_c, &p_a, &p_i, &p_b}) {
    need(v->size() == n, fmt::format("probability vectors need {} entries", n));
    for (double p : *v) need(p >= 0 && p <= 1, "probabilities are in [0, 1]");
  }
  need(initial_type >= 1 && initial_type <= types, "initial_type is a type 1..types");
  int row_sum = 0;
  for (int p = 0; p < types; ++p) {
    row_sum = 0;
    for (int k = 0; k < types; ++k) row_sum += mi(p, k);
    need(row_sum <= 62, "a growth unit holds at most 62 metamers");
    row_sum = 0;
    for (int k = 0; k < types; ++k) row_sum += nb(p, k);
    need(row_sum <= 62, "a metamer bears at most 62 lateral buds");
  }
}

void ArchitectureParams::declare_config(core::ConfigSchema& s) {
  const auto k = kang_example();
  s.add_int("growth.general.types", 3, 1, 16, "p_m: number of physiological ages");
  s.add_real_list("growth.general.m_i", k.m_i, -1, "-",
                  "M_I, row-major p_m x p_m: metamers of type k per growth unit of type p (eq. 1)");
  s.add_real_list("growth.general.n_b", k.n_b, -1, "-",
                  "N_B, row-major p_m x p_m: lateral buds of type k per metamer of type p (eq. 2)");
  s.add_real_list("growth.general.m_a", std::vector<double>{5, 3, 1}, -1, "cycles",
                  "M_A: growth cycles an apex keeps its type (0: forever) (eq. 3)");
  s.add_real_list("growth.general.t_a", std::vector<double>{2, 3, 0}, -1, "-",
                  "T_A: type an apex becomes after M_A cycles (0: stops) (eq. 4)");
  s.add_real_list("growth.general.p_c", std::vector<double>{1, 1, 1}, -1, "-",
                  "P_C: survival probability of an apex, per type");
  s.add_real_list("growth.general.p_a", std::vector<double>{0, 0, 0}, -1, "-",
                  "P_A: probability a surviving apex rests this cycle, per type");
  s.add_real_list("growth.general.p_i", std::vector<double>{1, 1, 1}, -1, "-",
                  "P_I: probability a potential metamer appears, per metamer type");
  s.add_real_list("growth.general.p_b", std::vector<double>{1, 1, 1}, -1, "-",
                  "P_B: probability a lateral bud branches (becomes an apex), per bud type");
  s.add_int("growth.general.initial_type", 1, 1, 16, "type of the apices created from a seed");
}

ArchitectureParams ArchitectureParams::from_config(const core::Config& c) {
  ArchitectureParams a;
  a.types = static_cast<int>(c.get_int("growth.general.types"));
  a.m_i = c.get_real_list("growth.general.m_i");
  a.n_b = c.get_real_list("growth.general.n_b");
  for (double x : c.get_real_list("growth.general.m_a")) a.m_a.push_back(static_cast<int>(x));
  for (double x : c.get_real_list("growth.general.t_a")) a.t_a.push_back(static_cast<int>(x));
  a.p_c = c.get_real_list("growth.general.p_c");
  a.p_a = c.get_real_list("growth.general.p_a");
  a.p_i = c.get_real_list("growth.general.p_i");
  a.p_b = c.get_real_list("growth.general.p_b");
  a.initial_type = static_cast<int>(c.get_int("growth.general.initial_type"));
  try {
    a.validate();
  } catch (const std::invalid_argument& e) {
    c.fail("growth.general", e.what());
  }
  return a;
}

std::vector<ExpectedCycle> expected_counts(const ArchitectureParams& a, int cycles) {
  const int n = a.types;
  // Expected apices by (type, growth cycles done in that type).
  std::map<std::pair<int, int>, double> state{{{a.initial_type - 1, 0}, 1.0}};
  std::vector<ExpectedCycle> out;
  for (int c = 0; c < cycles; ++c) {
    ExpectedCycle e;
    e.growth_units.assign(n, 0), e.metamers.assign(n, 0), e.laterals.assign(n, 0);
    std::map<std::pair<int, int>, double> next;
    for (const auto& [key, count] : state) {
      const auto [p, age] = key;
      const double alive = count * a.p_c[p];
      const double grow = alive * (1 - a.p_a[p]);
      next[key] += alive * a.p_a[p];  // resting apices keep type and age
      e.growth_units[p] += grow;
      for (int k = 0; k < n; ++k) {
        const double m = grow * a.mi(p, k) * a.p_i[k];
        e.metamers[k] += m;
        for (int j = 0; j < n; ++j) e.laterals[j] += m * a.nb(k, j) * a.p_b[j];
      }
      if (a.m_a[p] > 0 && age + 1 >= a.m_a[p]) {
        if (a.t_a[p] > 0) next[{a.t_a[p] - 1, 0}] += grow;
      } else {
        next[{p, age + 1}] += grow;
      }
    }
    for (int j = 0; j < n; ++j) next[{j, 0}] += e.laterals[j];
    e.apices_after.assign(n, 0);
    for (const auto& [key, count] : next) e.apices_after[key.first] += count;
    state.swap(next);
    out.push_back(e);
  }
  return out;
}

}  // namespace biota::models::plants
