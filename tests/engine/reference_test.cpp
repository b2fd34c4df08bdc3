// Reference simulator: section law, lattice against classical results,
// effect switches, added mass, flight (src/reference_section.cpp,
// src/reference_vlm.cpp).
#include "pteromys/reference.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "pteromys/io.hpp"
#include "test_support.hpp"

using namespace pteromys;

namespace {

constexpr double kRho = 1.2, kMu = 1.8e-5;

// Glider with one bare wing (mount at the origin, no fuselage): wind-tunnel model.
Glider bare_wing(const Polygon& outline, double thickness = 0.001) {
  Glider g;
  g.name = "bare";
  g.material = {thickness, 200.0};
  Wing w;
  w.name = "wing";
  w.outline = outline;
  w.mount = {0.0, 0.0, 0.0};
  g.wings.push_back(w);
  return g;
}

// Rectangle of chord c and span b, leading edge at x = 0.
Polygon rect_wing(double c, double b) { return test::rect(-c, -b / 2, 0.0, b / 2); }

// Ellipse of root chord c0 and span b with a straight mid-chord line
// (x = -c0/2 +- c(z)/2, c(z) = c0 sqrt(1 - (2z/b)^2)), n points per half.
Polygon ellipse_wing(double c0, double b, int n = 200) {
  Polygon p;
  for (int i = 0; i < 2 * n; ++i) {
    const double th = kPi * i / n;  // 0..2pi
    p.push_back({-c0 / 2 + c0 / 2 * std::cos(th), b / 2 * std::sin(th)});
  }
  return p;
}

// Glider with a rectangular main wing and a rectangular tail on a fuselage plate.
Glider wing_and_tail(double main_angle_deg = 2.0, double tail_angle_deg = 0.0) {
  Glider g = test::simple_glider(0.06, 0.4, -0.05, 0.0, main_angle_deg);
  Wing t;
  t.name = "tail";
  t.outline = rect_wing(0.04, 0.15);
  t.mount = {-0.25, 0.005, tail_angle_deg};
  g.wings.push_back(t);
  g.ballast.push_back({"nose", 0.004, -0.01, 0.0});
  return g;
}

ReferenceOptions with(Effects e, int span = 10, int chord = 4) {
  ReferenceOptions o;
  o.effects = e;
  o.span_panels = span;
  o.chord_panels = chord;
  return o;
}

FlightState level(double v, double alpha, double omega = 0, double height = 1e9) {
  FlightState s;
  s.v = {v, 0.0};
  s.beta = alpha;
  s.omega = omega;
  s.p = {0.0, height};
  return s;
}

double helmbold(double A, double a0 = 2 * kPi) {
  const double k = a0 / (kPi * A);
  return a0 / (std::sqrt(1 + k * k) + k);
}

}  // namespace

// ------------------------------------------------------------ section law

// Thin-plate theory gives dc_n/dalpha = 2 pi (Anderson, Fundamentals of
// Aerodynamics, section 4.7); at 1 deg 1.8 % of the blend is already the
// separated law (slope C_N90 / 0.56), so the tolerance is 2 %.
TEST(ReferenceSection, NormalForceFollowsThinPlateTheoryAtSmallAngles) {
  const SectionLaw law;
  const double a = deg2rad(1.0);
  EXPECT_NEAR(law.normal_force(a, 1.98) / a, 2 * kPi, 0.02 * 2 * kPi);
}

// A plate broadside to the flow: C_N = 1.98 in 2D (Hoerner, Fluid-Dynamic
// Drag, 1965, ch. 3); finite plates 1.17-1.2 for A = 1-5 and 1.98 as A grows.
TEST(ReferenceSection, BroadsideNormalForceIsHoerners) {
  const SectionLaw law;
  EXPECT_NEAR(law.normal_force(kPi / 2, 1.98), 1.98, 1e-12);
  EXPECT_NEAR(normal_force_90(1.0), 1.17, 0.02);
  EXPECT_NEAR(normal_force_90(5.0), 1.19, 0.02);
  EXPECT_NEAR(normal_force_90(1e6), 1.98, 0.01);
}

