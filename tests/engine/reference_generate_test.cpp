// Reference simulator: camera, tracking and synthetic datasets
// (src/reference_generate.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numeric>
#include <unistd.h>

#include "pteromys/analysis.hpp"
#include "pteromys/effects.hpp"
#include "pteromys/io.hpp"
#include "pteromys/mass.hpp"
#include "pteromys/reference.hpp"
#include "test_support.hpp"

using namespace pteromys;

namespace {

std::vector<std::pair<std::string, Glider>> training(int n) {
  const char* files[] = {"t17-canard", "t11-delta", "t05-tapered-strong", "t08-swept-45"};
  std::vector<std::pair<std::string, Glider>> out;
  for (int i = 0; i < n; ++i)
    out.emplace_back(files[i], load_glider(test::source_path(std::string("examples/training/") + files[i] +
                                                             ".glider.json")));
  return out;
}

GenerateOptions quick(std::uint64_t seed = 7) {
  GenerateOptions o;
  o.flights_per_glider = 3;
  o.seed = seed;
  return o;
}

std::string temp_dir(const std::string& tag) {
  char buf[] = "/tmp/pteromys_ref_XXXXXX";
  const char* d = mkdtemp(buf);
  if (!d) throw std::runtime_error("mkdtemp failed");
  return std::string(d) + "/" + tag;
}

}  // namespace

// A recorded point is c + k R(phi) (p - c): a camera at the wrong distance
// scales about the optical axis, a rolled camera rotates about it.
TEST(ReferenceCamera, ProjectsWithKnownScaleAndRoll) {
  CameraModel cam;
  cam.centre = {3.0, 1.0};
  cam.scale = 1.04;
  cam.roll_deg = 2.5;
  const double ph = 2.5 * kPi / 180, c = std::cos(ph), s = std::sin(ph);
  for (Vec2 p : {Vec2{0, 1.5}, Vec2{3, 1}, Vec2{7.2, -0.3}}) {
    const double dx = p.x - 3.0, dy = p.y - 1.0;
    const Vec2 q = cam.project(p);
    EXPECT_NEAR(q.x, 3.0 + 1.04 * (c * dx - s * dy), 1e-12);
    EXPECT_NEAR(q.y, 1.0 + 1.04 * (s * dx + c * dy), 1e-12);
  }
}

// Tracking a ballistic flight (known parabola) without noise: frames at
// k / fps on the camera clock from the first frame after release, positions
// of the parabola at (t - release), through the camera transform.
TEST(ReferenceCamera, TracksAKnownTrajectoryFrameByFrame) {
  Launch l;
  l.speed = 8;
  l.climb_deg = 10;
  l.height = 1.5;
  SimOptions o;
  o.t_max = 1.0;
  const Flight f = simulate(NoAero(), {0.01, 1e-5}, l, o, 9.81);
  CameraModel cam;
  cam.scale = 0.97;
  cam.roll_deg = -1.5;
  cam.noise_sigma_m = 0.0;
  const double release = 0.0537;
  const auto pts = track_flight(f, release, cam, TrackWindow::Launch, 17, [] { return 0.0; });
  ASSERT_EQ(pts.size(), 17u);
  const double vx = 8 * std::cos(deg2rad(10)), vy = 8 * std::sin(deg2rad(10));
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const double t = (2 + static_cast<double>(i)) / 30.0;  // first frame after 0.0537 s is 2/30
    EXPECT_NEAR(pts[i].t, t, 1e-12);
    const double tau = t - release;
    const Vec2 p{vx * tau, 1.5 + vy * tau - 0.5 * 9.81 * tau * tau};
    const Vec2 q = cam.project(p);
    EXPECT_NEAR(pts[i].x, q.x, 1e-9);
    EXPECT_NEAR(pts[i].y, q.y, 1e-9);
  }
}

// Same seed, same dataset, whatever the thread count; another seed differs.
TEST(ReferenceGenerate, IsDeterministicBySeed) {
  const auto g = training(2);
  GenerateOptions a = quick(), b = quick();
  a.threads = 1;
  b.threads = 2;
  const Dataset da = generate_dataset(g, a), db = generate_dataset(g, b);
  const Dataset dc = generate_dataset(g, quick(8));
  ASSERT_EQ(da.flights.size(), 6u);
  ASSERT_EQ(db.flights.size(), da.flights.size());
  bool differs = false;
  for (std::size_t i = 0; i < da.flights.size(); ++i) {
    ASSERT_EQ(da.flights[i].name, db.flights[i].name);
    ASSERT_EQ(da.flights[i].points.size(), db.flights[i].points.size());
    for (std::size_t k = 0; k < da.flights[i].points.size(); ++k) {
      EXPECT_EQ(da.flights[i].points[k].x, db.flights[i].points[k].x);
      EXPECT_EQ(da.flights[i].points[k].y, db.flights[i].points[k].y);
      EXPECT_EQ(da.flights[i].points[k].t, db.flights[i].points[k].t);
    }
    differs = differs || dc.flights[i].points.front().x != da.flights[i].points.front().x;
  }
  EXPECT_TRUE(differs);
}

