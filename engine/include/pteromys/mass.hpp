// Mass properties of a glider: mass, centre of gravity, pitch inertia.
#pragma once

#include <vector>

#include "pteromys/geometry.hpp"
#include "pteromys/glider.hpp"

namespace pteromys {

struct MassProperties {
  double mass = 0.0;     ///< kg
  Vec2 cg;               ///< glider frame (x, y) [m]
  double inertia = 0.0;  ///< pitch moment of inertia about the CG, about z [kg m^2]
};

/// Mass properties of the plates and ballast. Each plate has mass
/// area x thickness x density; a wing plate is centred on its own plane and is
/// placed by its mount (translation and rotation Theta). Pitch inertia is exact
/// for prismatic plates (the wing plate's thickness contributes t^2/12 per unit
/// mass). The overlap of plates at their joints and the material removed by
/// slots are ignored (both are below 1% of the mass for usual designs).
MassProperties mass_properties(const Glider& g);

/// Precomputed per-plate integrals, so that mass properties for new mounts or
/// ballast positions cost a few flops (used by the optimiser).
class MassModel {
 public:
  explicit MassModel(const Glider& g);
  /// Mass properties with the given mounts (one per wing, in order) and
  /// ballast positions (one per ballast item, glider frame [m]).
  MassProperties evaluate(const std::vector<Mount>& mounts,
                          const std::vector<Vec2>& ballast_positions) const;
  MassProperties evaluate(const Glider& g) const;

 private:
  double rho_t_ = 0.0, t_ = 0.0;
  AreaMoments fuselage_;
  std::vector<AreaMoments> wings_;  // in wing coordinates (x, z)
  std::vector<double> ballast_mass_;
};

}  // namespace pteromys
