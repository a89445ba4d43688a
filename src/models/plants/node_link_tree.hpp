#pragma once
/// \file node_link_tree.hpp
/// \brief The node-link tree of the tree paper, section 3 (after Kanayama & Masuyama 1997), in
/// the readings of ../shared/spec/tree.md section 2.2 and docs/tree.md.
///
/// Nodes are the turtle segments' end points plus one fixed root per distinct segment start
/// without a parent; the link into node P (from its parent) carries P's radius r_P and length
/// l_P, lumped at P: mass (1) m = pi r^2 l delta, area (2) s = 2 pi r l. Per step (dt):
///   (3) F_w = K_w (v_wind - v) s,  (4) F_g = m g,
///   (5) F_r = pi r^2 / l K_r (P' - P) with P' = P_parent + b, b = the initial link vector rotated
///       by the minimal rotation (quaternion) that takes the parent link's initial direction to
///       its current one (spec 2.2.4, [suggestion]; the first link's parent is the fixed ground),
///   (6) reaction on the parent j of k (grandparent i): F_d = -K_react |P_k - P_i| / |P_j - P_i|
///       times the part of F_r perpendicular to P_k - P_i (moment balance about P_i),
///   (7)-(9) v <- K_damp^(dt/dt_cal) v + F / m dt,  (10) P <- P + v dt (errata 3: with dt),
///   (11) link lengths restored root to tips; the velocity is then (P_new - P_old) / dt.
/// K_react (0.8) and K_damp (0.83) are the two K_d of the paper (errata 2). K_damp is a per-step
/// factor; it is calibrated for dt_cal (default 1/30 s, one animation frame) and rescaled as
/// K_damp^(dt/dt_cal) for other dt (errata 4), so dt = dt_cal is exactly the paper's (9).
#include <cstdint>
#include <vector>

#include "core/types.hpp"
#include "models/plants/turtle.hpp"

namespace biota::models::plants {

using core::Vec3;

/// \brief Constants of the paper's section 6 (SI).
struct NodeLinkParams {
  double density = 230;               ///< delta (kg/m^3)
  double k_restore = 1e4;             ///< K_r (N/m^2)
  double k_wind = 0.08;               ///< K_w (N s/m^3)
  double k_react = 0.8;               ///< K_d of (6)
  double k_damp = 0.83;               ///< K_d of (9), per step of dt_cal
  double damp_dt = 1.0 / 30;          ///< dt_cal (s)
  Vec3 gravity{0, -9.8, 0};           ///< m/s^2 (turtle frame: +y up)
  double r_min = 0.02, r_max = 0.05;  ///< radius range (m)
  bool pipe_radii = true;  ///< pipe model (r^2 ~ tips above); false: the turtle's widths scaled
};

/// \brief A tree of nodes and links; node arrays indexed so that parent[i] < i.
class NodeLinkTree {
 public:
  /// \brief Nodes from turtle segments scaled by `scale` (m per turtle unit), shifted by `base`.
  NodeLinkTree(const TurtleGeometry& g, double scale, const Vec3& base, const NodeLinkParams& p);
  /// \brief Nodes given directly (tests): positions, parents (-1 = fixed root), radii.
  NodeLinkTree(std::vector<Vec3> pos, std::vector<std::int64_t> parent, std::vector<double> radius,
               const NodeLinkParams& p);

  /// \brief One step of (3)-(11). `wind` holds the wind velocity at every node (roots ignored);
  /// `wind_force` (optional, size n) receives F_w of every node for the two-way coupling;
  /// `extra` (optional, size n) is added to the force (7) of every node (branch contacts).
  void step(double dt, const std::vector<Vec3>& wind, std::vector<Vec3>* wind_force = nullptr,
            const std::vector<Vec3>* extra = nullptr);

  std::size_t size() const { return pos_.size(); }
  const std::vector<Vec3>& positions() const { return pos_; }
  std::vector<Vec3>& positions() { return pos_; }
  const std::vector<Vec3>& velocities() const { return vel_; }
  std::vector<Vec3>& velocities() { return vel_; }
  const std::vector<Vec3>& initial_positions() const { return pos0_; }
  const std::vector<std::int64_t>& parents() const { return parent_; }
  const std::vector<double>& radii() const { return radius_; }
  const std::vector<double>& masses() const { return mass_; }
  /// \brief Largest |P - P(0)| over the nodes (m).
  double max_displacement() const;
  /// \brief Largest angle (rad) between a link and its initial direction.
  double max_bending_angle() const;
  /// \brief Highest node (m, along +y) minus the lowest root.
  double height() const;
  const NodeLinkParams& params() const { return p_; }

 private:
  void init();
  NodeLinkParams p_;
  std::vector<Vec3> pos_, pos0_, vel_, rest_, dir0_, force_, old_;
  std::vector<std::int64_t> parent_;
  std::vector<double> radius_, length_, mass_, area_, k_link_;
};

}  // namespace biota::models::plants
