// The diagnosis's fitting core and statistics (src/diagnose_fit.cpp,
// src/diagnose.cpp). Flights are simulated here by the corrected model with
// known effect strengths and launches; the fits must give those back. The
// whole pipeline on reference-simulator data is tested in
// tests/python/test_diagnose.py; the blind benchmark is bench/diagnosis/.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "pteromys/diagnose.hpp"
#include "pteromys/diagnose_fit.hpp"
#include "pteromys/effects.hpp"
#include "pteromys/io.hpp"
#include "pteromys/mass.hpp"
#include "test_support.hpp"

using namespace pteromys;

namespace {

/// Flights of three training gliders simulated by the baseline model with
/// the corrections `truth`, tracked at 20 fps for 1.2 s with Gaussian noise
/// `noise` [m] (seeded), launches varied over 6-9 m/s and 0-8 degrees.
Dataset corrected_flights(const EffectValues& truth, double noise, unsigned seed = 3) {
  Dataset d;
  d.tracking_sigma_m = noise > 0 ? noise : 1e-3;
  d.frame_rate_hz = 20;
  for (const char* k : {"t01-rectangular", "t04-tapered-mild", "t17-canard"})
    d.gliders[k] = load_glider(test::source_path(std::string("examples/training/") + k + ".glider.json"));
  std::mt19937 rng(seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  for (const auto& [key, g] : d.gliders) {
    d.glider_files[key] = "gliders/" + key + ".glider.json";
    const MountedGlider mg = mount(g, default_model());
    const GliderFeatures f = glider_features(g);
    const EffectAero aero(mg, f, truth, -1000.0);
    const RigidBody body{f.mass, f.inertia};
    TrackOptions to;
    to.sim.wind = {truth.wind, 0.0};
    for (int i = 0; i < 3; ++i) {
      LaunchParams L;
      L.t = 0.0;
      L.x = 0.0;
      L.y = 1.5;
      L.speed = 6.0 + 1.5 * i;
      L.climb = deg2rad(8.0 - 4.0 * i);
      L.pitch = L.climb + deg2rad(1.0 + i);
      L.pitch_rate = truth.launch_rotation;
      std::vector<double> t;
      for (int k = 0; k < 24; ++k) t.push_back(k / 20.0);
      const Track tr = simulate_track(aero, body, L, t, to);
      TrackedFlight fl;
      fl.name = key + "-" + std::to_string(i);
      fl.glider = key;
      for (std::size_t k = 0; k < t.size(); ++k) {
        const Vec2 q = world_to_camera(tr.positions[k], truth);
        fl.points.push_back({t[k], q.x + noise * n01(rng), q.y + noise * n01(rng)});
      }
      d.flights.push_back(fl);
    }
  }
  return d;
}

std::vector<int> all_flights(const Dataset& d) {
  std::vector<int> f;
  for (std::size_t i = 0; i < d.flights.size(); ++i) f.push_back(static_cast<int>(i));
  return f;
}

/// A whole diagnosis small enough for a test: 3 folds, one RBF centre,
/// only the candidates `effects`.
DiagnoseOptions small_diagnosis(std::vector<Effect> effects) {
  DiagnoseOptions o;
  o.folds = 3;
  o.effects = std::move(effects);
  o.fit.max_centres = 1;
  o.threads = 2;
  return o;
}

DiagFitOptions quick() {
  DiagFitOptions o;
  o.threads = 2;
  o.max_iterations = 12;
  return o;
}

}  // namespace

// The chi-square tail against textbook quantiles (e.g. Abramowitz & Stegun
// table 26.8): P(X > 3.8415 | 1) = 0.05, P(X > 5.9915 | 2) = 0.05,
// P(X > 23.2093 | 10) = 0.01; the quantile inverts the tail.
TEST(DiagnoseStatistics, ChiSquareTailMatchesTables) {
  EXPECT_NEAR(chi2_sf(3.841458820694124, 1), 0.05, 1e-9);
  EXPECT_NEAR(chi2_sf(5.991464547107979, 2), 0.05, 1e-9);
  EXPECT_NEAR(chi2_sf(23.209251158954356, 10), 0.01, 1e-9);
  EXPECT_NEAR(chi2_sf(2.0, 2), std::exp(-1.0), 1e-12);  // k = 2: exp(-x/2)
  for (double k : {1.0, 2.0, 5.0, 40.0})
    for (double p : {0.5, 0.05, 1e-3, 1e-6}) EXPECT_NEAR(chi2_sf(chi2_isf(p, k), k), p, 1e-6 * p + 1e-12);
}

// Exact flights of the baseline: the fit with nothing free reproduces them
// (launches recovered, residuals at round-off and step-size level).
TEST(DiagnosisFit, BaselineFlightsFitExactly) {
  const Dataset d = corrected_flights(EffectValues{}, 0.0);
  const DiagnosisData D(d, quick());
  const FitOutcome r = D.fit({default_model(), {}, {}}, all_flights(d), {});
  EXPECT_LT(r.rmse(), 1e-4);
  EXPECT_EQ(r.points, 9 * 24);
  EXPECT_EQ(r.launch_parameters, 45);
}

// A corrected model's strength is recovered from its own exact flights by
// variable projection from the baseline (strength 0) -- the fitting core,
// independent of how well a correction imitates the reference simulator.
TEST(DiagnosisFit, RecoversTheTrueStrengthOfItsOwnFlights) {
  struct Case {
    Effect e;
    double value;
    double tol;
  };
  for (const Case& c : {Case{Effect::PitchDamping, 0.8, 0.02}, Case{Effect::Wind, -1.5, 0.02},
                        Case{Effect::LaunchRotation, deg2rad(40.0), deg2rad(1.0)}}) {
    EffectValues truth;
    truth.at(c.e, 0) = c.value;
    const Dataset d = corrected_flights(truth, 0.0);
    const DiagnosisData D(d, quick());
    const FitOutcome r = D.fit({default_model(), {}, {}}, all_flights(d), {FreeParam::effect_param(c.e, 0)});
    EXPECT_NEAR(r.model.effects.at(c.e, 0), c.value, c.tol) << effect_name(c.e);
    EXPECT_LT(r.rmse(), 2e-3) << effect_name(c.e);
  }
}

// The camera's two parameters together, with 1 cm of tracking noise: the
// fitted scale and roll lie within 4 standard deviations of the truth (the
// Gauss-Newton covariance sigma^2 (J^T J)^-1 of the projected Jacobian).
TEST(DiagnosisFit, RecoversCameraScaleAndRollWithinTheirUncertainty) {
  EffectValues truth;
  truth.camera_scale = 0.04;
  truth.camera_roll = deg2rad(3.0);
  const double sigma = 0.01;
  const Dataset d = corrected_flights(truth, sigma, 11);
  const DiagnosisData D(d, quick());
  const std::vector<FreeParam> free = {FreeParam::effect_param(Effect::Camera, 0),
                                       FreeParam::effect_param(Effect::Camera, 1)};
  const FitOutcome r = D.fit({default_model(), {}, {}}, all_flights(d), free);
  const Eigen::MatrixXd J = D.projected_jacobian(r, free);
  const Eigen::MatrixXd cov = sigma * sigma * (J.transpose() * J).inverse();
  const double s0 = std::sqrt(cov(0, 0)) * D.scale(free[0]), s1 = std::sqrt(cov(1, 1)) * D.scale(free[1]);
  EXPECT_NEAR(r.model.effects.camera_scale, 0.04, 4 * s0 + 1e-4);
  EXPECT_NEAR(r.model.effects.camera_roll, deg2rad(3.0), 4 * s1 + 1e-4);
  EXPECT_LT(s0, 0.01);  // the data do constrain them
  // Residual at the noise level: SSE / (2N - 5F - 2) ~ sigma^2.
  const double dof = 2.0 * r.points - r.launch_parameters - 2;
  EXPECT_NEAR(r.sse / dof, sigma * sigma, 0.25 * sigma * sigma);
}

// Bad input is refused with a reason.
TEST(Diagnose, RefusesTooFewGlidersAndBadOptions) {
  Dataset d = corrected_flights(EffectValues{}, 0.01);
  DiagnoseOptions o;
  o.folds = 1;
  EXPECT_THROW(diagnose(d, o), InputError);
  o = {};
  o.effects = {Effect::Wind, Effect::Wind};
  EXPECT_THROW(diagnose(d, o), InputError);
  // Two gliders: no training and held-out gliders for every fold.
  d.gliders.erase("t17-canard");
  d.glider_files.erase("t17-canard");
  std::vector<TrackedFlight> kept;
  for (const auto& f : d.flights)
    if (f.glider != "t17-canard") kept.push_back(f);
  d.flights = kept;
  try {
    diagnose(d, {});
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("at least 3 gliders"), std::string::npos);
  }
}

