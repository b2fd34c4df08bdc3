#include "pteromys/aero.hpp"

#include <random>

#include <gtest/gtest.h>

#include "pteromys/io.hpp"
#include "test_support.hpp"

using namespace pteromys;

namespace {
std::shared_ptr<const CoefficientModel> models(int i) {
  if (i == 0) return std::make_shared<FlatPlateModel>();
  // An RBF model over a flat-plate prior with centres spread over the inputs.
  std::vector<RbfCentre> cs;
  int k = 0;
  for (double a : {3.0, 8.0, 15.0})
    for (double xl : {-20.0, 0.0, 30.0}) {
      const double bump = 0.05 * ((k++ % 3) - 1);
      cs.push_back({deg2rad(a), 2e4, deg2rad(xl), deg2rad(0.5 * xl), {0.03 + std::abs(bump), 0.1 * a / 8 + bump, -0.02}});
    }
  return std::make_shared<RbfModel>(cs, RbfScales{}, deg2rad(30), std::make_shared<FlatPlateModel>());
}
}  // namespace

// Tables (bicubic in log V and alpha, 0.25 deg spacing) reproduce direct
// evaluation within 0.1 % of the wing's largest lift over the range, for every
// example wing and both model kinds.
TEST(Aero, TablesAgreeWithDirectEvaluation) {
  const Environment env;
  std::mt19937 rng(5);
  for (int mi = 0; mi < 2; ++mi) {
    const auto model = models(mi);
    std::uniform_real_distribution<double> uv(2.0, 20.0), ua(-model->alpha_limit(), model->alpha_limit());
    for (const auto& [path, g] : test::examples())
      for (const auto& w : g.wings) {
        const WingElements el = slice_wing(w.outline, 0.005);
        const WingTable t(el, *model, env);
        double peak = 0;
        for (double a = -model->alpha_limit(); a <= model->alpha_limit(); a += 0.01)
          peak = std::max(peak, std::abs(wing_coefs_direct(el, *model, env, 7, a).lift));
        const double chord = el.planform_area / el.span;
        for (int i = 0; i < 200; ++i) {
          const double v = uv(rng), a = ua(rng);
          const WingCoefs d = wing_coefs_direct(el, *model, env, v, a), l = t.lookup(v, a);
          ASSERT_NEAR(l.lift, d.lift, 1e-3 * peak) << path << " " << w.name << " v=" << v << " a=" << a;
          ASSERT_NEAR(l.drag, d.drag, 1e-3 * peak) << path << " " << w.name;
          ASSERT_NEAR(l.moment, d.moment, 1e-3 * peak * chord) << path << " " << w.name;
        }
      }
  }
}

// Eq. 2 summed and moved to the CG is the same as adding, element by element,
// the air force applied at the element's quarter-chord point in the glider
// frame (vector cross products) plus its own quarter-chord moment.
TEST(Aero, CharacteristicFunctionMatchesVectorSumOverElements) {
  const Environment env;
  for (int mi = 0; mi < 2; ++mi) {
    const auto model = models(mi);
    for (const auto& [path, g] : test::examples()) {
      const MountedGlider mg = mount(g, model, env);
      for (double V : {4.0, 8.0})
        for (double gam : {-0.1, 0.02, 0.15}) {
          // Velocity direction in the glider frame: the nose is gamma above it.
          const Vec2 u{std::cos(gam), -std::sin(gam)};
          const Vec2 nrm{std::sin(gam), std::cos(gam)};  // lift direction
          const double q = 0.5 * env.air_density * V * V;
          Vec2 Fsum{};
          double T = 0;
          for (std::size_t j = 0; j < g.wings.size(); ++j) {
            const Mount& m = g.wings[j].mount;
            const double th = deg2rad(m.angle_deg);
            const double alpha = gam + th;
            for (const auto& e : mg.aero().elements(j).elements) {
              const Coefficients c = model->eval({alpha, env.air_density * V * e.chord / env.air_viscosity, e.xi_l, e.xi_t});
              const Vec2 F = (-q * e.area * c.cd) * u + (q * e.area * c.cl) * nrm;
              const Vec2 r = Vec2{m.x_m, m.y_m} + rotate({e.x_qc, 0}, th) - mg.mass().cg;
              Fsum = Fsum + F;
              T += cross(r, F) + q * e.area * e.chord * c.cm;
            }
          }
          const GliderForces f = mg.forces_direct(V, gam);
          const double drag = -dot(Fsum, u), lift = dot(Fsum, nrm);
          const double tol = 1e-12 * (std::abs(lift) + std::abs(drag) + 1e-6);
          EXPECT_NEAR(f.drag, drag, tol) << path;
          EXPECT_NEAR(f.lift, lift, tol) << path;
          EXPECT_NEAR(f.moment, T, tol * 0.5) << path;
        }
    }
  }
}

// Eq. 1: without Reynolds-number effects the forces scale with V^2. The
// flat-plate element's lift and moment-from-lift have no Re dependence.
TEST(Aero, LiftScalesWithSpeedSquared) {
  const auto model = std::make_shared<FlatPlateModel>();
  for (const auto& [path, g] : test::examples()) {
    const MountedGlider mg = mount(g, model);
    const double a = mg.forces_direct(5, 0.05).lift, b = mg.forces_direct(10, 0.05).lift;
    EXPECT_NEAR(b, 4 * a, 1e-12 * std::abs(b)) << path;
  }
}

// Table look-ups are what the simulation uses: F(V, gamma) from tables agrees
// with direct evaluation on the paper's 4 x 21 grid over Omega.
TEST(Aero, GliderForcesFromTablesOnOmegaGrid) {
  const auto model = default_model();
  for (const auto& [path, g] : test::examples()) {
    const MountedGlider mg = mount(g, model);
    const double W = mg.mass().mass * 9.81;
    for (int iv = 0; iv < 4; ++iv)
      for (int ig = 0; ig < 21; ++ig) {
        const double V = 6 + iv, gam = deg2rad(-10 + ig);
        const GliderForces t = mg.forces(V, gam), d = mg.forces_direct(V, gam);
        const double scale = std::max(W, std::abs(d.lift));
        EXPECT_NEAR(t.lift, d.lift, 2e-3 * scale) << path;
        EXPECT_NEAR(t.drag, d.drag, 2e-3 * scale) << path;
        EXPECT_NEAR(t.moment, d.moment, 2e-3 * scale * 0.05) << path;
      }
  }
}
