// Tests of src/fit_track.cpp: tracked-flight simulation and the launch fit (eq. 5).
#include <cmath>
#include <random>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "pteromys/fit.hpp"
#include "pteromys/io.hpp"
#include "pteromys/mass.hpp"
#include "test_support.hpp"

using namespace pteromys;

namespace {

Glider training_glider(const std::string& name) {
  return load_glider(test::source_path("examples/training/" + name + ".glider.json"));
}

struct Rig {
  Glider g;
  MountedGlider mg;
  RigidBody body;
  explicit Rig(const std::string& name)
      : g(training_glider(name)), mg(mount(g, std::make_shared<FlatPlateModel>())),
        body{mg.mass().mass, mg.mass().inertia} {}
};

LaunchParams some_launch() {
  LaunchParams p;
  p.t = 3.0;  // an arbitrary dataset time origin
  p.x = 0.4;
  p.y = 1.6;
  p.speed = 7.5;
  p.climb = deg2rad(6.0);
  p.pitch = deg2rad(9.0);
  return p;
}

std::vector<double> frame_times(double t0, int n, double fps = 30.0) {
  std::vector<double> t;
  for (int i = 0; i < n; ++i) t.push_back(t0 + i / fps);
  return t;
}

std::vector<TrackedPoint> as_points(const std::vector<double>& t, const std::vector<Vec2>& p) {
  std::vector<TrackedPoint> out;
  for (std::size_t i = 0; i < t.size(); ++i) out.push_back({t[i], p[i].x, p[i].y});
  return out;
}

// 12 frames of a throw without aerodynamics (a parabola), from the launch's time.
std::vector<TrackedPoint> ballistic_points(const Rig& s, const LaunchParams& truth) {
  const auto times = frame_times(truth.t, 12);
  return as_points(times, simulate_track(NoAero(), s.body, truth, times).positions);
}

}  // namespace

TEST(SimulateTrack, MatchesTheEngineSimulationAtStepTimes) {
  // Reference: the engine's own simulate() of the same initial state,
  // recorded every step. At times on the step grid the Hermite interpolation
  // returns the step values, so both agree to rounding (1e-9 m), whatever the
  // height offset (the quasi-static model does not depend on height). The
  // states' air speed and angle of attack too, which simulate_track fills
  // only where the tracked points fall (SimOptions::sample_air): in still
  // air and in a wind, whose air-relative velocity they must use.
  Rig s("t01-rectangular");
  const QuasiStaticAero qa(s.mg);
  LaunchParams p = some_launch();
  Launch l;
  l.speed = p.speed;
  l.climb_deg = rad2deg(p.climb);
  l.pitch_from_path = false;
  l.pitch_deg = rad2deg(p.pitch);
  l.height = p.y;
  for (const Vec2 wind : {Vec2{0, 0}, Vec2{-1.5, 0.4}}) {
    SimOptions so;
    so.t_max = 0.7;
    so.wind = wind;
    const Flight f = simulate(qa, s.body, l, so);
    std::vector<double> times;
    std::vector<FlightSample> ref;
    for (std::size_t k = 0; k < f.samples.size(); k += 25) {
      times.push_back(p.t + f.samples[k].t);
      ref.push_back(f.samples[k]);
    }
    TrackOptions to;
    to.sim.wind = wind;
    const Track tr = simulate_track(qa, s.body, p, times, to);
    ASSERT_EQ(tr.positions.size(), ref.size());
    for (std::size_t i = 0; i < ref.size(); ++i) {
      EXPECT_NEAR(tr.positions[i].x, p.x + ref[i].x, 1e-9) << i;
      EXPECT_NEAR(tr.positions[i].y, ref[i].y, 1e-9) << i;
      EXPECT_NEAR(tr.states[i].speed, ref[i].speed, 1e-9) << i;
      EXPECT_NEAR(tr.states[i].alpha, ref[i].alpha, 1e-9) << i;
      // Independently: the air speed is |v - wind|.
      EXPECT_NEAR(tr.states[i].speed, std::hypot(ref[i].vx - wind.x, ref[i].vy - wind.y), 1e-9) << i;
    }
    EXPECT_FALSE(tr.ended_early);
    EXPECT_FALSE(tr.left_model_range);
  }
}

