/// \file test_lsystem.cpp
/// \brief The L-system engine: exact module counts and turtle extents of the tree paper's Fig. 1
/// and of ABOP figures (derived by hand in the comments), expressions, parametric conditions,
/// bracket-aware context matching (ABOP 1.8), the Galton-Watson mean of a stochastic grammar, and
/// one test per grammar error (each a single `file:line:col: ...` line).
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>

#include "core/error.hpp"
#include "models/plants/lsystem.hpp"
#include "models/plants/turtle.hpp"

using namespace biota::models::plants;

namespace {

std::map<char, long long> counts(const ModuleString& s) {
  std::map<char, long long> c;
  for (char x : s.sym) ++c[x];
  return c;
}

std::string error_of(const std::string& text) {
  try {
    parse_lsystem(text, "g.lsys");
  } catch (const biota::core::InputError& e) {
    return e.what();
  }
  return "";
}

const double s20 = std::sin(20 * std::numbers::pi / 180),
             s40 = std::sin(40 * std::numbers::pi / 180);

}  // namespace

TEST(LSystem, PaperFigure1CountsAndExtent) {
  // F -> F[+F]F[-F][F] (13 modules, 5 F, 8 others). After 1 step: 13 modules, 5 F. After 2:
  // 5 * 13 + 8 = 73 modules, 25 F, bracket pairs 3 + 5 * 3 = 18.
  const auto ls = parse_lsystem("axiom: F\nderivations: 2\nangle: 20\nF -> F[+F]F[-F][F]\n", "p");
  const auto s = derive(ls, {});
  EXPECT_EQ(s.size(), 73u);
  auto c = counts(s);
  EXPECT_EQ(c['F'], 25);
  EXPECT_EQ(c['['], 18);
  EXPECT_EQ(c['+'], 6);
  const auto g = interpret(ls, s);
  EXPECT_EQ(g.segments.size(), 25u);
  // Height: the trunk F F of the first F (0..2), the trunk F F of the third top-level F (2..4),
  // then the vertical top-level [F] expanded to F F [F]: 4..6 and 6..7. Every tilted branch
  // ends lower, so max y = 7.
  EXPECT_NEAR(g.hi.y, 7, 1e-12);
  EXPECT_EQ(g.lo.y, 0);
  // Min x: the top-level [+F] (at y = 2, heading +20 deg towards -x) expands to F F [F] all at
  // +20 deg: 3 sin 20. Max x: the top-level [-F] (at y = 4, -20 deg) expands to F, F, then
  // [-F] at -40 deg: 2 sin 20 + sin 40. The plane is z = 0 (only + and -).
  EXPECT_NEAR(g.lo.x, -3 * s20, 1e-12);
  EXPECT_NEAR(g.hi.x, 2 * s20 + s40, 1e-12);
  EXPECT_EQ(g.lo.z, 0);
  EXPECT_EQ(g.hi.z, 0);
}

TEST(LSystem, AbopFigure124aCounts) {
  // ABOP Fig. 1.24a: F -> F[+F]F[-F]F, 25.7 deg, n = 5. Each F gives 5 F and 6 other modules:
  // F(5) = 5^5 = 3125, others 6 (1 + 5 + ... + 5^4) = 1.5 (5^5 - 1) = 4686, total 7811, bracket
  // pairs (5^5 - 1) / 2 = 1562. The trunk is F F F at every level (no turn on it): height 3^5 =
  // 243, and every branch ends below its parent axis' top.
  const auto ls = parse_lsystem("axiom: F\nderivations: 5\nangle: 25.7\nF -> F[+F]F[-F]F\n", "a");
  const auto s = derive(ls, {});
  EXPECT_EQ(s.size(), 7811u);
  auto c = counts(s);
  EXPECT_EQ(c['F'], 3125);
  EXPECT_EQ(c['['], 1562);
  const auto g = interpret(ls, s);
  EXPECT_NEAR(g.hi.y - g.lo.y, 243, 1e-9);
}

