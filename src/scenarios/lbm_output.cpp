#include "scenarios/lbm_output.hpp"

#include <fmt/format.h>

namespace biota::scenarios {

io::OutputLayout grid_output_layout(const core::Config& cfg, const grid::Decomposition& decomp,
                                    double dx, const core::Vec3& origin) {
  auto layout = io::output_layout(cfg, decomp.global_cells(), dx, origin);
  if (decomp.rank() == 0 && (cfg.has("output.region") || layout.stride > 1 || layout.compression))
    fmt::print("{}\n", layout.describe(decomp.global_cells(), dx, origin));
  return layout;
}

void add_lbm_fields(io::OutputStep& out, const solvers::lbm::LbmSolver& lbm) {
  const auto n = lbm.decomposition().local_cells();
  const auto& u = lbm.velocity();
  const auto& rho = lbm.density();
  const auto& units = lbm.units();
  // One array at a time: each is handed over (and reduced to output.region / output.stride)
  // before the next is built, so a large grid holds at most one unselected array.
  auto owned_cells = [&](int ncomp, auto&& value) {
    std::vector<double> a;
    a.reserve(static_cast<std::size_t>(ncomp * n.product()));
    for (int k = 0; k < n.z; ++k)
      for (int j = 0; j < n.y; ++j)
        for (int i = 0; i < n.x; ++i)
          for (int c = 0; c < ncomp; ++c) a.push_back(value(i, j, k, c));
    return a;
  };
  out.add_vector("velocity",
                 owned_cells(3, [&](int i, int j, int k,
                                    int c) { return units.velocity_to_si(u(i, j, k, c)); }),
                 "m/s");
  out.add_scalar(
      "density",
      owned_cells(1, [&](int i, int j, int k, int) { return units.density_to_si(rho(i, j, k)); }),
      "kg/m^3");
  out.add_scalar(
      "pressure",
      owned_cells(1, [&](int i, int j, int k, int) { return units.pressure_to_si(rho(i, j, k)); }),
      "Pa");
}

}  // namespace biota::scenarios
