#pragma once
/// \file dhar.hpp
/// \brief Exact stationary mean avalanche size of the abelian sandpile (Dhar 1990).
#include <cstdint>

namespace biota::models::flock {

/// \brief Exact mean avalanche size (topplings per drive, empty avalanches included) of the BTW
/// sandpile of Sandpile in its stationary state, for drives at uniformly random sites.
///
/// Dhar (Phys. Rev. Lett. 64, 1613, 1990): the expected number of topplings at j caused by a grain
/// added at i is G_ij = (Δ⁻¹)_ij, with the toppling matrix Δ_ii = z_c + 1, Δ_ij = -1 for face
/// neighbours (open boundaries: neighbours outside the lattice are absent). Hence
/// ⟨s⟩ = (1/N) Σ_ij (Δ⁻¹)_ij = (1/N) 1ᵀ x with Δ x = 1. Δ is symmetric positive definite
/// (strictly diagonally dominant on boundary rows, irreducible), so x comes from a matrix-free
/// conjugate-gradient solve to ~1e-14 relative residual; cost O(N · L) — fine up to L ≈ 100.
/// \param threshold z_c of the model (topple iff h > z_c); 5 is the paper's value (spec 2.3).
/// \throws std::invalid_argument if a size is < 1 or threshold < 5.
double dhar_mean_avalanche_size(int lx, int ly, int lz, int threshold = 5);

}  // namespace biota::models::flock
