#include "solvers/mac/boundary.hpp"

#include "core/error.hpp"

namespace biota::solvers::mac {

const std::vector<std::string>& boundary_type_names() {
  static const std::vector<std::string> names{
      "periodic", "inflow", "outflow", "convective_outflow", "noslip", "freeslip", "ground"};
  return names;
}

BoundaryType parse_boundary_type(const std::string& name, const std::string& key) {
  const auto& n = boundary_type_names();
  for (std::size_t i = 0; i < n.size(); ++i)
    if (n[i] == name) return static_cast<BoundaryType>(i);
  std::string list;
  for (const auto& s : n) list += (list.empty() ? "" : ", ") + s;
  throw core::InputError(key + " = \"" + name + "\": unknown boundary type (one of {" + list +
                         "})");
}

const std::string& to_string(BoundaryType t) {
  return boundary_type_names()[static_cast<int>(t)];
}

std::string face_name(int axis, int side) {
  return std::string(1, "xyz"[axis]) + (side ? "_hi" : "_lo");
}

void validate(const Boundaries& b, const std::string& prefix) {
  bool inflow = false, outflow = false;
  for (int a = 0; a < 3; ++a) {
    const bool p0 = b[a][0].type == BoundaryType::kPeriodic;
    const bool p1 = b[a][1].type == BoundaryType::kPeriodic;
    if (p0 != p1)
      throw core::InputError(prefix + face_name(a, p0 ? 1 : 0) + " must be \"periodic\" because " +
                             prefix + face_name(a, p0 ? 0 : 1) + " is");
    for (int s = 0; s < 2; ++s) {
      inflow |= b[a][s].type == BoundaryType::kInflow;
      outflow |= b[a][s].type == BoundaryType::kOutflow ||
                 b[a][s].type == BoundaryType::kConvectiveOutflow;
    }
  }
  if (inflow && !outflow)
    throw core::InputError(prefix + "*: an inflow face needs an outflow face (mass balance)");
}

}  // namespace biota::solvers::mac
