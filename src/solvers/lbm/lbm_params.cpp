// LBM deck keys and their checks: face types, inlet disc and outlet annulus on their face,
// LbmParams from the deck (units through UnitConverter), the memory estimate per rank.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/error.hpp"
#include "solvers/lbm/lbm_solver.hpp"
#include "solvers/lbm/unit_converter.hpp"

namespace biota::solvers::lbm {
namespace {

const char* kFaceNames[6] = {"x_lo", "x_hi", "y_lo", "y_hi", "z_lo", "z_hi"};

int face_index(const core::Config& cfg, const std::string& key) {
  const std::string& v = cfg.get_string(key);
  if (v == "none") return -1;
  for (int f = 0; f < 6; ++f)
    if (v == kFaceNames[f]) return f;
  cfg.fail(key, "is not a face");
}

// True if a cell centre ((i + 1/2) dx, (j + 1/2) dx) of an n0 x n1 face lies at a distance in
// [r_min, r_max] from (c0, c1): one interval test per row, so O(n1) even on a huge face.
bool ring_selects_a_cell(int n0, int n1, double dx, double c0, double c1, double r_min,
                         double r_max) {
  for (int j = 0; j < n1; ++j) {
    const double dy2 = ((j + 0.5) * dx - c1) * ((j + 0.5) * dx - c1);
    if (dy2 > r_max * r_max) continue;
    const double hi = std::sqrt(r_max * r_max - dy2);
    const double lo = r_min * r_min > dy2 ? std::sqrt(r_min * r_min - dy2) : 0.0;
    for (const double sign : {1.0, -1.0}) {  // a - c0 in [lo, hi] or in [-hi, -lo]
      const double a_lo = sign > 0 ? c0 + lo : c0 - hi, a_hi = sign > 0 ? c0 + hi : c0 - lo;
      const double first = std::max(0.0, std::ceil(a_lo / dx - 0.5));
      if (first < n0 && (first + 0.5) * dx <= a_hi) return true;
    }
  }
  return false;
}

// The inlet disc and the outlet annulus must lie on their face and select at least one cell: an
// inlet centred outside the tank was accepted and the run went on without a jet.
void check_face_patch(const core::Config& cfg, const LbmParams& p, int face,
                      const std::string& prefix, const double center[2], double r_min, double r_max,
                      const std::string& radius_keys) {
  if (face < 0) return;
  const int axis = face / 2;
  const int t0 = axis == 0 ? 1 : 0, t1 = axis == 2 ? 1 : 2;
  const char* names = "xyz";
  const double l0 = p.cells[t0] * p.dx, l1 = p.cells[t1] * p.dx;
  const std::string face_text = fmt::format(
      "the {} face spans {} in [0, {}] m and {} in [0, {}] m (lbm.n{}, lbm.n{} x lbm.dx)",
      kFaceNames[face], names[t0], l0, names[t1], l1, names[t0], names[t1]);
  if (!(center[0] >= 0 && center[0] <= l0 && center[1] >= 0 && center[1] <= l1))
    cfg.fail(prefix + ".center", "lies outside the face: " + face_text);
  if (r_min > r_max)
    cfg.fail(prefix + ".r_min", fmt::format("exceeds {}.r_max = {}", prefix, r_max));
  if (!ring_selects_a_cell(p.cells[t0], p.cells[t1], p.dx, center[0], center[1], r_min, r_max))
    cfg.fail(prefix + ".center",
             fmt::format("with {} selects no cell centre ({} m apart) of the face; {}", radius_keys,
                         p.dx, face_text));
}
}  // namespace

double InletPatch::time_factor(double t) const {
  double ramp = 1.0;
  if (ramp_time > 0 && t < ramp_time)
    ramp = 0.5 * (1.0 - std::cos(std::numbers::pi * t / ramp_time));
  return ramp * (1.0 + pulse_amplitude * std::sin(2.0 * std::numbers::pi * t / pulse_period));
}

FaceType parse_face_type(const core::Config& cfg, const std::string& key) {
  const std::string& v = cfg.get_string(key);
  if (v == "periodic") return FaceType::kPeriodic;
  if (v == "wall") return FaceType::kWall;
  if (v == "free_slip") return FaceType::kFreeSlip;
  if (v == "pressure") return FaceType::kPressure;
  if (v == "zero_gradient") return FaceType::kZeroGradient;
  cfg.fail(key, "is not a boundary type");
}

void LbmSolver::declare_config(core::ConfigSchema& s) {
  s.add_string("lbm.lattice", "D3Q15", {"D3Q15", "D3Q19"},
               "velocity set (D3Q15 is the seaweed paper's)");
  s.add_string("lbm.collision", "bgk", {"bgk", "trt"}, "collision operator");
  s.add_real("lbm.trt_magic", 3.0 / 16.0, 0.0, 10.0, "-",
             "TRT magic parameter Lambda (3/16: exact bounce-back wall for Poiseuille)", true);
  s.add_int("lbm.nx", 100, 2, 100000, "lattice cells along x");
  s.add_int("lbm.ny", 100, 2, 100000, "lattice cells along y");
  s.add_int("lbm.nz", 100, 2, 100000, "lattice cells along z");
  s.add_real("lbm.dx", 0.01, 0.0, std::nullopt, "m", "lattice spacing", true);
  s.add_real("lbm.dt", 1.0 / 600.0, 0.0, std::nullopt, "s", "lattice time step", true);
  s.add_real("lbm.density", 998.0, 0.0, std::nullopt, "kg/m^3", "fluid density rho0", true);
  s.add_real("lbm.tau", std::nullopt, 0.5, 5.0, "-",
             "(optional) relaxation time; sets the viscosity (give tau or viscosity)", true);
  s.add_real("lbm.viscosity", std::nullopt, 0.0, std::nullopt, "m^2/s",
             "(optional) kinematic viscosity; sets tau (give tau or viscosity)", true);
  s.add_real("lbm.reference_velocity", std::nullopt, 0.0, std::nullopt, "m/s",
             "(optional) largest expected speed for the Mach check (default: inlet speed)");
  s.add_real("lbm.max_mach", 0.3, 0.0, 0.5, "-", "largest allowed Mach number", true);
  for (const char* f : kFaceNames)
    s.add_string(std::string("lbm.boundary.") + f, "wall",
                 {"periodic", "wall", "free_slip", "pressure", "zero_gradient"},
                 std::string("boundary type of face ") + f);
  s.add_real_list("lbm.body_force", std::vector<double>{0, 0, 0}, 3, "N/m^3",
                  "uniform body-force density on the fluid");
  const std::vector<std::string> faces = {"none", "x_lo", "x_hi", "y_lo", "y_hi", "z_lo", "z_hi"};
  s.add_string("lbm.inlet.face", "none", faces, "face carrying the velocity-inlet disc");
  s.add_real_list("lbm.inlet.center", std::vector<double>{0, 0}, 2, "m",
                  "disc centre in the face's tangential axes (x,y order)");
  s.add_real("lbm.inlet.radius", 0.0, 0.0, std::nullopt, "m", "disc radius");
  s.add_real("lbm.inlet.speed", 0.0, 0.0, std::nullopt, "m/s", "peak inflow speed");
  s.add_string("lbm.inlet.profile", "parabolic", {"parabolic", "uniform"}, "radial profile");
  s.add_real("lbm.inlet.ramp_time", 0.0, 0.0, std::nullopt, "s", "smooth start-up time");
  s.add_real("lbm.inlet.pulse_amplitude", 0.0, 0.0, 1.0, "-", "relative pulsation amplitude");
  s.add_real("lbm.inlet.pulse_period", 1.0, 0.0, std::nullopt, "s", "pulsation period", true);
  s.add_string("lbm.outlet.face", "none", faces, "face carrying the outlet annulus");
  s.add_string("lbm.outlet.type", "pressure", {"pressure", "zero_gradient"}, "outlet condition");
  s.add_real_list("lbm.outlet.center", std::vector<double>{0, 0}, 2, "m", "annulus centre");
  s.add_real("lbm.outlet.r_min", 0.0, 0.0, std::nullopt, "m", "annulus inner radius");
  s.add_real("lbm.outlet.r_max", 1e9, 0.0, std::nullopt, "m", "annulus outer radius");
}

std::vector<core::MemoryItem> LbmSolver::memory_estimate(const grid::Decomposition& decomp,
                                                         const LbmParams& params) {
  const Index3 n = decomp.local_cells();
  const double cells = double(n.x + 2) * double(n.y + 2) * double(n.z + 2);  // one ghost layer
  const double surface = 2.0 * (double(n.x) * n.y + double(n.y) * n.z + double(n.x) * n.z);
  const double nq = params.lattice == "D3Q19" ? 19 : 15;
  // One population buffer (in-place AA streaming); force 3, rho 1, u 3 reals; a solid byte; about
  // nq/3 boundary links per wall cell (their plans: 40 B for both parities); an output step holds
  // 5 reals per owned cell and MPI-IO's buffers, 8 reals in all (measured with heaptrack at 200^3
  // on 2 ranks: peak heap 996 MB, estimate 1.02 GB).
  return {{"populations", nq * 8 * cells},
          {"fields", 7 * 8 * cells + cells},
          {"boundary links", surface * nq / 3 * 40},
          {"output", 8 * 8 * double(n.x) * n.y * n.z}};
}

LbmParams LbmParams::from_config(const core::Config& cfg) {
  LbmParams p;
  p.lattice = cfg.get_string("lbm.lattice");
  p.trt = cfg.get_string("lbm.collision") == "trt";
  // Keys of a mode the deck does not use are not read, so that a run reports them as unused
  // (Config::unused_given_keys): the TRT magic number under BGK, an absent inlet's or outlet's
  // geometry.
  if (p.trt) p.magic = cfg.get_real("lbm.trt_magic");
  p.cells = {int(cfg.get_int("lbm.nx")), int(cfg.get_int("lbm.ny")), int(cfg.get_int("lbm.nz"))};
  p.dx = cfg.get_real("lbm.dx");
  p.dt = cfg.get_real("lbm.dt");
  p.density = cfg.get_real("lbm.density");
  const bool has_tau = cfg.has("lbm.tau"), has_nu = cfg.has("lbm.viscosity");
  if (has_tau == has_nu)
    cfg.fail(has_tau ? "lbm.tau" : "lbm.viscosity",
             has_tau
                 ? "conflicts with lbm.viscosity; give exactly one of lbm.tau (0.5, 5] or "
                   "lbm.viscosity (0, inf)"
                 : "is missing; give exactly one of lbm.tau (0.5, 5] or lbm.viscosity (0, inf)");
  p.viscosity = has_nu ? cfg.get_real("lbm.viscosity")
                       : (cfg.get_real("lbm.tau") - 0.5) / 3.0 * p.dx * p.dx / p.dt;
  for (int f = 0; f < 6; ++f)
    p.faces[f] = parse_face_type(cfg, std::string("lbm.boundary.") + kFaceNames[f]);
  for (int a = 0; a < 3; ++a)
    if ((p.faces[2 * a] == FaceType::kPeriodic) != (p.faces[2 * a + 1] == FaceType::kPeriodic))
      cfg.fail(std::string("lbm.boundary.") + kFaceNames[2 * a + 1],
               fmt::format("must be periodic exactly when lbm.boundary.{} is", kFaceNames[2 * a]));
  const auto& bf = cfg.get_real_list("lbm.body_force");
  p.body_force = {bf[0], bf[1], bf[2]};
  p.inlet.face = face_index(cfg, "lbm.inlet.face");
  // The speed and the pulse amplitude set the reference velocity (below) with or without an inlet.
  p.inlet.speed = cfg.get_real("lbm.inlet.speed");
  p.inlet.pulse_amplitude = cfg.get_real("lbm.inlet.pulse_amplitude");
  if (p.inlet.face >= 0) {
    const auto& inlet_center = cfg.get_real_list("lbm.inlet.center");
    p.inlet.center[0] = inlet_center[0];
    p.inlet.center[1] = inlet_center[1];
    p.inlet.radius = cfg.get_real("lbm.inlet.radius");
    p.inlet.parabolic = cfg.get_string("lbm.inlet.profile") == "parabolic";
    p.inlet.ramp_time = cfg.get_real("lbm.inlet.ramp_time");
    p.inlet.pulse_period = cfg.get_real("lbm.inlet.pulse_period");
  }
  if (p.inlet.face >= 0 && p.faces[p.inlet.face] == FaceType::kPeriodic)
    cfg.fail("lbm.inlet.face", "lies on a periodic face");
  p.outlet.face = face_index(cfg, "lbm.outlet.face");
  if (p.outlet.face >= 0) {
    p.outlet.type = cfg.get_string("lbm.outlet.type") == "pressure" ? FaceType::kPressure
                                                                    : FaceType::kZeroGradient;
    const auto& outlet_center = cfg.get_real_list("lbm.outlet.center");
    p.outlet.center[0] = outlet_center[0];
    p.outlet.center[1] = outlet_center[1];
    p.outlet.r_min = cfg.get_real("lbm.outlet.r_min");
    p.outlet.r_max = cfg.get_real("lbm.outlet.r_max");
  }
  if (p.outlet.face >= 0 && p.faces[p.outlet.face] == FaceType::kPeriodic)
    cfg.fail("lbm.outlet.face", "lies on a periodic face");
  check_face_patch(cfg, p, p.inlet.face, "lbm.inlet", p.inlet.center, 0.0, p.inlet.radius,
                   fmt::format("lbm.inlet.radius = {}", p.inlet.radius));
  check_face_patch(
      cfg, p, p.outlet.face, "lbm.outlet", p.outlet.center, p.outlet.r_min, p.outlet.r_max,
      fmt::format("lbm.outlet.r_min = {}, lbm.outlet.r_max = {}", p.outlet.r_min, p.outlet.r_max));
  p.max_mach = cfg.get_real("lbm.max_mach");
  p.reference_velocity = cfg.has("lbm.reference_velocity")
                             ? cfg.get_real("lbm.reference_velocity")
                             : p.inlet.speed * (1.0 + p.inlet.pulse_amplitude);
  // Stability: the derived tau and the Mach number must stay in range.
  UnitConverter u(p.dx, p.dt, p.density, p.viscosity, p.reference_velocity);
  if (!(u.tau() > 0.5 + 1e-6) || u.tau() > 5.0)
    cfg.fail(has_tau ? "lbm.tau" : "lbm.viscosity",
             fmt::format("gives tau = {:.6g} with lbm.dx = {} and lbm.dt = {}; allowed tau: "
                         "(0.500001, 5]",
                         u.tau(), p.dx, p.dt));
  if (u.mach() > p.max_mach)
    throw core::InputError(fmt::format(
        "{}: reference velocity {} m/s (lbm.reference_velocity or lbm.inlet.speed) gives Mach "
        "{:.3f} with lbm.dx = {} and lbm.dt = {}; allowed: Mach <= lbm.max_mach = {} (reduce "
        "lbm.dt)",
        cfg.source(), p.reference_velocity, u.mach(), p.dx, p.dt, p.max_mach));
  return p;
}

}  // namespace biota::solvers::lbm
