// Deck keys of the flock scenario (schema: type, default, range, unit, doc per key) and the
// checks between them.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "scenarios/flock_scenario.hpp"

namespace biota::scenarios {

void FlockScenario::check_scales(const core::Config& c, const grid::Decomposition& decomp,
                                 double dx) {
  const double radius = c.get_real("flock.boids.perception_radius"), dt = c.get_real("flock.dt");
  // The ghost layer is one radius deep.
  if (const auto t = particles::thinnest_split_block(decomp, dx); radius > t.width)
    c.fail("flock.boids.perception_radius",
           fmt::format("m is wider than the thinnest rank block ({} m along axis {} with {} ranks "
                       "along it); allowed: at most {} m, or fewer ranks",
                       t.width, t.axis, decomp.dims()[t.axis], t.width));
  // OrderedCellList bins a rank's points and ghosts in cubes of edge radius / reach, at most
  // 2^26 of them.
  const int reach = static_cast<int>(c.get_int("flock.domain.bin_reach"));
  const double widest[3] = {decomp.widest(0) * dx, decomp.widest(1) * dx, decomp.widest(2) * dx};
  const auto bins = [&](double r) {
    double n = 1;
    for (double w : widest) n *= std::floor((w + 2 * r) * reach / r) + 2;
    return n;
  };
  constexpr double kMaxBins = 67108864;  // 2^26
  if (bins(radius) > kMaxBins) {
    double lo = radius, hi = radius;  // the least radius within the cap, to 1%
    while (bins(hi) > kMaxBins) hi *= 2;
    while (hi > 1.01 * lo) (bins(std::sqrt(lo * hi)) > kMaxBins ? lo : hi) = std::sqrt(lo * hi);
    c.fail("flock.boids.perception_radius",
           fmt::format("m gives about {:.3g} cell-list bins of edge radius / "
                       "flock.domain.bin_reach on a rank; allowed: at least {:.3g} m (at most "
                       "2^26 bins) on this rank grid, or more ranks",
                       bins(radius), hi));
  }
  // Per frame a boid moves less than its perception radius: a faster one could pass through a
  // neighbour's whole perception sphere unseen (and a speed of 1e300 m/s put boids where no
  // cell list could bin them).
  const double noise = c.get_real("flock.noise.max_speed");
  const double prey_top = c.get_real("flock.boids.max_speed") * (1 + noise);
  if (prey_top * dt > radius)
    c.fail("flock.boids.max_speed",
           fmt::format(
               "m/s moves a prey up to {:.6g} m per frame (with flock.noise.max_speed = {} and "
               "flock.dt = {} s), more than flock.boids.perception_radius = {} m; "
               "allowed: at most {:.6g} m/s",
               prey_top * dt, noise, dt, radius, radius / (dt * (1 + noise))));
  const double predator = c.get_real("flock.predator.max_speed");
  if (c.get_int("flock.predator.count") > 0 && predator * dt > radius)
    c.fail("flock.predator.max_speed",
           fmt::format("m/s moves the predator {:.6g} m per frame (flock.dt = {} s), more than "
                       "flock.boids.perception_radius = {} m; allowed: at most {:.6g} m/s",
                       predator * dt, dt, radius, radius / dt));
  // From its second frame the rules hold a boid to its top speed ("uniform" launches nobody).
  const double launch = c.get_real("flock.takeoff.speed"),
               top = c.get_real("flock.boids.max_speed");
  if (launch > top && c.get_string("flock.takeoff.ifs") != "uniform")
    c.fail("flock.takeoff.speed",
           fmt::format("m/s is faster than flock.boids.max_speed; allowed: [0, {}] m/s", top));
}

void FlockScenario::declare_config(core::ConfigSchema& s) {
  // Domain.
  s.add_real_list("flock.domain.size", std::vector<double>{60, 60, 40}, 3, "m",
                  "box [0, size]; each size must be a multiple of flock.domain.dx");
  s.add_real(
      "flock.domain.dx", 4.0, 0.0, std::nullopt, "m",
      "cell of the rank decomposition: ranks own whole cells, the load balance moves the cut "
      "by whole cells (smaller: finer cuts), every block at least one perception radius "
      "thick",
      true);
  s.add_string("flock.domain.boundary", "walls", {"walls", "periodic"},
               "soft walls (boids pushed back inside a margin) or a periodic box");
  s.add_real("flock.domain.wall_margin", 5.0, 0.0, std::nullopt, "m",
             "thickness of the soft-wall layer", true);
  s.add_real("flock.domain.wall_weight", 20.0, 0.0, std::nullopt, "m/s^2",
             "soft-wall push at the wall (quadratic in depth)");
  s.add_int("flock.domain.bin_reach", 1, 1, 4,
            "neighbour bins have edge perception_radius / reach (more, smaller bins: fewer "
            "candidates, more rows)");
  s.add_int("flock.balance.interval", 16, 0, 1'000'000'000,
            "steps between load-balance checks: the cut between ranks moves so that each rank "
            "gets boids in proportion to its measured speed (0: the even cut throughout; no "
            "effect on the results)");
  s.add_real("flock.balance.tolerance", 0.05, 0.0, 10.0, "-",
             "the cut moves when the slowest rank's rules time exceeds the mean by more than "
             "this fraction");
  s.add_real("flock.dt", 0.05, 0.0, std::nullopt, "s", "time step (one animation frame)", true);
  s.add_int("flock.stats_interval", 5, 1, 1'000'000'000, "steps between rows of flock_order.csv");
  // Boids (spec 2.1).
  s.add_int("flock.prey.count", 0, 0, 100000000,
            "number of prey; 0: L^3 (one per sandpile site, the paper's choice)");
  s.add_real("flock.boids.perception_radius", 3.0, 0.0, std::nullopt, "m",
             "neighbours are perceived within this radius (the ghost cutoff)", true);
  s.add_real("flock.boids.fov_degrees", 270.0, 0.0, 360.0, "deg",
             "field of view (full cone angle about the velocity; 360: all around)", true);
  s.add_real("flock.boids.cruising_distance", 1.0, 0.0, std::nullopt, "m",
             "optimal cruising distance d*: separation acts below it", true);
  s.add_real("flock.boids.separation_weight", 10.0, 0.0, std::nullopt, "1/s^2",
             "separation weight (priority 2, after flee)");
  s.add_real("flock.boids.alignment_weight", 2.0, 0.0, std::nullopt, "1/s",
             "alignment (velocity matching) weight (priority 4)");
  s.add_real("flock.boids.cohesion_weight", 0.5, 0.0, std::nullopt, "1/s^2",
             "cohesion (flock centring) weight (priority 5)");
  s.add_string("flock.boids.alignment", "average", {"average", "nearest"},
               "match the mean velocity of perceived boids (Reynolds) or the nearest one (paper)");
  s.add_real("flock.boids.max_speed", 4.0, 0.0, std::nullopt, "m/s", "maximum speed", true);
  s.add_real("flock.boids.min_speed", 1.0, 0.0, std::nullopt, "m/s",
             "minimum speed of a flying boid");
  s.add_real("flock.boids.max_accel", 20.0, 0.0, std::nullopt, "m/s^2",
             "acceleration budget of the prioritised allocation", true);
  // Predator and prey (spec 2.2).
  s.add_int("flock.predator.count", 1, 0, 64, "number of predators");
  s.add_real("flock.predator.start_time", 10.0, 0.0, std::nullopt, "s",
             "predators wait until this time");
  s.add_real_list("flock.predator.start", std::vector<double>{5, 5, 30}, 3, "m",
                  "position of predator 0 (predator p starts 2 m further along x per p)");
  s.add_real("flock.predator.max_speed", 6.0, 0.0, std::nullopt, "m/s", "predator max speed", true);
  s.add_real("flock.predator.max_accel", 15.0, 0.0, std::nullopt, "m/s^2",
             "predator acceleration budget", true);
  s.add_real("flock.predator.chase_weight", 15.0, 0.0, std::nullopt, "m/s^2",
             "pull towards the nearest prey");
  s.add_real("flock.prey.flee_radius", 8.0, 0.0, std::nullopt, "m",
             "prey flee a predator closer than this");
  s.add_real("flock.prey.flee_weight", 8.0, 0.0, std::nullopt, "m/s^2",
             "flee acceleration (priority 1)");
  s.add_real("flock.prey.flee_boost_weight", 60.0, 0.0, std::nullopt, "m/s^2",
             "flee acceleration of prey whose site toppled (any distance)");
  s.add_int("flock.prey.flee_frames", 40, 0, 1'000'000'000,
            "frames a prey flees with the boost after its site toppled");
  // Sandpile coupling (spec 2.3, 2.5).
  s.add_int("flock.sandpile.size", 10, 1, 400, "edge L of the L^3 sandpile lattice");
  s.add_real("flock.sandpile.trigger_radius", 10.0, 0.0, std::nullopt, "m",
             "grains are added while a predator is this close to its nearest prey");
  s.add_int("flock.sandpile.grains_per_frame", 1, 1, 1000,
            "grains added per frame per triggering predator");
  s.add_int("flock.sandpile.warmup", 0, 0, 1'000'000'000,
            "random drives before t = 0 (not recorded) to reach the critical state (spec 5.17)");
  s.add_string("flock.sandpile.order", "waves", {"waves", "stack"},
               "toppling order (waves measures durations; both give the same avalanches)");
  // 1/f noise (spec 2.6).
  s.add_real("flock.noise.hurst", 0.2, 0.01, 0.99, "-", "Hurst exponent of every fBm");
  s.add_string("flock.noise.signal", "path", {"path", "increments"},
               "heading noise from the fBm path (1/f^(2H+1)) or its increments (1/f^(2H-1))");
  s.add_int("flock.noise.levels", 8, 1, 20,
            "heading noise: flock.noise.heading is its RMS change over 2^levels frames (blocks of "
            "one long fBm path)");
  s.add_real("flock.noise.heading", 0.3, 0.0, std::nullopt, "rad",
             "RMS turn of the acceleration direction");
  s.add_real("flock.noise.cruising_distance", 0.15, 0.0, 0.9, "-",
             "relative RMS spread of d* (2D fBm over the take-off grid)");
  s.add_real("flock.noise.max_speed", 0.1, 0.0, 0.9, "-",
             "relative RMS spread of the max speed (2D fBm over the take-off grid)");
  // Take-off (spec 2.7).
  s.add_string("flock.takeoff.ifs", "gasket", {"gasket", "fern", "tetrahedron", "user", "uniform"},
               "chaos game of the take-off positions (uniform: random in the box, all flying at "
               "t = 0; for benchmarks)");
  s.add_int("flock.takeoff.dim", 2, 2, 3, "dimension of user maps (2: 7 reals/map, 3: 13)");
  s.add_real_list("flock.takeoff.maps", std::vector<double>{}, -1, "-",
                  "user IFS maps: 2D 'a b c d e f p' per map, 3D A(9) T(3) p");
  s.add_string("flock.takeoff.plane", "xy", {"xy", "xz"},
               "plane of a 2D chaos game (xy: ground, xz: a vertical 'tree')");
  s.add_real_list("flock.takeoff.origin", std::vector<double>{20, 20, 1}, 3, "m",
                  "lower corner of the take-off pattern");
  s.add_real("flock.takeoff.scale", 20.0, 0.0, std::nullopt, "m",
             "largest extent of the take-off pattern", true);
  s.add_real("flock.takeoff.interval", 0.005, 0.0, std::nullopt, "s",
             "time between consecutive take-offs (in chaos-game order)");
  s.add_real("flock.takeoff.speed", 2.0, 0.0, std::nullopt, "m/s", "launch speed");
  s.add_real_list("flock.takeoff.direction", std::vector<double>{0, 0, 1}, 3, "-",
                  "launch direction (a random 30% sideways part is added per boid)");
}

}  // namespace biota::scenarios