// A flat plate is symmetric: c_n is odd in alpha and the same for the flow
// from behind (alpha -> pi - alpha).
TEST(ReferenceSection, NormalForceIsOddAndSymmetricUnderFlowReversal) {
  const SectionLaw law;
  for (double d = 0.5; d < 180; d += 3.7) {
    const double a = deg2rad(d);
    EXPECT_DOUBLE_EQ(law.normal_force(-a, 1.5), -law.normal_force(a, 1.5)) << d;
    EXPECT_NEAR(law.normal_force(kPi - a, 1.5), law.normal_force(a, 1.5), 1e-12) << d;
  }
}

// The 2D law is monotone in alpha on [0, 90 deg], so the decambering solve
// has one solution; its derivative matches central differences.
TEST(ReferenceSection, NormalForceIsMonotoneWithExactDerivative) {
  const SectionLaw law;
  double prev = -1;
  for (int i = 0; i <= 900; ++i) {
    const double a = deg2rad(0.1 * i);
    double d = 0;
    const double c = law.normal_force(a, 1.98, &d);
    EXPECT_GE(c, prev - 1e-12) << 0.1 * i;
    prev = c;
    const double h = 1e-6;
    const double num = (law.normal_force(a + h, 1.98) - law.normal_force(a - h, 1.98)) / (2 * h);
    EXPECT_NEAR(d, num, 1e-5 * std::max(1.0, std::abs(d))) << 0.1 * i;
  }
}

// Laminar Blasius friction on both faces, 2 x 1.328 / sqrt(Re) (Schlichting,
// Boundary-Layer Theory, eq. 7.34); continuous at the transition Reynolds number.
TEST(ReferenceSection, FrictionIsBlasiusAndContinuousAtTransition) {
  const SectionLaw law;
  EXPECT_NEAR(law.friction(1e4), 2.656 / 100.0, 1e-12);
  EXPECT_NEAR(law.friction(law.transition_re * (1 - 1e-9)), law.friction(law.transition_re * (1 + 1e-9)), 1e-9);
  EXPECT_GT(law.friction(5e6), 2 * 1.328 / std::sqrt(5e6));  // turbulent above
}

// Centre of pressure at the quarter chord in attached flow, mid-chord broadside.
TEST(ReferenceSection, CentreOfPressureMovesFromQuarterToMidChord) {
  const SectionLaw law;
  EXPECT_NEAR(law.centre_of_pressure(deg2rad(2), 1.98), 0.25, 0.01);
  EXPECT_NEAR(law.centre_of_pressure(kPi / 2, 1.98), 0.5, 1e-12);
}

TEST(ReferenceEffects, ParsesSpecificationsAndRejectsUnknownNames) {
  EXPECT_EQ(parse_effects("baseline").describe(), "none");
  const Effects p = parse_effects("physics");
  EXPECT_TRUE(p.downwash.on && p.added_mass.on && !p.wind.on && !p.camera.on);
  Effects e = parse_effects("downwash,wind");
  EXPECT_TRUE(e.downwash.on && e.wind.on && !e.finite_span.on);
  apply_strengths(e, "wind=2.5,camera=1");
  EXPECT_DOUBLE_EQ(e.wind.factor(), 2.5);
  EXPECT_TRUE(e.camera.on);
  apply_strengths(e, "wind=0");
  EXPECT_FALSE(e.wind.on);
  EXPECT_THROW(parse_effects("downwash,vortex"), InputError);
  EXPECT_THROW(apply_strengths(e, "wind"), InputError);
  EXPECT_THROW(apply_strengths(e, "wind=abc"), InputError);
  EXPECT_THROW(apply_strengths(e, "wind=nan"), InputError);
  EXPECT_EQ(Effects::names().size(), 9u);
}

// ------------------------------------------------- lattice vs classical

// Prandtl: an elliptic wing has uniform downwash and the least induced drag,
// C_Di = C_L^2 / (pi A). Tolerance 2 % (polygonal planform, 20 strips).
TEST(ReferenceLattice, EllipticWingInducedDragIsCl2OverPiA) {
  for (double A : {2.0, 6.0, 10.0}) {
    const double c0 = 0.1, b = kPi * A * c0 / 4;
    const ReferenceAero r(bare_wing(ellipse_wing(c0, b)), Vec2{-c0 / 2, 0}, with(Effects::physics(), 20));
    const PotentialSolution ps = r.potential(deg2rad(4));
    const double A_exact = b * b / ps.area;
    EXPECT_NEAR(ps.cdi / (ps.cl * ps.cl / (kPi * A_exact)), 1.0, 0.02) << "A = " << A;
  }
}