TEST(LSystem, AbopFigure124dTwoProductions) {
  // ABOP Fig. 1.24d: X -> F[+X]F[-X]+X, F -> FF, n = 7. X(n) = 3^n; F(n) = 2 F(n-1) + 2 X(n-1):
  // 0, 2, 10, 38, 130, 422, 1330, 4118. The successor of X has 11 modules, 7 of them neither F
  // nor X ([ + ] [ - ] +), so the others number 7 (1 + 3 + ... + 3^6) = 7 (3^7 - 1) / 2 = 7651;
  // total 4118 + 2187 + 7651 = 13956.
  const auto ls =
      parse_lsystem("axiom: X\nderivations: 7\nangle: 20\nX -> F[+X]F[-X]+X\nF -> FF\n", "d");
  const auto s = derive(ls, {});
  auto c = counts(s);
  EXPECT_EQ(c['X'], 2187);
  EXPECT_EQ(c['F'], 4118);
  EXPECT_EQ(s.size(), 13956u);
}

TEST(LSystem, Expressions) {
  auto v = [](const std::string& e) {
    return parse_expression(e, {"e", 1, 1}, {"x"}, {{"R", 0.5}})
        .eval(std::vector<double>{3}.data());
  };
  EXPECT_EQ(v("2 + 3 * 4 ^ 2"), 50);
  EXPECT_EQ(v("-2 ^ 2"), -4);      // ^ binds tighter than unary minus
  EXPECT_EQ(v("2 ^ 3 ^ 2"), 512);  // right associative
  EXPECT_EQ(v("x * R"), 1.5);
  EXPECT_EQ(v("1 < 2 && !(3 > 4)"), 1);
  EXPECT_EQ(v("x >= 3 || 0"), 1);
  EXPECT_EQ(v("x != 3"), 0);
  EXPECT_EQ(v("min(x, 2) + max(x, 2) + floor(2.7) + abs(-1) + sqrt(16)"), 12);
  EXPECT_NEAR(v("sin(pi / 2) + cos(0) + tan(0) + exp(0) + log(1)"), 3, 1e-15);
  EXPECT_EQ(v("1e-1 * 10"), 1);
}

TEST(LSystem, ParametricConditionStopsGrowth) {
  // A(l) : l > 0.1 -> F(l) A(l R): A(1), A(0.5), A(0.25), A(0.125) apply, A(0.0625) does not, so
  // after 10 steps: F(1) F(0.5) F(0.25) F(0.125) A(0.0625), height 1.875 exactly.
  const auto ls = parse_lsystem(
      "#define R 0.5\naxiom: A(1)\nderivations: 10\nA(l) : l > 0.1 -> F(l) A(l * R)\n", "c");
  const auto s = derive(ls, {});
  EXPECT_EQ(s.to_string(), "F(1)F(0.5)F(0.25)F(0.125)A(0.0625)");
  const auto g = interpret(ls, s);
  EXPECT_EQ(g.segments.size(), 4u);
  EXPECT_EQ(g.hi.y, 1.875);
  // Branching with two conditions in file order: 1 + 2 + 4 + 8 = 15 F, 16 A(0.0625) remain.
  const auto b = parse_lsystem(
      "axiom: A(1)\nangle: 30\nA(l) : l > 0.1 -> F(l)[+A(l/2)][-A(l/2)]\nA(l) : l <= 0.1 -> "
      "A(l)\n",
      "b");
  auto c = counts(derive(b, {.derivations = 10}));
  EXPECT_EQ(c['F'], 15);
  EXPECT_EQ(c['A'], 16);
}

TEST(LSystem, ContextSignalPropagation) {
  // ABOP 1.8 signal: b < a -> b, b -> a moves b one module right per step.
  const auto ls = parse_lsystem("axiom: baaaaaaa\nb < a -> b\nb -> a\n", "s");
  EXPECT_EQ(derive(ls, {.derivations = 3}).to_string(), "aaabaaaa");
}

