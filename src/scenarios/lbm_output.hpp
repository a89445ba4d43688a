#pragma once
/// \file lbm_output.hpp
/// \brief Adds the LBM's macroscopic fields (SI units) to an output step; shared by scenarios.
#include "io/output_step.hpp"
#include "solvers/lbm/lbm_solver.hpp"

namespace biota::scenarios {

/// \brief The output layout of a grid scenario (output.region/stride/chunk/compression, checked
/// against the grid); rank 0 prints it when it differs from "whole grid, uncompressed".
io::OutputLayout grid_output_layout(const core::Config& cfg, const grid::Decomposition& decomp,
                                    double dx, const core::Vec3& origin);

/// \brief velocity [m/s], density [kg/m^3], pressure deviation [Pa] of the owned cells.
void add_lbm_fields(io::OutputStep& out, const solvers::lbm::LbmSolver& lbm);

}  // namespace biota::scenarios
