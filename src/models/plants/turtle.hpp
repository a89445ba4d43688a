#pragma once
/// \file turtle.hpp
/// \brief 3D turtle interpretation of a derived L-system string (ABOP 1.5 and 2.2) into branch
/// segments.
///
/// Conventions (docs/tree.md "Turtle"): the turtle starts at the origin with heading H = +y, left
/// L = -x and up U = +z (H x L = U). Every turn is a right-handed rotation about one frame axis by
/// the module's parameter in degrees, or the file's `angle:` without one:
///   `+` / `-`  about U by +a / -a (`+` turns H towards L: counter-clockwise seen from +z),
///   `&` / `^`  about L by +a / -a (`&` pitches H down, towards -U),
///   `\` / `/`  about H by +a / -a (roll), `|` about U by 180 degrees,
///   `$` rolls so that L is horizontal (L = V x H / |V x H|, V = +y).
/// `F(l)`, `G(l)` draw a segment of length l (the file's `step:` without a parameter), `f(l)`,
/// `g(l)` move without drawing, `!(w)` sets the width (radius = w / 2), `[` / `]` push / pop the
/// whole state. After each move the tropism of ABOP 2.2 turns H by e |H x T| about H x T.
/// A segment's branch order is the bracket depth at which it is drawn; its parent is the last
/// segment drawn before it in the same state (none at the start or after an `f` move).
#include <cstdint>
#include <vector>

#include "core/types.hpp"
#include "models/plants/lsystem.hpp"

namespace biota::models::plants {

/// \brief One drawn segment.
struct TurtleSegment {
  core::Vec3 start, end;
  double radius = 0;
  int order = 0;
  std::int64_t parent = -1;  ///< index of the parent segment, -1 for none
};

/// \brief Segments and their bounding box (of all segment end points; the origin if none).
struct TurtleGeometry {
  std::vector<TurtleSegment> segments;
  core::Vec3 lo, hi;
};

/// \brief Interpret `s` with the turtle settings (angle, step, width, tropism) of `ls`.
TurtleGeometry interpret(const LSystem& ls, const ModuleString& s);

}  // namespace biota::models::plants
