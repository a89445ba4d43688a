// Reading an L-system file (ABOP notation: #define constants, context, conditions,
// stochastic groups) into an LSystem. The derivation is in lsystem.cpp.

#include "models/plants/lsystem.hpp"

#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <sstream>
#include <string_view>
#include <unordered_map>

#include "core/config.hpp"
#include "core/error.hpp"

namespace biota::models::plants {

namespace {

constexpr std::string_view kSymbols = "+-&^\\/|$[]!'~{}%.";

bool is_symbol(char c) {
  return std::isalpha(static_cast<unsigned char>(c)) || kSymbols.find(c) != std::string_view::npos;
}

/// Turtle symbols that take an optional length / angle / width when no production defines them.
bool optional_param_symbol(char c) {
  return std::string_view("FfGg+-&^\\/").find(c) != std::string_view::npos;
}
bool no_param_symbol(char c) {
  return std::string_view("[]|$").find(c) != std::string_view::npos;
}

std::string trim(std::string_view s) {
  std::size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return std::string(s.substr(a, b - a));
}

/// One module as written: symbol, its column, and the raw argument texts with their columns.
struct RawModule {
  char sym = 0;
  int col = 0;
  std::vector<std::string> args;
  std::vector<int> arg_cols;
};

class FileParser {
 public:
  FileParser(const std::string& text, const std::string& file) : text_(text) { ls_.file = file; }

  LSystem parse() {
    std::istringstream in(text_);
    std::string line;
    bool have_axiom = false;
    struct Pending {
      std::string text;
      int line;
    };
    std::vector<Pending> productions;
    int axiom_line = 0, axiom_col = 0;
    std::string axiom_text;
    while (std::getline(in, line)) {
      ++line_no_;
      if (auto c = line.find("//"); c != std::string::npos) line.erase(c);
      const std::string t = trim(line);
      if (t.empty()) continue;
      const int indent = static_cast<int>(line.find_first_not_of(" \t"));
      if (t.rfind("#define", 0) == 0) {
        parse_define(line, indent + 7);
        continue;
      }
      if (t[0] == '#') continue;  // comment
      if (line.find("->") != std::string::npos) {
        productions.push_back({line, line_no_});
        continue;
      }
      const auto colon = line.find(':');
      if (colon == std::string::npos)
        fail(line_no_, indent + 1,
             "expected 'key: value' (axiom, derivations, angle, ignore, step, width, tropism) "
             "or a production 'pred -> successor'");
      const std::string key = trim(std::string_view(line).substr(0, colon));
      const std::string value = line.substr(colon + 1);
      const int vcol = static_cast<int>(colon) + 2;
      if (key == "axiom") {
        have_axiom = true, axiom_text = value, axiom_line = line_no_, axiom_col = vcol;
      } else if (key == "derivations") {
        const double v = constant_value(value, vcol);
        if (v < 0 || v != std::floor(v) || v > 1000)
          fail(line_no_, vcol, "expected a whole number of derivations in [0, 1000]");
        ls_.derivations = static_cast<int>(v);
      } else if (key == "angle") {
        ls_.angle_deg = constant_value(value, vcol);
      } else if (key == "step") {
        ls_.step = constant_value(value, vcol);
      } else if (key == "width") {
        ls_.initial_width = constant_value(value, vcol);
      } else if (key == "ignore") {
        for (std::size_t k = 0; k < value.size(); ++k) {
          const char c = value[k];
          if (std::isspace(static_cast<unsigned char>(c))) continue;
          if (!is_symbol(c) || c == '[' || c == ']')
            fail(line_no_, vcol + static_cast<int>(k),
                 "expected module symbols to ignore (letters or + - & ^ \\ / | $ ! ' ~ { } % .; "
                 "not brackets)");
          ls_.ignored[static_cast<unsigned char>(c)] = true;
        }
      } else if (key == "tropism") {
        // Four numbers: T (x y z, turtle frame) and the elasticity e.
        std::istringstream vs(value);
        std::vector<double> v;
        std::string w;
        while (vs >> w) v.push_back(constant_value(w, vcol));
        if (v.size() != 4) fail(line_no_, vcol, "expected 'tropism: Tx Ty Tz e' (four numbers)");
        for (int d = 0; d < 3; ++d) ls_.tropism[d] = v[d];
        ls_.elasticity = v[3];
      } else {
        fail(line_no_, indent + 1,
             fmt::format("unknown key '{}' (expected axiom, derivations, angle, ignore, step, "
                         "width, tropism, #define or a production)",
                         key));
      }
    }
    if (!have_axiom) fail(1, 1, "expected an 'axiom:' line");
    for (const auto& p : productions) parse_production(p.text, p.line);
    build_groups();
    check_arities();
    // The axiom last: its modules must agree with the predecessors' parameter counts.
    auto raw = split_modules(axiom_text, axiom_line, axiom_col, false);
    check_brackets(raw, axiom_line);
    for (const auto& m : raw) {
      check_arity(m, axiom_line);
      std::vector<double> v;
      for (std::size_t a = 0; a < m.args.size(); ++a)
        v.push_back(constant_value(m.args[a], m.arg_cols[a], axiom_line));
      ls_.axiom.push(m.sym, v.data(), static_cast<int>(v.size()));
    }
    return std::move(ls_);
  }

