// Photon tracing and insolation calibration (spec moss.md 2.5, erratum 2; issue 10 section 2):
// an open plane receives S_open, a plane half under a roof is dark under it without indirect light
// and lit by interreflection with it, a closed diffuse box stores 1/(1 - rho) photons per emitted
// photon, and the distributed counts equal a brute-force count of all hits (so S does not depend
// on the rank count, to the last bit).
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <cstdio>
#include <numeric>

#include "models/moss/photon_map.hpp"

using namespace biota::models::moss;
using biota::core::Vec3;

namespace {

struct Mesh {
  std::vector<Vec3> v;
  std::vector<std::array<int, 3>> t;
  void quad(Vec3 a, Vec3 b, Vec3 c, Vec3 d) {  // counter-clockwise seen from the front
    const int i = static_cast<int>(v.size());
    v.insert(v.end(), {a, b, c, d});
    t.push_back({i, i + 1, i + 2});
    t.push_back({i, i + 2, i + 3});
  }
};

Mesh floor_plane() {
  Mesh m;
  m.quad({-1, 0, -1}, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1});  // normal +y
  return m;
}

std::vector<Vec3> grid_points(double x0, double x1, int nx, double z0, double z1, int nz) {
  std::vector<Vec3> q;
  for (int i = 0; i < nx; ++i)
    for (int k = 0; k < nz; ++k)
      q.push_back({x0 + (x1 - x0) * i / std::max(1, nx - 1), 0.0,
                   z0 + (z1 - z0) * k / std::max(1, nz - 1)});
  return q;
}

bool rank0() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r == 0;
}

double mean(const std::vector<double>& a) {
  return std::accumulate(a.begin(), a.end(), 0.0) / static_cast<double>(a.size());
}

// Brute-force count of every hit of all photons (traced serially on this rank) within r.
std::vector<long long> brute_counts(const PhotonTracer& tr, const SquareLight& l,
                                    const BoundingSphere& s, const PhotonMapSettings& st,
                                    std::uint64_t seed, std::uint64_t day,
                                    const std::vector<Vec3>& q) {
  std::vector<PhotonHit> hits;
  tr.trace(l, s, seed, day, 0, static_cast<std::uint64_t>(st.photons), st.indirect, st.max_bounces,
           hits);
  std::vector<long long> c(q.size(), 0);
  for (std::size_t i = 0; i < q.size(); ++i)
    for (const auto& h : hits) {
      const Vec3 d = h.x - q[i];
      if (biota::core::dot(d, d) < st.radius * st.radius) ++c[i];
    }
  return c;
}

}  // namespace

TEST(PhotonMap, OpenPlaneReceivesOpenInsolation) {
  const Mesh m = floor_plane();
  PhotonTracer tr(m.v, m.t, std::vector<double>(m.t.size(), 0.5));
  const auto sphere = tr.bounding_sphere();
  PhotonMapSettings st;
  st.photons = 40000;
  st.radius = 0.1;
  st.open_insolation = 120;
  st.reference = Vec3{0, 0, 0};
  st.distance_factor = 10;
  const auto light = sun_light(sun_direction_from_angles(90, 0), sphere, st.distance_factor);
  PhotonMap map(MPI_COMM_WORLD, {-1, -0.1, -1}, {1, 0.1, 1}, st.radius);
  const auto q = grid_points(-0.6, 0.6, 7, -0.6, 0.6, 7);  // disjoint disks, 2 r apart
  PhotonMapStats stats;
  const auto s = map.insolation(tr, light, sphere, 7, 3, st, q, &stats);
  EXPECT_EQ(stats.photons, st.photons);
  if (rank0())
    std::printf("open plane: mean S %.2f W/m2 (S_open 120) over %zu disks\n", mean(s), s.size());
  EXPECT_NEAR(mean(s), 120.0, 0.04 * 120);              // about 4 standard errors of the mean
  for (double v : s) EXPECT_NEAR(v, 120.0, 0.3 * 120);  // 4 standard errors of one count
  // Same counts as a brute-force search over every hit: independent of the decomposition.
  EXPECT_EQ(map.counts(), brute_counts(tr, light, sphere, st, 7, 3, q));
}

