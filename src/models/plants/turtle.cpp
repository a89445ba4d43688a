#include "models/plants/turtle.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace biota::models::plants {

using core::Vec3;

namespace {

struct TurtleState {
  Vec3 pos, h{0, 1, 0}, l{-1, 0, 0}, u{0, 0, 1};
  double width = 1;
  int order = 0;
  std::int64_t parent = -1;
};

// Right-handed rotation of the pair (a, b) about the third axis c = a x b by angle t:
// a' = a cos t + b sin t, b' = b cos t - a sin t.
void rotate_pair(Vec3& a, Vec3& b, double t) {
  const double c = std::cos(t), s = std::sin(t);
  const Vec3 a2 = a * c + b * s, b2 = b * c - a * s;
  a = a2, b = b2;
}

Vec3 rotate_about(const Vec3& v, const Vec3& axis, double t) {  // Rodrigues, unit axis
  const double c = std::cos(t), s = std::sin(t);
  return v * c + cross(axis, v) * s + axis * (dot(axis, v) * (1 - c));
}

}  // namespace

TurtleGeometry interpret(const LSystem& ls, const ModuleString& s) {
  constexpr double deg = std::numbers::pi / 180;
  TurtleGeometry g;
  TurtleState t;
  t.width = ls.initial_width;
  std::vector<TurtleState> stack;
  const Vec3 tropism{ls.tropism[0], ls.tropism[1], ls.tropism[2]};
  const Vec3 up{0, 1, 0};
  bool any = false;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const char c = s.sym[i];
    const bool has = s.nparam[i] > 0;
    const double a = (has ? s.param(i)[0] : ls.angle_deg) * deg;
    switch (c) {
      case 'F':
      case 'G':
      case 'f':
      case 'g': {
        const double len = has ? s.param(i)[0] : ls.step;
        const Vec3 start = t.pos;
        t.pos = t.pos + t.h * len;
        if (c == 'F' || c == 'G') {
          g.segments.push_back({start, t.pos, 0.5 * t.width, t.order, t.parent});
          t.parent = static_cast<std::int64_t>(g.segments.size()) - 1;
          for (const Vec3& p : {start, t.pos}) {
            if (!any) g.lo = g.hi = p, any = true;
            for (int d = 0; d < 3; ++d)
              g.lo[d] = std::min(g.lo[d], p[d]), g.hi[d] = std::max(g.hi[d], p[d]);
          }
        } else {
          t.parent = -1;
        }
        if (ls.elasticity != 0) {
          const Vec3 ax = cross(t.h, tropism);
          const double n = norm(ax);
          if (n > 0) {
            const Vec3 axis = ax / n;
            const double alpha = ls.elasticity * n;
            t.h = rotate_about(t.h, axis, alpha);
            t.l = rotate_about(t.l, axis, alpha);
            t.u = rotate_about(t.u, axis, alpha);
          }
        }
        break;
      }
      case '+':
        rotate_pair(t.h, t.l, a);
        break;
      case '-':
        rotate_pair(t.h, t.l, -a);
        break;
      case '&':
        rotate_pair(t.h, t.u, -a);
        break;  // about L: H' = H cos - U sin (down)
      case '^':
        rotate_pair(t.h, t.u, a);
        break;
      case '\\':
        rotate_pair(t.l, t.u, a);
        break;  // about H
      case '/':
        rotate_pair(t.l, t.u, -a);
        break;
      case '|':
        rotate_pair(t.h, t.l, std::numbers::pi);
        break;
      case '$': {
        const Vec3 lv = cross(up, t.h);
        const double n = norm(lv);
        if (n > 1e-12) {
          t.l = lv / n;
          t.u = cross(t.h, t.l);
        }
        break;
      }
      case '!':
        t.width = s.param(i)[0];
        break;
      case '[':
        stack.push_back(t);
        ++t.order;
        break;
      case ']':
        if (!stack.empty()) t = stack.back(), stack.pop_back();
        break;
      default:
        break;
    }
  }
  return g;
}

}  // namespace biota::models::plants
