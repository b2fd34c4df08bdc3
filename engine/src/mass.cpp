#include "pteromys/mass.hpp"

namespace pteromys {

MassModel::MassModel(const Glider& g)
    : rho_t_(g.material.density_kg_m3 * g.material.thickness_m),
      t_(g.material.thickness_m),
      fuselage_(area_moments(g.fuselage)) {
  for (const auto& w : g.wings) wings_.push_back(area_moments(w.outline));
  for (const auto& b : g.ballast) ballast_mass_.push_back(b.mass_kg);
}

MassProperties MassModel::evaluate(const std::vector<Mount>& mounts,
                                   const std::vector<Vec2>& ballast_positions) const {
  // Accumulate mass M, first moment S (about the glider origin) and the polar
  // second moment J = int |r|^2 dm about the origin; then shift to the CG.
  double M = rho_t_ * fuselage_.A;
  Vec2 S{rho_t_ * fuselage_.Sx, rho_t_ * fuselage_.Sy};
  double J = rho_t_ * (fuselage_.Sxx + fuselage_.Syy);
  for (std::size_t j = 0; j < wings_.size(); ++j) {
    // Wing plate: points P + R(Theta) (x_w, y_w), y_w in [-t/2, t/2] across the
    // plate. |r|^2 = |P|^2 + 2 P . R(x_w, y_w) + x_w^2 + y_w^2 integrated over
    // the plate; int y_w = 0 and int y_w^2 = t^3 / 12 per unit area.
    const AreaMoments& w = wings_[j];
    const Mount& m = mounts.at(j);
    const Vec2 P{m.x_m, m.y_m};
    const double th = deg2rad(m.angle_deg);
    const double mw = rho_t_ * w.A;
    const Vec2 first_local = rotate({rho_t_ * w.Sx, 0.0}, th);  // int R(x_w, 0) dm
    M += mw;
    S = S + mw * P + first_local;
    J += mw * dot(P, P) + 2 * dot(P, first_local) + rho_t_ * w.Sxx +
         mw * (t_ * t_ / 12.0);
  }
  for (std::size_t k = 0; k < ballast_mass_.size(); ++k) {
    const Vec2 q = ballast_positions.at(k);
    M += ballast_mass_[k];
    S = S + ballast_mass_[k] * q;
    J += ballast_mass_[k] * dot(q, q);
  }
  MassProperties out;
  out.mass = M;
  out.cg = M > 0 ? (1.0 / M) * S : Vec2{};
  out.inertia = J - M * dot(out.cg, out.cg);
  return out;
}

MassProperties MassModel::evaluate(const Glider& g) const {
  std::vector<Mount> mounts;
  for (const auto& w : g.wings) mounts.push_back(w.mount);
  std::vector<Vec2> bp;
  for (const auto& b : g.ballast) bp.push_back({b.x_m, b.y_m});
  return evaluate(mounts, bp);
}

MassProperties mass_properties(const Glider& g) { return MassModel(g).evaluate(g); }

}  // namespace pteromys