TEST(SimulateTrack, BallisticMotionIsExactBetweenSteps) {
  // Without air the CG follows the parabola p0 + v0 t - g t^2 / 2 exactly;
  // velocity Verlet is exact for constant acceleration and the cubic Hermite
  // interpolation reproduces a quadratic exactly, so any time (on or off the
  // 2 ms grid) is exact to rounding.
  Rig s("t01-rectangular");
  const NoAero none;
  const LaunchParams p = some_launch();
  std::vector<double> times = {3.0, 3.0011, 3.0333, 3.25, 3.5551, 3.9};
  const Track tr = simulate_track(none, s.body, p, times);
  for (std::size_t i = 0; i < times.size(); ++i) {
    const double t = times[i] - p.t;
    EXPECT_NEAR(tr.positions[i].x, p.x + p.speed * std::cos(p.climb) * t, 1e-9);
    EXPECT_NEAR(tr.positions[i].y, p.y + p.speed * std::sin(p.climb) * t - 0.5 * 9.81 * t * t, 1e-9);
  }
}

TEST(SimulateTrack, IgnoresTheGroundByDefaultAndStopsAtItWithoutOffset) {
  Rig s("t01-rectangular");
  const QuasiStaticAero qa(s.mg);
  LaunchParams p = some_launch();
  p.y = 0.05;  // 5 cm above the dataset's y = 0
  p.climb = deg2rad(-20);
  p.pitch = p.climb;
  const auto times = frame_times(p.t, 20);
  const Track tr = simulate_track(qa, s.body, p, times);
  EXPECT_FALSE(tr.ended_early);
  EXPECT_LT(tr.positions.back().y, -0.5);  // well below y = 0: the fit sees the whole flight

  TrackOptions o;
  o.height_offset = 0;
  o.continue_outside_range = false;
  const Track grounded = simulate_track(qa, s.body, p, times, o);
  EXPECT_TRUE(grounded.ended_early);
  EXPECT_EQ(grounded.end, FlightEnd::Ground);
  EXPECT_LT(grounded.end_time, times.back());
}

TEST(SimulateTrack, ReportsFlightsThatLeaveTheModelRangeButKeepsSimulating) {
  // A launch pitched 45 deg above its path: the wings are beyond the model's
  // 40 deg limit; the engine's simulate() would stop there ("unstable"), the
  // track continues with the table's edge values and says so.
  Rig s("t01-rectangular");
  const QuasiStaticAero qa(s.mg);
  LaunchParams p = some_launch();
  p.pitch = p.climb + deg2rad(45.0);
  const Track tr = simulate_track(qa, s.body, p, frame_times(p.t, 20));
  EXPECT_TRUE(tr.left_model_range);
  EXPECT_FALSE(tr.ended_early);
  for (const auto& q : tr.positions) EXPECT_TRUE(std::isfinite(q.x) && std::isfinite(q.y));
}

TEST(LaunchFit, RecoversKnownLaunchFromNoiseFreePoints) {
  Rig s("t07-swept-30");
  const QuasiStaticAero qa(s.mg);
  const LaunchParams truth = some_launch();
  const auto times = frame_times(truth.t, 18);
  const auto pts = as_points(times, simulate_track(qa, s.body, truth, times).positions);
  LaunchFitOptions o;  // the paper's M = 10
  const LaunchFit f = fit_launch(qa, s.body, pts, o);
  // Exact data: the least-squares optimum is the truth; tolerances are the
  // solver's (tolerances 1e-10 on a well-conditioned 5-parameter problem).
  EXPECT_LT(f.rmse_m, 1e-6);
  EXPECT_NEAR(f.launch.t, truth.t, 1e-12);
  EXPECT_NEAR(f.launch.x, truth.x, 1e-5);
  EXPECT_NEAR(f.launch.y, truth.y, 1e-5);
  EXPECT_NEAR(f.launch.speed, truth.speed, 1e-4);
  EXPECT_NEAR(rad2deg(f.launch.climb), rad2deg(truth.climb), 1e-3);
  EXPECT_NEAR(rad2deg(f.launch.pitch), rad2deg(truth.pitch), 1e-2);
}

