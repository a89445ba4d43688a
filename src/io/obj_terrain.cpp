#include "io/obj_terrain.hpp"

#include <fmt/format.h>
#include <stb_image.h>
#include <tiny_obj_loader.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>

#include "core/error.hpp"

namespace biota::io {

namespace {

using core::InputError;
using core::Vec3;

struct Image {
  int w = 0, h = 0, channels = 0;
  std::unique_ptr<unsigned char, void (*)(void*)> data{nullptr, stbi_image_free};
  std::array<double, 3> texel(double u, double v) const {
    u -= std::floor(u);
    v -= std::floor(v);
    const int i = std::min(w - 1, static_cast<int>(u * w));
    const int j = std::min(h - 1, static_cast<int>((1.0 - v) * h));  // OBJ v is up, rows go down
    const unsigned char* p = data.get() + (static_cast<std::size_t>(j) * w + i) * channels;
    if (channels < 3) return {p[0] / 255.0, p[0] / 255.0, p[0] / 255.0};
    return {p[0] / 255.0, p[1] / 255.0, p[2] / 255.0};
  }
};

std::string colour_text(const std::array<double, 3>& c) {
  return fmt::format("#{:02x}{:02x}{:02x}", static_cast<int>(std::lround(c[0] * 255)),
                     static_cast<int>(std::lround(c[1] * 255)),
                     static_cast<int>(std::lround(c[2] * 255)));
}

// tinyobjloader reads "nan" and "inf" as 0 without a word, so the vertex lines are checked first.
void check_vertex_lines(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  for (long lineno = 1; std::getline(in, line); ++lineno) {
    if (line.size() < 2 || line[0] != 'v' || (line[1] != ' ' && line[1] != '\t')) continue;
    const char* p = line.c_str() + 2;
    for (int k = 0; k < 3; ++k) {
      char* end = nullptr;
      const double x = std::strtod(p, &end);
      if (end == p || !std::isfinite(x))
        throw InputError(fmt::format("{}: line {}: vertex coordinate is not a finite number: '{}'",
                                     path, lineno, line));
      p = end;
    }
  }
}

}  // namespace

TerrainMesh read_obj_terrain(const std::string& path, const std::vector<PaletteColour>& palette,
                             double tolerance, const std::string& up) {
  namespace fs = std::filesystem;
  if (!fs::is_regular_file(path)) throw InputError(fmt::format("{}: terrain file not found", path));
  if (up != "y" && up != "z")
    throw InputError(fmt::format("{}: up axis '{}' (allowed: y, z)", path, up));
  check_vertex_lines(path);
  tinyobj::ObjReaderConfig cfg;
  cfg.triangulate = true;
  cfg.mtl_search_path = fs::path(path).parent_path().string();
  tinyobj::ObjReader reader;
  if (!reader.ParseFromFile(path, cfg)) {
    std::string e = reader.Error();
    while (!e.empty() && (e.back() == '\n' || e.back() == '\r')) e.pop_back();
    for (auto& ch : e)
      if (ch == '\n') ch = ' ';
    throw InputError(fmt::format("{}: cannot parse OBJ: {}", path, e));
  }
  const auto& attrib = reader.GetAttrib();
  const auto& materials = reader.GetMaterials();

  TerrainMesh mesh;
  const std::size_t nv = attrib.vertices.size() / 3;
  mesh.vertices.resize(nv);
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (std::size_t i = 0; i < nv; ++i) {
    const double x = attrib.vertices[3 * i], y = attrib.vertices[3 * i + 1],
                 z = attrib.vertices[3 * i + 2];
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
      throw InputError(
          fmt::format("{}: vertex {} is not a finite number ({} {} {})", path, i + 1, x, y, z));
    mesh.vertices[i] = up == "y" ? Vec3{x, y, z} : Vec3{x, z, -y};
    for (int d = 0; d < 3; ++d) {
      lo[d] = std::min(lo[d], mesh.vertices[i][d]);
      hi[d] = std::max(hi[d], mesh.vertices[i][d]);
    }
  }

  // Textures, loaded once per material.
  std::vector<Image> tex(materials.size());
  for (std::size_t m = 0; m < materials.size(); ++m) {
    mesh.material_names.push_back(materials[m].name);
    if (materials[m].diffuse_texname.empty()) continue;
    const std::string file =
        (fs::path(cfg.mtl_search_path) / materials[m].diffuse_texname).string();
    Image& im = tex[m];
    im.data.reset(stbi_load(file.c_str(), &im.w, &im.h, &im.channels, 0));
    if (!im.data)
      throw InputError(fmt::format("{}: texture '{}' of material '{}' cannot be read ({})", path,
                                   file, materials[m].name, stbi_failure_reason()));
  }

  const double diag2 = core::dot(hi - lo, hi - lo);
  const long long nt = static_cast<long long>(attrib.texcoords.size() / 2);
  for (const auto& shape : reader.GetShapes()) {
    const auto& idx = shape.mesh.indices;
    for (std::size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f) {
      const std::size_t face = mesh.triangles.size() + 1;
      // tinyobjloader passes indices past the lists through unchecked: a face naming vertex 999
      // of 50 would read past the arrays.
      std::array<int, 3> t{};
      double u = 0, v = 0;
      bool have_uv = true;
      for (int k = 0; k < 3; ++k) {
        const auto& ix = idx[3 * f + k];
        if (ix.vertex_index < 0)
          throw InputError(
              fmt::format("{}: face {} (shape '{}') has a relative vertex index "
                          "before the first vertex; allowed: -1 to -(vertices so far)",
                          path, face, shape.name));
        if (static_cast<std::size_t>(ix.vertex_index) >= nv)
          throw InputError(fmt::format(
              "{}: face {} (shape '{}') names vertex {}; allowed: 1 to {} (the file's vertices)",
              path, face, shape.name, static_cast<long long>(ix.vertex_index) + 1, nv));
        if (ix.texcoord_index >= nt)
          throw InputError(fmt::format(
              "{}: face {} (shape '{}') names texture coordinate {}; "
              "allowed: 1 to {} (the file's vt lines)",
              path, face, shape.name, static_cast<long long>(ix.texcoord_index) + 1, nt));
        t[k] = ix.vertex_index;
        if (ix.texcoord_index < 0) {
          have_uv = false;
        } else {
          u += attrib.texcoords[2 * ix.texcoord_index] / 3.0;
          v += attrib.texcoords[2 * ix.texcoord_index + 1] / 3.0;
        }
      }
      const Vec3 a = mesh.vertices[t[0]], b = mesh.vertices[t[1]], c = mesh.vertices[t[2]];
      const double area2 = core::norm(core::cross(b - a, c - a));
      if (!(area2 > 2e-12 * diag2))
        throw InputError(fmt::format("{}: face {} (shape '{}') is degenerate (area {:.3g} m^2)",
                                     path, face, shape.name, area2 / 2));
      const int m = shape.mesh.material_ids[f];
      std::array<double, 3> colour{1, 1, 1};
      if (m >= 0) {
        colour = {materials[m].diffuse[0], materials[m].diffuse[1], materials[m].diffuse[2]};
        if (tex[m].data && have_uv) colour = tex[m].texel(u, v);
      }
      int best = -1;
      double best_d = std::numeric_limits<double>::infinity();
      for (std::size_t p = 0; p < palette.size(); ++p) {
        double d2 = 0;
        for (int k = 0; k < 3; ++k)
          d2 += (colour[k] - palette[p].rgb[k]) * (colour[k] - palette[p].rgb[k]);
        if (d2 < best_d) best_d = d2, best = static_cast<int>(p);
      }
      if (best < 0 || std::sqrt(best_d) > tolerance) {
        std::string allowed;
        for (const auto& p : palette)
          allowed +=
              fmt::format("{}{} {}", allowed.empty() ? "" : ", ", p.name, colour_text(p.rgb));
        throw InputError(fmt::format(
            "{}: face {} has colour {} (material '{}'), not within {} of any soil colour ({})",
            path, face, colour_text(colour), m >= 0 ? materials[m].name : "none", tolerance,
            allowed));
      }
      mesh.triangles.push_back(t);
      mesh.palette_index.push_back(best);
      mesh.material.push_back(m);
    }
  }
  if (mesh.triangles.empty()) throw InputError(fmt::format("{}: no faces", path));
  return mesh;
}

void write_obj(const std::string& path, const TerrainMesh& mesh) {
  std::ofstream out(path);
  out.precision(17);
  for (const auto& v : mesh.vertices) out << "v " << v.x << ' ' << v.y << ' ' << v.z << '\n';
  for (const auto& t : mesh.triangles)
    out << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
}

}  // namespace biota::io