 private:
  [[noreturn]] void fail(int line, int col, const std::string& what) const {
    throw core::InputError(fmt::format("{}:{}:{}: {}", ls_.file, line, col, what));
  }
  SourcePos pos(int line, int col) const { return {ls_.file, line, col}; }

  double constant_value(const std::string& text, int col, int line = -1) {
    if (line < 0) line = line_no_;
    const int lead = static_cast<int>(text.find_first_not_of(" \t"));
    if (lead < 0) fail(line, col, "expected a value");
    const auto e = parse_expression(trim(text), pos(line, col + lead), {}, constants_);
    return e.eval(nullptr);
  }

  void parse_define(const std::string& line, int after) {
    // #define name value
    std::size_t i = static_cast<std::size_t>(after);
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    const std::size_t start = i;
    while (i < line.size() && (std::isalnum(static_cast<unsigned char>(line[i])) || line[i] == '_'))
      ++i;
    if (i == start || std::isdigit(static_cast<unsigned char>(line[start])))
      fail(line_no_, static_cast<int>(start) + 1, "expected '#define name value'");
    const std::string name = line.substr(start, i - start);
    const std::string rest = line.substr(i);
    if (trim(rest).empty())
      fail(line_no_, static_cast<int>(i) + 1, "expected a value after the name");
    constants_[name] = constant_value(rest, static_cast<int>(i) + 1);
  }

  /// Split a module string into modules with raw argument texts.
  std::vector<RawModule> split_modules(const std::string& s, int line, int col0,
                                       bool allow_context_sep) {
    std::vector<RawModule> out;
    std::size_t i = 0;
    while (i < s.size()) {
      const char c = s[i];
      if (std::isspace(static_cast<unsigned char>(c))) {
        ++i;
        continue;
      }
      if (!is_symbol(c) || (allow_context_sep && (c == '<' || c == '>')))
        fail(line, col0 + static_cast<int>(i),
             fmt::format("expected a module symbol (a letter or + - & ^ \\ / | $ [ ] ! ' ~ {{ }} % "
                         ".), found '{}'",
                         c));
      RawModule m;
      m.sym = c;
      m.col = col0 + static_cast<int>(i);
      ++i;
      if (i < s.size() && s[i] == '(') {
        ++i;
        int depth = 0;
        std::size_t start = i;
        for (;; ++i) {
          if (i >= s.size())
            fail(line, col0 + static_cast<int>(i),
                 fmt::format("expected ')' closing the "
                             "parameters of '{}'",
                             c));
          if (s[i] == '(')
            ++depth;
          else if (s[i] == ')' && depth-- == 0)
            break;
          else if (s[i] == ',' && depth == 0) {
            m.args.push_back(s.substr(start, i - start));
            m.arg_cols.push_back(col0 + static_cast<int>(start));
            start = i + 1;
          }
        }
        m.args.push_back(s.substr(start, i - start));
        m.arg_cols.push_back(col0 + static_cast<int>(start));
        if (m.args.size() == 1 && trim(m.args[0]).empty())
          fail(line, col0 + static_cast<int>(start), "expected a parameter inside '()'");
        ++i;
      }
      out.push_back(std::move(m));
    }
    return out;
  }

  void check_brackets(const std::vector<RawModule>& ms, int line) {
    std::vector<int> open;
    for (const auto& m : ms) {
      if (m.sym == '[') open.push_back(m.col);
      if (m.sym == ']') {
        if (open.empty()) fail(line, m.col, "unbalanced brackets: ']' without a matching '['");
        open.pop_back();
      }
    }
    if (!open.empty())
      fail(line, open.back(), "unbalanced brackets: '[' is never closed (expected ']')");
  }

  ModulePattern pattern_of(const RawModule& m, int line) {
    ModulePattern p;
    p.sym = m.sym;
    for (std::size_t a = 0; a < m.args.size(); ++a) {
      const std::string name = trim(m.args[a]);
      bool ok =
          !name.empty() && (std::isalpha(static_cast<unsigned char>(name[0])) || name[0] == '_');
      for (char ch : name) ok = ok && (std::isalnum(static_cast<unsigned char>(ch)) || ch == '_');
      if (!ok) fail(line, m.arg_cols[a], "expected a formal parameter name");
      p.formals.push_back(name);
    }
    return p;
  }