// Helmbold's lift slope a0 / (sqrt(1 + (a0 / pi A)^2) + a0 / pi A) with
// a0 = 2 pi (Helmbold 1942; e.g. Anderson eq. 5.81): within 4 % for the
// elliptic wing, 7 % for rectangles (the formula ignores planform; lifting-
// surface results for rectangles lie a few per cent below it).
TEST(ReferenceLattice, LiftSlopeMatchesHelmbold) {
  for (double A : {1.0, 2.0, 4.0, 6.0, 10.0}) {
    const double c0 = 0.1;
    const ReferenceAero e(bare_wing(ellipse_wing(c0, kPi * A * c0 / 4)), Vec2{}, with(Effects::physics(), 20));
    const ReferenceAero r(bare_wing(rect_wing(c0, A * c0)), Vec2{}, with(Effects::physics(), 20));
    const double a = deg2rad(2);
    EXPECT_NEAR(e.potential(a).cl / a / helmbold(A), 1.0, 0.04) << "elliptic A = " << A;
    EXPECT_NEAR(r.potential(a).cl / a / helmbold(A), 1.0, 0.07) << "rectangular A = " << A;
  }
}

// Refining the lattice converges: the changes shrink and the last is below 1 %.
TEST(ReferenceLattice, LiftSlopeConvergesWithPanelCount) {
  std::vector<double> s;
  for (int n : {10, 20, 40, 80}) {
    const ReferenceAero r(bare_wing(rect_wing(0.1, 0.4)), Vec2{}, with(Effects::physics(), n));
    s.push_back(r.potential(deg2rad(2)).cl);
  }
  for (std::size_t i = 2; i < s.size(); ++i) EXPECT_LT(std::abs(s[i] - s[i - 1]), std::abs(s[i - 1] - s[i - 2]));
  EXPECT_LT(std::abs(s[3] - s[2]) / s[3], 0.01);
}

// ------------------------------------------------------ effect switches

// With every effect off, the reference is a 2D strip model of its own
// section law: each plate carries q S c_n(alpha) normal to itself at the
// centre of pressure and friction + edge drag along itself. Independent sum
// here for a glider of two rectangular wings (all strips of a rectangle alike).
TEST(ReferenceEffects, AllOffEqualsStripModelOfTheSameSectionLaw) {
  const Glider g = wing_and_tail(3.0, -1.0);
  const MassProperties mp = mass_properties(g);
  const ReferenceAero r(g, mp.cg, with(Effects::baseline()));
  const SectionLaw law;
  for (double ad : {-6.0, 0.0, 4.0, 12.0, 35.0, 80.0}) {
    const double V = 8.0, gamma = deg2rad(ad);
    Vec2 F{};
    double M = 0;
    for (const Wing& w : g.wings) {
      const double th = deg2rad(w.mount.angle_deg);
      const double c = w.outline[1].x - w.outline[0].x, b = w.outline[2].y - w.outline[1].y;
      const double a = gamma + th, S = c * b, q = 0.5 * kRho * V * V;
      const Vec2 cdir{std::cos(th), std::sin(th)}, ndir{-std::sin(th), std::cos(th)};
      const double N = q * S * law.normal_force(a, 1.98);
      const double vt = V * std::cos(a);
      const double T = -0.5 * kRho * vt * vt * S *
                       (law.friction(kRho * vt * c / kMu) + law.edge_drag * g.material.thickness_m / c);
      const Vec2 le = Vec2{w.mount.x_m, w.mount.y_m} - mp.cg;
      const Vec2 rcp = le - (law.centre_of_pressure(a, 1.98) * c) * cdir;
      const Vec2 rmid = le - (0.5 * c) * cdir;
      F = F + N * ndir + T * cdir;
      M += cross(rcp, N * ndir) + cross(rmid, T * cdir);
    }
    const ReferenceLoads L = r.loads(level(V, gamma));
    EXPECT_NEAR(L.force_body.x, F.x, 1e-9 * (1 + std::abs(F.x))) << ad;
    EXPECT_NEAR(L.force_body.y, F.y, 1e-9 * (1 + std::abs(F.y))) << ad;
    EXPECT_NEAR(L.moment, M, 1e-9 * (1 + std::abs(M))) << ad;
  }
}

