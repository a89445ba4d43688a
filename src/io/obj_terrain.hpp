#pragma once
/// \file obj_terrain.hpp
/// \brief Terrain mesh from a Wavefront OBJ with its MTL and texture images (tinyobjloader,
/// stb_image), each triangle classified into one class of a colour palette (the moss model's soil
/// types: humus, sand, asphalt) by the texture colour at the triangle's centroid.
///
/// A triangle's colour: the material's diffuse texture (map_Kd) sampled at the centroid's texture
/// coordinate (nearest texel, v up as in OBJ, coordinates wrapped into [0, 1)); a material without
/// a texture, or a triangle without texture coordinates, uses the material's Kd. The nearest
/// palette colour (Euclidean in RGB [0, 1]) within `tolerance` is the class; an unmatched colour is
/// an input error naming the file, the face and the colour.
///
/// +y is up (the moss paper's frame). A z-up file is read with up = "z" and turned by +90° about x
/// into the y-up frame: (x, y, z) -> (x, z, -y), so right-handedness and outward normals are kept.
#include <array>
#include <string>
#include <vector>

#include "core/types.hpp"

namespace biota::io {

/// \brief One palette entry: name and colour in RGB [0, 1].
struct PaletteColour {
  std::string name;
  std::array<double, 3> rgb;
};

/// \brief Triangles, vertices, and per-triangle class and material.
struct TerrainMesh {
  std::vector<core::Vec3> vertices;
  std::vector<std::array<int, 3>> triangles;
  std::vector<int> palette_index;  ///< per triangle, into the palette
  std::vector<int> material;       ///< per triangle, into material_names (-1: none)
  std::vector<std::string> material_names;
};

/// \brief Read and check a terrain. Throws core::InputError (one line naming the file) on a missing
/// or unparsable file, no faces, non-finite vertices, a degenerate triangle (area below 1e-12 of
/// the bounding box diagonal squared), an unreadable texture, or a colour outside the palette.
TerrainMesh read_obj_terrain(const std::string& path, const std::vector<PaletteColour>& palette,
                             double tolerance, const std::string& up = "y");

/// \brief Write a TerrainMesh as OBJ (positions and faces only; tests and tools).
void write_obj(const std::string& path, const TerrainMesh& mesh);

}  // namespace biota::io