  void parse_production(const std::string& line, int ln) {
    const std::size_t arrow = line.find("->");
    std::string lhs = line.substr(0, arrow);
    // Condition: after the first ':' of the left side.
    std::string cond;
    int cond_col = 0;
    if (auto c = lhs.find(':'); c != std::string::npos) {
      cond = lhs.substr(c + 1);
      cond_col = static_cast<int>(c) + 2;
      lhs.erase(c);
    }
    Production p;
    p.line = ln;
    // Context separators '<' and '>' outside parentheses.
    std::size_t lt = std::string::npos, gt = std::string::npos;
    int depth = 0;
    for (std::size_t i = 0; i < lhs.size(); ++i) {
      if (lhs[i] == '(') ++depth;
      if (lhs[i] == ')') --depth;
      if (depth == 0 && lhs[i] == '<') {
        if (lt != std::string::npos) fail(ln, static_cast<int>(i) + 1, "expected one '<' at most");
        lt = i;
      }
      if (depth == 0 && lhs[i] == '>') {
        if (gt != std::string::npos) fail(ln, static_cast<int>(i) + 1, "expected one '>' at most");
        gt = i;
      }
    }
    if (lt != std::string::npos && gt != std::string::npos && gt < lt)
      fail(ln, static_cast<int>(gt) + 1, "expected 'left < pred > right' (left context first)");
    const std::size_t pred_begin = lt == std::string::npos ? 0 : lt + 1;
    const std::size_t pred_end = gt == std::string::npos ? lhs.size() : gt;
    if (lt != std::string::npos) {
      auto left = split_modules(lhs.substr(0, lt), ln, 1, true);
      if (left.empty()) fail(ln, static_cast<int>(lt) + 1, "expected a left context before '<'");
      for (const auto& m : left) {
        if (m.sym == '[' || m.sym == ']')
          fail(ln, m.col, "expected modules in the left context (brackets are not allowed there)");
        p.left.push_back(pattern_of(m, ln));
      }
    }
    auto pred = split_modules(lhs.substr(pred_begin, pred_end - pred_begin), ln,
                              static_cast<int>(pred_begin) + 1, true);
    if (pred.size() != 1 || pred[0].sym == '[' || pred[0].sym == ']')
      fail(ln, static_cast<int>(pred_begin) + 1,
           "expected exactly one predecessor module (not a bracket) before '->'");
    p.pred = pattern_of(pred[0], ln);
    if (gt != std::string::npos) {
      auto right = split_modules(lhs.substr(gt + 1), ln, static_cast<int>(gt) + 2, true);
      if (right.empty()) fail(ln, static_cast<int>(gt) + 2, "expected a right context after '>'");
      check_brackets(right, ln);
      for (const auto& m : right) p.right.push_back(pattern_of(m, ln));
    }
    std::vector<std::string> formals;
    for (const auto& m : p.left) formals.insert(formals.end(), m.formals.begin(), m.formals.end());
    formals.insert(formals.end(), p.pred.formals.begin(), p.pred.formals.end());
    for (const auto& m : p.right) formals.insert(formals.end(), m.formals.begin(), m.formals.end());
    p.n_formals = static_cast<int>(formals.size());
    if (!trim(cond).empty()) {
      p.has_condition = true;
      const int lead = static_cast<int>(cond.find_first_not_of(" \t"));
      p.condition = parse_expression(trim(cond), pos(ln, cond_col + lead), formals, constants_);
    } else if (cond_col > 0) {
      fail(ln, cond_col, "expected a condition after ':'");
    }
    // Successor, with an optional probability "(p)" first.
    std::size_t s = arrow + 2;
    while (s < line.size() && std::isspace(static_cast<unsigned char>(line[s]))) ++s;
    if (s < line.size() && line[s] == '(') {
      const auto close = line.find(')', s);
      if (close == std::string::npos)
        fail(ln, static_cast<int>(s) + 1, "expected ')' after the probability");
      p.stochastic = true;
      p.probability =
          constant_value(line.substr(s + 1, close - s - 1), static_cast<int>(s) + 2, ln);
      if (!(p.probability >= 0 && p.probability <= 1))
        fail(ln, static_cast<int>(s) + 2,
             fmt::format("expected a probability in [0, 1], found {}", p.probability));
      s = close + 1;
    }
    const std::string succ_text = line.substr(s);
    auto succ = split_modules(succ_text, ln, static_cast<int>(s) + 1, false);
    check_brackets(succ, ln);
    for (const auto& m : succ) {
      SuccessorModule sm;
      sm.sym = m.sym;
      for (std::size_t a = 0; a < m.args.size(); ++a) {
        const int lead = static_cast<int>(m.args[a].find_first_not_of(" \t"));
        sm.args.push_back(
            parse_expression(trim(m.args[a]), pos(ln, m.arg_cols[a] + lead), formals, constants_));
      }
      raw_succ_.push_back({ln, m});
      p.successor.push_back(std::move(sm));
    }
    std::string key;
    for (char ch : lhs + ":" + cond)
      if (!std::isspace(static_cast<unsigned char>(ch))) key += ch;
    lhs_keys_.push_back(key);
    ls_.productions.push_back(std::move(p));
  }