// finite_span off: every strip sees exactly its geometric angle of attack;
// on: the wing's own trailing vortices lower it (induced angle > 0 at alpha > 0).
TEST(ReferenceEffects, FiniteSpanOffMakesEverySectionTwoDimensional) {
  const Glider g = bare_wing(rect_wing(0.06, 0.3));
  Effects e = Effects::physics();
  e.finite_span.on = false;
  const ReferenceAero off(g, Vec2{}, with(e));
  const ReferenceAero on(g, Vec2{}, with(Effects::physics()));
  const double a = deg2rad(6);
  for (double ae : off.loads(level(8, a)).strip_alpha_eff) EXPECT_NEAR(ae, a, 1e-12);
  for (double ae : on.loads(level(8, a)).strip_alpha_eff) EXPECT_LT(ae, a - deg2rad(0.5));
}

// downwash off: each wing is solved alone, so the tail carries exactly the
// forces of the tail without the main wing. On: the main wing's downwash
// lowers the tail's lift (dε/dα > 0).
TEST(ReferenceEffects, DownwashOffLeavesTheTailAsIfAlone) {
  const Glider g = wing_and_tail(2.0, 0.0);
  Glider tail_only = g;
  tail_only.wings.erase(tail_only.wings.begin());
  const Vec2 ref = mass_properties(g).cg;
  Effects e = Effects::physics();
  e.downwash.on = false;
  const ReferenceAero both(g, ref, with(e)), alone(tail_only, ref, with(e));
  const ReferenceAero with_dw(g, ref, with(Effects::physics()));
  // equal up to the decambering solve's tolerance (1e-9 of the speed)
  for (double ad : {-4.0, 2.0, 8.0, 25.0}) {
    const FlightState s = level(8, deg2rad(ad));
    const ReferenceLoads a = both.loads(s), b = alone.loads(s);
    EXPECT_NEAR(a.wing_force[1].x, b.wing_force[0].x, 1e-8) << ad;
    EXPECT_NEAR(a.wing_force[1].y, b.wing_force[0].y, 1e-8) << ad;
    EXPECT_NEAR(a.wing_moment[1], b.wing_moment[0], 1e-8) << ad;
  }
  const FlightState s = level(8, deg2rad(5));
  EXPECT_LT(with_dw.loads(s).wing_force[1].y, both.loads(s).wing_force[1].y - 1e-3);
}

// ground_effect off: forces do not depend on height. On: the lift at a fixed
// angle of attack grows toward the ground and equals free air above the grid.
TEST(ReferenceEffects, GroundEffectOnlyWhenOnAndFadesWithHeight) {
  const Glider g = wing_and_tail(2.0, 0.0);
  const Vec2 ref = mass_properties(g).cg;
  Effects e = Effects::physics();
  e.ground_effect.on = false;
  const ReferenceAero off(g, ref, with(e)), on(g, ref, with(Effects::physics()));
  const double a = deg2rad(5);
  const GliderForces f0 = off.forces(8, a, 0, 1e9);
  for (double h : {0.04, 0.1, 0.3, 1.0}) {
    const GliderForces f = off.forces(8, a, 0, h);
    EXPECT_EQ(f.lift, f0.lift);
    EXPECT_EQ(f.drag, f0.drag);
    EXPECT_EQ(f.moment, f0.moment);
  }
  // 10 m is beyond the height grid (3 spans): free air within 0.1 %
  double prev = on.forces(8, a, 0, 10.0).lift;
  EXPECT_NEAR(prev, on.forces(8, a, 0, 1e9).lift, 1e-3 * prev);
  for (double h : {1.0, 0.3, 0.1, 0.04}) {
    const double l = on.forces(8, a, 0, h).lift;
    EXPECT_GT(l, prev) << h;
    prev = l;
  }
  EXPECT_GT(prev / on.forces(8, a, 0, 1e9).lift, 1.05);
}

