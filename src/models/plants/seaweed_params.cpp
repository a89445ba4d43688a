/// \file seaweed_params.cpp
/// \brief Deck keys, derived quantities and the particle layout of the seaweed bodies (split from
/// seaweed_mechanics.cpp, which holds the dynamics).
#include <fmt/format.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>
#include <string>

#include "core/error.hpp"
#include "models/plants/seaweed_mechanics.hpp"

namespace biota::models::plants {

void MechanicsParams::declare_config(core::ConfigSchema& s) {
  s.add_real("seaweed.radius", 0.005, 0.0, std::nullopt, "m", "sphere radius (growth points)",
             true);
  s.add_real("seaweed.spacing", 0.01, 0.0, std::nullopt, "m", "max sphere spacing along stems",
             true);
  s.add_real("seaweed.plant_density", 1200, 0.0, std::nullopt, "kg/m^3", "plant density", true);
  s.add_real("seaweed.water_density", 998, 0.0, std::nullopt, "kg/m^3", "water density (eq. 9, 10)",
             true);
  s.add_real("seaweed.gravity", 9.8, 0.0, std::nullopt, "m/s^2", "gravitational acceleration");
  s.add_real("seaweed.drag_cd", 1.0, 0.0, std::nullopt, "-", "drag coefficient C_D (eq. 10)");
  s.add_real("seaweed.joint.stiffness", 50, 0.0, std::nullopt, "N/m",
             "stretch spring at the joint anchor", true);
  s.add_real("seaweed.joint.damping", 0.01, 0.0, std::nullopt, "N s/m", "stretch damper");
  s.add_real("seaweed.joint.bend_stiffness", 1e-4, 0.0, std::nullopt, "N m/rad",
             "3-DOF rotational spring");
  s.add_real("seaweed.joint.bend_damping", 2e-7, 0.0, std::nullopt, "N m s/rad",
             "rotational damper");
  s.add_real("seaweed.joint.force_limit", 1000, 0.0, std::nullopt, "N", "F_c of eq. 8", true);
  s.add_real("seaweed.joint.torque_limit", 1000, 0.0, std::nullopt, "N m", "T_c of eq. 8", true);
  s.add_real("seaweed.contact.stiffness", 50, 0.0, std::nullopt, "N/m", "normal contact spring");
  s.add_real("seaweed.contact.damping", 0.01, 0.0, std::nullopt, "N s/m", "normal contact damper");
  s.add_real("seaweed.contact.friction", 0.5, 0.0, std::nullopt, "-",
             "Coulomb friction coefficient");
  s.add_real("seaweed.contact.tangential_damping", 0.01, 0.0, std::nullopt, "N s/m",
             "viscous tangential friction below the Coulomb cap");
  s.add_real("seaweed.cluster_margin", 0.001, 0.0, std::nullopt, "m", "gap counted as contact");
  s.add_real("seaweed.skin", 0.01, 0.0, std::nullopt, "m", "neighbour-list skin");
  s.add_int("seaweed.substeps", 20, 1, 10000, "mechanics sub-steps per physics step");
  s.add_int("seaweed.sub_step_block", -1, -1, 1000000000,
            "owned spheres per block of a mechanics sub-step (0: a rank's spheres in one block; "
            "-1: blocks of 2048 where a rank owns more than 32768 spheres and the interactions "
            "shared between blocks add at most a tenth); changes no result, only speed");
}

MechanicsParams MechanicsParams::from_config(const core::Config& c) {
  MechanicsParams p;
  p.radius = c.get_real("seaweed.radius");
  p.spacing = c.get_real("seaweed.spacing");
  p.plant_density = c.get_real("seaweed.plant_density");
  p.water_density = c.get_real("seaweed.water_density");
  p.gravity = c.get_real("seaweed.gravity");
  p.drag_cd = c.get_real("seaweed.drag_cd");
  p.joint_k = c.get_real("seaweed.joint.stiffness");
  p.joint_c = c.get_real("seaweed.joint.damping");
  p.bend_k = c.get_real("seaweed.joint.bend_stiffness");
  p.bend_c = c.get_real("seaweed.joint.bend_damping");
  p.force_limit = c.get_real("seaweed.joint.force_limit");
  p.torque_limit = c.get_real("seaweed.joint.torque_limit");
  p.contact_k = c.get_real("seaweed.contact.stiffness");
  p.contact_c = c.get_real("seaweed.contact.damping");
  p.friction = c.get_real("seaweed.contact.friction");
  p.friction_c = c.get_real("seaweed.contact.tangential_damping");
  p.cluster_margin = c.get_real("seaweed.cluster_margin");
  p.skin = c.get_real("seaweed.skin");
  p.substeps = static_cast<int>(c.get_int("seaweed.substeps"));
  p.sub_step_block = c.get_int("seaweed.sub_step_block");
  return p;
}

Real MechanicsParams::mass() const {
  return plant_density * 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;
}
Real MechanicsParams::inertia() const {
  return 0.4 * mass() * radius * radius;
}

Real MechanicsParams::ghost_cutoff() const {
  return std::max(2 * radius + cluster_margin + skin, 2 * spacing + skin);
}

Real MechanicsParams::omega_max() const {
  // A sphere in a chain has two joints and at most ~12 contacts; each joint spring also acts on
  // the rotation through the anchor lever r (k r^2 / I = 2.5 k / m).
  const Real m = mass();
  const Real lin = (2 * joint_k * 2 + 12 * contact_k) / m;
  const Real rot = 2 * joint_k * 2.5 / m + 2 * bend_k / inertia();
  return std::sqrt(lin + rot);
}

particles::ParticleLayout seaweed_layout() {
  particles::ParticleLayout l;
  l.add_real("v", 3, true, true);
  l.add_real("q", 4, true, true);
  l.add_real("omega", 3, true, true);
  l.add_real("force", 3, false, false);
  l.add_real("torque", 3, false, false);
  l.add_real("u_fluid", 3, true, false);
  // Joint rest data and the drag impulse travel with ghosts: a joint or a contact is evaluated by
  // every rank owning one of its spheres, and spreading reads ghosts' impulses (decomposition
  // invariance, see begin_step).
  l.add_real("drag_impulse", 3, true, true);
  // A joint's anchor in its child's frame. Its parent's anchor is the mirror, 0 - anchor_child,
  // and its rest relative orientation the identity: every sphere is built with the identity
  // orientation at the midpoint anchor (SeaweedBodies::build), so neither is stored.
  l.add_real("anchor_child", 3, true, true);
  l.add_position("x_sample", true, true);  // shifted with periodic images (spreading point)
  l.add_real("joint_force", 1, true, false);
  l.add_real("joint_torque", 1, true, false);
  l.add_real("radius", 1, true, true);
  l.add_u64("plant", 1, true, true);
  l.add_u64("parent", 1, true, true);
  return l;
}

void to_current_seaweed_rows(std::vector<double>& rows, int& width, const std::string& path,
                             MPI_Comm comm) {
  const particles::ParticleSet set(seaweed_layout());
  const int current = set.pack_width(false);
  constexpr int kDropped = 7;  // anchor_parent (3), q_rest (4)
  // The width is the dataset's, the same on every rank: every rank returns or throws alike.
  if (width == current) return;
  if (width != current + kDropped)
    throw core::InputError(fmt::format(
        "{}: seaweed_particles rows have {} values; this version reads {} (another layout)", path,
        width, current));
  int anchor_end = 0;  // one past anchor_child in a row (the migrating columns in layout order)
  for (const auto& a : set.layout().reals())
    if (a.migrate) {
      anchor_end += a.ncomp;
      if (a.name == "anchor_child") break;
    }
  const std::size_t n = rows.size() / static_cast<std::size_t>(width);
  long long odd = 0;  // rows whose dropped values are not the implied ones
  for (std::size_t r = 0; r < n; ++r) {
    const double* in = rows.data() + r * static_cast<std::size_t>(width);
    const double* dropped = in + anchor_end;
    bool implied = dropped[3] == 1 && dropped[4] == 0 && dropped[5] == 0 && dropped[6] == 0;
    for (int d = 0; d < 3; ++d)
      implied = implied && std::bit_cast<std::uint64_t>(dropped[d]) ==
                               std::bit_cast<std::uint64_t>(0.0 - in[anchor_end - 3 + d]);
    odd += implied ? 0 : 1;
    double* out = rows.data() + r * static_cast<std::size_t>(current);  // out <= in: in place
    std::memmove(out, in, sizeof(double) * static_cast<std::size_t>(anchor_end));
    std::memmove(out + anchor_end, dropped + kDropped,
                 sizeof(double) * static_cast<std::size_t>(current - anchor_end));
  }
  rows.resize(n * static_cast<std::size_t>(current));
  width = current;
  MPI_Allreduce(MPI_IN_PLACE, &odd, 1, MPI_LONG_LONG, MPI_SUM, comm);  // every rank throws alike
  if (odd > 0)
    throw core::InputError(path + ": " + std::to_string(odd) +
                           " seaweed_particles rows have a parent anchor other than the mirror of "
                           "the child anchor or a rest orientation other than the identity");
}

}  // namespace biota::models::plants
