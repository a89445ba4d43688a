#pragma once
/// \file unit_converter.hpp
/// \brief Physical (SI) <-> lattice units for the LBM: dx [m], dt [s], rho0 [kg/m^3].
#include <string>

namespace biota::solvers::lbm {

/// \brief Conversion factors and the derived relaxation time; checks the stable range.
class UnitConverter {
 public:
  /// \param viscosity kinematic viscosity [m^2/s]; \param reference_velocity the largest expected
  /// speed [m/s] (sets the Mach number).
  UnitConverter(double dx, double dt, double density, double viscosity, double reference_velocity);

  double dx() const { return dx_; }
  double dt() const { return dt_; }
  double density() const { return rho0_; }
  /// \brief Relaxation time tau = 3 nu dt/dx^2 + 1/2.
  double tau() const { return tau_; }
  double lattice_viscosity() const { return nu_lat_; }
  double mach() const { return mach_; }
  double velocity_to_lattice(double u) const { return u * dt_ / dx_; }
  double velocity_to_si(double u) const { return u * dx_ / dt_; }
  /// \brief Force density [N/m^3] to lattice force density.
  double force_density_to_lattice(double f) const { return f * dt_ * dt_ / (rho0_ * dx_); }
  double force_density_to_si(double f) const { return f * rho0_ * dx_ / (dt_ * dt_); }
  /// \brief Force [N] on a body to lattice force (per cell volume summed): F dt^2/(rho0 dx^4).
  double force_to_lattice(double f) const {
    return f * dt_ * dt_ / (rho0_ * dx_ * dx_ * dx_ * dx_);
  }
  double force_to_si(double f) const { return f * rho0_ * dx_ * dx_ * dx_ * dx_ / (dt_ * dt_); }
  double density_to_si(double rho) const { return rho * rho0_; }
  /// \brief Pressure deviation [Pa] from lattice density: c_s^2 (rho - 1) rho0 dx^2/dt^2.
  double pressure_to_si(double rho) const {
    return (rho - 1.0) / 3.0 * rho0_ * dx_ * dx_ / (dt_ * dt_);
  }
  /// \brief Multi-line summary printed at start-up.
  std::string summary() const;

 private:
  double dx_, dt_, rho0_, nu_, u_ref_;
  double nu_lat_, tau_, mach_;
};

}  // namespace biota::solvers::lbm
