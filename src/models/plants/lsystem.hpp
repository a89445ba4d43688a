#pragma once
/// \file lsystem.hpp
/// \brief L-system grammars (ABOP, "The Algorithmic Beauty of Plants") read from a `.lsys` file and
/// derived in parallel rewriting: deterministic, stochastic (ABOP 1.7), parametric with conditions
/// (ABOP 1.10) and bracket-aware context-sensitive (ABOP 1.8) productions. Pure model code: no MPI,
/// no solver. The file syntax is documented in docs/tree.md ("L-system files").
///
/// Stochastic choices draw from core::Rng keyed by (seed, tree id) with the counter (derivation
/// step << 40 | module position, kLSystem), so a tree's string depends only on its file, seed and
/// id, never on the rank that derives it.
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/error.hpp"
#include "models/plants/lsystem_expr.hpp"

namespace biota::models::plants {

/// \brief A derived string: one symbol per module, its parameters stored flat.
struct ModuleString {
  std::vector<char> sym;
  std::vector<std::uint32_t> first;  ///< index of the module's first parameter in `params`
  std::vector<std::uint8_t> nparam;
  std::vector<double> params;

  std::size_t size() const { return sym.size(); }
  const double* param(std::size_t i) const { return params.data() + first[i]; }
  void clear() { sym.clear(), first.clear(), nparam.clear(), params.clear(); }
  void push(char s, const double* p, int n) {
    sym.push_back(s);
    first.push_back(static_cast<std::uint32_t>(params.size()));
    nparam.push_back(static_cast<std::uint8_t>(n));
    params.insert(params.end(), p, p + n);
  }
  /// \brief The string in file syntax, e.g. `F(1)[+A(0.5,2)]`.
  std::string to_string() const;
};

/// \brief A module of a predecessor or context: symbol and the names of its formal parameters.
struct ModulePattern {
  char sym = 0;
  std::vector<std::string> formals;
};

/// \brief A module of a successor: symbol and one expression per parameter.
struct SuccessorModule {
  char sym = 0;
  std::vector<LExpr> args;
};

/// \brief One production `left < pred > right : condition -> (p) successor`.
struct Production {
  std::vector<ModulePattern> left;  ///< left context, in string order (no brackets)
  ModulePattern pred;
  std::vector<ModulePattern> right;  ///< right context, may contain '[' and ']'
  bool has_condition = false;
  LExpr condition;
  double probability = 1;
  bool stochastic = false;  ///< a probability was written
  std::vector<SuccessorModule> successor;
  int n_formals = 0;  ///< left, pred and right formals, bound in that order
  int line = 0;
};

/// \brief A parsed `.lsys` file.
struct LSystem {
  std::string file;
  ModuleString axiom;
  int derivations = 0;
  double angle_deg = 90;            ///< default turning angle of + - & ^ \ /
  double step = 1;                  ///< default length of F and f
  double initial_width = 1;         ///< width at the start (radius = width / 2)
  double tropism[3] = {0, 0, 0};    ///< tropism vector T (turtle frame, ABOP 2.2)
  double elasticity = 0;            ///< e of ABOP 2.2: after each F, turn by e |H x T| towards T
  std::array<bool, 256> ignored{};  ///< symbols skipped in context matching
  std::vector<Production> productions;
  /// \brief Productions with the same left side (context, predecessor, condition), file order;
  /// a group of more than one is a stochastic choice.
  std::vector<std::vector<int>> groups;
  std::array<std::vector<int>, 256> groups_of_symbol;  ///< group ids by predecessor, file order
};

/// \brief Parse a grammar. Errors: core::InputError `file:line:col: what was expected`.
LSystem parse_lsystem(const std::string& text, const std::string& file_name);
/// \brief Read and parse a file (core::InputError if it cannot be read).
LSystem read_lsystem(const std::string& path);

/// \brief Options of one derivation.
struct DeriveOptions {
  int derivations = -1;  ///< < 0: the file's `derivations:`
  std::uint64_t seed = 1;
  std::uint64_t tree_id = 0;
  std::size_t max_modules = 10'000'000;  ///< a longer string stops with ModuleCapError
};

/// \brief A derivation grew past DeriveOptions::max_modules: `file: derivation d of n exceeds the
/// module cap of N`. The caller knows which deck key or option set the cap and the derivations,
/// and names them; derivations() - 1 is the most that fit.
class ModuleCapError : public core::InputError {
 public:
  ModuleCapError(const std::string& message, int derivation)
      : core::InputError(message), derivation_(derivation) {}
  int derivation() const { return derivation_; }  ///< the first derivation over the cap (1-based)

 private:
  int derivation_;
};

/// \brief Apply the productions `derivations` times to the axiom (ABOP parallel rewriting: in
/// each module the first production, in file order, whose context and condition match).
ModuleString derive(const LSystem& ls, const DeriveOptions& opt);

/// \brief Context matching alone (tests): does production `p` match module `i` of `s`, and what
/// parameters does it bind (left, pred, right formals in that order)?
bool context_matches(const LSystem& ls, const Production& p, const ModuleString& s,
                     const std::vector<std::int64_t>& brackets, std::size_t i, double* bound);
/// \brief Position of the matching bracket of every `[` and `]` (-1 elsewhere). Requires a
/// balanced string.
std::vector<std::int64_t> match_brackets(const ModuleString& s);
/// \brief Parse a module string with constant parameters (tests, axioms).
ModuleString parse_module_string(const std::string& text);

}  // namespace biota::models::plants