// The dataset follows the spec: the writer's checks pass and load_dataset
// reads back the flights, the per-flight true launch and the settings.
TEST(ReferenceGenerate, WritesADatasetThatReadsBack) {
  const auto g = training(2);
  GenerateOptions o = quick();
  o.camera.noise_sigma_m = 0.03;
  o.camera.frame_rate_hz = 60;
  const Dataset d = generate_dataset(g, o);
  const std::string dir = temp_dir("ds");
  save_dataset(d, dir);
  const Dataset r = load_dataset(dir + "/dataset.json");
  EXPECT_EQ(r.flights.size(), d.flights.size());
  EXPECT_EQ(r.gliders.size(), 2u);
  EXPECT_DOUBLE_EQ(r.frame_rate_hz, 60.0);
  EXPECT_DOUBLE_EQ(r.tracking_sigma_m, 0.03);
  for (const auto& f : r.flights) {
    EXPECT_GE(f.points.size(), 15u);
    EXPECT_LE(f.points.size(), 20u);
    for (const char* k : {"true_speed_m_s", "true_climb_deg", "true_pitch_deg", "true_pitch_rate_deg_s",
                          "true_height_m", "true_release_t_s", "true_end"})
      EXPECT_TRUE(f.extra.count(k)) << k;
    const double v = std::stod(f.extra.at("true_speed_m_s"));
    EXPECT_GT(v, 6.0);
    EXPECT_LT(v, 12.0);
    // frames at 1/60 s
    for (std::size_t k = 1; k < f.points.size(); ++k)
      EXPECT_NEAR(f.points[k].t - f.points[k - 1].t, 1.0 / 60, 1e-9);
  }
}

// Tracking noise: the difference between a noisy and a noise-free recording
// of the same draws has standard deviation sigma per coordinate (chi-square
// bounds for ~700 samples: +-10 %).
TEST(ReferenceGenerate, TrackingNoiseHasTheRequestedSigma) {
  const auto g = training(2);
  GenerateOptions clean = quick(), noisy = quick();
  clean.flights_per_glider = noisy.flights_per_glider = 20;
  clean.camera.noise_sigma_m = 0.0;
  noisy.camera.noise_sigma_m = 0.05;
  const Dataset a = generate_dataset(g, clean), b = generate_dataset(g, noisy);
  double s2 = 0;
  int n = 0;
  for (std::size_t i = 0; i < a.flights.size(); ++i)
    for (std::size_t k = 0; k < a.flights[i].points.size(); ++k) {
      const double dx = b.flights[i].points[k].x - a.flights[i].points[k].x;
      const double dy = b.flights[i].points[k].y - a.flights[i].points[k].y;
      s2 += dx * dx + dy * dy;
      n += 2;
    }
  ASSERT_GT(n, 1000);
  EXPECT_NEAR(std::sqrt(s2 / n), 0.05, 0.005);
}

// Session effects: a headwind shortens the recorded distance; the camera
// effect scales and rolls every recorded point about the camera centre;
// launch_rotation adds its nominal pitch rate at release.
TEST(ReferenceGenerate, SessionEffectsActAsDocumented) {
  const auto g = training(1);
  GenerateOptions base = quick();
  base.camera.noise_sigma_m = 0;
  base.window = TrackWindow::Whole;
  GenerateOptions wind = base, cam = base, rot = base;
  wind.effects.wind.on = true;
  wind.effects.wind.strength = 2.0;  // 2 m/s headwind
  cam.effects.camera.on = true;
  rot.effects.launch_rotation.on = true;
  const Dataset d0 = generate_dataset(g, base), dw = generate_dataset(g, wind);
  const Dataset dc = generate_dataset(g, cam), dr = generate_dataset(g, rot);
  for (std::size_t i = 0; i < d0.flights.size(); ++i) {
    EXPECT_LT(dw.flights[i].points.back().x, d0.flights[i].points.back().x - 0.5);
    // camera: the same flight seen through k = 1.03, phi = 2 deg
    CameraModel c;
    c.scale = 1 + c.scale_error;
    c.roll_deg = c.roll_error_deg;
    for (std::size_t k = 0; k < d0.flights[i].points.size(); ++k) {
      const Vec2 q = c.project({d0.flights[i].points[k].x, d0.flights[i].points[k].y});
      EXPECT_NEAR(dc.flights[i].points[k].x, q.x, 1e-9);
      EXPECT_NEAR(dc.flights[i].points[k].y, q.y, 1e-9);
    }
    const double r0 = std::stod(d0.flights[i].extra.at("true_pitch_rate_deg_s"));
    const double r1 = std::stod(dr.flights[i].extra.at("true_pitch_rate_deg_s"));
    EXPECT_DOUBLE_EQ(r0, 0.0);
    EXPECT_GT(r1, 0.0);  // 60 +- 20 deg/s
    EXPECT_LT(r1, 150.0);
  }
}

