#pragma once
/// \file lbm_output.hpp
/// \brief Adds the LBM's macroscopic fields (SI units) to an output step; shared by scenarios.
#include "io/output_step.hpp"
#include "solvers/lbm/lbm_solver.hpp"

namespace biota::scenarios {

/// \brief velocity [m/s], density [kg/m^3], pressure deviation [Pa] of the owned cells.
void add_lbm_fields(io::OutputStep& out, const solvers::lbm::LbmSolver& lbm);

}  // namespace biota::scenarios
