#include "solvers/lbm/unit_converter.hpp"

#include <fmt/format.h>

#include <cmath>

namespace biota::solvers::lbm {

UnitConverter::UnitConverter(double dx, double dt, double density, double viscosity,
                             double reference_velocity)
    : dx_(dx), dt_(dt), rho0_(density), nu_(viscosity), u_ref_(reference_velocity) {
  nu_lat_ = nu_ * dt_ / (dx_ * dx_);
  tau_ = 3.0 * nu_lat_ + 0.5;
  mach_ = velocity_to_lattice(u_ref_) * std::sqrt(3.0);
}

std::string UnitConverter::summary() const {
  return fmt::format(
      "LBM units: dx = {:.6g} m, dt = {:.6g} s, rho0 = {:.6g} kg/m^3, nu = {:.6g} m^2/s\n"
      "           lattice nu = {:.6g}, tau = {:.6g} (omega = {:.6g}), reference u = {:.6g} m/s "
      "= {:.6g} lattice, Mach = {:.4f}",
      dx_, dt_, rho0_, nu_, nu_lat_, tau_, 1.0 / tau_, u_ref_, velocity_to_lattice(u_ref_), mach_);
}

}  // namespace biota::solvers::lbm
