#include "pteromys/mass.hpp"

#include <gtest/gtest.h>

#include "test_support.hpp"

using namespace pteromys;
using pteromys::test::rect;

namespace {
Glider plate_only(double L, double H, double t, double rho) {
  Glider g;
  g.material = {t, rho};
  g.fuselage = rect(-L, -H / 2, 0, H / 2);
  return g;
}
}  // namespace

// A rectangular plate L x H: m = rho t L H, CG at its centre,
// I_zz = m (L^2 + H^2) / 12 (thin plate, axis normal to the plate).
TEST(Mass, RectangularFuselagePlate) {
  const double L = 0.3, H = 0.02, t = 0.001, rho = 180;
  const MassProperties mp = mass_properties(plate_only(L, H, t, rho));
  const double m = rho * t * L * H;
  EXPECT_NEAR(mp.mass, m, 1e-15);
  EXPECT_NEAR(mp.cg.x, -L / 2, 1e-14);
  EXPECT_NEAR(mp.cg.y, 0, 1e-14);
  EXPECT_NEAR(mp.inertia, m * (L * L + H * H) / 12, 1e-14 * m);
}

// A rectangular wing plate (chord c along x, span b along z, thickness t
// across) turned by Theta: about the pitch axis through its centroid the
// inertia is m (c^2 + t^2) / 12 whatever Theta, and its centroid sits at
// mount + R(Theta) (-c/2, 0).
TEST(Mass, RotatedWingPlateInertiaIsIndependentOfAngle) {
  const double c = 0.06, b = 0.4, t = 0.003, rho = 180;
  for (double th : {0.0, 7.0, -20.0, 45.0}) {
    // Negligible fuselage (1e-10 m^2, 4e-9 of the wing) so that the wing alone counts.
    Glider g = plate_only(1e-5, 1e-5, t, rho);
    Wing w;
    w.name = "w";
    w.outline = rect(-c, -b / 2, 0, b / 2);
    w.mount = {0.1, 0.02, th};
    g.wings.push_back(w);
    const MassProperties mp = mass_properties(g);
    const double m = rho * t * c * b;
    EXPECT_NEAR(mp.mass, m, 1e-8 * m);
    const Vec2 expect = Vec2{0.1, 0.02} + rotate({-c / 2, 0}, deg2rad(th));
    EXPECT_NEAR(mp.cg.x, expect.x, 1e-9);
    EXPECT_NEAR(mp.cg.y, expect.y, 1e-9);
    EXPECT_NEAR(mp.inertia, m * (c * c + t * t) / 12, 1e-6 * m * c * c);
  }
}

// Two point masses m1, m2 at distance d: I about the common CG is
// m1 m2 / (m1 + m2) d^2 (reduced mass).
TEST(Mass, BallastFollowsParallelAxisTheorem) {
  Glider g = plate_only(1e-3, 1e-3, 1e-3, 1e-9);
  g.ballast.push_back({"a", 0.002, 0.0, 0.0});
  g.ballast.push_back({"b", 0.003, -0.1, 0.05});
  const MassProperties mp = mass_properties(g);
  const double d2 = 0.1 * 0.1 + 0.05 * 0.05;
  EXPECT_NEAR(mp.mass, 0.005, 1e-12);
  EXPECT_NEAR(mp.cg.x, -0.06, 1e-9);
  EXPECT_NEAR(mp.cg.y, 0.03, 1e-9);
  EXPECT_NEAR(mp.inertia, 0.002 * 0.003 / 0.005 * d2, 1e-12);
}

// The fast mass model used by the optimiser agrees with a fresh computation
// after mounts move, for every example.
TEST(Mass, MassModelMatchesRecomputationForMovedMounts) {
  for (auto [path, g] : test::examples()) {
    const MassModel mm(g);
    for (auto& w : g.wings) {
      w.mount.x_m -= 0.01;
      w.mount.angle_deg += 3;
    }
    const MassProperties a = mm.evaluate(g), b = mass_properties(g);
    EXPECT_NEAR(a.mass, b.mass, 1e-15) << path;
    EXPECT_NEAR(a.cg.x, b.cg.x, 1e-14) << path;
    EXPECT_NEAR(a.inertia, b.inertia, 1e-15) << path;
  }
}