TEST(LSystem, ContextBracketAware) {
  const auto ls =
      parse_lsystem("axiom: X\nignore: + -\nB < A -> X\nA > C -> Y\nBC < S > G[H]M -> Z\n", "ctx");
  auto matches = [&](int prod, const std::string& str, std::size_t at) {
    const auto s = parse_module_string(str);
    double bound[8];
    return context_matches(ls, ls.productions[prod], s, match_brackets(s), at, bound);
  };
  // Left context B < A: branches on the left are skipped, the branch containing A is climbed out
  // of, ignored symbols are skipped; a sibling branch holding B or a different module does not
  // count.
  EXPECT_TRUE(matches(0, "BA", 1));
  EXPECT_TRUE(matches(0, "B[C]A", 4));
  EXPECT_TRUE(matches(0, "B[A]", 2));
  EXPECT_TRUE(matches(0, "B+-A", 3));
  EXPECT_TRUE(matches(0, "B[C][D]+A", 8));
  EXPECT_FALSE(matches(0, "[B]A", 3));
  EXPECT_FALSE(matches(0, "BCA", 2));
  EXPECT_FALSE(matches(0, "A", 0));
  // Right context A > C: branches on the right are skipped; the end of A's branch ends the search.
  EXPECT_TRUE(matches(1, "A[B]C", 0));
  EXPECT_TRUE(matches(1, "A-C", 0));
  EXPECT_FALSE(matches(1, "A[C]", 0));
  EXPECT_FALSE(matches(1, "[A]C", 1));
  EXPECT_FALSE(matches(1, "ABC", 0));
  // ABOP Fig. 1.31: BC < S > G[H]M applies to S in ABC[DE][SG[HI[JK]L]MNO].
  EXPECT_TRUE(matches(2, "ABC[DE][SG[HI[JK]L]MNO]", 8));
  EXPECT_FALSE(matches(2, "ABC[DE][SG[HI[JK]L]NO]", 8));
}

TEST(LSystem, ContextBindsParameters) {
  const auto ls =
      parse_lsystem("axiom: A(1)B(2)C(4)\nA(x) < B(y) > C(z) : x + z > y -> B(x + y + z)\n", "p");
  EXPECT_EQ(derive(ls, {.derivations = 1}).to_string(), "A(1)B(7)C(4)");
  EXPECT_EQ(derive(ls, {.derivations = 2}).to_string(), "A(1)B(7)C(4)");  // 5 > 7 fails
}

TEST(LSystem, StochasticGaltonWatsonMean) {
  // A -> AA (1/2), A (1/4), B (1/4): offspring mean mu = 1.25, variance s2 = 2.25 - mu^2 =
  // 0.6875. After n steps E[Z_n] = mu^n and Var Z_n = s2 mu^(n-1) (mu^n - 1) / (mu - 1).
  const auto ls = parse_lsystem("axiom: A\nA -> (0.5) A A\nA -> (0.25) A\nA -> (0.25) B\n", "gw");
  const int n = 6, trees = 4000;
  const double mu = 1.25, s2 = 0.6875;
  const double mean = std::pow(mu, n),
               var = s2 * std::pow(mu, n - 1) * (std::pow(mu, n) - 1) / (mu - 1);
  double sum = 0;
  for (int t = 0; t < trees; ++t)
    sum += counts(
        derive(ls, {.derivations = n, .seed = 7, .tree_id = static_cast<std::uint64_t>(t)}))['A'];
  const double se = std::sqrt(var / trees), z = (sum / trees - mean) / se;
  EXPECT_LT(std::abs(z), 3) << "sample mean " << sum / trees << " expected " << mean << " se "
                            << se;
  // Same key, same tree; the string never depends on anything but (seed, tree id).
  EXPECT_EQ(derive(ls, {.derivations = n, .seed = 7, .tree_id = 3}).to_string(),
            derive(ls, {.derivations = n, .seed = 7, .tree_id = 3}).to_string());
}

TEST(LSystem, ModuleCap) {
  const auto ls = parse_lsystem("axiom: F\nF -> FF\n", "cap.lsys");
  EXPECT_EQ(derive(ls, {.derivations = 10, .max_modules = 1024}).size(), 1024u);
  try {
    derive(ls, {.derivations = 11, .max_modules = 1024});
    FAIL();
  } catch (const biota::core::InputError& e) {
    EXPECT_NE(
        std::string(e.what()).find("cap.lsys: derivation 11 of 11 exceeds the module cap of 1024"),
        std::string::npos)
        << e.what();
  }
}

