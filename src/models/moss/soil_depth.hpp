#pragma once
/// \file soil_depth.hpp
/// \brief Soil depth h per terrain triangle (spec moss.md 3.5.3, erratum 16): the vertical extent
/// of the solid below the triangle's centroid, found by a ray cast along -y to the next face,
/// in mm, capped at 1000; 1 mm for faces with no thickness in y (|n_y| < 0.1: walls) and for faces
/// that look down (n_y < 0: the underside of the roof).
#include <array>
#include <vector>

#include "models/moss/photon_tracer.hpp"

namespace biota::models::moss {

/// \brief h in mm for every triangle; call before mosses are added to the tracer's scene.
std::vector<double> soil_depth_mm(const PhotonTracer& tracer, const std::vector<Vec3>& vertices,
                                  const std::vector<std::array<int, 3>>& triangles);

}  // namespace biota::models::moss
