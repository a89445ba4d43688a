#include "models/plants/lsystem.hpp"

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/rng.hpp"

namespace biota::models::plants {

std::string ModuleString::to_string() const {
  std::string s;
  for (std::size_t i = 0; i < size(); ++i) {
    s += sym[i];
    if (nparam[i] == 0) continue;
    s += '(';
    for (int a = 0; a < nparam[i]; ++a) {
      if (a) s += ',';
      s += fmt::format("{}", param(i)[a]);
    }
    s += ')';
  }
  return s;
}

std::vector<std::int64_t> match_brackets(const ModuleString& s) {
  std::vector<std::int64_t> m(s.size(), -1), open;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s.sym[i] == '[') open.push_back(static_cast<std::int64_t>(i));
    if (s.sym[i] == ']' && !open.empty()) {
      m[i] = open.back();
      m[open.back()] = static_cast<std::int64_t>(i);
      open.pop_back();
    }
  }
  return m;
}

namespace {

bool bind(const ModulePattern& pat, const ModuleString& s, std::size_t j, double*& out) {
  if (s.sym[j] != pat.sym || s.nparam[j] != pat.formals.size()) return false;
  for (std::size_t a = 0; a < pat.formals.size(); ++a) *out++ = s.param(j)[a];
  return true;
}

}  // namespace

bool context_matches(const LSystem& ls, const Production& p, const ModuleString& s,
                     const std::vector<std::int64_t>& br, std::size_t i, double* bound) {
  if (s.sym[i] != p.pred.sym || s.nparam[i] != p.pred.formals.size()) return false;
  const auto ignored = [&](char c) { return ls.ignored[static_cast<unsigned char>(c)]; };
  std::size_t n_left = 0;
  for (const auto& m : p.left) n_left += m.formals.size();
  // Left context (ABOP 1.8): walk towards the root, skipping whole branches on the left (']' ...
  // '[') and climbing out of the branch that contains the module ('[').
  double* lp = bound + n_left;
  std::int64_t j = static_cast<std::int64_t>(i);
  for (std::size_t k = p.left.size(); k-- > 0;) {
    const auto& pat = p.left[k];
    for (--j; j >= 0; --j) {
      const char c = s.sym[j];
      if (c == ']')
        j = br[j];
      else if (c != '[' && !ignored(c))
        break;
    }
    if (j < 0) return false;
    lp -= pat.formals.size();
    double* w = lp;
    if (!bind(pat, s, static_cast<std::size_t>(j), w)) return false;
  }
  double* out = bound + n_left;
  bind(p.pred, s, i, out);
  // Right context: walk towards the tips, skipping branches that the pattern does not enter; the
  // end of the current branch (']') ends the search.
  std::size_t q = i + 1;
  const std::size_t n = s.size();
  for (const auto& pat : p.right) {
    if (pat.sym == '[') {
      while (q < n && ignored(s.sym[q])) ++q;
      if (q >= n || s.sym[q] != '[') return false;
      ++q;
      continue;
    }
    if (pat.sym == ']') {  // rest of the branch the pattern entered is not constrained
      while (q < n && s.sym[q] != ']')
        q = s.sym[q] == '[' ? static_cast<std::size_t>(br[q]) + 1 : q + 1;
      if (q >= n) return false;
      ++q;
      continue;
    }
    for (; q < n; ++q) {
      const char c = s.sym[q];
      if (c == '[')
        q = static_cast<std::size_t>(br[q]);
      else if (c == ']')
        return false;
      else if (!ignored(c))
        break;
    }
    if (q >= n || !bind(pat, s, q, out)) return false;
    ++q;
  }
  return true;
}

ModuleString derive(const LSystem& ls, const DeriveOptions& opt) {
  const int steps = opt.derivations >= 0 ? opt.derivations : ls.derivations;
  ModuleString cur = ls.axiom, next;
  std::vector<double> bound(64), args(64);
  for (int d = 0; d < steps; ++d) {
    const auto br = match_brackets(cur);
    next.clear();
    for (std::size_t i = 0; i < cur.size(); ++i) {
      const auto& groups = ls.groups_of_symbol[static_cast<unsigned char>(cur.sym[i])];
      bool applied = false;
      for (int g : groups) {
        const auto& group = ls.groups[g];
        const Production& lhs = ls.productions[group.front()];
        if (static_cast<std::size_t>(lhs.n_formals) > bound.size()) bound.resize(lhs.n_formals);
        if (!context_matches(ls, lhs, cur, br, i, bound.data())) continue;
        if (lhs.has_condition && lhs.condition.eval(bound.data()) == 0) continue;
        int chosen = group.front();
        if (group.size() > 1) {
          core::Rng rng(opt.seed, opt.tree_id, (static_cast<std::uint64_t>(d) << 40) | i,
                        core::RngPurpose::kLSystem);
          const double u = rng.uniform();
          double acc = 0;
          chosen = group.back();  // rounding of the cumulative sum
          for (int k : group) {
            acc += ls.productions[k].probability;
            if (u < acc) {
              chosen = k;
              break;
            }
          }
        }
        for (const auto& m : ls.productions[chosen].successor) {
          if (m.args.size() > args.size()) args.resize(m.args.size());
          for (std::size_t a = 0; a < m.args.size(); ++a) args[a] = m.args[a].eval(bound.data());
          next.push(m.sym, args.data(), static_cast<int>(m.args.size()));
        }
        applied = true;
        break;
      }
      if (!applied) next.push(cur.sym[i], cur.param(i), cur.nparam[i]);
      if (next.size() > opt.max_modules)
        throw ModuleCapError(fmt::format("{}: derivation {} of {} exceeds the module cap of {}",
                                         ls.file, d + 1, steps, opt.max_modules),
                             d + 1);
    }
    std::swap(cur, next);
  }
  return cur;
}

}  // namespace biota::models::plants
