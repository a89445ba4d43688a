#pragma once
/// \file architecture.hpp
/// \brief The general stochastic architectural model of the seaweed paper (digest sections 2.2 and
/// 2.3; GreenLab-type, Kang et al. 2008): p_m physiological ages (axis types), the matrices M_I
/// (metamers of type k in a growth unit of type p, eq. 1) and N_B (lateral buds of type k borne by
/// a metamer of type p, eq. 2), the change of physiological age of an apex M_A / T_A (eq. 3, 4),
/// and the probabilities P_C (apex survival), P_A (a surviving apex rests this cycle), P_I
/// (a metamer appears) and P_B (a lateral bud branches, i.e. becomes a new apex).
///
/// Reading (docs/seaweed.md): every potential element is an independent Bernoulli trial with the
/// probability of the type the trial is about: an apex of type p survives with P_C[p] and, if it
/// survives, rests with P_A[p]; otherwise it builds a growth unit of type p with M_I[p][k]
/// potential metamers of type k, each appearing with P_I[k]; a metamer of type k bears N_B[k][j]
/// potential lateral buds of type j, each branching with P_B[j]. An apex that grew M_A[p] times
/// becomes type T_A[p] (0: it stops); M_A[p] = 0 means it never changes. Types are 1-based as in
/// the paper; arrays here are 0-based.
#include <cstdint>
#include <vector>

#include "core/config.hpp"

namespace biota::models::plants {

/// \brief Parameters of the general model (row-major p_m x p_m matrices).
struct ArchitectureParams {
  int types = 3;                           ///< p_m
  std::vector<double> m_i, n_b;            ///< [p][k], counts (integers)
  std::vector<int> m_a, t_a;               ///< per type; t_a 1-based, 0 = stop
  std::vector<double> p_c, p_a, p_i, p_b;  ///< per type
  int initial_type = 1;                    ///< type of the apices created from a seed (1-based)

  int mi(int p, int k) const { return static_cast<int>(m_i[p * types + k]); }
  int nb(int p, int k) const { return static_cast<int>(n_b[p * types + k]); }
  /// \brief The paper's worked example (eq. 1-4) with all probabilities 1 (deterministic).
  static ArchitectureParams kang_example();
  /// \brief Throws std::invalid_argument naming the inconsistent entry.
  void validate() const;
  /// \brief Declare the `growth.general.*` keys (defaults: the worked example).
  static void declare_config(core::ConfigSchema& schema);
  static ArchitectureParams from_config(const core::Config& cfg);
};

/// \brief Expected counts of one cycle (per seed apex), by type (0-based).
struct ExpectedCycle {
  std::vector<double> growth_units, metamers, laterals, apices_after;
};

/// \brief Expected counts per cycle for one apex of `initial_type`, from the linear mean-field
/// recursion over (type, age) (exact for expectations: all trials are independent).
std::vector<ExpectedCycle> expected_counts(const ArchitectureParams& a, int cycles);

}  // namespace biota::models::plants