// The whole pipeline, small enough to run under the sanitizers: flights of
// the baseline model itself with 1 cm noise leave no gap, so no candidate is
// significant and the verdict is "none"; the held-out chi-square ratio is
// that of noise (about 1), and the JSON has the spec's keys.
TEST(Diagnose, FlightsOfTheBaselineModelLeaveNoGap) {
  const Dataset d = corrected_flights(EffectValues{}, 0.01, 7);
  const DiagnoseOptions o = small_diagnosis({Effect::Wind, Effect::LaunchRotation});
  const DiagnoseResult r = diagnose(d, o);
  EXPECT_EQ(r.verdict, "none") << r.summary;
  EXPECT_LT(r.holdout_chi2_ratio, 1.3) << r.summary;
  EXPECT_GT(r.holdout_chi2_ratio, 0.5) << r.summary;
  ASSERT_EQ(r.effects.size(), 2u);
  for (const auto& e : r.effects) EXPECT_FALSE(e.significant) << e.name;
  const nlohmann::json j = diagnosis_json(r, o);
  EXPECT_EQ(j.at("verdict"), "none");
  EXPECT_TRUE(j.at("baseline").contains("fit_rmse_m"));
  EXPECT_TRUE(j.at("baseline").contains("holdout_rmse_m"));
  for (const auto& e : j.at("effects"))
    for (const char* k : {"name", "holdout_rmse_m", "shrink", "significant"}) EXPECT_TRUE(e.contains(k)) << k;
}

