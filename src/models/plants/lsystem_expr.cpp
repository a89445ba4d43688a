#include "models/plants/lsystem_expr.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <numbers>

#include "core/error.hpp"

namespace biota::models::plants {

namespace {

using Op = LExpr::Op;

/// Recursive-descent parser emitting postfix code.
class ExprParser {
 public:
  ExprParser(std::string_view text, const SourcePos& where, const std::vector<std::string>& formals,
             const std::unordered_map<std::string, double>& constants)
      : s_(text), where_(where), formals_(formals), constants_(constants) {}

  LExpr parse() {
    parse_or();
    skip_space();
    if (i_ < s_.size()) fail(i_, "an operator or the end of the expression");
    int depth = 0, max_depth = 0;  // eval() uses a fixed stack
    for (const auto& in : out_.code) {
      const bool push = in.op == Op::kConst || in.op == Op::kParam;
      const bool binary = !push && in.op != Op::kNeg && in.op != Op::kNot &&
                          (in.op < Op::kSqrt || in.op == Op::kMin || in.op == Op::kMax);
      depth += push ? 1 : (binary ? -1 : 0);
      max_depth = std::max(max_depth, depth);
    }
    if (max_depth > LExpr::kMaxStack) fail_msg(0, "expression nested too deeply");
    return std::move(out_);
  }

 private:
  [[noreturn]] void fail(std::size_t at, const std::string& expected) const {
    throw core::InputError(fmt::format("{}:{}:{}: expected {}", where_.file, where_.line,
                                       where_.col + static_cast<int>(at), expected));
  }
  [[noreturn]] void fail_msg(std::size_t at, const std::string& msg) const {
    throw core::InputError(fmt::format("{}:{}:{}: {}", where_.file, where_.line,
                                       where_.col + static_cast<int>(at), msg));
  }
  void skip_space() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
  }
  bool eat(std::string_view tok) {
    skip_space();
    if (s_.substr(i_, tok.size()) == tok) {
      i_ += tok.size();
      return true;
    }
    return false;
  }
  void emit(Op op, int param = 0, double value = 0) { out_.code.push_back({op, param, value}); }

  void parse_or() {
    parse_and();
    while (eat("||")) parse_and(), emit(Op::kOr);
  }
  void parse_and() {
    parse_equality();
    while (eat("&&")) parse_equality(), emit(Op::kAnd);
  }
  void parse_equality() {
    parse_relational();
    for (;;) {
      if (eat("=="))
        parse_relational(), emit(Op::kEq);
      else if (eat("!="))
        parse_relational(), emit(Op::kNe);
      else
        return;
    }
  }
  void parse_relational() {
    parse_additive();
    for (;;) {
      if (eat("<="))
        parse_additive(), emit(Op::kLe);
      else if (eat(">="))
        parse_additive(), emit(Op::kGe);
      else if (eat("<"))
        parse_additive(), emit(Op::kLt);
      else if (eat(">"))
        parse_additive(), emit(Op::kGt);
      else
        return;
    }
  }
  void parse_additive() {
    parse_multiplicative();
    for (;;) {
      if (eat("+"))
        parse_multiplicative(), emit(Op::kAdd);
      else if (eat("-"))
        parse_multiplicative(), emit(Op::kSub);
      else
        return;
    }
  }
  void parse_multiplicative() {
    parse_unary();
    for (;;) {
      if (eat("*"))
        parse_unary(), emit(Op::kMul);
      else if (eat("/"))
        parse_unary(), emit(Op::kDiv);
      else
        return;
    }
  }
  void parse_unary() {
    skip_space();
    if (eat("-")) return parse_unary(), emit(Op::kNeg);
    if (i_ < s_.size() && s_[i_] == '!' && s_.substr(i_, 2) != "!=") {
      ++i_;
      return parse_unary(), emit(Op::kNot);
    }
    if (eat("+")) return parse_unary();
    parse_power();
  }
  void parse_power() {
    parse_primary();
    if (eat("^")) parse_unary(), emit(Op::kPow);  // right associative, binds tighter than unary
  }
  void parse_primary() {
    skip_space();
    if (i_ >= s_.size()) fail(i_, "a number, a parameter name or '('");
    const char c = s_[i_];
    if (c == '(') {
      ++i_;
      parse_or();
      if (!eat(")")) fail(i_, "')'");
      return;
    }
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') {
      const std::size_t start = i_;
      while (i_ < s_.size() && (std::isdigit(static_cast<unsigned char>(s_[i_])) || s_[i_] == '.'))
        ++i_;
      if (i_ < s_.size() && (s_[i_] == 'e' || s_[i_] == 'E')) {
        std::size_t j = i_ + 1;
        if (j < s_.size() && (s_[j] == '+' || s_[j] == '-')) ++j;
        if (j < s_.size() && std::isdigit(static_cast<unsigned char>(s_[j]))) {
          i_ = j;
          while (i_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[i_]))) ++i_;
        }
      }
      const std::string num(s_.substr(start, i_ - start));
      char* end = nullptr;
      const double v = std::strtod(num.c_str(), &end);
      if (end != num.c_str() + num.size()) fail(start, "a number");
      emit(Op::kConst, 0, v);
      return;
    }
    if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
      const std::size_t start = i_;
      while (i_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[i_])) || s_[i_] == '_'))
        ++i_;
      const std::string name(s_.substr(start, i_ - start));
      skip_space();
      if (i_ < s_.size() && s_[i_] == '(') return parse_call(name, start);
      for (std::size_t k = 0; k < formals_.size(); ++k)
        if (formals_[k] == name) return emit(Op::kParam, static_cast<int>(k));
      if (auto it = constants_.find(name); it != constants_.end())
        return emit(Op::kConst, 0, it->second);
      if (name == "pi") return emit(Op::kConst, 0, std::numbers::pi);
      std::string known;
      for (const auto& f : formals_) {
        if (!known.empty()) known += ", ";
        known += f;
      }
      fail_msg(start, fmt::format("unknown symbol '{}' (expected a parameter of the predecessor{}, "
                                  "a #define constant or a function)",
                                  name, known.empty() ? "" : " (" + known + ")"));
    }
    fail(i_, "a number, a parameter name or '('");
  }
  void parse_call(const std::string& name, std::size_t start) {
    struct Fn {
      const char* name;
      Op op;
      int nargs;
    };
    static const Fn fns[] = {{"sqrt", Op::kSqrt, 1}, {"sin", Op::kSin, 1},     {"cos", Op::kCos, 1},
                             {"tan", Op::kTan, 1},   {"exp", Op::kExp, 1},     {"log", Op::kLog, 1},
                             {"abs", Op::kAbs, 1},   {"floor", Op::kFloor, 1}, {"min", Op::kMin, 2},
                             {"max", Op::kMax, 2}};
    const Fn* fn = nullptr;
    for (const auto& f : fns)
      if (name == f.name) fn = &f;
    if (!fn)
      fail_msg(start, fmt::format("unknown function '{}' (expected sqrt sin cos tan exp log abs "
                                  "floor min max)",
                                  name));
    eat("(");
    for (int a = 0; a < fn->nargs; ++a) {
      if (a > 0 && !eat(","))
        fail(i_, fmt::format("',' ({}() takes {} arguments)", name, fn->nargs));
      parse_or();
    }
    if (!eat(")"))
      fail(i_, fmt::format("')' ({}() takes {} argument{})", name, fn->nargs,
                           fn->nargs == 1 ? "" : "s"));
    emit(fn->op);
  }

  std::string_view s_;
  SourcePos where_;
  const std::vector<std::string>& formals_;
  const std::unordered_map<std::string, double>& constants_;
  std::size_t i_ = 0;
  LExpr out_;
};

}  // namespace

