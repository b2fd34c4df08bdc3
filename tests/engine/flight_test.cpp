#include "pteromys/flight.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include "pteromys/io.hpp"
#include "test_support.hpp"

using namespace pteromys;

namespace {
const FlightSample& at_time(const Flight& f, double t) {
  for (const auto& s : f.samples)
    if (std::abs(s.t - t) < 1e-9) return s;
  throw std::runtime_error("no sample at t=" + std::to_string(t));
}
}  // namespace

// With the air removed the flight is the exact parabola x = v cos(c) t,
// y = h + v sin(c) t - g t^2 / 2, pitch = pitch0 + omega0 t (Verlet is exact
// for constant acceleration), and ground contact is where the parabola meets
// y = 0.
TEST(Flight, BallisticWhenAirIsRemoved) {
  const double g = 9.81;
  for (Integrator integ : {Integrator::Verlet, Integrator::RK4}) {
    Launch l;
    l.speed = 7;
    l.climb_deg = 10;
    l.height = 1.5;
    l.pitch_rate_deg_s = 30;
    SimOptions o;
    o.integrator = integ;
    const Flight f = simulate(NoAero(), {0.01, 1e-5}, l, o, g);
    const double c = deg2rad(10), vx = 7 * std::cos(c), vy = 7 * std::sin(c);
    ASSERT_GT(f.samples.size(), 100u);
    for (std::size_t i = 0; i + 1 < f.samples.size(); ++i) {
      const auto& s = f.samples[i];
      ASSERT_NEAR(s.x, vx * s.t, 1e-11);
      ASSERT_NEAR(s.y, 1.5 + vy * s.t - 0.5 * g * s.t * s.t, 1e-11);
      ASSERT_NEAR(s.pitch, c + deg2rad(30) * s.t, 1e-11);
    }
    const double t_ground = (vy + std::sqrt(vy * vy + 2 * g * 1.5)) / g;
    EXPECT_EQ(f.end, FlightEnd::Ground);
    EXPECT_TRUE(f.stable);
    // Linear interpolation of the last step: error g dt^2 / (8 |vy|) ~ 1e-6 s.
    EXPECT_NEAR(f.flight_time, t_ground, 1e-5);
    EXPECT_NEAR(f.distance, vx * t_ground, 1e-4);
    EXPECT_NEAR(f.samples.back().y, 0.0, 1e-15);
  }
}

// The same through the whole pipeline for every example: with the air's density
// set to zero the quasi-static model gives no force and the flight is the
// parabola of the launch, for any glider.
TEST(Flight, EveryExampleIsBallisticWithoutAir) {
  Environment vacuum;
  vacuum.air_density = 0;
  for (const auto& [path, g] : test::examples()) {
    const MountedGlider mg = mount(g, default_model(), vacuum);
    for (const Launch& l : standard_launches(1.5)) {
      const Flight f = simulate(QuasiStaticAero(mg), {mg.mass().mass, mg.mass().inertia}, l);
      const double c = deg2rad(l.climb_deg), vx = l.speed * std::cos(c), vy = l.speed * std::sin(c);
      for (std::size_t i = 0; i + 1 < f.samples.size(); ++i) {
        const auto& s = f.samples[i];
        ASSERT_NEAR(s.x, vx * s.t, 1e-11) << path;
        ASSERT_NEAR(s.y, 1.5 + vy * s.t - 0.5 * 9.81 * s.t * s.t, 1e-11) << path;
        ASSERT_NEAR(s.pitch, c, 1e-12) << path;
      }
      // The pitch stays put while the path steepens, so the angle of attack
      // grows; the flight ends at the ground or, once a wing passes the
      // model's range, as unstable (the simulator cannot know the air is gone).
      if (f.end == FlightEnd::Ground)
        EXPECT_NEAR(f.flight_time, (vy + std::sqrt(vy * vy + 2 * 9.81 * 1.5)) / 9.81, 1e-5) << path;
      else
        EXPECT_GT(f.max_alpha, mg.alpha_limit()) << path;
    }
  }
}