TEST(LSystem, GrammarErrorsNameFileLineColumn) {
  auto expect = [](const std::string& text, const std::string& where, const std::string& what) {
    const auto e = error_of(text);
    EXPECT_EQ(e.rfind(where, 0), 0u) << e;
    EXPECT_NE(e.find(what), std::string::npos) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  };
  expect("axiom: A(1)\nA(l) : q > 1 -> A(l)\n", "g.lsys:2:8:", "unknown symbol 'q'");
  expect("axiom: F\nF -> F[+F\n", "g.lsys:2:7:", "unbalanced brackets");
  expect("axiom: F]\n", "g.lsys:1:9:", "unbalanced brackets");
  expect("axiom: F\nF -> (0.5) F\nF -> (0.4) FF\n", "g.lsys:2:1:", "sum to 1, they sum to 0.9");
  expect("axiom: F\nF -> F\nF -> FF\n", "g.lsys:2:1:", "expected a probability");
  expect("axiom: A(1)\nA(l) -> A(l, 2)\n", "g.lsys:2:9:", "parameter-count mismatch");
  expect("axiom: A(1, 2)\nA(l) -> A(l)\n", "g.lsys:1:8:", "parameter-count mismatch");
  expect("axiom: A(1)\nA(l) -> F(l +)\n", "g.lsys:2:14:", "expected a number");
  expect("axiom: F\nderivations: two\n", "g.lsys:2:14:", "unknown symbol 'two'");
  expect("axiom: F\nF -> F)\n", "g.lsys:2:7:", "expected a module symbol");
  expect("axiom F\n", "g.lsys:1:1:", "expected 'key: value'");
  expect("angle: 20\n", "g.lsys:1:1:", "expected an 'axiom:' line");
  expect("axiom: A\nA(x) : -> A\n", "g.lsys:2:7:", "expected a condition");
  expect("axiom: !F\n", "g.lsys:1:8:", "'!(w)'");
}

TEST(Turtle, FrameConventions) {
  auto end_of = [](const std::string& str) {
    auto ls = parse_lsystem("axiom: " + str + "\nangle: 90\n", "t");
    const auto g = interpret(ls, ls.axiom);
    return g.segments.back().end;
  };
  auto near = [](biota::core::Vec3 a, biota::core::Vec3 b) {
    return std::abs(a.x - b.x) < 1e-12 && std::abs(a.y - b.y) < 1e-12 &&
           std::abs(a.z - b.z) < 1e-12;
  };
  EXPECT_TRUE(near(end_of("F"), {0, 1, 0}));     // H = +y
  EXPECT_TRUE(near(end_of("F+F"), {-1, 1, 0}));  // + turns towards L = -x
  EXPECT_TRUE(near(end_of("F-F"), {1, 1, 0}));
  EXPECT_TRUE(near(end_of("F&F"), {0, 1, -1}));  // & pitches down, towards -U = -z
  EXPECT_TRUE(near(end_of("F^F"), {0, 1, 1}));
  // / rolls by -90 about H: U becomes L = -x, so & then pitches towards +x.
  EXPECT_TRUE(near(end_of("F/&F"), {1, 1, 0}));
  EXPECT_TRUE(near(end_of("F|F"), {0, 0, 0}));
  EXPECT_TRUE(near(end_of("F(2)+(45)-(45)F(0.5)"), {0, 2.5, 0}));
  EXPECT_TRUE(near(end_of("f(3)F"), {0, 4, 0}));
}

TEST(Turtle, TropismWidthOrderParent) {
  // Tropism T = +x, e = 0.2: after the first F, H x T = -z with |H x T| = 1, so H turns by 0.2 rad
  // about -z, towards +x: the second segment ends at (sin 0.2, 1 + cos 0.2, 0).
  auto ls = parse_lsystem("axiom: !(0.4)F[+F]F\ntropism: 1 0 0 0.2\nangle: 30\n", "t");
  const auto g = interpret(ls, ls.axiom);
  ASSERT_EQ(g.segments.size(), 3u);
  EXPECT_NEAR(g.segments[2].end.x, std::sin(0.2), 1e-12);
  EXPECT_NEAR(g.segments[2].end.y, 1 + std::cos(0.2), 1e-12);
  EXPECT_EQ(g.segments[0].radius, 0.2);
  EXPECT_EQ(g.segments[0].parent, -1);
  EXPECT_EQ(g.segments[1].parent, 0);
  EXPECT_EQ(g.segments[1].order, 1);
  EXPECT_EQ(g.segments[2].parent, 0);
  EXPECT_EQ(g.segments[2].order, 0);
  // $ levels L: after rolling by 90 and pitching, $ makes L horizontal again.
  auto lv = parse_lsystem("axiom: &(30)/(40)$F\n", "t");
  const auto h = interpret(lv, lv.axiom);
  EXPECT_NEAR(h.segments[0].end.y, std::cos(30 * std::numbers::pi / 180), 1e-12);
}
