// Soil depth h on the shipped scene (erratum 16): ground top = its height above the bottom face,
// roof top = the 5 cm slab, walls and the roof's underside 1 mm.
#include <gtest/gtest.h>

#include "io/obj_terrain.hpp"
#include "models/moss/soil_depth.hpp"

using namespace biota;

TEST(MossSoilDepth, PaperScene) {
  const std::vector<io::PaletteColour> pal{{"humus", {0x5c / 255.0, 0x33 / 255.0, 0x17 / 255.0}},
                                           {"sand", {0xcc / 255.0, 0x99 / 255.0, 0x33 / 255.0}},
                                           {"asphalt", {0.5, 0.5, 0.5}}};
  const auto m = io::read_obj_terrain(BIOTA_SOURCE_DIR "/input/moss/scene.obj", pal, 0.1);
  models::moss::PhotonTracer tr(m.vertices, m.triangles,
                                std::vector<double>(m.triangles.size(), 0));
  const auto h = models::moss::soil_depth_mm(tr, m.vertices, m.triangles);
  int ground = 0, roof = 0, thin = 0;
  for (std::size_t f = 0; f < m.triangles.size(); ++f) {
    const auto& t = m.triangles[f];
    const auto a = m.vertices[t[0]], b = m.vertices[t[1]], c = m.vertices[t[2]];
    const auto n = core::cross(b - a, c - a);
    const double cy = (a.y + b.y + c.y) / 3;
    const double cz = (a.z + b.z + c.z) / 3;
    if (m.material_names[m.material[f]] == "ground" && cz > 0.1) {
      EXPECT_NEAR(h[f], 1000 * cy, 1.0) << "face " << f;  // float rays: about 0.01 mm
      ++ground;
    } else if (n.y > 0 && std::abs(cy - 1.5) < 1e-9) {
      EXPECT_NEAR(h[f], 50.0, 0.01);
      ++roof;
    } else if (n.y <= 0) {
      EXPECT_EQ(h[f], 1.0);
      ++thin;
    }
  }
  EXPECT_GT(ground, 3000);
  EXPECT_EQ(roof, 4);  // roof top and the back wall's top, which lies in the roof's plane
  EXPECT_GT(thin, 100);
}