LExpr parse_expression(std::string_view text, const SourcePos& where,
                       const std::vector<std::string>& formals,
                       const std::unordered_map<std::string, double>& constants) {
  return ExprParser(text, where, formals, constants).parse();
}

bool LExpr::constant() const {
  for (const auto& in : code)
    if (in.op == Op::kParam) return false;
  return true;
}

double LExpr::eval(const double* params) const {
  double st[kMaxStack];
  int n = 0;
  for (const auto& in : code) {
    switch (in.op) {
      case Op::kConst:
        st[n++] = in.value;
        break;
      case Op::kParam:
        st[n++] = params[in.param];
        break;
      case Op::kNeg:
        st[n - 1] = -st[n - 1];
        break;
      case Op::kNot:
        st[n - 1] = st[n - 1] == 0 ? 1 : 0;
        break;
      case Op::kSqrt:
        st[n - 1] = std::sqrt(st[n - 1]);
        break;
      case Op::kSin:
        st[n - 1] = std::sin(st[n - 1]);
        break;
      case Op::kCos:
        st[n - 1] = std::cos(st[n - 1]);
        break;
      case Op::kTan:
        st[n - 1] = std::tan(st[n - 1]);
        break;
      case Op::kExp:
        st[n - 1] = std::exp(st[n - 1]);
        break;
      case Op::kLog:
        st[n - 1] = std::log(st[n - 1]);
        break;
      case Op::kAbs:
        st[n - 1] = std::abs(st[n - 1]);
        break;
      case Op::kFloor:
        st[n - 1] = std::floor(st[n - 1]);
        break;
      default: {
        const double b = st[--n], a = st[n - 1];
        double r = 0;
        switch (in.op) {
          case Op::kAdd:
            r = a + b;
            break;
          case Op::kSub:
            r = a - b;
            break;
          case Op::kMul:
            r = a * b;
            break;
          case Op::kDiv:
            r = a / b;
            break;
          case Op::kPow:
            r = std::pow(a, b);
            break;
          case Op::kLt:
            r = a < b;
            break;
          case Op::kLe:
            r = a <= b;
            break;
          case Op::kGt:
            r = a > b;
            break;
          case Op::kGe:
            r = a >= b;
            break;
          case Op::kEq:
            r = a == b;
            break;
          case Op::kNe:
            r = a != b;
            break;
          case Op::kAnd:
            r = (a != 0) && (b != 0);
            break;
          case Op::kOr:
            r = (a != 0) || (b != 0);
            break;
          case Op::kMin:
            r = std::min(a, b);
            break;
          case Op::kMax:
            r = std::max(a, b);
            break;
          default:
            break;
        }
        st[n - 1] = r;
      }
    }
  }
  return n > 0 ? st[n - 1] : 0;
}

}  // namespace biota::models::plants