TEST(PhotonMap, HalfRoofShadeAndIndirectLight) {
  Mesh m = floor_plane();
  m.quad({-1, 0.5, -1}, {0, 0.5, -1}, {0, 0.5, 1}, {-1, 0.5, 1});  // roof over x < 0, normal -y
  const auto q_shade = grid_points(-0.8, -0.4, 3, -0.6, 0.6, 5);
  const auto q_open = grid_points(0.4, 0.8, 3, -0.6, 0.6, 5);
  std::vector<Vec3> q = q_shade;
  q.insert(q.end(), q_open.begin(), q_open.end());
  const std::size_t ns = q_shade.size();
  PhotonMapSettings st;
  st.photons = 40000;
  st.reference = Vec3{0, 0, 0};  // S_open on the floor
  st.open_insolation = 100;
  st.distance_factor = 10;
  PhotonMap map(MPI_COMM_WORLD, {-1, -0.1, -1}, {1, 0.6, 1}, st.radius);
  auto run = [&](double rho, bool indirect) {
    PhotonTracer tr(m.v, m.t, std::vector<double>(m.t.size(), rho));
    const auto sphere = tr.bounding_sphere();
    st.indirect = indirect;
    const auto light = sun_light(sun_direction_from_angles(90, 0), sphere, st.distance_factor);
    auto s = map.insolation(tr, light, sphere, 11, 1, st, q);
    if (rho > 0 && indirect) {
      EXPECT_EQ(map.counts(), brute_counts(tr, light, sphere, st, 11, 1, q));
    }
    return std::pair{std::vector<double>(s.begin(), s.begin() + ns),
                     std::vector<double>(s.begin() + ns, s.end())};
  };
  const auto [shade_black, open_black] = run(0.0, true);
  for (double v : shade_black) EXPECT_EQ(v, 0.0);
  EXPECT_NEAR(mean(open_black), 100.0, 5.0);  // 30 disks of ~200 photons: 1.6 % noise
  const auto [shade_direct, open_direct] = run(0.6, false);  // experiment 1: indirect off
  for (double v : shade_direct) EXPECT_EQ(v, 0.0);
  const auto [shade_lit, open_lit] = run(0.6, true);
  if (rank0())
    std::printf(
        "half roof: S under the roof %.2f (rho 0) %.2f (rho 0.6, direct only) %.2f (rho 0.6, "
        "indirect); open %.2f %.2f %.2f W/m2\n",
        mean(shade_black), mean(shade_direct), mean(shade_lit), mean(open_black), mean(open_direct),
        mean(open_lit));
  EXPECT_GT(mean(shade_lit), 1.0);  // interreflection under the roof (2.25: ~90 photons, 5 sd)
  EXPECT_LT(mean(shade_lit), 0.5 * mean(open_lit));
}

TEST(PhotonMap, ClosedBoxStoresOneOverOneMinusRho) {
  // Unit box (inward faces; orientation does not matter for diffuse hits), light inside.
  Mesh m;
  const Vec3 c[8] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                     {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  m.quad(c[0], c[1], c[2], c[3]);
  m.quad(c[4], c[7], c[6], c[5]);
  m.quad(c[0], c[4], c[5], c[1]);
  m.quad(c[3], c[2], c[6], c[7]);
  m.quad(c[0], c[3], c[7], c[4]);
  m.quad(c[1], c[5], c[6], c[2]);
  for (double rho : {0.5, 0.8}) {
    PhotonTracer tr(m.v, m.t, std::vector<double>(m.t.size(), rho));
    const auto sphere = tr.bounding_sphere();
    SquareLight light{{0.5, 0.5, 0.5}, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}, 0.05};
    PhotonMapSettings st;
    st.photons = 30000;
    st.max_bounces = 1000;
    PhotonMap map(MPI_COMM_WORLD, {0, 0, 0}, {1, 1, 1}, st.radius);
    PhotonMapStats stats;
    map.insolation(tr, light, sphere, 5, 0, st, {{0.5, 0.0, 0.5}}, &stats);
    EXPECT_EQ(stats.draws, stats.photons);  // the light is inside the sphere: no culling
    const double per_photon = double(stats.stored) / double(stats.photons);
    const double sd = std::sqrt(rho / ((1 - rho) * (1 - rho)) / double(stats.photons));
    if (rank0())
      std::printf("closed box rho %.1f: %.4f stored per photon (1/(1-rho) = %.4f, sd %.4f)\n", rho,
                  per_photon, 1 / (1 - rho), sd);
    EXPECT_NEAR(per_photon, 1 / (1 - rho), 5 * sd) << "rho " << rho;
  }
}