// The whole diagnosis on flights of the corrected model itself (pitch damping
// at its full size, 2 mm noise): the true candidate is the verdict with its
// strength recovered, and no candidate explains the flights worse than the
// baseline it contains (strength 0) -- on all gliders and on held-out ones.
TEST(Diagnose, FindsTheCorrectionThatMadeTheFlights) {
  EffectValues truth;
  truth.pitch_damping = 1.0;
  const Dataset d = corrected_flights(truth, 0.002, 5);
  const DiagnoseOptions o = small_diagnosis({Effect::PitchDamping, Effect::AddedMass});  // they damp pitch alike
  const DiagnoseResult r = diagnose(d, o);
  EXPECT_EQ(r.verdict, "pitch_damping") << r.summary;
  for (const auto& e : r.effects) {
    EXPECT_LE(e.fit_rmse_m, r.fit_rmse_m * (1 + 1e-12)) << e.name;
    if (e.effect == Effect::PitchDamping) {
      ASSERT_EQ(e.parameters.size(), 1u);
      EXPECT_NEAR(e.parameters[0], 1.0, 0.1);
      EXPECT_TRUE(e.significant);
    }
  }
}

// A polished fit (centre values free with an effect) pays for moving a value
// away from the start model: with a very strong pull the values stay where
// they were and the fit is the fixed-coefficient one; without it they move
// and fit the flights at least as well (the pull is a Tikhonov term, not a
// constraint).
TEST(DiagnosisFit, PolishedCentreValuesArePulledTowardTheStart) {
  EffectValues truth;
  truth.pitch_damping = 1.0;
  const Dataset d = corrected_flights(truth, 0.002, 9);
  FitOptions fo;
  fo.max_centres = 1;
  fo.threads = 2;
  const auto rbf = fit_coefficients(d, fo).model;
  ASSERT_TRUE(rbf);
  ASSERT_GE(rbf->centres().size(), 1u);
  std::vector<FreeParam> free;
  for (std::size_t k = 0; k < 3 * rbf->centres().size(); ++k) free.push_back(FreeParam::coefficient(static_cast<int>(k)));
  free.push_back(FreeParam::effect_param(Effect::PitchDamping, 0));
  auto deviation = [&](const FitOutcome& r) {  // largest change of a value, in scale units (cd 0.02, cl 0.1, cm 0.02)
    const auto m = std::dynamic_pointer_cast<const RbfModel>(r.model.coefficients);
    double dev = 0;
    for (std::size_t k = 0; k < m->centres().size(); ++k) {
      const Coefficients a = m->centres()[k].value, b = rbf->centres()[k].value;
      dev = std::max({dev, std::abs(a.cd - b.cd) / 0.02, std::abs(a.cl - b.cl) / 0.1, std::abs(a.cm - b.cm) / 0.02});
    }
    return dev;
  };
  DiagFitOptions loose = quick(), tight = quick();
  loose.coefficient_regularisation_m = 0.0;
  tight.coefficient_regularisation_m = 100.0;
  const DiagnosisData Dl(d, loose), Dt(d, tight);
  const DiagModel start{rbf, {}, {}};
  const FitOutcome rl = Dl.fit(start, all_flights(d), free), rt = Dt.fit(start, all_flights(d), free);
  EXPECT_GT(deviation(rl), 1e-3);
  EXPECT_LT(deviation(rt), 1e-2 * deviation(rl));
  EXPECT_LE(rl.sse, rt.sse * (1 + 1e-9));
}