// The Verlet trajectory converges with second order as the step shrinks,
// toward an RK4 reference with a tiny step, for every example.
TEST(Flight, TrajectoryConvergesAsTimeStepShrinks) {
  const auto model = default_model();
  for (const auto& [path, gl] : test::examples()) {
    const MountedGlider mg = mount(gl, model);
    const QuasiStaticAero qa(mg);
    const RigidBody body{mg.mass().mass, mg.mass().inertia};
    Launch l;
    l.speed = 8;
    SimOptions ref;
    ref.dt = 1e-4;
    ref.integrator = Integrator::RK4;
    const Flight fr = simulate(qa, body, l, ref);
    // Compare at a time on the grid of every step size, before the flight ends.
    const double tc = std::floor(0.8 * fr.flight_time / 0.004) * 0.004;
    ASSERT_GT(tc, 0.1) << path;
    const auto& r = at_time(fr, tc);
    std::vector<double> err;
    for (double dt : {0.004, 0.002, 0.001}) {
      SimOptions o;
      o.dt = dt;
      const Flight f = simulate(qa, body, l, o);
      const auto& s = at_time(f, tc);
      err.push_back(std::hypot(s.x - r.x, s.y - r.y));
    }
    EXPECT_LT(err[1], err[0] / 3) << path << " errors " << err[0] << " " << err[1];
    EXPECT_LT(err[2], err[1] / 3) << path << " errors " << err[1] << " " << err[2];
    EXPECT_LT(err[1], 5e-3) << path << ": default step 2 ms should be within 5 mm";
  }
}

// The flight's largest wing angle (its stall check) is the wings' largest
// angle along the trajectory. Verlet checks it where it evaluates the force,
// each step's predicted state, whose velocity differs from the step's end by
// O(h^2); recomputed independently at every recorded end of a step it agrees
// to within the change of the angle over one step (the last step, cut at the
// ground, is recorded at the contact point, not at its end).
TEST(Flight, MaxAlphaIsTheWingsLargestAngleAlongTheFlight) {
  const auto model = default_model();
  int compared = 0;
  for (const auto& [path, gl] : test::examples()) {
    const MountedGlider mg = mount(gl, model);
    const QuasiStaticAero qa(mg);
    const RigidBody body{mg.mass().mass, mg.mass().inertia};
    for (const Launch& l : standard_launches(1.5)) {
      for (Integrator integ : {Integrator::Verlet, Integrator::RK4}) {
        SimOptions o;
        o.integrator = integ;
        const Flight f = simulate(qa, body, l, o);
        ASSERT_GT(f.samples.size(), 3u) << path;
        double m = 0, step = 0, prev = 0;
        for (std::size_t i = 0; i < f.samples.size(); ++i) {  // the launch state included
          const auto& x = f.samples[i];
          FlightState st;
          st.p = {x.x, x.y};
          st.v = {x.vx, x.vy};
          st.beta = x.pitch;
          st.omega = x.omega;
          const double a = qa.max_alpha(st);
          if (i > 1) step = std::max(step, std::abs(a - prev));
          prev = a;
          m = std::max(m, a);
        }
        EXPECT_NEAR(f.max_alpha, m, step + 1e-6) << path << " launch " << l.speed << " m/s";
        if (integ == Integrator::RK4 && f.end == FlightEnd::TimeLimit)
          EXPECT_EQ(f.max_alpha, m) << path;  // RK4 checks every recorded state
        ++compared;
      }
    }
  }
  EXPECT_GT(compared, 10);
}