TEST(ReferenceGenerate, RejectsBadOptions) {
  const auto g = training(1);
  GenerateOptions o = quick();
  o.flights_per_glider = 0;
  EXPECT_THROW(generate_dataset(g, o), InputError);
  o = quick();
  o.points_min = 3;
  EXPECT_THROW(generate_dataset(g, o), InputError);
  o = quick();
  o.camera.noise_sigma_m = std::nan("");
  EXPECT_THROW(generate_dataset(g, o), InputError);
  o = quick();
  o.launcher.speed_min = 12;
  o.launcher.speed_max = 8;
  EXPECT_THROW(generate_dataset(g, o), InputError);
  EXPECT_THROW(generate_dataset({}, quick()), InputError);
  auto two = training(1);
  two.push_back(two.front());
  EXPECT_THROW(generate_dataset(two, quick()), InputError);
  auto bad = training(1);
  bad.front().first = "../evil";
  EXPECT_THROW(generate_dataset(bad, quick()), InputError);
}

// Launches that never give 6 tracked points (here a delta whose main wing is
// mounted at 40 deg: it tumbles within a few frames in most draws) are left
// out and counted, and the dataset stays valid; strict refuses them. When
// no glider gives a single flight (every launch dives into the ground) the
// dataset is refused.
TEST(ReferenceGenerate, LeavesOutLaunchesThatCannotBeTrackedAndSaysSo) {
  auto g = training(2);  // canard, delta
  g[1].second.wings[0].mount.angle_deg = 40;
  ASSERT_TRUE(validation_problems(g[1].second).empty());
  GenerateOptions o = quick();
  GenerateStats st;
  const Dataset d = generate_dataset(g, o, &st);
  EXPECT_GE(st.dropped, 1);
  EXPECT_EQ(static_cast<int>(d.flights.size()) + st.dropped, 6);
  EXPECT_GT(st.redrawn, 0);
  EXPECT_TRUE(st.dropped_gliders.empty());
  EXPECT_TRUE(dataset_problems(d).empty());
  o.strict = true;
  EXPECT_THROW(generate_dataset(g, o), InputError);
  GenerateOptions dive = quick();
  dive.launcher.climb_min_deg = dive.launcher.climb_max_deg = -80;
  dive.launcher.pitch_offset_deg = 0;
  dive.launcher.height = 0.05;
  dive.launcher.height_sigma = 0;
  EXPECT_THROW(generate_dataset(g, dive), InputError);
}

// A glide found on the reference simulator's forces is an equilibrium of its
// flight: started there, high above the ground, the glider keeps its speed,
// path and pitch for 4 s (pitch damping on, so that the tiny error of the
// start dies out instead of exciting an undamped oscillation).
TEST(ReferenceGenerate, SteadyGlideIsAnEquilibriumOfTheReferenceFlight) {
  for (const auto& [key, g] : training(3)) {
    ReferenceOptions ro;
    ro.effects = Effects::baseline();
    ro.effects.pitch_damping.on = true;
    ro.effects.finite_span.on = true;
    const MassProperties mp = mass_properties(g);
    const ReferenceAero ref(g, mp.cg, ro);
    const RigidBody body{mp.mass, mp.inertia};
    const Glide gl = steady_glide(ref, body);
    ASSERT_TRUE(gl.exists) << key;
    EXPECT_GT(gl.speed, 2.0) << key;
    EXPECT_LT(gl.speed, 12.0) << key;
    Launch l;
    l.speed = gl.speed;
    l.climb_deg = -rad2deg(gl.path_angle);
    l.pitch_from_path = false;
    l.pitch_deg = rad2deg(gl.gamma - gl.path_angle);  // gamma = theta + beta
    l.height = 60;
    SimOptions so;
    so.t_max = 4.0;
    const Flight f = simulate(ref, body, l, so);
    ASSERT_TRUE(f.stable) << key;
    const FlightSample& e = f.samples.back();
    EXPECT_NEAR(e.t, 4.0, 1e-9) << key;
    EXPECT_NEAR(e.speed, gl.speed, 0.005 * gl.speed) << key;
    EXPECT_NEAR(e.alpha, gl.gamma, deg2rad(0.1)) << key;
    EXPECT_NEAR(-std::atan2(e.vy, e.vx), gl.path_angle, deg2rad(0.1)) << key;
  }
}

