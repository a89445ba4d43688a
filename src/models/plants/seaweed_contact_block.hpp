#pragma once
/// \file seaweed_contact_block.hpp
/// \brief contact_law (seaweed_contact_law.hpp) for kContactBlock pairs at once, in vector lanes.
/// Every lane performs exactly the scalar operations in the same order (the build uses
/// -ffp-contract=off; vector add, mul, div and sqrt are the same IEEE operations as scalar ones),
/// so a pair gets the same bits in a block as alone.
#include <cstdint>

#include "models/plants/seaweed_contact_law.hpp"

namespace biota::models::plants {

inline constexpr int kContactBlock = 8;

/// \brief Results of a block, one lane per pair (a, b): the force f on a (b gets -f) and the
/// torques ta on a and tb on b; +0 where the pair does not touch.
struct ContactBlockOut {
  using Lane = Real[kContactBlock];
  Lane fx, fy, fz, tax, tay, taz, tbx, tby, tbz;
};

/// \brief The law for the pairs (a[l], b[l]) of slots in `hot` (lower global id first): one
/// evaluation gives both spheres' results.
void evaluate_contact_block(const SphereHot* hot, const std::uint32_t* a, const std::uint32_t* b,
                            const ContactLaw& law, ContactBlockOut& out);

}  // namespace biota::models::plants
