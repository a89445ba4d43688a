#include "core/error.hpp"
#include "scenarios/flock_scenario.hpp"
#include "scenarios/moss_scenario.hpp"
#include "scenarios/scenario.hpp"
#include "scenarios/seaweed_scenario.hpp"
#include "scenarios/tank_scenario.hpp"
#include "scenarios/tree_scenario.hpp"
#include "scenarios/wind_scenario.hpp"

namespace biota::scenarios {

void Scenario::poison_for_test() {
  throw core::UnstableError("test hook: injected health failure on this rank only");
}

std::vector<ScenarioInfo> all_scenarios() {
  return {
      {"tank", "LBM water tank with the fountain jet (seaweed paper, no plants)",
       &TankScenario::declare_config,
       [](const RunContext& c) -> std::unique_ptr<Scenario> {
         return std::make_unique<TankScenario>(c);
       }},
      {"seaweed",
       "Ulva population grown stochastically, rigid-sphere bodies in the LBM fountain tank",
       &SeaweedScenario::declare_config,
       [](const RunContext& c) -> std::unique_ptr<Scenario> {
         return std::make_unique<SeaweedScenario>(c);
       }},
      {"wind", "wind over open ground on the staggered MAC solver (tree paper section 4)",
       &WindScenario::declare_config,
       [](const RunContext& c) -> std::unique_ptr<Scenario> {
         return std::make_unique<WindScenario>(c);
       }},
      {"tree",
       "L-system trees (node-link model) swaying in the MAC wind, two-way coupled (tree paper)",
       &TreeScenario::declare_config,
       [](const RunContext& c) -> std::unique_ptr<Scenario> {
         return std::make_unique<TreeScenario>(c);
       }},
      {"flock",
       "Boids taking off in chaos-game order, schooling, attacked by predators, breaking up in "
       "3D-sandpile avalanches, with 1/f (fBm) noise",
       &FlockScenario::declare_config,
       [](const RunContext& c) -> std::unique_ptr<Scenario> {
         return std::make_unique<FlockScenario>(c);
       }},
      {"moss",
       "three moss species spreading over a polygon terrain for 300 days, lit by photon mapping "
       "(direct + indirect light, mosses as occluders), with a daily soil heat/water balance",
       &MossScenario::declare_config,
       [](const RunContext& c) -> std::unique_ptr<Scenario> {
         return std::make_unique<MossScenario>(c);
       }},
  };
}

}  // namespace biota::scenarios
