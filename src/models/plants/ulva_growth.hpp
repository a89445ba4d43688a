#pragma once
/// \file ulva_growth.hpp
/// \brief Stochastic architectural growth of a population of Ulva (paper sections 3-3 to 3-5):
/// growth units, elongation G(l, phi, theta, psi), environment factor e, and interference
/// avoidance with personal-space spheres.
///
/// Decomposition invariance: the whole population is grown serially and identically on every
/// rank (50 plants x 5 cycles is a few thousand buds). Every random draw comes from a Philox stream
/// keyed by (seed, growth-unit global id, cycle, purpose) and growth units are processed in global
/// id order, so conflicts between plants in one cycle are resolved by that fixed priority and the
/// result does not depend on the rank count or on any processing order.
#include <cstdint>
#include <vector>

#include "core/config.hpp"
#include "core/quat.hpp"
#include "core/types.hpp"
#include "models/plants/architecture.hpp"

namespace biota::models::plants {

using core::GlobalId;
using core::Real;
using core::Vec3;

/// \brief Parameters (paper Table 1 defaults; lengths in metres, angles in degrees).
struct GrowthParams {
  std::uint64_t seed = 1;
  int cycles = 5;                          ///< p_max, "Step size sigma"
  Real p_grow = 0.8;                       ///< P_I, "Growth probability p"
  int initial_branches = 10;               ///< growth units created from a seed
  int branches_min = 0, branches_max = 2;  ///< lateral growth units per new bud (uniform)
  Real length_min = 0.02, length_max = 0.04;
  Real roll_max = 45, pitch_max = 45, yaw_max = 45;  ///< symmetric ranges [-max, max]
  Real env_min = 1.0, env_max = 1.5;
  int env_regions = 5;
  Vec3 env_centre{};      ///< centre of the concentric regions (horizontal distance)
  Real env_radius = 0.3;  ///< outer radius of the last region (m)
  Real personal_radius = 0.015;
  bool interference = true;
  int max_retries = 20;
  /// \brief false: the Ulva model (paper 3-3, eq. 5-7; the default, the paper's experiment);
  /// true: the general model of `arch` (paper 3-1/3-2, eq. 1-4) with the same elongation,
  /// environment factor and interference avoidance.
  bool general = false;
  ArchitectureParams arch = ArchitectureParams::kang_example();

  /// \brief Declare the `growth.*` keys.
  static void declare_config(core::ConfigSchema& schema);
  /// \brief Read the `growth.*` keys (env_centre/env_radius are set by the scenario).
  static GrowthParams from_config(const core::Config& cfg);
};

/// \brief One bud (node) of a plant; stems join a bud to its parent.
struct Bud {
  GlobalId id = 0;
  GlobalId parent = ~GlobalId{0};  ///< none for the seed
  int plant = 0;
  int cycle = 0;  ///< cycle in which the bud was created (0 = seed)
  int type = 0;   ///< general model: physiological age of the metamer (1-based); 0 seed / Ulva
  Vec3 pos{};
};

/// \brief Counts of one growth cycle (for tests and logs).
struct CycleStats {
  long long tips_before = 0;  ///< growth units that could grow
  long long grown = 0;        ///< metamers created
  long long trials = 0;       ///< Bernoulli trials with P_I (= tips_before)
  long long successes = 0;    ///< trials that succeeded (grown + blocked)
  long long blocked = 0;      ///< metamers given up after max_retries
  long long retries = 0;      ///< interference redraws
  long long laterals = 0;     ///< lateral growth units created
  // General model only (sized `types`, 0-based type):
  long long died = 0, rested = 0;           ///< apices lost (1 - P_C) / resting (P_A)
  std::vector<long long> units_by_type;     ///< growth units built
  std::vector<long long> metamers_by_type;  ///< metamers created (after interference)
  std::vector<long long> laterals_by_type;  ///< lateral buds that branched (new apices)
};

/// \brief The grown population.
struct Population {
  std::vector<Bud> buds;          ///< ordered by id (id == index)
  std::vector<CycleStats> stats;  ///< one per cycle
};

/// \brief Environment factor e of the region containing `p` (concentric regions, outer grow more).
Real environment_factor(const GrowthParams& gp, const Vec3& p);

/// \brief Grow `seeds.size()` plants from the seed positions for gp.cycles cycles (Ulva model, or
/// the general model when gp.general).
Population grow_population(const GrowthParams& gp, const std::vector<Vec3>& seeds);

}  // namespace biota::models::plants

namespace biota::models::plants {
/// \brief Seed positions: uniform in the box [lo, hi) with a minimum spacing, drawn plant by
/// plant from Philox streams keyed by (seed, plant, attempt); identical on every rank.
std::vector<Vec3> place_seeds(std::uint64_t seed, int n, const Vec3& lo, const Vec3& hi,
                              Real min_spacing);
}  // namespace biota::models::plants
