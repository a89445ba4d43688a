#pragma once
/// \file life_cycle.hpp
/// \brief One moss's daily growth, death and reproduction triggers (spec moss.md 2.7, eqs. 3.20
/// to 3.23, errata 21 to 24), and the directions of new gemmae and spores. Pure functions; the
/// placement (falling seeds, back faces, moss on moss, surface-of-patch rule) is the caller's.
#include "core/rng.hpp"
#include "core/types.hpp"
#include "models/moss/fitness.hpp"

namespace biota::models::moss {

/// \brief Persistent state of one living moss.
struct MossState {
  double g_moss = 0;       ///< (3.21) total growth since germination
  double g_max = 0;        ///< running maximum of g_moss (gemma trigger, erratum 22)
  long long age_days = 0;  ///< days since germination
};

/// \brief What one day did to a moss.
struct MossDay {
  double growth = 0;   ///< D of (3.20)
  bool dies = false;   ///< G_moss < τ_d and D < 0 (erratum 21)
  int gemmae = 0;      ///< multiples of 0.5 newly crossed by the running maximum (erratum 22)
  bool spore = false;  ///< G_moss >= 2, D > 0 and a spore day (erratum 23: rain days, one spore)
};

/// \brief Advance one moss by one day with fitness G; `spore_day` says whether spores can form.
MossDay moss_day(const Species& sp, double fitness_today, bool spore_day, MossState& st);

/// \brief I of (3.22): uniform over the unit sphere.
core::Vec3 gemma_direction(core::Rng& rng);
/// \brief I_N of (3.23): uniform over the solid angle of the two cones 0° < φ < 45° and
/// 135° < φ < 180° about the unit normal n (erratum 24: both cones kept as printed).
core::Vec3 spore_direction(const core::Vec3& n, core::Rng& rng);

}  // namespace biota::models::moss
