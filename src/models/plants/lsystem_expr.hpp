#pragma once
/// \file lsystem_expr.hpp
/// \brief Arithmetic expressions of parametric L-systems (ABOP ch. 1.10): parsed once into a small
/// stack program, evaluated per module with the bound formal parameters.
///
/// Grammar (C precedence, lowest first): `||`, `&&`, `== !=`, `< <= > >=`, `+ -`, `* /`, unary
/// `- ! +`, `^` (power, right associative), primary: number, formal parameter, constant
/// (`#define`, substituted at parse time), `pi`, function call (sqrt sin cos tan exp log abs min
/// max floor; angles in radians), parentheses. Comparisons and logic give 1 or 0; a condition is
/// true when its value is non-zero.
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace biota::models::plants {

/// \brief One compiled expression.
class LExpr {
 public:
  enum class Op : unsigned char {
    kConst,
    kParam,
    kNeg,
    kNot,
    kAdd,
    kSub,
    kMul,
    kDiv,
    kPow,
    kLt,
    kLe,
    kGt,
    kGe,
    kEq,
    kNe,
    kAnd,
    kOr,
    kSqrt,
    kSin,
    kCos,
    kTan,
    kExp,
    kLog,
    kAbs,
    kMin,
    kMax,
    kFloor
  };
  struct Instr {
    Op op;
    int param = 0;
    double value = 0;
  };
  static constexpr int kMaxStack = 64;
  /// \brief Value with formal parameters `params` (indexed as at parse time).
  double eval(const double* params) const;
  /// \brief True if the expression uses no formal parameter (then `eval(nullptr)` is valid).
  bool constant() const;
  std::vector<Instr> code;
};

/// \brief Where a piece of text comes from, for error messages.
struct SourcePos {
  std::string file;
  int line = 1;
  int col = 1;  ///< 1-based column of the first character of the text
};

/// \brief Parse `text` as one expression. `formals` are the names of the bound parameters (their
/// index is the position); `constants` the `#define`d names. Throws core::InputError with
/// `file:line:col: ...` on a syntax error or an unknown name.
LExpr parse_expression(std::string_view text, const SourcePos& where,
                       const std::vector<std::string>& formals,
                       const std::unordered_map<std::string, double>& constants);

}  // namespace biota::models::plants
