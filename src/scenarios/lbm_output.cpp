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
  std::vector<double> vel, dens, pres;
  vel.reserve(3 * n.product());
  dens.reserve(n.product());
  pres.reserve(n.product());
  for (int k = 0; k < n.z; ++k)
    for (int j = 0; j < n.y; ++j)
      for (int i = 0; i < n.x; ++i) {
        for (int c = 0; c < 3; ++c) vel.push_back(units.velocity_to_si(u(i, j, k, c)));
        dens.push_back(units.density_to_si(rho(i, j, k)));
        pres.push_back(units.pressure_to_si(rho(i, j, k)));
      }
  out.add_vector("velocity", std::move(vel), "m/s");
  out.add_scalar("density", std::move(dens), "kg/m^3");
  out.add_scalar("pressure", std::move(pres), "Pa");
}

}  // namespace biota::scenarios