TEST(LaunchFit, NoisyPointsGiveErrorsWithinTheStatisticalBound) {
  // 5 cm tracking noise on 18 points, launch fitted to all of them. The
  // expected scatter of the estimate is the Gauss-Newton covariance
  // sigma^2 (J^T J)^-1 at the truth (J: sensitivity of the positions to the
  // five parameters, by central differences here). Each parameter's error
  // must stay within 4 standard deviations, over 8 noise draws.
  Rig s("t10-forward-swept-30");
  const QuasiStaticAero qa(s.mg);
  const LaunchParams truth = some_launch();
  const auto times = frame_times(truth.t, 18);
  const auto clean = simulate_track(qa, s.body, truth, times).positions;
  const double sigma = 0.05;
  // Sensitivities.
  Eigen::MatrixXd J(2 * times.size(), 5);
  for (int j = 0; j < 5; ++j) {
    LaunchParams a = truth, b = truth;
    double* pa[5] = {&a.x, &a.y, &a.speed, &a.climb, &a.pitch};
    double* pb[5] = {&b.x, &b.y, &b.speed, &b.climb, &b.pitch};
    const double h = 1e-5;
    *pa[j] += h;
    *pb[j] -= h;
    const auto ta = simulate_track(qa, s.body, a, times).positions, tb = simulate_track(qa, s.body, b, times).positions;
    for (std::size_t i = 0; i < times.size(); ++i) {
      J(2 * i, j) = (ta[i].x - tb[i].x) / (2 * h);
      J(2 * i + 1, j) = (ta[i].y - tb[i].y) / (2 * h);
    }
  }
  const Eigen::MatrixXd cov = sigma * sigma * (J.transpose() * J).inverse();
  std::mt19937 rng(7);
  std::normal_distribution<double> N(0.0, sigma);
  LaunchFitOptions o;
  o.points = 0;
  for (int draw = 0; draw < 8; ++draw) {
    std::vector<Vec2> noisy = clean;
    for (auto& q : noisy) q = {q.x + N(rng), q.y + N(rng)};
    const LaunchFit f = fit_launch(qa, s.body, as_points(times, noisy), o);
    const double err[5] = {f.launch.x - truth.x, f.launch.y - truth.y, f.launch.speed - truth.speed,
                           f.launch.climb - truth.climb, f.launch.pitch - truth.pitch};
    for (int j = 0; j < 5; ++j) EXPECT_LT(std::abs(err[j]), 4 * std::sqrt(cov(j, j))) << "draw " << draw << " param " << j;
    // The residual is the noise: RMS distance about sigma sqrt(2 (1 - 5/36))
    // (36 residuals, 5 parameters); its spread is about 1/sqrt(2 x 31) of
    // that, so 0.65 sigma is 4 standard deviations.
    EXPECT_NEAR(f.rmse_m, sigma * std::sqrt(2 * (1 - 5.0 / 36)), 0.65 * sigma);
  }
}

TEST(LaunchFit, BallisticFitRecoversTheParabola) {
  Rig s("t01-rectangular");
  const NoAero none;
  const LaunchParams truth = some_launch();
  const auto pts = ballistic_points(s, truth);
  LaunchFitOptions o;
  o.fit_pitch = false;
  const LaunchFit f = fit_launch(none, s.body, pts, o);
  EXPECT_LT(f.rmse_m, 1e-7);
  EXPECT_NEAR(f.launch.speed, truth.speed, 1e-5);
  EXPECT_NEAR(f.launch.climb, truth.climb, 1e-6);
}

// One or two points cannot place a launch (a parabola needs three); the
// fit took them as three without a word. 0 means all points.
TEST(LaunchFit, RefusesFewerThanThreePoints) {
  Rig s("t01-rectangular");
  const NoAero none;
  const auto pts = ballistic_points(s, some_launch());
  LaunchFitOptions o;
  o.fit_pitch = false;
  for (int n : {-1, 1, 2}) {
    o.points = n;
    EXPECT_THROW(fit_launch(none, s.body, pts, o), InputError) << n;
  }
  o.points = 0;
  EXPECT_LT(fit_launch(none, s.body, pts, o).rmse_m, 1e-7);
}

TEST(LaunchFit, FirstGuessComesFromTheFirstPointsAndRejectsBackwardFlights) {
  // A parabola through the first points gives the velocity exactly for
  // ballistic points (quadratic in time).
  std::vector<TrackedPoint> pts;
  for (int i = 0; i < 8; ++i) {
    const double t = 1.0 + i / 30.0, tau = t - 1.0;
    pts.push_back({t, 2.0 + 6.0 * tau, 1.0 + 1.0 * tau - 4.905 * tau * tau});
  }
  const LaunchParams g = initial_launch_guess(pts);
  EXPECT_NEAR(g.x, 2.0, 1e-9);
  EXPECT_NEAR(g.speed, std::hypot(6.0, 1.0), 1e-9);
  EXPECT_NEAR(g.climb, std::atan2(1.0, 6.0), 1e-9);
  EXPECT_DOUBLE_EQ(g.pitch, g.climb);
  for (auto& p : pts) p.x = -p.x;
  EXPECT_THROW(initial_launch_guess(pts), InputError);
}
