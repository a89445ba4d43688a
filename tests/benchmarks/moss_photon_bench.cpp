// Moss photon-map speed (issue 10 section 5): photon-surface interactions per second per core on
// the paper's scene, beside the raw Embree closest-hit rate on the same scene (the peer figure),
// and the photon map's redistribution + kd-tree build + query time per day.
//   mpiexec -n 2 build/tests/benchmarks/biota_bench_moss_photons input/moss/scene.obj 8192 10 16384
// arguments: scene, photons per day, days, mosses (1 cm boxes at random ground points).
#include <mpi.h>

#include <chrono>
#include <cstdio>
#include <string>

#include "core/rng.hpp"
#include "io/obj_terrain.hpp"
#include "models/moss/photon_map.hpp"

using namespace biota;
using models::moss::Vec3;

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const std::string scene = argc > 1 ? argv[1] : "input/moss/scene.obj";
  const long long photons = argc > 2 ? std::stoll(argv[2]) : 8192;
  const int days = argc > 3 ? std::stoi(argv[3]) : 10;
  const int mosses = argc > 4 ? std::stoi(argv[4]) : 16384;
  const std::vector<io::PaletteColour> pal{{"humus", {0x5c / 255.0, 0x33 / 255.0, 0x17 / 255.0}},
                                           {"sand", {0xcc / 255.0, 0x99 / 255.0, 0x33 / 255.0}},
                                           {"asphalt", {0.5, 0.5, 0.5}}};
  const auto mesh = io::read_obj_terrain(scene, pal, 0.1);
  models::moss::PhotonTracer tr(mesh.vertices, mesh.triangles,
                                std::vector<double>(mesh.triangles.size(), 0.2));
  const auto sphere = tr.bounding_sphere();
  // Mosses: random ground points found by rays cast down (the same on every rank).
  std::vector<Vec3> moss;
  for (int m = 0; m < mosses; ++m) {
    core::Rng rng(1, static_cast<std::uint64_t>(m), 0, core::RngPurpose::kPlacement);
    const Vec3 o{rng.uniform(0, 2), 1.4, rng.uniform(0.7, 2)};
    if (auto h = tr.cast(o, {0, -1, 0})) moss.push_back(h->x + Vec3{0, 0.005, 0});
  }
  tr.set_mosses(moss, 0.01, 0.2);
  std::vector<Vec3> q;
  for (const auto& t : mesh.triangles)
    q.push_back((mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]) / 3.0);
  models::moss::PhotonMapSettings st;
  st.photons = photons;
  models::moss::PhotonMap map(MPI_COMM_WORLD, {0, 0, 0}, {2, 1.5, 2}, st.radius);
  const auto light = models::moss::sun_light({0, 1, 0}, sphere, st.distance_factor);
  double trace = 0, mapt = 0, wall = 0;
  long long stored = 0;
  for (int d = 0; d < days; ++d) {
    models::moss::PhotonMapStats s;
    MPI_Barrier(MPI_COMM_WORLD);
    const double t0 = MPI_Wtime();
    map.insolation(tr, light, sphere, 1, static_cast<std::uint64_t>(d), st, q, &s);
    wall += MPI_Wtime() - t0;
    trace += s.trace_seconds;
    mapt += s.map_seconds;
    stored += s.stored;
  }
  double trace_max = 0, map_max = 0;
  MPI_Reduce(&trace, &trace_max, 1, MPI_DOUBLE, MPI_MAX, 0, MPI_COMM_WORLD);
  MPI_Reduce(&mapt, &map_max, 1, MPI_DOUBLE, MPI_MAX, 0, MPI_COMM_WORLD);
  // Peer: raw closest-hit rays from random points above the scene towards random ground points.
  const int nray = 200000;
  const double r0 = MPI_Wtime();
  long long hit = 0;
  for (int i = 0; i < nray; ++i) {
    core::Rng rng(2, static_cast<std::uint64_t>(i), 0, core::RngPurpose::kTest);
    const Vec3 o{rng.uniform(0, 2), 3.0, rng.uniform(0, 2)};
    const Vec3 to{rng.uniform(0, 2), 0.3, rng.uniform(0, 2)};
    hit += tr.cast(o, to - o).has_value();
  }
  const double raw = nray / (MPI_Wtime() - r0);
  if (rank == 0) {
    std::printf("scene %s: %zu triangles, %zu mosses, %lld photons/day, %d days, %d ranks\n",
                scene.c_str(), mesh.triangles.size(), moss.size(), photons, days, size);
    std::printf(
        "photon-surface interactions per second per core: %.3g (peer: raw Embree "
        "closest-hit rays/s on this scene, rank 0: %.3g; %lld of %d hit)\n",
        double(stored) / size / trace_max, raw, hit, nray);
    std::printf(
        "per day: trace %.4f s, photon map (redistribute + ghosts + kd-tree + %zu queries)"
        " %.4f s, wall %.4f s (slowest rank)\n",
        trace_max / days, q.size(), map_max / days, wall / days);
  }
  MPI_Finalize();
  return 0;
}