// pitch_damping off: the pitch rate changes nothing. On, with 2D strips: the
// normal force follows the 3/4-chord rule and each plate adds the thin-airfoil
// camber moment c_m,c/4 = -(pi/8) omega c / V (Theodorsen's quasi-steady
// limit), independent sums here; a tail behind the CG damps the pitch.
TEST(ReferenceEffects, PitchDampingFollowsTheThreeQuarterChordRule) {
  const Glider g = wing_and_tail(2.0, 0.0);
  const MassProperties mp = mass_properties(g);
  Effects e = Effects::baseline();
  const ReferenceAero off(g, mp.cg, with(e));
  e.pitch_damping.on = true;
  const ReferenceAero on(g, mp.cg, with(e));
  const double V = 8, gamma = deg2rad(3), w = 2.0;  // rad/s
  const GliderForces f0 = off.forces(V, gamma, 0), f1 = off.forces(V, gamma, w);
  EXPECT_EQ(f0.lift, f1.lift);
  EXPECT_EQ(f0.moment, f1.moment);
  // independent strip model with the pitch rate
  const SectionLaw law;
  Vec2 F{};
  double M = 0;
  const Vec2 vb = {V * std::cos(gamma), -V * std::sin(gamma)};  // glider velocity, glider frame
  for (const Wing& wg : g.wings) {
    const double th = deg2rad(wg.mount.angle_deg);
    const double c = wg.outline[1].x - wg.outline[0].x, b = wg.outline[2].y - wg.outline[1].y, S = c * b;
    const Vec2 cdir{std::cos(th), std::sin(th)}, ndir{-std::sin(th), std::cos(th)};
    const Vec2 le = Vec2{wg.mount.x_m, wg.mount.y_m} - mp.cg;
    const Vec2 p34 = le - (0.75 * c) * cdir;
    const Vec2 vp{vb.x - w * p34.y, vb.y + w * p34.x};
    const double un = -dot(vp, ndir), ut = dot(vp, cdir);
    const double a = std::atan2(un, ut), v2 = un * un + ut * ut;
    const double N = 0.5 * kRho * v2 * S * law.normal_force(a, 1.98);
    const double T = -0.5 * kRho * ut * ut * S *
                     (law.friction(kRho * std::abs(ut) * c / kMu) + law.edge_drag * g.material.thickness_m / c);
    const double cm = -(kPi / 8) * w * c / V * law.attached_fraction(a);
    const Vec2 rcp = le - (law.centre_of_pressure(a, 1.98) * c) * cdir;
    F = F + N * ndir + T * cdir;
    M += cross(rcp, N * ndir) + cross(le - (0.5 * c) * cdir, T * cdir) + 0.5 * kRho * V * V * S * c * cm;
  }
  const ReferenceLoads L = on.loads(level(V, gamma, w));
  EXPECT_NEAR(L.force_body.y, F.y, 1e-6 * std::abs(F.y));
  EXPECT_NEAR(L.force_body.x, F.x, 1e-6 * (std::abs(F.x) + 1e-3));
  EXPECT_NEAR(L.moment, M, 1e-6 * std::abs(M) + 1e-9);
  EXPECT_LT(on.forces(V, gamma, w).moment, on.forces(V, gamma, 0).moment);  // damping
}

// fuselage_drag: a rectangular fuselage plate of length L and height h in the
// flow along it carries Blasius friction on both faces,
// D = 1.328 h sqrt(rho mu V^3 L) (Schlichting eq. 7.34 integrated), plus the
// edge pressure drag q C_e t h; off: nothing.
TEST(ReferenceEffects, FuselageDragIsBlasiusFrictionOfThePlate) {
  Glider g = bare_wing(rect_wing(0.05, 0.3));
  const double L = 0.3, h = 0.02;
  g.fuselage = test::rect(-L, -h / 2, 0.0, h / 2);
  Effects e = Effects::baseline();
  const ReferenceAero off(g, Vec2{}, with(e));
  e.fuselage_drag.on = true;
  const ReferenceAero on(g, Vec2{}, with(e));
  const double V = 7;
  const ReferenceLoads a = on.loads(level(V, 0)), b = off.loads(level(V, 0));
  EXPECT_EQ(b.fuselage_force.x, 0.0);
  const SectionLaw law;
  const double D = 1.328 * h * std::sqrt(kRho * kMu * V * V * V * L) +
                   0.5 * kRho * V * V * law.edge_drag * g.material.thickness_m * h;
  EXPECT_NEAR(-a.fuselage_force.x, D, 1e-9 * D);
  EXPECT_NEAR(a.fuselage_force.y, 0.0, 1e-12);
  EXPECT_NEAR(a.force_body.x - b.force_body.x, a.fuselage_force.x, 1e-12);
}