  void build_groups() {
    std::unordered_map<std::string, int> group_of;
    for (std::size_t i = 0; i < ls_.productions.size(); ++i) {
      auto [it, fresh] = group_of.emplace(lhs_keys_[i], static_cast<int>(ls_.groups.size()));
      if (fresh) {
        ls_.groups.emplace_back();
        ls_.groups_of_symbol[static_cast<unsigned char>(ls_.productions[i].pred.sym)].push_back(
            it->second);
      }
      ls_.groups[it->second].push_back(static_cast<int>(i));
    }
    for (const auto& g : ls_.groups) {
      double sum = 0;
      for (int i : g) sum += ls_.productions[i].probability;
      const auto& first = ls_.productions[g.front()];
      if (g.size() > 1) {
        for (int i : g)
          if (!ls_.productions[i].stochastic)
            fail(ls_.productions[i].line, 1,
                 fmt::format("expected a probability '(p)' after '->': {} productions share this "
                             "left side (a stochastic choice)",
                             g.size()));
      }
      if (std::abs(sum - 1) > 1e-9)
        fail(first.line, 1,
             fmt::format("expected the probabilities of the productions of '{}' with this left "
                         "side to sum to 1, they sum to {}",
                         first.pred.sym, sum));
    }
  }

  void check_arities() {
    for (const auto& p : ls_.productions) {
      auto [it, fresh] = arity_.emplace(p.pred.sym, static_cast<int>(p.pred.formals.size()));
      if (!fresh && it->second != static_cast<int>(p.pred.formals.size()))
        fail(p.line, 1,
             fmt::format("parameter-count mismatch: '{}' has {} parameter(s) here but {} in an "
                         "earlier production",
                         p.pred.sym, p.pred.formals.size(), it->second));
    }
    for (const auto& p : ls_.productions) {
      for (const auto* ctx : {&p.left, &p.right})
        for (const auto& m : *ctx) {
          if (m.sym == '[' || m.sym == ']') continue;
          RawModule r;
          r.sym = m.sym;
          r.args = m.formals;
          r.col = 1;
          check_arity(r, p.line);
        }
    }
    for (const auto& [ln, m] : raw_succ_) check_arity(m, ln);
  }

  void check_arity(const RawModule& m, int line) {
    const int n = static_cast<int>(m.args.size());
    if (auto it = arity_.find(m.sym); it != arity_.end()) {
      if (it->second != n)
        fail(line, m.col,
             fmt::format("parameter-count mismatch: expected {} parameter(s) for '{}' (as in its "
                         "production), found {}",
                         it->second, m.sym, n));
      return;
    }
    if (no_param_symbol(m.sym)) {
      if (n != 0) fail(line, m.col, fmt::format("expected no parameters for '{}'", m.sym));
      return;
    }
    if (m.sym == '!') {
      if (n != 1) fail(line, m.col, "expected one parameter: '!(w)' sets the width");
      return;
    }
    if (optional_param_symbol(m.sym)) {
      if (n > 1) fail(line, m.col, fmt::format("expected at most one parameter for '{}'", m.sym));
      return;
    }
    auto [it, fresh] = free_arity_.emplace(m.sym, n);
    if (!fresh && it->second != n)
      fail(line, m.col,
           fmt::format("parameter-count mismatch: expected {} parameter(s) for '{}' (as at its "
                       "first use), found {}",
                       it->second, m.sym, n));
  }

  const std::string& text_;
  LSystem ls_;
  int line_no_ = 0;
  std::unordered_map<std::string, double> constants_;
  std::vector<std::string> lhs_keys_;
  std::vector<std::pair<int, RawModule>> raw_succ_;
  std::unordered_map<char, int> arity_, free_arity_;
};

}  // namespace

LSystem parse_lsystem(const std::string& text, const std::string& file_name) {
  return FileParser(text, file_name).parse();
}

LSystem read_lsystem(const std::string& path) {
  return parse_lsystem(
      core::read_input_file(path, "an L-system file", "cannot read the L-system file"), path);
}

ModuleString parse_module_string(const std::string& text) {
  return parse_lsystem("axiom: " + text + "\n", "<string>").axiom;
}

}  // namespace biota::models::plants
