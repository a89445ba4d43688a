// Terrain OBJ/MTL/PNG reader: the shipped paper scene, the z-up frame, and one clear input error
// per kind of bad mesh (spec issue 10, section 1).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.hpp"
#include "io/obj_terrain.hpp"

using biota::core::InputError;
using biota::io::PaletteColour;
using biota::io::read_obj_terrain;

namespace {
namespace fs = std::filesystem;

const std::vector<PaletteColour> kPalette{{"humus", {0x5c / 255.0, 0x33 / 255.0, 0x17 / 255.0}},
                                          {"sand", {0xcc / 255.0, 0x99 / 255.0, 0x33 / 255.0}},
                                          {"asphalt", {0x80 / 255.0, 0x80 / 255.0, 0x80 / 255.0}}};

fs::path scratch() {
  const fs::path d = fs::temp_directory_path() / ("biota_obj_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

std::string write(const std::string& name, const std::string& text) {
  const fs::path p = scratch() / name;
  std::ofstream(p) << text;
  return p.string();
}

// Expect an InputError whose message names the file and contains `what`.
void expect_error(const std::string& path, const std::string& what) {
  try {
    read_obj_terrain(path, kPalette, 0.1);
    FAIL() << "no error for " << path;
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(path), std::string::npos) << m;
    EXPECT_NE(m.find(what), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << "one line: " << m;
  }
}

const char* kTri = "v 0 0 0\nv 1 0 0\nv 0 0 1\n";
}  // namespace

TEST(ObjTerrain, PaperScene) {
  const auto m = read_obj_terrain(BIOTA_SOURCE_DIR "/input/moss/scene.obj", kPalette, 0.1);
  ASSERT_EQ(m.triangles.size(), 3546u);
  int count[3] = {0, 0, 0};
  double top_area[3] = {0, 0, 0};
  for (std::size_t f = 0; f < m.triangles.size(); ++f) {
    ++count[m.palette_index[f]];
    const auto& t = m.triangles[f];
    const auto n = biota::core::cross(m.vertices[t[1]] - m.vertices[t[0]],
                                      m.vertices[t[2]] - m.vertices[t[0]]);
    if (m.material_names[m.material[f]] == "ground" && n.y > 0)
      top_area[m.palette_index[f]] += 0.5 * n.y;  // horizontal projection
  }
  EXPECT_GT(count[0], 0);
  EXPECT_GT(count[1], 0);
  EXPECT_GT(count[2], 0);
  // Texture bands: humus x < 1.2, sand [1.2, 1.55) and [1.8, 2), asphalt [1.55, 1.8) (5 cm cells).
  EXPECT_NEAR(top_area[0], 2 * 1.2, 1e-9);
  EXPECT_NEAR(top_area[1], 2 * 0.55, 1e-9);
  EXPECT_NEAR(top_area[2], 2 * 0.25, 1e-9);
}

TEST(ObjTerrain, ZUpIsTurnedIntoYUp) {
  const auto mtl = write("zup.mtl", "newmtl a\nKd 0.5 0.5 0.5\n");
  const auto obj =
      write("zup.obj", "mtllib zup.mtl\nusemtl a\nv 0 0 0\nv 1 0 0\nv 0 1 0.5\nf 1 2 3\n");
  const auto m = read_obj_terrain(obj, kPalette, 0.1, "z");
  EXPECT_EQ(m.vertices[2].x, 0.0);
  EXPECT_EQ(m.vertices[2].y, 0.5);   // z -> y
  EXPECT_EQ(m.vertices[2].z, -1.0);  // y -> -z
  EXPECT_EQ(m.palette_index[0], 2);  // asphalt grey
  (void)mtl;
}

TEST(ObjTerrain, BadMeshes) {
  expect_error((scratch() / "missing.obj").string(), "not found");
  expect_error(write("empty.obj", "# nothing\nv 0 0 0\n"), "no faces");
  expect_error(write("nan.obj", std::string("v nan 0 0\nv 1 0 0\nv 0 0 1\nf 1 2 3\n")),
               "not a finite number");
  expect_error(write("degenerate.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n"), "degenerate");
  // Indices past the lists (tinyobjloader passes them through; reading them crashed the run).
  expect_error(write("far.obj", std::string(kTri) + "f 1 2 999\n"),
               "face 1 (shape '') names vertex 999; allowed: 1 to 3");
  expect_error(write("before.obj", std::string(kTri) + "f 1 2 -9\n"),
               "relative vertex index before the first vertex");
  expect_error(write("farvt.obj", std::string(kTri) + "vt 0 0\nf 1/1 2/1 3/7\n"),
               "names texture coordinate 7; allowed: 1 to 1");
  write("badtex.mtl", "newmtl t\nKd 1 1 1\nmap_Kd nothere.png\n");
  expect_error(write("badtex.obj", std::string("mtllib badtex.mtl\nusemtl t\n") + kTri +
                                       "vt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n"),
               "cannot be read");
  write("garbage.png", "not a png");
  write("garbagetex.mtl", "newmtl t\nKd 1 1 1\nmap_Kd garbage.png\n");
  expect_error(write("garbagetex.obj", std::string("mtllib garbagetex.mtl\nusemtl t\n") + kTri +
                                           "vt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n"),
               "cannot be read");
  write("green.mtl", "newmtl g\nKd 0 1 0\n");
  expect_error(write("green.obj", std::string("mtllib green.mtl\nusemtl g\n") + kTri + "f 1 2 3\n"),
               "#00ff00");
}
