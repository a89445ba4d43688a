// The moss paper's two experiments (spec moss.md section 4) at reduced size: the paper's scene,
// 2048 photons a day, 40 days, 256 initial mosses. Full-size numbers (8192 photons, 300 days):
// docs/moss.md.
//
// 1. Indirect light on vs off: with indirect light more mosses live on the back floor under the
//    roof (z < 0.5 m, 0.15 m < x < 1.85 m: away from the shadow edges, blurred by the 0.1 m
//    photon radius and the light's ~3° half-width, at the front and at the open sides). Without
//    it S = 0 there, G < τ_b for every species of Table 4.2 (checked below), so nothing
//    germinates there: only the initial mosses remain.
// 2. Air temperature 288.15 K vs 293.15 K: the paper reports more spreading at 288.15 K. This
//    model gives the opposite, and the test pins the cause: mosses live in shade, where the soil
//    model puts T_s 7-13 K below the air (3.11), i.e. below every species' optimum
//    (T0 + T1) / 2 = 285.65-287.65 K at both air temperatures, so warmer air brings T_s closer to
//    the optimum (docs/moss.md, "Experiment 2").
#include <gtest/gtest.h>
#include <mpi.h>

#include <cstdio>
#include <string>

#include "core/config.hpp"
#include "core/timers.hpp"
#include "models/moss/fitness.hpp"
#include "scenarios/moss_scenario.hpp"

using namespace biota;

namespace {

struct Result {
  long long live = 0, back = 0, back_initial = 0, germinated_back = 0;
  double mean_ts = 0;  // mean T_s of the faces under live mosses
};

Result run(const std::string& name, std::vector<std::string> set) {
  core::ConfigSchema s;
  s.add_string("scenario", std::nullopt, {}, "scenario");
  s.add_int("seed", 12345, 0, 1'000'000'000'000'000'000, "seed");
  scenarios::MossScenario::declare_config(s);
  set.push_back(std::string("moss.terrain.file=\"") + BIOTA_SOURCE_DIR + "/input/moss/scene.obj\"");
  const auto cfg = core::Config::from_string(
      s, "scenario = \"moss\"\nseed = 5\n[moss]\ninitial = 256\n[moss.light]\nphotons = 2048\n",
      name + ".toml", set);
  core::Timers timers;
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  scenarios::RunContext ctx{MPI_COMM_WORLD, cfg, timers,
                            "moss_exp_" + name + "_np" + std::to_string(size)};
  scenarios::MossScenario sc(ctx);
  auto back = [](const core::Vec3& x) {
    return x.z < 0.5 && x.x > 0.15 && x.x < 1.85 && x.y < 1.0;
  };
  Result r;
  for (const auto& x : sc.gather_mosses()) r.back_initial += back(x.x) ? 1 : 0;
  for (int d = 0; d < 40; ++d) sc.step();
  const auto m = sc.gather_mosses();
  r.live = static_cast<long long>(m.size());
  for (const auto& x : m) {
    r.mean_ts += sc.face_temperature()[x.face];
    r.back += back(x.x) ? 1 : 0;
    r.germinated_back += (back(x.x) && x.age < 40) ? 1 : 0;  // initial ones are 40 days old
  }
  r.mean_ts /= std::max<double>(1, r.live);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank == 0)
    std::printf(
        "%-10s live %lld, back floor %lld (day 0: %lld, germinated there: %lld), mean T_s "
        "under mosses %.2f K\n",
        name.c_str(), r.live, r.back, r.back_initial, r.germinated_back, r.mean_ts);
  return r;
}

// The paper's setting (indirect light, 288.15 K), shared by both experiments.
const Result& base() {
  static const Result r = run("base", {});
  return r;
}

}  // namespace

TEST(MossExperiments, IndirectLightGrowsMossUnderTheRoof) {
  const Result& on = base();
  const Result off = run("direct", {"moss.light.indirect=false"});
  EXPECT_GT(on.back, off.back);
  EXPECT_GT(on.germinated_back, 0) << "with indirect light seeds germinate under the roof";
  EXPECT_EQ(off.germinated_back, 0) << "S = 0 under the roof: G < tau_b for every species";
  EXPECT_LE(off.back, off.back_initial);
  // The reason, from (3.17) and (3.24): at S = 0 and the coldest plausible shade T_s the
  // germination test fails for every species even at the best L (g(L) <= 1).
  for (const auto& sp : models::moss::paper_species())
    EXPECT_LT(models::moss::fitness(sp, 275.0, 1.0, 0.0), sp.tau_b) << sp.name;
}

TEST(MossExperiments, WarmerAirSpreadsFasterBecauseShadedSoilIsBelowTheOptimum) {
  const Result& cool = base();
  const Result warm = run("t293", {"moss.weather.temperature=293.15"});
  double lowest_optimum = 1e9;
  for (const auto& sp : models::moss::paper_species())
    lowest_optimum = std::min(lowest_optimum, 0.5 * (sp.t0 + sp.t1));
  EXPECT_LT(cool.mean_ts, lowest_optimum);
  EXPECT_LT(warm.mean_ts, lowest_optimum);
  EXPECT_LT(cool.mean_ts, warm.mean_ts);
  EXPECT_GT(warm.live, cool.live) << "the paper's claim (more at 288.15 K) would hold if T_s were "
                                     "above the optimum";
}