// added_mass: a plate accelerating normal to itself carries rho pi c^2 b / 4
// (2D apparent mass of a flat plate, e.g. Newman, Marine Hydrodynamics, 4.13).
// Released from rest, a level plate falls with g M / (M + m_a) at first.
TEST(ReferenceEffects, AddedMassOfAPlateIsRhoPiC2BOver4) {
  const double c = 0.08, b = 0.4;
  const Glider g = bare_wing(rect_wing(c, b));
  Effects e = Effects::baseline();
  const ReferenceAero off(g, Vec2{-c / 2, 0}, with(e));
  e.added_mass.on = true;
  const ReferenceAero on(g, Vec2{-c / 2, 0}, with(e));
  const double ma = kRho * kPi * c * c * b / 4;
  EXPECT_NEAR(on.plate_added_mass(), ma, 1e-12);
  EXPECT_FALSE(off.has_added_mass());
  ASSERT_TRUE(on.has_added_mass());
  const AddedMass am = on.added_mass(level(0.0, 0.0));
  EXPECT_NEAR(am.m[1][1], ma, 1e-12);
  EXPECT_NEAR(am.m[0][0], 0.0, 1e-15);
  const RigidBody body{0.01, 1e-5};
  FlightState s;
  s.p = {0, 10};
  SimOptions o;
  o.dt = 1e-4;
  o.t_max = 1e-3;
  const Flight f = simulate_from(on, body, s, o, 9.81);
  const Flight f0 = simulate_from(off, body, s, o, 9.81);
  const double ay = f.samples.back().vy / f.samples.back().t;
  EXPECT_NEAR(ay, -9.81 * body.mass / (body.mass + ma), 1e-3 * 9.81);
  EXPECT_NEAR(f0.samples.back().vy / f0.samples.back().t, -9.81, 1e-3 * 9.81);
}

// ------------------------------------------------------------- flight

// The reference plugs into simulate() like the baseline; a trimmed canard of
// the training set glides to the ground with every effect on and stays in
// attached flow; the unconverged-solve counter stays at zero.
TEST(ReferenceFlight, TrainingCanardGlidesWithEveryEffect) {
  const Glider g = load_glider(test::source_path("examples/training/t17-canard.glider.json"));
  const MassProperties mp = mass_properties(g);
  const ReferenceAero r(g, ReferenceOptions{});
  Launch l;
  l.speed = 8;
  l.climb_deg = 5;
  const Flight f = simulate(r, {mp.mass, mp.inertia}, l);
  EXPECT_EQ(f.end, FlightEnd::Ground) << f.reason;
  EXPECT_TRUE(f.stable);
  EXPECT_GT(f.distance, 5.0);
  EXPECT_LT(f.max_alpha, deg2rad(20));
  EXPECT_EQ(r.unconverged_count(), 0);
}

// The decambering solve converges at every angle of attack, pitch rate and
// height a flight can meet.
TEST(ReferenceFlight, DecamberingConvergesEverywhere) {
  const Glider g = wing_and_tail(2.0, -1.0);
  const ReferenceAero r(g, ReferenceOptions{});
  for (double ad = -180; ad < 180; ad += 7.5)
    for (double w : {-6.0, 0.0, 6.0})
      for (double h : {0.05, 0.5, 1e9}) {
        const ReferenceLoads L = r.loads(level(7, deg2rad(ad), w, h));
        EXPECT_TRUE(L.converged) << ad << " " << w << " " << h;
        EXPECT_TRUE(std::isfinite(L.force_body.x) && std::isfinite(L.force_body.y) && std::isfinite(L.moment));
      }
  EXPECT_EQ(r.unconverged_count(), 0);
}

TEST(ReferenceFlight, RejectsImpossibleOptions) {
  const Glider g = wing_and_tail();
  ReferenceOptions o;
  o.span_panels = 0;
  EXPECT_THROW(ReferenceAero(g, o), InputError);
  o = ReferenceOptions{};
  o.effects.downwash.strength = -1;
  EXPECT_THROW(ReferenceAero(g, o), InputError);
  Glider none = g;
  none.wings.clear();
  EXPECT_THROW(ReferenceAero(none, ReferenceOptions{}), InputError);
}
