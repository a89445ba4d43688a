#include "scenarios/lbm_output.hpp"

namespace biota::scenarios {

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