// Trimming for a reality (as a person bends the tail and adds nose weight)
// puts the reference's pitch equilibrium at the requested angle of attack
// with at least a 5 % static margin; the dataset's gliders are the trimmed
// ones, and their glide in that reality is at the requested angle.
TEST(ReferenceGenerate, RetrimPutsTheEquilibriumAtTheRequestedAngle) {
  GenerateOptions o = quick();
  o.effects = Effects::baseline();
  o.effects.downwash.on = true;  // a reality the drawn gliders are not trimmed for
  o.retrim = true;
  o.retrim_alpha_deg = 2.5;
  const auto gl = training(3);
  const Dataset d = generate_dataset(gl, o);
  ReferenceOptions ro = o.aero;
  ro.effects = o.effects;
  for (const auto& [key, g0] : gl) {
    const Glider& g = d.gliders.at(key);
    const GliderFeatures f = glider_features(g0);
    ASSERT_GE(f.trim_wing, 0);
    const double turned = g.wings[f.trim_wing].mount.angle_deg - g0.wings[f.trim_wing].mount.angle_deg;
    bool weighted = false;
    for (const auto& b : g.ballast) weighted = weighted || b.name == "trim weight";
    for (const auto& fl : d.flights)
      if (fl.glider == key) {
        EXPECT_NEAR(std::stod(fl.extra.at("trim_turn_deg")), turned, 1e-6) << key;
        EXPECT_EQ(std::stod(fl.extra.at("trim_weight_kg")) > 0, weighted) << key;
      }
    const MassProperties mp = mass_properties(g);
    const ReferenceAero ref(g, mp.cg, ro);
    EXPECT_NEAR(level_forces(ref, 5.0, deg2rad(2.5)).moment, 0.0, 1e-7) << key;
    const double h = deg2rad(0.5);
    const GliderForces up = level_forces(ref, 5.0, deg2rad(2.5) + h), dn = level_forces(ref, 5.0, deg2rad(2.5) - h);
    const double margin = -(up.moment - dn.moment) / (up.lift - dn.lift) / f.wings[f.main_wing].mean_chord;
    EXPECT_GE(margin, 0.05 - 1e-9) << key;
    const Glide glide = steady_glide(ref, RigidBody{mp.mass, mp.inertia});
    ASSERT_TRUE(glide.exists) << key;
    EXPECT_NEAR(rad2deg(glide.gamma), 2.5, 0.2) << key;  // at the glide speed, not 5 m/s
  }
}

// Relative launch speeds are multiples of each glider's glide speed in the
// simulated reality: the recorded true speeds lie in [min, max] glide
// speeds (up to the launcher's 4 % spread), and the column says the speed.
TEST(ReferenceGenerate, RelativeLaunchSpeedsFollowTheGlideSpeed) {
  GenerateOptions o = quick();
  o.flights_per_glider = 4;
  o.launcher.speed_relative = true;
  o.launcher.speed_min = 1.0;
  o.launcher.speed_max = 1.4;
  o.launcher.speed_sigma = 0.0;
  const auto gl = training(2);
  const Dataset d = generate_dataset(gl, o);
  ReferenceOptions ro = o.aero;
  ro.effects = o.effects;
  for (const auto& [key, g] : gl) {
    const MassProperties mp = mass_properties(g);
    const Glide glide = steady_glide(ReferenceAero(g, mp.cg, ro), RigidBody{mp.mass, mp.inertia});
    ASSERT_TRUE(glide.exists);
    int n = 0;
    for (const auto& fl : d.flights)
      if (fl.glider == key) {
        ++n;
        EXPECT_NEAR(std::stod(fl.extra.at("glide_speed_m_s")), glide.speed, 1e-6 * glide.speed);
        const double v = std::stod(fl.extra.at("true_speed_m_s"));
        EXPECT_GE(v, 1.0 * glide.speed - 1e-9) << key;
        EXPECT_LE(v, 1.4 * glide.speed + 1e-9) << key;
      }
    EXPECT_EQ(n, 4);
  }
  // A glider that cannot glide in this reality is refused by name.
  auto bad = training(1);
  double tail_x = 1e9;  // the CG far behind the neutral point: no pitch-stable trim
  for (const auto& q : bad[0].second.fuselage) tail_x = std::min(tail_x, q.x);
  bad[0].second.ballast.push_back({"tail weight", 2 * mass_properties(bad[0].second).mass, tail_x + 0.005, 0.0});
  try {
    generate_dataset(bad, o);
    ADD_FAILURE() << "a glider without a glide was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'t17-canard' has no steady glide"), std::string::npos) << e.what();
  }
}