// A launch whose nose points 60 deg above its path starts with the wings
// near 60 deg (the body's angle of attack plus mounting angles of a few
// degrees), outside the model's +-40 deg: it is not flown, and the reason
// says it was the launch. 20 deg above the path is inside and flies, with
// the launch's angle counted in max_alpha.
TEST(Flight, ALaunchOutsideTheModelsRangeIsNotFlown) {
  const auto model = default_model();
  const Glider gl = load_glider(test::source_path("examples/gliders/rectangular.glider.json"));
  const MountedGlider mg = mount(gl, model);
  const QuasiStaticAero qa(mg);
  const RigidBody body{mg.mass().mass, mg.mass().inertia};
  for (Integrator integ : {Integrator::Verlet, Integrator::RK4}) {
    SimOptions o;
    o.integrator = integ;
    Launch l;
    l.speed = 7;
    l.climb_deg = 5;
    l.pitch_from_path = false;
    l.pitch_deg = 65;
    const Flight f = simulate(qa, body, l, o);
    EXPECT_FALSE(f.stable);
    EXPECT_EQ(f.end, FlightEnd::Unstable);
    EXPECT_EQ(f.samples.size(), 1u);
    EXPECT_EQ(f.flight_time, 0.0);
    EXPECT_NE(f.reason.find("at launch"), std::string::npos) << f.reason;
    EXPECT_GT(f.max_alpha, deg2rad(55.0));
    EXPECT_EQ(f.max_alpha, qa.max_alpha(launch_state(l)));

    l.pitch_deg = 25;
    const Flight g = simulate(qa, body, l, o);
    ASSERT_GT(g.samples.size(), 3u) << g.reason;
    EXPECT_GE(g.max_alpha, qa.max_alpha(launch_state(l)));
    EXPECT_GT(g.max_alpha, deg2rad(15.0));
  }
}

// A single wing without tail, CG behind the quarter chord: pitch-unstable. The
// simulator must say so rather than report a distance as if it flew.
TEST(Flight, TaillessGliderWithAftCgIsMarkedUnstable) {
  Glider g = test::simple_glider(0.06, 0.4, -0.02, 0.0, 3.0);
  g.ballast.push_back({"tail weight", 0.01, -0.28, 0.0});
  const MountedGlider mg = mount(g, default_model());
  Launch l;
  l.speed = 7;
  const Flight f = simulate(QuasiStaticAero(mg), {mg.mass().mass, mg.mass().inertia}, l);
  EXPECT_FALSE(f.stable);
  EXPECT_EQ(f.end, FlightEnd::Unstable);
  EXPECT_FALSE(f.reason.empty());
}

TEST(Flight, StandardLaunchesAreThePapersSix) {
  const auto ls = standard_launches(1.5);
  ASSERT_EQ(ls.size(), 6u);
  const double speeds[] = {7, 7, 9, 9, 11, 11}, angles[] = {0, 10, 0, 10, 0, 10};
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(ls[i].speed, speeds[i]);
    EXPECT_EQ(ls[i].climb_deg, angles[i]);
    EXPECT_EQ(ls[i].height, 1.5);
    const FlightState s = launch_state(ls[i]);
    EXPECT_NEAR(angle_of_attack(s), 0.0, 1e-15);  // launched with the nose along the path
  }
}

TEST(Flight, RejectsNonPhysicalBodies) {
  EXPECT_THROW(simulate(NoAero(), {0, 1e-5}, Launch{}), InputError);
  SimOptions o;
  o.dt = 0;
  EXPECT_THROW(simulate(NoAero(), {0.01, 1e-5}, Launch{}, o), InputError);
}

// Every command's --dt and every binding's dt go through check_time_step:
// its bounds are inclusive, NaN is refused, and the message names the
// option it was given.
TEST(Flight, TimeStepIsCheckedAgainstItsBounds) {
  EXPECT_EQ(check_time_step(1e-5, "--dt"), 1e-5);
  EXPECT_EQ(check_time_step(0.002, "--dt"), 0.002);
  EXPECT_EQ(check_time_step(0.05, "--dt"), 0.05);
  for (double bad : {0.0, -0.002, 9.9e-6, 0.0501, std::nan(""), std::numeric_limits<double>::infinity()}) {
    try {
      check_time_step(bad, "the simulation step");
      ADD_FAILURE() << bad << " was accepted";
    } catch (const InputError& e) {
      // the bounds as a person writes them, and the value given
      std::ostringstream given;
      given.precision(9);
      given << bad;
      EXPECT_EQ(std::string(e.what()), "the simulation step must be in [1e-05, 0.05] s, got " + given.str());
    }
  }
}
