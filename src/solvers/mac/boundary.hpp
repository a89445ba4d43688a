#pragma once
/// \file boundary.hpp
/// \brief Boundary conditions of the wind box, one per face.
#include <array>
#include <string>
#include <vector>

#include "core/types.hpp"

namespace biota::solvers::mac {

/// \brief Kind of a box face.
enum class BoundaryType {
  kPeriodic,           ///< paired with the opposite face
  kInflow,             ///< prescribed normal velocity (uniform or log profile), p: Neumann
  kOutflow,            ///< zero normal gradient of velocity, p = 0 on the face
  kConvectiveOutflow,  ///< du/dt + U_c du/dn = 0 (U_c = mean outflow speed), p = 0 on the face
  kNoSlip,             ///< wall, velocity = wall velocity (tangential; moving lid), p: Neumann
  kFreeSlip,           ///< wall, zero normal velocity and zero tangential stress
  kGround,             ///< wall with the rough-wall log-law stress (roughness length z0)
};

/// \brief Names accepted in decks, in the order of BoundaryType.
const std::vector<std::string>& boundary_type_names();
/// \brief Parse a name; throws core::InputError naming `key` and the allowed names.
BoundaryType parse_boundary_type(const std::string& name, const std::string& key);
const std::string& to_string(BoundaryType t);
/// \brief Face names x_lo, x_hi, y_lo, ... for [axis][side] (as in the LBM decks).
std::string face_name(int axis, int side);

/// \brief One face: its type and (no-slip) wall velocity.
struct FaceBoundary {
  BoundaryType type = BoundaryType::kNoSlip;
  core::Vec3 wall_velocity{};
};
using Boundaries = std::array<std::array<FaceBoundary, 2>, 3>;

/// \brief Inflow profile.
struct InflowProfile {
  enum Kind { kUniform, kLog } kind = kUniform;
  core::Real speed = 0;                ///< m/s (uniform speed or speed at reference_height)
  core::Real reference_height = 10;    ///< m above the low face of the vertical axis
  core::Real roughness_length = 0.03;  ///< m (open, flat terrain)
};

/// \brief Check the combination (periodic faces paired, inflow needs an outflow, ...); throws
/// core::InputError with `prefix` + face name in the message.
void validate(const Boundaries& b, const std::string& prefix);

}  // namespace biota::solvers::mac
