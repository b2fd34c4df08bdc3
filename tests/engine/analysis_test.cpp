#include "pteromys/analysis.hpp"

#include <gtest/gtest.h>

#include "pteromys/io.hpp"
#include "test_support.hpp"

using namespace pteromys;

// At a trim point the pitching moment vanishes and restores (dT/dgamma < 0).
TEST(Analysis, TrimPointsAreStableEquilibria) {
  const auto model = default_model();
  for (const auto& [path, g] : test::examples()) {
    const MountedGlider mg = mount(g, model);
    TrimPoint t;
    if (!find_trim(mg, 7.0, deg2rad(-20), deg2rad(20), &t)) continue;
    const double scale = std::abs(mg.forces(7, t.gamma + 0.05).moment) + 1e-12;
    EXPECT_NEAR(mg.forces(7, t.gamma).moment, 0.0, 1e-9 * scale) << path;
    EXPECT_LT(t.dmoment_dgamma, 0) << path;
  }
}

// The neutral point is where dT/dgamma vanishes: with the CG put there the
// moment's slope is about zero.
TEST(Analysis, MomentSlopeVanishesAboutTheNeutralPoint) {
  const auto model = default_model();
  for (const auto& [path, g] : test::examples()) {
    const MountedGlider mg = mount(g, model);
    for (double gm : {deg2rad(-2.0), deg2rad(3.0)}) {
      const double xnp = neutral_point(mg, 7.0, gm);
      MassProperties mp = mg.mass();
      mp.cg.x = xnp;
      const MountedGlider at_np(mg.aero_ptr(), mg.mounts(), mp);
      const double h = deg2rad(0.25);
      const double s_np = (at_np.forces(7, gm + h).moment - at_np.forces(7, gm - h).moment) / (2 * h);
      const double s_cg = (mg.forces(7, gm + h).moment - mg.forces(7, gm - h).moment) / (2 * h);
      EXPECT_LT(std::abs(s_np), 0.01 * std::abs(s_cg) + 1e-9) << path;
    }
  }
}

// Classical result: wings with equal lift slopes and no mutual interference
// have their neutral point at the area-weighted mean of their aerodynamic
// centres (quarter-chord points). The flat-plate element gives every element
// the same slope, so at gamma = 0 with zero mounting angles the neutral point
// is sum(a_i x_qc,i) / sum(a_i) over all elements (drag terms shift it by
// well under a millimetre).
TEST(Analysis, NeutralPointIsAreaWeightedQuarterChordForEqualSlopes) {
  const auto model = std::make_shared<FlatPlateModel>();
  for (auto [path, g] : test::examples()) {
    for (auto& w : g.wings) w.mount.angle_deg = 0;
    const MountedGlider mg = mount(g, model);
    double sa = 0, sx = 0;
    for (std::size_t j = 0; j < g.wings.size(); ++j)
      for (const auto& e : mg.aero().elements(j).elements) {
        sa += e.area;
        sx += e.area * (g.wings[j].mount.x_m + e.x_qc);
      }
    EXPECT_NEAR(neutral_point(mg, 7.0, 0.0), sx / sa, 1e-3) << path;
  }
}

// In a steady glide the air force balances the weight and the glide ratio
// equals lift / drag = cot(path angle).
TEST(Analysis, SteadyGlideBalancesWeight) {
  const auto model = default_model();
  for (const auto& [path, g] : test::examples()) {
    const MountedGlider mg = mount(g, model);
    const Glide gl = steady_glide(mg, deg2rad(-20), deg2rad(20));
    if (!gl.exists) continue;
    const GliderForces f = mg.forces(gl.speed, gl.gamma);
    const double W = mg.mass().mass * 9.81;
    EXPECT_NEAR(std::hypot(f.lift, f.drag), W, 1e-4 * W) << path;
    EXPECT_NEAR(gl.ratio, 1 / std::tan(gl.path_angle), 1e-9 * gl.ratio) << path;
  }
}

// The glide search works on any aerodynamic model: through QuasiStaticAero
// (world-frame forces turned back into F(V, gamma) by level_forces) it finds
// the mounted glider's own glide, and level_forces returns the mounted
// glider's forces at any (V, gamma).
TEST(Analysis, SteadyGlideOfAnyModelMatchesTheMountedGlider) {
  const auto model = default_model();
  int compared = 0;
  for (const auto& [path, g] : test::examples()) {
    const MountedGlider mg = mount(g, model);
    const QuasiStaticAero qa(mg);
    for (double v : {4.0, 7.5})
      for (double gm : {-0.1, 0.05, 0.2}) {
        const GliderForces a = mg.forces(v, gm), b = level_forces(qa, v, gm);
        EXPECT_NEAR(b.lift, a.lift, 1e-12 + 1e-9 * std::abs(a.lift)) << path;
        EXPECT_NEAR(b.drag, a.drag, 1e-12 + 1e-9 * std::abs(a.drag)) << path;
        EXPECT_NEAR(b.moment, a.moment, 1e-14 + 1e-9 * std::abs(a.moment)) << path;
      }
    const Glide a = steady_glide(mg, deg2rad(-15), deg2rad(25));
    const Glide b = steady_glide(qa, RigidBody{mg.mass().mass, mg.mass().inertia}, 9.81);
    ASSERT_EQ(a.exists, b.exists) << path;
    if (!a.exists) continue;
    ++compared;
    EXPECT_NEAR(b.speed, a.speed, 1e-6 * a.speed) << path;
    EXPECT_NEAR(b.gamma, a.gamma, 1e-8) << path;
    EXPECT_NEAR(b.ratio, a.ratio, 1e-6 * a.ratio) << path;
  }
  EXPECT_GE(compared, 10);
}

// A wing alone with the CG far behind it cannot fly, and the report says why.
TEST(Analysis, UnflyableDesignGetsReasons) {
  Glider g = test::simple_glider(0.06, 0.4, -0.02, 0.0, 3.0);
  g.ballast.push_back({"tail weight", 0.01, -0.28, 0.0});
  const Flyability f = analyse(mount(g, default_model()), {"main"});
  EXPECT_FALSE(f.flyable);
  ASSERT_FALSE(f.reasons.empty());
  EXPECT_NE(f.reasons.front().find("pitch"), std::string::npos) << f.reasons.front();
}
