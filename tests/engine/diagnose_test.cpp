// The diagnosis's fitting core and statistics (src/diagnose_fit.cpp,
// src/diagnose.cpp). Flights are simulated here by the corrected model with
// known effect strengths and launches; the fits must give those back. The
// whole pipeline on reference-simulator data is tested in
// tests/python/test_diagnose.py; the blind benchmark is bench/diagnosis/.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <random>
#include <map>
#include <regex>
#include <set>
#include <string>
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
/// `rates` (one per flight, in order) gives each flight its own pitch rate at
/// the first point instead of truth.launch_rotation [rad/s].
Dataset corrected_flights(const EffectValues& truth, double noise, unsigned seed = 3,
                          const std::vector<double>& rates = {}) {
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
      L.pitch_rate = rates.empty() ? truth.launch_rotation : rates.at(d.flights.size());
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

/// On flights that carry effects `a` and `b`: one is the verdict and the
/// other the only effect of `also`, given the verdict significant with the
/// verdict's effect still needed given it, and the verdict's not replaced.
/// Returns the other (empty, the failure recorded, when the verdict is
/// neither or `also` is not exactly the other).
std::string second_effect_found(const DiagnoseResult& r, const std::string& a, const std::string& b) {
  if (r.verdict != a && r.verdict != b) {
    ADD_FAILURE() << "verdict " << r.verdict << ", not " << a << " or " << b << ": " << r.summary;
    return {};
  }
  const std::string other = r.verdict == a ? b : a;
  if (r.also != std::vector<std::string>{other}) {
    ADD_FAILURE() << "also is not [" << other << "]: " << r.summary;
    return {};
  }
  for (const auto& e : r.effects)
    if (e.name == other) {
      EXPECT_TRUE(e.given_verdict.significant) << other;
      EXPECT_TRUE(e.given_verdict.verdict_still_needed) << other;
      // The first round's guards, made given the verdict too: every held-out
      // glider counted, one fitted value per fold, both passed.
      EXPECT_EQ(e.given_verdict.gliders_total, r.gliders) << other;
      EXPECT_EQ(e.given_verdict.fold_parameters.size(), static_cast<std::size_t>(r.folds)) << other;
      EXPECT_TRUE(e.given_verdict.robust_pass) << e.given_verdict.note;
      EXPECT_TRUE(e.given_verdict.bound_pass) << e.given_verdict.note;
      EXPECT_EQ(e.given_verdict.note.rfind("with " + r.verdict + " in the model, significant", 0), 0u)
          << e.given_verdict.note;
    }
  EXPECT_TRUE(r.replaced.empty()) << r.replaced;
  // The summary offers `also` as a lead, not as a second effect shown (on
  // the blind benchmark's single-effect flights most entries were wrong).
  EXPECT_NE(r.summary.find(other + " (" ), std::string::npos) << r.summary;
  EXPECT_NE(r.summary.find("perhaps a second effect, perhaps what " + r.verdict + "'s fit left"), std::string::npos)
      << r.summary;
  return other;
}

/// Flights of the model with pitch damping at its full size (2 mm noise, 3
/// gliders), diagnosed with pitch damping and wind as candidates, profiled
/// starts on (two gliders per fold's training set) and no second round.
struct PitchDampingCase {
  Dataset flights;
  DiagnoseOptions options;
};
/// small_diagnosis with profiled starts (two gliders per fold's training
/// set, of corrected_flights' three) and no second round.
DiagnoseOptions profiled_diagnosis(std::vector<Effect> effects) {
  DiagnoseOptions o = small_diagnosis(std::move(effects));
  o.profile = true;
  o.profile_min_gliders = 2;  // three gliders, two per fold's training set
  o.second_effect = false;
  return o;
}

/// The same diagnosis with no candidate refitted from its linearised step
/// and no steps carried into the folds: every fit of a candidate starts at
/// strength 0 (or, with theory_starts, also at its theoretical size) at the
/// centre values from before the baseline's step, and is not refitted at
/// the baseline's final ones (refit_unstepped: with it, finite span on the
/// flights of AnUnexplainedGapIsSearchedAgainFromTheoreticalSizes is found
/// by the first search, 20 % held out).
DiagnoseOptions unstepped(DiagnoseOptions o) {
  o.profiled_candidates = 0;
  o.carry_steps = false;
  o.refit_unstepped = false;
  return o;
}

/// How many progress lines contain `needle`.
int lines_with(const std::vector<std::string>& lines, const std::string& needle) {
  return static_cast<int>(
      std::count_if(lines.begin(), lines.end(), [&](const std::string& l) { return l.find(needle) != std::string::npos; }));
}

PitchDampingCase profiled_pitch_damping_case() {
  EffectValues truth;
  truth.pitch_damping = 1.0;
  return {corrected_flights(truth, 0.002, 5), profiled_diagnosis({Effect::PitchDamping, Effect::Wind})};
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

// The hold of a theoretical-size start (DiagnoseOptions::hold_theory) by
// its definition: 1 mm^2 of variance a squared residual, one strength
// parameter at the 1 % level (6.63, A & S table 26.8). Freed 1 mm^2 better
// is delta chi2 1, held; 10 mm^2 better is 10, rejected. Not rejected but
// beaten by the other start while the freed fit beats it: freed instead.
// Beaten by the other start as the freed fit is too: held (neither wins).
TEST(DiagnoseStatistics, ATheoreticalSizeIsHeldUnlessRejectedOrOutdone) {
  const double s2 = 1e-6, needed = chi2_isf(0.01, 1);
  EXPECT_NEAR(needed, 6.634896601021214, 1e-6);
  TheoryHold t = theory_hold(1.001e-3, 1.000e-3, 1.2e-3, s2, needed);
  EXPECT_NEAR(t.delta_chi2, 1.0, 1e-9);
  EXPECT_TRUE(t.held());
  t = theory_hold(1.010e-3, 1.000e-3, 1.2e-3, s2, needed);
  EXPECT_NEAR(t.delta_chi2, 10.0, 1e-9);
  EXPECT_TRUE(t.rejected);
  EXPECT_FALSE(t.held());
  t = theory_hold(1.003e-3, 1.000e-3, 1.002e-3, s2, needed);
  EXPECT_FALSE(t.rejected);
  EXPECT_TRUE(t.outdone);
  EXPECT_FALSE(t.held());
  t = theory_hold(1.003e-3, 1.000e-3, 0.9e-3, s2, needed);
  EXPECT_FALSE(t.outdone);
  EXPECT_TRUE(t.held());
  // a freed fit that failed (NaN) never displaces the held one
  t = theory_hold(1.003e-3, std::nan(""), 1.002e-3, s2, needed);
  EXPECT_TRUE(t.held());
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

// PTEROMYS_FIT_STATS (docs/diagnosis.md, Speed): every fit prints one line
// whose simulation count is the fit's own (FitOutcome::simulations, counted
// apart from the line's), with the multi-started launch fits' share of it no
// larger than the whole; without the variable nothing is printed.
TEST(DiagnosisFit, FitStatsLineAgreesWithTheFit) {
  EffectValues truth;
  truth.at(Effect::Wind, 0) = -1.5;
  const Dataset d = corrected_flights(truth, 0.0);
  const DiagnosisData D(d, quick());
  const std::vector<FreeParam> free{FreeParam::effect_param(Effect::Wind, 0)};
  ::unsetenv("PTEROMYS_FIT_STATS");
  testing::internal::CaptureStderr();
  D.fit({default_model(), {}, {}}, all_flights(d), free);
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
  ::setenv("PTEROMYS_FIT_STATS", "1", 1);
  testing::internal::CaptureStderr();
  const FitOutcome r = D.fit({default_model(), {}, {}}, all_flights(d), free);
  const std::string line = testing::internal::GetCapturedStderr();
  ::unsetenv("PTEROMYS_FIT_STATS");
  int flights = 0, np = 0, iterations = 0;
  double seconds = 0, rmse = 0;
  long sims = 0, fb_sims = 0, fbs = 0, kept = 0, refresh = 0;
  ASSERT_EQ(std::sscanf(line.c_str(),
                        "fit: %d flights, %d free, %d iterations, %lf s: %ld simulations, %ld in %ld trial fallbacks "
                        "(%ld kept), %ld in refreshes; rmse %lf m",
                        &flights, &np, &iterations, &seconds, &sims, &fb_sims, &fbs, &kept, &refresh, &rmse),
            10)
      << line;
  EXPECT_EQ(std::count(line.begin(), line.end(), '\n'), 1) << line;
  EXPECT_EQ(flights, static_cast<int>(all_flights(d).size()));
  EXPECT_EQ(np, 1);
  EXPECT_EQ(iterations, r.iterations);
  EXPECT_EQ(sims, r.simulations);
  EXPECT_GE(seconds, 0.0);
  EXPECT_LE(fb_sims + refresh, sims);
  EXPECT_LE(kept, fbs);
  EXPECT_NEAR(rmse, r.rmse(), 1e-3 * r.rmse() + 1e-12);
}

// Launch rotation as a launch value: every flight's own pitch rate (here
// 10-90 deg/s, as a thrower's) is recovered from its exact flight, while one
// rate shared by all flights cannot fit them (it leaves the spread about the
// mean, tens of deg/s, unexplained).
TEST(DiagnosisFit, RecoversEveryFlightsOwnLaunchRotation) {
  std::vector<double> rates;
  for (int i = 0; i < 9; ++i) rates.push_back(deg2rad(10.0 + 10.0 * ((i * 4) % 9)));  // 10, 50, 90, 40, ... deg/s
  const Dataset d = corrected_flights(EffectValues{}, 0.0, 3, rates);
  const DiagnosisData D(d, quick());
  DiagModel per_flight{default_model(), {}, {}};
  per_flight.effects.launch_rotation_per_flight = true;
  const FitOutcome r = D.fit(per_flight, all_flights(d), {});
  EXPECT_EQ(r.launch_parameters, 6 * 9);
  EXPECT_LT(r.rmse(), 2e-3);
  ASSERT_EQ(r.flights.size(), rates.size());
  for (std::size_t i = 0; i < rates.size(); ++i)
    EXPECT_NEAR(rad2deg(r.flights[i].launch.pitch_rate), rad2deg(rates[i]), 1.0) << d.flights[i].name;
  const FitOutcome common = D.fit({default_model(), {}, {}}, all_flights(d), {FreeParam::effect_param(Effect::LaunchRotation, 0)});
  EXPECT_EQ(common.launch_parameters, 5 * 9);
  EXPECT_GT(common.rmse(), 5 * r.rmse());
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

// One linearised step (DiagnosisData::linear_step, used by the profiled
// candidates): a camera error is nearly linear in the recorded positions, so
// one Gauss-Newton step from the baseline's launch fit lands within a few
// percent of the true scale and roll of exact flights; the linearised SSE it
// predicts is below the start's; a damped step goes part of the way. A
// Jacobian of the wrong shape and a fraction outside (0, 1] are refused.
TEST(DiagnosisFit, LinearStepFindsANearlyLinearCameraError) {
  EffectValues truth;
  truth.camera_scale = 0.02;
  truth.camera_roll = deg2rad(1.0);
  const Dataset d = corrected_flights(truth, 0.0);
  const DiagnosisData D(d, quick());
  const FitOutcome at = D.fit({default_model(), {}, {}}, all_flights(d), {});
  const std::vector<FreeParam> free = {FreeParam::effect_param(Effect::Camera, 0),
                                       FreeParam::effect_param(Effect::Camera, 1)};
  const Eigen::MatrixXd J = D.projected_jacobian(at, free);
  double predicted = -1;
  const DiagModel m = D.linear_step(at, free, J, {0, 1}, &predicted);
  EXPECT_NEAR(m.effects.camera_scale, 0.02, 0.002);
  EXPECT_NEAR(m.effects.camera_roll, deg2rad(1.0), deg2rad(0.1));
  EXPECT_GE(predicted, 0.0);
  EXPECT_LT(predicted, 0.1 * at.sse);
  const FitOutcome after = D.fit(m, all_flights(d), {});
  EXPECT_LT(after.sse, 0.05 * at.sse);
  // Half the step moves the strengths half as far; the linearised SSE at a
  // fraction t of the least-squares step is |r|^2 - (2t - t^2) |P r|^2, at
  // t = 1/2 the start's less 3/4 of the full step's gain.
  double predicted_half = -1;
  const DiagModel h = D.linear_step(at, free, J, {0, 1}, &predicted_half, 0.5);
  EXPECT_NEAR(h.effects.camera_scale, 0.5 * m.effects.camera_scale, 1e-12);
  EXPECT_NEAR(h.effects.camera_roll, 0.5 * m.effects.camera_roll, 1e-12);
  EXPECT_NEAR(predicted_half, at.sse - 0.75 * (at.sse - predicted), 1e-9 * at.sse);
  EXPECT_THROW(D.linear_step(at, free, J.leftCols(1), {0}), InputError);
  EXPECT_THROW(D.linear_step(at, free, J, {2}), InputError);
  EXPECT_THROW(D.linear_step(at, free, J, {0, 1}, nullptr, 0.0), InputError);
  EXPECT_THROW(D.linear_step(at, free, J, {0, 1}, nullptr, 1.5), InputError);
}

// The same step on the RBF centre values: a model whose values were moved
// (lift +0.03, moment +0.004 at every centre) is stepped back toward the one
// fitted to the flights, and the flights' error falls to a small part of the
// moved model's, with the pull toward the start (the moved values) in place.
TEST(DiagnosisFit, LinearStepOnTheCentreValuesUndoesAMove) {
  const Dataset d = corrected_flights(EffectValues{}, 0.0);
  FitOptions fo;
  fo.max_centres = 1;
  fo.threads = 2;
  const auto rbf = fit_coefficients(d, fo).model;
  ASSERT_TRUE(rbf);
  std::vector<Coefficients> moved;
  for (const auto& c : rbf->centres()) moved.push_back({c.value.cd, c.value.cl + 0.03, c.value.cm + 0.004});
  const DiagnosisData D(d, quick());
  const FitOutcome fitted = D.fit({rbf, {}, {}}, all_flights(d), {});
  const FitOutcome at = D.fit({rbf->with_values(moved), {}, {}}, all_flights(d), {});
  ASSERT_GT(at.sse, 10 * fitted.sse);  // the move matters
  std::vector<FreeParam> free;
  std::vector<int> cols;
  for (std::size_t k = 0; k < 3 * rbf->centres().size(); ++k) {
    free.push_back(FreeParam::coefficient(static_cast<int>(k)));
    cols.push_back(static_cast<int>(k));
  }
  const DiagModel m = D.linear_step(at, free, D.projected_jacobian(at, free), cols);
  const FitOutcome after = D.fit(m, all_flights(d), {});
  EXPECT_LT(after.sse, 0.2 * at.sse);
  const auto back = std::dynamic_pointer_cast<const RbfModel>(m.coefficients);
  ASSERT_TRUE(back);
  for (std::size_t k = 0; k < moved.size(); ++k)  // toward the fitted values
    EXPECT_LT(std::abs(back->centres()[k].value.cl - rbf->centres()[k].value.cl), 0.03) << k;
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
  DiagnoseOptions o = small_diagnosis({Effect::Wind, Effect::LaunchRotation});
  o.profile = false;  // fixed coefficients only; the default (profiled starts) below
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
  // With profiled starts (the default: the baseline's linearised step, the
  // candidates' linearised gains): still no gap and nothing significant.
  // Small enough that the profiled path also runs under the sanitizers.
  // Three gliders are fewer than the default profile_min_gliders: the
  // default runs with fixed coefficients (no linearised step reported); with
  // the threshold lowered the profiled path runs.
  DiagnoseOptions op = o;
  op.profile = DiagnoseOptions{}.profile;
  EXPECT_TRUE(op.profile) << "profiled starts are the default";
  EXPECT_GT(op.profile_min_gliders, 3);
  std::vector<std::string> messages;
  auto stepped = [&](const DiagnoseOptions& opts, DiagnoseResult& out) {
    bool seen = false;
    messages.clear();
    out = diagnose(d, opts, [&](const DiagnoseProgress& p) {
      seen = seen || p.message.find("linearised step") != std::string::npos;
      messages.push_back(p.message);
    });
    return seen;
  };
  DiagnoseResult rd;
  EXPECT_FALSE(stepped(op, rd)) << "profiled on 3 gliders";
  EXPECT_EQ(rd.verdict, "none") << rd.summary;
  op.profile_min_gliders = 2;
  DiagnoseResult rp;
  EXPECT_TRUE(stepped(op, rp)) << "no profiled step with the threshold at 2 gliders";
  EXPECT_EQ(rp.verdict, "none") << rp.summary;
  EXPECT_LT(rp.holdout_chi2_ratio, 1.3) << rp.summary;
  for (const auto& e : rp.effects) EXPECT_FALSE(e.significant) << e.name;
  // The fold rule (docs/diagnosis.md): on flights without any effect no
  // candidate is supported by a fold's training gliders, so wherever a
  // candidate kept the centre values from before the baseline's own step
  // it is replaced by the baseline's fit, and its fold strengths are then
  // exactly 0. The profiled baseline's step moves the centre values in
  // some fold, so the rule must fire at least once here.
  const std::regex fired(R"(fold (\d+)/\d+: (\w+) is not supported by the training gliders)");
  int fired_count = 0;
  for (const auto& m : messages) {
    std::smatch g;
    if (!std::regex_search(m, g, fired)) continue;
    ++fired_count;
    const int k = std::stoi(g[1].str()) - 1;
    const auto it = std::find_if(rp.effects.begin(), rp.effects.end(),
                                 [&](const EffectResult& e) { return e.name == g[2].str(); });
    ASSERT_NE(it, rp.effects.end()) << m;
    ASSERT_LT(k, static_cast<int>(it->fold_parameters.size())) << m;
    for (double v : it->fold_parameters[k]) EXPECT_EQ(v, 0.0) << m;
  }
  EXPECT_GT(fired_count, 0) << "the fold rule never fired on effect-free flights with profiled starts";
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
  // The summary gives the fitted strength with the theory's size to read it by.
  EXPECT_TRUE(std::regex_search(r.summary, std::regex(R"(fitted strength [0-9.]+ \(1 would be its theoretical size\)\.)")))
      << r.summary;
  for (const auto& e : r.effects) {
    EXPECT_LE(e.fit_rmse_m, r.fit_rmse_m * (1 + 1e-12)) << e.name;
    if (e.effect == Effect::PitchDamping) {
      ASSERT_EQ(e.parameters.size(), 1u);
      EXPECT_NEAR(e.parameters[0], 1.0, 0.1);
      EXPECT_TRUE(e.significant);
    }
  }
}

// Profiled starts (DiagnoseOptions::profile): on the same flights (pitch
// damping at full size, 2 mm noise) with one RBF centre, the coefficients
// fitted without the effect leave the fixed-coefficient candidate at 0.9 cm
// (4.5 sigma); refitted from the linearised step and jointly with the centre
// values, pitch damping reaches the tracking noise (RMSE under 2 sigma) at
// its true strength, and it is the verdict.
TEST(Diagnose, ProfiledStartsFitTheTrueCorrectionToTheNoise) {
  auto [d, o] = profiled_pitch_damping_case();
  o.carry_steps = false;  // with it: CarriedStepsRefitTheAllGliderCandidatesInEveryFold
  std::vector<std::string> lines;
  const DiagnoseResult r = diagnose(d, o, [&](const DiagnoseProgress& p) { lines.push_back(p.message); });
  for (const auto& l : lines) EXPECT_EQ(l.find("stepped on all gliders"), std::string::npos) << l;
  EXPECT_EQ(r.verdict, "pitch_damping") << r.summary;
  bool seen = false;
  for (const auto& e : r.effects)
    if (e.effect == Effect::PitchDamping) {
      seen = true;
      ASSERT_EQ(e.parameters.size(), 1u);
      EXPECT_NEAR(e.parameters[0], 1.0, 0.1);
      EXPECT_LT(e.fit_rmse_m, 2 * 0.002);
    }
  EXPECT_TRUE(seen);
}

// The profiled starts' screen is kept in the result
// (EffectResult::linearised_delta_chi2, per fold too) so that rules choosing
// among candidates by it can be replayed on stored results. On flights of
// the model with pitch damping at its full size the true correction's
// linearised gain leads wind's on all gliders and in every fold (the data
// were made with pitch damping and no wind); the figures are the ones the
// progress lines print (three significant digits), and the JSON writes a
// screen that did not run as null.
TEST(Diagnose, TheScreensLinearisedGainsAreKeptPerCandidateAndFold) {
  auto [d, o] = profiled_pitch_damping_case();
  std::vector<std::string> lines;
  const DiagnoseResult r = diagnose(d, o, [&](const DiagnoseProgress& p) { lines.push_back(p.message); });
  const EffectResult *pd = nullptr, *wind = nullptr;
  for (const auto& e : r.effects) (e.effect == Effect::PitchDamping ? pd : wind) = &e;
  ASSERT_TRUE(pd && wind);
  const std::size_t folds = r.fold_gliders.size();
  ASSERT_EQ(folds, 3u);
  for (const EffectResult* e : {pd, wind}) {
    EXPECT_TRUE(std::isfinite(e->linearised_delta_chi2)) << e->name;
    ASSERT_EQ(e->fold_linearised_delta_chi2.size(), folds) << e->name;
    for (double g : e->fold_linearised_delta_chi2) EXPECT_TRUE(std::isfinite(g)) << e->name;
  }
  EXPECT_GT(pd->linearised_delta_chi2, wind->linearised_delta_chi2);
  for (std::size_t k = 0; k < folds; ++k)
    EXPECT_GT(pd->fold_linearised_delta_chi2[k], wind->fold_linearised_delta_chi2[k]) << "fold " << k + 1;
  // The all-glider progress line names the stepped candidates with their gains.
  const std::string line = "all gliders: candidates refitted from the linearised step with the centre values: ";
  const std::string needle = "pitch_damping (linearised delta chi2 ";
  bool seen = false;
  for (const auto& l : lines) {
    if (l.rfind(line, 0) != 0) continue;
    const auto at = l.find(needle);
    ASSERT_NE(at, std::string::npos) << l;
    const double printed = std::stod(l.substr(at + needle.size()));
    EXPECT_NEAR(pd->linearised_delta_chi2, printed, 5e-3 * std::abs(printed)) << l;
    seen = true;
  }
  EXPECT_TRUE(seen) << "no all-glider screen line";
  // JSON: the figures, and null where no screen ran.
  DiagnoseResult copy = r;
  const nlohmann::json j = diagnosis_json(copy, o);
  for (const auto& e : j["effects"]) {
    ASSERT_TRUE(e["linearised_delta_chi2"].is_number()) << e.dump();
    ASSERT_EQ(e["fold_linearised_delta_chi2"].size(), folds) << e.dump();
  }
  for (auto& e : copy.effects) {
    e.linearised_delta_chi2 = std::numeric_limits<double>::quiet_NaN();
    e.fold_linearised_delta_chi2.assign(folds, std::numeric_limits<double>::quiet_NaN());
  }
  for (const auto& e : diagnosis_json(copy, o)["effects"]) {
    EXPECT_TRUE(e["linearised_delta_chi2"].is_null()) << e.dump();
    for (const auto& g : e["fold_linearised_delta_chi2"]) EXPECT_TRUE(g.is_null()) << e.dump();
  }
}

// The verdict's strength: with no candidate refitted from its linearised
// step (DiagnoseOptions::profiled_candidates = 0) the fits keep the
// baseline's coefficients, which take part of the damping (about 0.93 at a
// fit error near 0.9 cm, four times the 2 mm noise, on these flights). The
// held-out gliders confirm pitch damping, so by default the held-out-led
// step refits it from its own step on all gliders before its likelihood
// ratio (DiagnoseOptions::heldout_steps); without those, the verdict's
// effect is refitted so after the decision. Either way the reported
// strength and fit error are the truth's (strength 1 within 0.1) and the
// noise's; without the refit the fit error assertion fails.
TEST(Diagnose, TheVerdictsStrengthIsRefittedFromItsStepWhenNoCandidateWas) {
  auto [d, o] = profiled_pitch_damping_case();
  o.profiled_candidates = 0;
  for (const bool heldout_steps : {true, false}) {
    SCOPED_TRACE(heldout_steps ? "held-out-led steps" : "without held-out-led steps");
    o.heldout_steps = heldout_steps;
    std::vector<std::string> lines;
    const DiagnoseResult r = diagnose(d, o, [&](const DiagnoseProgress& p) { lines.push_back(p.message); });
    ASSERT_EQ(r.verdict, "pitch_damping") << r.summary;
    EXPECT_EQ(lines_with(lines, "all gliders, held-out-led: pitch_damping (held-out shrink"), heldout_steps ? 1 : 0);
    EXPECT_EQ(lines_with(lines, "the verdict's strength: pitch_damping refitted from its linearised step"),
              heldout_steps ? 0 : 1);
    for (const auto& e : r.effects)
      if (e.effect == Effect::PitchDamping) {
        ASSERT_EQ(e.parameters.size(), 1u);
        EXPECT_NEAR(e.parameters[0], 1.0, 0.1);
        EXPECT_LT(e.fit_rmse_m, 2 * 0.002);
      }
  }
  // Refused: a negative count.
  o.profiled_candidates = -1;
  EXPECT_THROW(diagnose(d, o), InputError);
}

// (DiagnoseOptions::heldout_fold_start, on by default since 2026-12-03) The held-out-led
// refit of the case above also starts pitch damping at the mean of its
// folds' fitted strengths, switched on from the baseline in steps: with
// leader_reached at 100 the start is made even where the step reached it,
// and its line names the folds' mean, which is the mean of the strengths
// the result reports for the folds. Off, no such start; the
// verdict and its strength (the truth's 1 within 0.1) either way.
TEST(Diagnose, AHeldOutLedRefitCanStartFromTheFoldsMeanStrength) {
  auto [d, o] = profiled_pitch_damping_case();
  o.profiled_candidates = 0;
  o.leader_reached = 100;
  for (const bool fold_start : {true, false}) {
    SCOPED_TRACE(fold_start ? "with the folds' start" : "without");
    o.heldout_fold_start = fold_start;
    std::vector<std::string> lines;
    const DiagnoseResult r = diagnose(d, o, [&](const DiagnoseProgress& p) { lines.push_back(p.message); });
    ASSERT_EQ(r.verdict, "pitch_damping") << r.summary;
    const auto& pd = *std::find_if(r.effects.begin(), r.effects.end(),
                                   [](const EffectResult& e) { return e.effect == Effect::PitchDamping; });
    ASSERT_EQ(pd.fold_parameters.size(), static_cast<std::size_t>(o.folds));
    double mean = 0;
    for (const auto& fp : pd.fold_parameters) mean += fp.at(0) / o.folds;
    ASSERT_GT(mean, 0.5);
    const std::string ramp = "all gliders, held-out-led: pitch_damping switched on to its folds' mean strength (strength ";
    EXPECT_EQ(lines_with(lines, ramp), fold_start ? 1 : 0);
    for (const auto& l : lines)
      if (l.find(ramp) != std::string::npos) {
        const double shown = std::stod(l.substr(l.find(ramp) + ramp.size()));
        EXPECT_NEAR(shown, mean, 0.001 * mean) << l;  // printed to 3 significant digits
      }
    if (fold_start)
      EXPECT_GE(lines_with(lines, "its folds' mean strength"), 2);  // the ramp and the refit from there
    else
      EXPECT_EQ(lines_with(lines, "its folds' mean strength"), 0);
    EXPECT_NEAR(pd.parameters.at(0), 1.0, 0.1);
  }
}

// Carried steps (DiagnoseOptions::carry_steps): a candidate refitted from
// its linearised step on all gliders is refitted from its step in every
// fold, also where the fold's training gliders give it no gain, and the
// fold's progress line marks it so. Flights where only the rectangular
// glider's carry pitch damping at full size (the two others are the
// baseline model's, 2 mm noise): on all gliders its gain passes the
// threshold; in the fold that holds the rectangular glider out the training
// gliders have none, so there pitch damping is stepped only when carried;
// in the other folds its own gain passes and it is not marked. Without the
// option the fold holding the rectangular glider out steps nothing.
TEST(Diagnose, CarriedStepsRefitTheAllGliderCandidatesInEveryFold) {
  EffectValues truth;
  truth.pitch_damping = 1.0;
  const std::string damped = "t01-rectangular";
  Dataset d = corrected_flights(EffectValues{}, 0.002, 5);
  {
    const Dataset with = corrected_flights(truth, 0.002, 5);
    for (std::size_t i = 0; i < d.flights.size(); ++i)
      if (d.flights[i].glider == damped) d.flights[i] = with.flights.at(i);
  }
  DiagnoseOptions o = profiled_diagnosis({Effect::PitchDamping});
  // The folds' screen at the test's level (by default every positive gain
  // is stepped, and that fold would step pitch damping without carrying).
  o.step_alpha = o.alpha;
  const std::string line = "candidates refitted from the linearised step with the centre values: ";
  const std::string name = "pitch_damping (linearised delta chi2 ";
  const std::string mark = "; stepped on all gliders)";
  // Per fold (by its held-out glider): the fold's line after "values: ".
  auto steps = [&](bool carry, DiagnoseResult& r) {
    o.carry_steps = carry;
    std::vector<std::string> lines;
    r = diagnose(d, o, [&](const DiagnoseProgress& p) { lines.push_back(p.message); });
    std::map<std::string, std::string> by_glider;
    std::string all;
    for (const auto& l : lines) {
      const auto at = l.find(line);
      if (at == std::string::npos) continue;
      if (l.rfind("all gliders", 0) == 0) {
        all = l.substr(at + line.size());
        continue;
      }
      std::smatch m;
      const std::regex fold(R"(^fold (\d)/3: )");
      if (!std::regex_search(l, m, fold)) {
        ADD_FAILURE() << l;
        continue;
      }
      const auto& held = r.fold_gliders.at(std::stoi(m[1].str()) - 1);
      if (held.size() != 1) {
        ADD_FAILURE() << "fold " << m[1] << " holds out " << held.size() << " gliders";
        continue;
      }
      by_glider[held[0]] = l.substr(at + line.size());
    }
    EXPECT_EQ(all.rfind(name, 0), 0u) << "pitch damping not stepped on all gliders: " << all;
    EXPECT_EQ(by_glider.size(), 3u);
    return by_glider;
  };
  DiagnoseResult r;
  for (const auto& [glider, stepped] : steps(true, r)) {
    const auto at = stepped.find(name);
    ASSERT_NE(at, std::string::npos) << glider << " held out: " << stepped;
    const bool marked = stepped.substr(stepped.find(')', at) - mark.size() + 1, mark.size()) == mark;
    EXPECT_EQ(marked, glider == damped) << glider << " held out: " << stepped;
  }
  const auto off = steps(false, r);
  ASSERT_TRUE(off.count(damped));
  EXPECT_EQ(off.at(damped).rfind("none passes the threshold", 0), 0u) << off.at(damped);
  for (const auto& [glider, stepped] : off) EXPECT_EQ(stepped.find(mark), std::string::npos) << stepped;
}

// The all-gliders leader's start in the folds (under carry_steps): the
// aerodynamic correction that led the profiled screen on all gliders is
// also started in every fold at the strength the fit to all gliders found,
// from the launches and trims fitted there, unless the fold's own
// linearised step already fitted it at leader_reached (0.5) of that
// strength or more. Flights with pitch damping at full size (2 mm noise):
// pitch damping leads on all gliders (fitted 0.97). With leader_reached
// 100 every fold's progress says it was started at that strength; by
// default every fold either starts it or says its step reached at least
// half of it, with the strengths to show it (here at least one does: the
// flights are the corrected model's own), and a fold that says so makes
// no start. Without carried steps no fold does either, nor with them but
// without the leader's start (leader_start false). (Where the leader's fit
// to all gliders ends at 0 there is nothing to start from: pitch damping
// on one glider of three, CarriedStepsRefitTheAllGliderCandidatesInEveryFold's
// flights.)
TEST(Diagnose, TheLeaderOnAllGlidersIsAlsoStartedAtItsStrengthThereInEveryFold) {
  EffectValues truth;
  truth.pitch_damping = 1.0;
  const Dataset d = corrected_flights(truth, 0.002, 5);
  DiagnoseOptions o = profiled_diagnosis({Effect::PitchDamping});
  const std::regex start(R"(^fold (\d)/3: pitch_damping started at its strength on all gliders \(strength ([0-9.e-]+)\) from the launches and trims fitted there)");
  const std::regex reached(R"(^fold (\d)/3: pitch_damping's linearised step here fitted strength ([0-9.e-]+), at least 0.5 of its strength on all gliders \(strength ([0-9.e-]+)\): not started there)");
  struct Folds {
    std::set<int> started, skipped;
  };
  auto folds_of = [&](bool carry, bool lead, double reach) {
    o.carry_steps = carry;
    o.leader_start = lead;
    o.leader_reached = reach;
    Folds f;
    const DiagnoseResult r = diagnose(d, o, [&](const DiagnoseProgress& p) {
      std::smatch m;
      if (std::regex_search(p.message, m, start)) {
        EXPECT_GT(std::stod(m[2].str()), 0.0) << p.message;
        f.started.insert(std::stoi(m[1].str()));
      }
      if (std::regex_search(p.message, m, reached)) {
        EXPECT_GE(std::stod(m[2].str()), 0.5 * std::stod(m[3].str())) << p.message;
        f.skipped.insert(std::stoi(m[1].str()));
      }
    });
    return f;
  };
  const Folds always = folds_of(true, true, 100.0);
  EXPECT_EQ(always.started, (std::set<int>{1, 2, 3}));
  EXPECT_TRUE(always.skipped.empty());
  const Folds by_default = folds_of(true, true, 0.5);
  std::set<int> both = by_default.started;
  both.insert(by_default.skipped.begin(), by_default.skipped.end());
  EXPECT_EQ(both, (std::set<int>{1, 2, 3}));
  for (int k : by_default.skipped) EXPECT_EQ(by_default.started.count(k), 0u) << "fold " << k;
  EXPECT_FALSE(by_default.skipped.empty()) << "no fold's step reached the leader: the rule was not exercised";
  const Folds no_carry = folds_of(false, true, 0.5), no_lead = folds_of(true, false, 0.5);
  EXPECT_TRUE(no_carry.started.empty() && no_carry.skipped.empty());
  EXPECT_TRUE(no_lead.started.empty() && no_lead.skipped.empty());
}

// The leader's start's edge rule: a leader whose fit to all gliders ends at
// the bound guard's edge of its range is not started there in the folds.
// Flights with pitch damping at 4, beyond its range's bound of 3 (2 mm
// noise): the fit to all gliders can only end at the bound, so every fold
// says so and none starts there; at 1 (the test above) every fold does.
TEST(Diagnose, ALeaderFittedAtTheEdgeOfItsRangeIsNotStartedThereInTheFolds) {
  EffectValues truth;
  truth.pitch_damping = 4.0;
  const Dataset d = corrected_flights(truth, 0.002, 5);
  const DiagnoseOptions o = profiled_diagnosis({Effect::PitchDamping});
  ASSERT_GT(truth.pitch_damping, effect_spec(Effect::PitchDamping).parameters[0].upper);
  const std::regex edge(R"(^fold (\d)/3: pitch_damping's fit on all gliders is at the edge of its range: not started there)");
  std::set<int> skipped;
  int starts = 0;
  const DiagnoseResult r = diagnose(d, o, [&](const DiagnoseProgress& p) {
    std::smatch m;
    if (std::regex_search(p.message, m, edge)) skipped.insert(std::stoi(m[1].str()));
    if (p.message.find("at its strength on all gliders (") != std::string::npos) ++starts;
  });
  EXPECT_EQ(skipped, (std::set<int>{1, 2, 3}));
  EXPECT_EQ(starts, 0);
  ASSERT_EQ(r.effects.size(), 1u);
  EXPECT_TRUE(values_at_range_edge(Effect::PitchDamping, r.effects[0].parameters)) << r.effects[0].parameters[0];
}

// The profiled starts' screen in the folds (DiagnoseOptions::step_alpha).
// Flights of the baseline model (2 mm noise), pitch damping and wind as
// candidates: at the test's level (step_alpha 0: alpha) no linearised gain
// passes in the first fold, whose progress line names the largest positive
// gain left under the threshold; at level 1 (the default) every candidate
// with a positive gain is stepped there, that one first, with the same
// gain, marked as under the test's threshold. The fit to all gliders keeps the test's level: its line is the
// same at both levels. Levels outside [0, 1] are refused.
TEST(Diagnose, TheStepScreensLevelDecidesWhichCandidatesAreStepped) {
  const Dataset d = corrected_flights(EffectValues{}, 0.002, 5);
  DiagnoseOptions o = profiled_diagnosis({Effect::PitchDamping, Effect::Wind});
  const std::string line = "candidates refitted from the linearised step with the centre values: ";
  struct Lines {
    std::string all, fold1;
  };
  auto lines_at = [&](double level) {
    o.step_alpha = level;
    Lines found;
    const DiagnoseResult r = diagnose(d, o, [&](const DiagnoseProgress& p) {
      const auto at = p.message.find(line);
      if (at == std::string::npos) return;
      if (p.message.rfind("all gliders: ", 0) == 0) found.all = p.message.substr(at + line.size());
      if (p.message.rfind("fold 1/3: ", 0) == 0) found.fold1 = p.message.substr(at + line.size());
    });
    EXPECT_EQ(diagnosis_json(r, o)["options"].value("step_alpha", -1.0), level > 0 ? level : o.alpha);
    return found;
  };
  const Lines at_alpha = lines_at(0);
  const std::string under = "none passes the threshold; largest under the threshold: ";
  ASSERT_EQ(at_alpha.fold1.rfind(under, 0), 0u) << at_alpha.fold1;
  const std::string largest = at_alpha.fold1.substr(under.size());  // "NAME (GAIN)"
  const auto open = largest.find(" (");
  ASSERT_NE(open, std::string::npos) << largest;
  const std::string gain = largest.substr(open + 2, largest.size() - open - 3);
  const Lines lax = lines_at(1);
  EXPECT_EQ(lax.fold1.rfind(largest.substr(0, open) + " (linearised delta chi2 " + gain + "; under the test's threshold)", 0),
            0u)
      << lax.fold1 << " / " << at_alpha.fold1;
  EXPECT_FALSE(at_alpha.all.empty());
  EXPECT_EQ(lax.all, at_alpha.all);
  for (double bad : {-0.1, 1.5, std::nan("")}) {
    o.step_alpha = bad;
    EXPECT_THROW(diagnose(d, o), InputError) << bad;
  }
}

// Per-flight launch rotation (every flight's own pitch rate) has no shared
// strength to step; with DiagnoseOptions::step_per_flight its centre values
// take their linearised step from its fit. Flights of the baseline model
// whose launches each carry their own pitch rate (10-90 deg/s, 2 mm noise):
// with the option the step is taken on all gliders and in the three folds,
// and the candidate explains the flights near the tracking noise (fit RMSE
// under 1.5 sigma; one RBF centre here, so the step moves little: 2.59 mm
// against 2.61 mm without) and never worse than without it; without the
// option no such step is reported.
TEST(Diagnose, PerFlightRatesStepTheirCentreValues) {
  std::vector<double> rates;
  for (int i = 0; i < 9; ++i) rates.push_back(deg2rad(10.0 + 10.0 * ((i * 4) % 9)));
  const Dataset d = corrected_flights(EffectValues{}, 0.002, 13, rates);
  DiagnoseOptions o = profiled_diagnosis({Effect::LaunchRotation});
  const std::string step = "launch_rotation with its centre values from the linearised step";
  auto run = [&](bool on, int& steps) {
    o.step_per_flight = on;
    steps = 0;
    const DiagnoseResult r = diagnose(d, o, [&](const DiagnoseProgress& p) {
      if (p.message.find(step) != std::string::npos) ++steps;
    });
    EXPECT_EQ(diagnosis_json(r, o)["options"].value("step_per_flight", !on), on);
    for (const auto& e : r.effects)
      if (e.effect == Effect::LaunchRotation) return e.fit_rmse_m;
    ADD_FAILURE() << "no launch_rotation entry";
    return 1.0;
  };
  int with_steps = 0, without_steps = 0;
  const double with = run(true, with_steps);
  const double without = run(false, without_steps);
  EXPECT_EQ(with_steps, 4);  // all gliders and three folds
  EXPECT_EQ(without_steps, 0);
  EXPECT_LT(with, 1.5 * 0.002);
  EXPECT_LE(with, without + 1e-6);
}

// A candidate that is not refitted from its linearised step (here every
// flight's own launch rate, whose step is off by default) is fitted at the
// coefficients the baseline had before its own step. Where the baseline
// keeps that step, the candidate is fitted again at the baseline's final
// centre values: otherwise it does not nest the baseline it is tested
// against (blind launch rotation at 1, seed 35: likelihood ratio 0.75
// against the truth's 306, 181 so refitted). On flights of the model with
// every flight's own rate (10-90 deg/s, 2 mm noise) the refit is made once
// per kept baseline step and the rates fit the flights to the noise. (These
// flights do not show the size of the change, the blind benchmark does:
// without the refit only the count fails.)
TEST(Diagnose, AnUnsteppedCandidateIsRefittedFromTheBaselinesFinalCentreValues) {
  std::vector<double> rates;
  for (int i = 0; i < 9; ++i) rates.push_back(deg2rad(10.0 + 10.0 * ((i * 4) % 9)));
  const Dataset d = corrected_flights(EffectValues{}, 0.002, 13, rates);
  DiagnoseOptions o = profiled_diagnosis({Effect::LaunchRotation});
  ASSERT_FALSE(o.step_per_flight);
  int baseline_steps = 0, refits = 0;
  const DiagnoseResult r = diagnose(d, o, [&](const DiagnoseProgress& p) {
    if (p.message.find("baseline from the linearised step on its centre values and trims") != std::string::npos &&
        p.message.find("; kept)") != std::string::npos)
      ++baseline_steps;
    if (p.message.find("launch_rotation refitted at the baseline's final centre values") != std::string::npos) ++refits;
  });
  ASSERT_GT(baseline_steps, 0) << "no baseline step kept: the case does not test the refit";
  EXPECT_EQ(refits, baseline_steps);
  EXPECT_EQ(r.verdict, "launch_rotation") << r.summary;
  for (const auto& e : r.effects)
    if (e.effect == Effect::LaunchRotation) {
      EXPECT_LT(e.fit_rmse_m, 1.5 * 0.002);
      EXPECT_NEAR(rad2deg(e.rate_mean), 50.0, 10.0);
    }
}

// The oracle (the baseline plus the known correction, centre values refitted
// with it): on flights of the model with pitch damping at its full size and
// 2 mm noise, the oracle at the true strength predicts the held-out gliders
// to the tracking noise (held-out chi-square ratio near 1) and shrinks the
// baseline's held-out error at least as much as the fitted candidate; an
// oracle with a wrong correction (added mass, which also damps pitch) at its
// theoretical size predicts them worse than the true one. Bad oracle
// specifications are refused with the reason.
TEST(Diagnose, OracleWithTheTrueCorrectionPredictsToTheNoise) {
  EffectValues truth;
  truth.pitch_damping = 1.0;
  const Dataset d = corrected_flights(truth, 0.002, 5);
  DiagnoseOptions o = small_diagnosis({Effect::PitchDamping});
  o.full_fit = false;
  o.second_effect = false;
  o.oracle = oracle_from("pitch_damping=1", "--oracle");
  std::vector<std::string> lines;
  const DiagnoseResult r = diagnose(d, o, [&](const DiagnoseProgress& p) { lines.push_back(p.message); });
  ASSERT_TRUE(r.oracle.has_value());
  ASSERT_EQ(r.oracle->fold_holdout_rmse_m.size(), 3u);
  // Its progress (the oracle's fits can take many minutes a fold on data far
  // from the model): in every fold the four steps toward the known effects
  // in order, the centre values' refit, then one line whose held-out figure
  // is the one reported for that fold.
  {
    const std::regex step(R"(^fold (\d)/3, the oracle: training gliders at (\d)/4 of the known effects: RMSE)");
    const std::regex centre(R"(^fold (\d)/3, the oracle: centre values refitted: RMSE [0-9.]+ cm on training gliders)");
    const std::regex done(
        R"(^fold (\d)/3: oracle \(the baseline plus the known effects, centre values refitted\): RMSE [0-9.]+ cm on )"
        R"(training gliders, ([0-9.]+) cm on held-out gliders)");
    std::vector<int> next_step(3, 1), centres(3, 0), dones(3, 0);
    for (const auto& l : lines) {
      std::smatch m;
      if (std::regex_search(l, m, step)) {
        const int k = std::stoi(m[1].str()) - 1;
        ASSERT_TRUE(k >= 0 && k < 3) << l;
        EXPECT_EQ(std::stoi(m[2].str()), next_step[k]) << l;
        EXPECT_EQ(centres[k] + dones[k], 0) << "a step after the fold's oracle refit: " << l;
        ++next_step[k];
      } else if (std::regex_search(l, m, centre)) {
        const int k = std::stoi(m[1].str()) - 1;
        ASSERT_TRUE(k >= 0 && k < 3) << l;
        EXPECT_EQ(next_step[k], 5) << "the centre values refitted before the fourth step: " << l;
        ++centres[k];
      } else if (std::regex_search(l, m, done)) {
        const int k = std::stoi(m[1].str()) - 1;
        ASSERT_TRUE(k >= 0 && k < 3) << l;
        EXPECT_EQ(centres[k], 1) << l;
        EXPECT_NEAR(std::stod(m[2].str()), 100 * r.oracle->fold_holdout_rmse_m[k], 0.051) << l;
        ++dones[k];
      }
    }
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(next_step[k], 5) << "fold " << k + 1;
      EXPECT_EQ(centres[k], 1) << "fold " << k + 1;
      EXPECT_EQ(dones[k], 1) << "fold " << k + 1;
    }
  }
  EXPECT_LT(r.oracle->holdout_chi2_ratio, 1.5) << r.summary;
  EXPECT_GT(r.oracle->holdout_chi2_ratio, 0.5) << r.summary;
  ASSERT_EQ(r.effects.size(), 1u);
  EXPECT_GE(r.oracle->shrink, r.effects[0].shrink - 0.02) << r.summary;
  EXPECT_GT(r.holdout_chi2_ratio, 3.0) << "the baseline should miss damped flights: " << r.summary;
  const nlohmann::json j = diagnosis_json(r, o);
  EXPECT_DOUBLE_EQ(j.at("oracle").at("effects").at("pitch_damping").at("strength").get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(j.at("oracle").at("shrink").get<double>(), r.oracle->shrink);
  // Its evidence on the training gliders: the baseline misses damped flights
  // (held-out chi-square ratio > 3) and the true correction brings them to
  // the noise, so in every fold the gain is far over the likelihood-ratio
  // threshold for one parameter at the diagnosis's level.
  ASSERT_EQ(r.oracle->fold_train_delta_chi2.size(), 3u);
  for (double x : r.oracle->fold_train_delta_chi2) EXPECT_GT(x, chi2_isf(o.alpha, 1)) << r.summary;
  EXPECT_GT(r.oracle->train_delta_chi2, chi2_isf(o.alpha, 1)) << r.summary;
  EXPECT_DOUBLE_EQ(j.at("oracle").at("train_delta_chi2").get<double>(), r.oracle->train_delta_chi2);
  EXPECT_EQ(j.at("oracle").at("fold_train_delta_chi2").size(), 3u);

  o.oracle = oracle_from("added_mass=1", "--oracle");
  const DiagnoseResult wrong = diagnose(d, o);
  ASSERT_TRUE(wrong.oracle.has_value());
  EXPECT_GT(wrong.oracle->holdout_rmse_m, 1.2 * r.oracle->holdout_rmse_m) << wrong.summary;
  // The wrong correction explains the training gliders less than the true one.
  EXPECT_LT(wrong.oracle->train_delta_chi2, r.oracle->train_delta_chi2) << wrong.summary;

  for (const char* bad : {"", "wind", "wind=", "wind=x", "wind=nan", "wind=1:2", "gravity=1", "wind=1,wind=2",
                          "ground_effect=50"}) {
    DiagnoseOptions b = small_diagnosis({Effect::Wind});
    EXPECT_THROW(
        {
          b.oracle = oracle_from(bad, "--oracle");
          diagnose(d, b);
        },
        InputError)
        << bad;
  }
  DiagnoseOptions direct = small_diagnosis({Effect::Wind});  // set without oracle_from: diagnose() checks it too
  direct.oracle = {{Effect::Wind, {1.0, 2.0}}};
  EXPECT_THROW(diagnose(d, direct), InputError);

  // Plausible sizes: the same "EFFECT=V[:V2]" form, each value positive
  // ("inf" lifts a limit).
  const auto lim = plausible_from("camera=0.05:3,wind=inf", "--plausible");
  ASSERT_EQ(lim.size(), 2u);
  EXPECT_EQ(lim[0].first, Effect::Camera);
  EXPECT_DOUBLE_EQ(lim[0].second[1], 3.0);
  EXPECT_TRUE(std::isinf(lim[1].second[0]));
  for (const char* bad : {"", "camera=0.05", "camera=0.05:0", "camera=-0.05:3", "wind=nan", "wind=1,wind=2", "gust=1"})
    EXPECT_THROW(plausible_from(bad, "--plausible"), InputError) << bad;
  DiagnoseOptions neg = small_diagnosis({Effect::Wind});  // set directly: diagnose() checks it
  neg.plausible = {{Effect::Wind, {-1.0}}};
  EXPECT_THROW(diagnose(d, neg), InputError);
}

// The whole pipeline with launch rotation as a launch value (the default):
// flights of the baseline model, each thrown with its own pitch rate (10-90
// deg/s, 5 mm noise), are explained by launch_rotation, whose reported
// strength is the flights' mean rate (truth 50 deg/s); its tests count one
// degree of freedom per flight. Wind, the other candidate, is not significant.
TEST(Diagnose, EachFlightsOwnLaunchRotationIsFound) {
  std::vector<double> rates;
  for (int i = 0; i < 9; ++i) rates.push_back(deg2rad(10.0 + 10.0 * ((i * 4) % 9)));
  const Dataset d = corrected_flights(EffectValues{}, 0.005, 13, rates);
  const DiagnoseOptions o = small_diagnosis({Effect::Wind, Effect::LaunchRotation});
  ASSERT_TRUE(o.launch_rotation_per_flight);
  const DiagnoseResult r = diagnose(d, o);
  EXPECT_EQ(r.verdict, "launch_rotation") << r.summary;
  for (const auto& e : r.effects) {
    if (e.effect != Effect::LaunchRotation) {
      EXPECT_FALSE(e.significant) << e.name;
      continue;
    }
    ASSERT_EQ(e.parameters.size(), 1u);
    // Within 30 %: the coefficients fitted to the same flights take up part
    // of the rotation (as they take part of pitch damping; docs/diagnosis.md).
    EXPECT_NEAR(rad2deg(e.parameters[0]), 50.0, 15.0);
    EXPECT_TRUE(e.significant) << e.note << "; shrink " << e.shrink << ", without " << e.robust_without << " "
                               << e.robust_shrink << ", improved " << e.gliders_improved << "/" << e.gliders_total;
    // The glider guard: an effect of every flight helps every held-out glider
    // (the pooled shrink may still rest mostly on one, a geometry that shows
    // it most); the smallest leave-one-glider-out shrink is at most the pooled.
    EXPECT_EQ(e.gliders_improved, e.gliders_total);
    EXPECT_TRUE(e.robust_pass);
    EXPECT_LE(e.robust_shrink, e.shrink + 1e-12);
    EXPECT_FALSE(e.robust_without.empty());
    EXPECT_GT(e.holdout_threshold, 9.0);  // chi-square quantile with one degree per held-out flight (9), not 1
    // The held-out flights' own rates share the launcher's direction.
    EXPECT_TRUE(e.rate_test);
    EXPECT_TRUE(e.rate_mean_pass);
    EXPECT_NEAR(rad2deg(e.rate_mean), 50.0, 15.0);
    EXPECT_GT(e.rate_mean_t, 0.0);
  }
}

// Rates that do not share a direction (-120 to 120 deg/s, mean 0): a free
// sixth launch value fits them, but no launcher turns gliders both ways on
// average; launch_rotation is not significant, and its note says why.
TEST(Diagnose, LaunchRatesWithoutACommonDirectionAreNotALauncherRotation) {
  std::vector<double> rates;
  for (int i = 0; i < 9; ++i) rates.push_back(deg2rad(-120.0 + 30.0 * ((i * 4) % 9)));
  const Dataset d = corrected_flights(EffectValues{}, 0.005, 13, rates);
  const DiagnoseResult r = diagnose(d, small_diagnosis({Effect::Wind, Effect::LaunchRotation}));
  for (const auto& e : r.effects) {
    if (e.effect != Effect::LaunchRotation) {
      EXPECT_FALSE(e.rate_test) << e.name;
      continue;
    }
    EXPECT_TRUE(e.rate_test);
    EXPECT_FALSE(e.rate_mean_pass) << "mean " << rad2deg(e.rate_mean) << " deg/s, p " << e.rate_mean_p;
    EXPECT_LT(std::abs(rad2deg(e.rate_mean)), 15.0);
    EXPECT_FALSE(e.significant);
    EXPECT_TRUE(e.lr_pass) << "delta chi2 " << e.delta_chi2 << " p " << e.p_value << " shrink " << e.shrink << " "
                           << e.note;  // the rates themselves are found: the launch fit leaves them out
    EXPECT_NE(e.note.find("do not share a direction"), std::string::npos) << e.note;
  }
  EXPECT_NE(r.verdict, "launch_rotation") << r.summary;
}

// The second round: flights with a headwind *and* a camera error (2 mm noise)
// give one of the two as the verdict and the other in `also` (significant
// when added to it, and the verdict's effect still needed when added to the
// other: both are real), while fuselage drag -- which can absorb part of a
// headwind's slowing on its own -- is not significant given the verdict.
TEST(Diagnose, SecondRoundFindsTheSecondEffectAndOnlyIt) {
  EffectValues both;
  both.wind = -1.0;
  both.camera_scale = 0.04;
  both.camera_roll = deg2rad(3.0);
  const DiagnoseOptions o = small_diagnosis({Effect::Wind, Effect::Camera, Effect::FuselageDrag});
  ASSERT_TRUE(o.second_effect);
  const DiagnoseResult r = diagnose(corrected_flights(both, 0.002, 17), o);
  const std::string other = second_effect_found(r, "wind", "camera");
  ASSERT_FALSE(other.empty());
  for (const auto& e : r.effects) {
    EXPECT_EQ(e.given_verdict.tested, e.name != r.verdict) << e.name;
    if (e.effect == Effect::FuselageDrag) EXPECT_FALSE(e.given_verdict.significant);
  }
  EXPECT_TRUE(r.alternatives.empty());  // each adds to the other: both are told apart
  const nlohmann::json j = diagnosis_json(r, o);
  EXPECT_EQ(j.at("also"), nlohmann::json::array({other}));
}

// The second round's re-check with the centre values re-tuned. Flights of
// the model with pitch damping at its full size and a 1 m/s headwind, 2 mm
// noise: the verdict's profiled centre values absorb the other effect, so
// with them held fixed it fits a small part of its size in every fold and
// fails the held-out test (seen: wind -0.04 to -0.10 m/s given pitch
// damping, 0.4 % further held-out shrink). Re-checked with the centre values
// re-tuned (and the verdict alone given the same chance) the second effect is
// found at its true size, and the verdict's effect is still needed given it;
// fuselage drag, absent from the flights, stays out.
TEST(Diagnose, SecondRoundReChecksWithTheCentreValuesReTuned) {
  EffectValues both;
  both.wind = -1.0;
  both.pitch_damping = 1.0;
  DiagnoseOptions o = small_diagnosis({Effect::PitchDamping, Effect::Wind, Effect::FuselageDrag});
  o.profile = true;
  o.profile_min_gliders = 2;  // three gliders, two per fold's training set
  const DiagnoseResult r = diagnose(corrected_flights(both, 0.002, 5), o);
  const std::string other = second_effect_found(r, "pitch_damping", "wind");
  ASSERT_FALSE(other.empty());
  for (const auto& e : r.effects) {
    if (e.name == other) {
      EXPECT_TRUE(e.given_verdict.retuned);
      // Two looks at the data: the p-value is twice the chi-square tail (one
      // degree of freedom, closed form) and the test still passes at that.
      EXPECT_TRUE(e.given_verdict.rechecked);
      EXPECT_NEAR(e.given_verdict.p_value, std::min(1.0, 2 * std::erfc(std::sqrt(e.given_verdict.delta_chi2 / 2))),
                  1e-9 + 1e-6 * e.given_verdict.p_value);
      ASSERT_EQ(e.given_verdict.parameters.size(), 1u);
      // the truth: -1 m/s (wind), 1 (pitch damping)
      if (other == "wind") EXPECT_NEAR(e.given_verdict.parameters[0], -1.0, 0.15);
      else EXPECT_NEAR(e.given_verdict.parameters[0], 1.0, 0.2);
    }
    if (e.effect == Effect::FuselageDrag) EXPECT_FALSE(e.given_verdict.significant);
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

// The second round's decision from its tests (the fits are exercised by
// SecondRoundFindsTheSecondEffectAndOnlyIt; here every branch of the rule,
// with tests set by hand): `also` ordered by shrink given the verdict; an
// effect of `also`, significant on its own, that leaves the verdict's effect
// superfluous replaces it; one that is only significant given the verdict
// does not; effects that add nothing given the verdict while the verdict's
// adds nothing given them are `alternatives`.
TEST(Diagnose, SecondRoundDecisionFollowsItsRule) {
  auto effect = [](bool first, bool given, double shrink, bool reverse, bool needed) {
    EffectResult r;
    r.significant = first;
    r.given_verdict.tested = true;
    r.given_verdict.significant = given;
    r.given_verdict.shrink = shrink;
    r.given_verdict.reverse_tested = reverse;
    r.given_verdict.verdict_still_needed = needed;
    return r;
  };
  EffectResult verdict;
  verdict.significant = true;  // not tested given itself
  {  // Two further effects, both real: `also` best first, nothing replaced.
    const std::vector<EffectResult> e = {verdict, effect(false, true, 0.1, true, true), effect(true, true, 0.3, true, true)};
    const SecondRoundOutcome s = second_round_outcome(e, 0);
    EXPECT_EQ(s.verdict, 0);
    EXPECT_EQ(s.replaced, -1);
    EXPECT_EQ(s.also, (std::vector<int>{2, 1}));
    EXPECT_TRUE(s.alternatives.empty());
  }
  {  // Effect 2 explains what the verdict explained and more: it replaces it.
    const std::vector<EffectResult> e = {verdict, effect(false, true, 0.2, true, true), effect(true, true, 0.1, true, false)};
    const SecondRoundOutcome s = second_round_outcome(e, 0);
    EXPECT_EQ(s.verdict, 2);
    EXPECT_EQ(s.replaced, 0);
    EXPECT_TRUE(s.also.empty());
    EXPECT_TRUE(s.alternatives.empty());
  }
  {  // Not significant on its own: it cannot replace the verdict, it stays in `also`.
    const std::vector<EffectResult> e = {verdict, effect(false, true, 0.2, true, false)};
    const SecondRoundOutcome s = second_round_outcome(e, 0);
    EXPECT_EQ(s.verdict, 0);
    EXPECT_EQ(s.replaced, -1);
    EXPECT_EQ(s.also, (std::vector<int>{1}));
  }
  {  // Significant on its own, nothing given the verdict, and the verdict
     // nothing given it: an alternative. One whose reverse test keeps the
     // verdict is not.
    const std::vector<EffectResult> e = {effect(true, false, 0.0, true, false), verdict,
                                         effect(true, false, 0.0, true, true), effect(false, false, 0.0, false, true)};
    const SecondRoundOutcome s = second_round_outcome(e, 1);
    EXPECT_EQ(s.verdict, 1);
    EXPECT_EQ(s.alternatives, (std::vector<int>{0}));
    EXPECT_TRUE(s.also.empty());
  }
  EXPECT_THROW(second_round_outcome({verdict}, 3), InputError);
}

// The identifiability preference (DiagnoseOptions::prefer_identifiable). The
// blind pitch-damping + wind case (seed 42), per-glider held-out RMSE in cm
// of the camera (30.1 %, collinearity 100 %) and of the wind (26.2 %), equal
// points per glider: paired t of the wind's excess 1.0994 (scipy.stats.ttest_rel),
// Student's 0.99 quantile with 7 degrees of freedom 2.9980 (scipy.stats.t.ppf):
// the camera's advantage is not significant and the wind is named. The same
// camera, better on every glider by 4-7 (t 14.35 by scipy), keeps the verdict.
// Nothing changes when the best effect is distinguishable, when no other
// significant effect is, or with one glider (no test possible).
TEST(Diagnose, IdentifiablePreferenceNamesTheEffectCoefficientsCannotImitate) {
  auto effect = [](bool significant, bool indistinguishable, double shrink) {
    EffectResult r;
    r.significant = significant;
    r.indistinguishable = indistinguishable;
    r.shrink = shrink;
    return r;
  };
  const std::vector<double> cam_cm = {2.0508, 1.5623, 2.2790, 1.4575, 3.2651, 1.4208, 1.6001, 1.9381};
  const std::vector<double> wind_cm = {2.0910, 1.6450, 2.2370, 1.4375, 3.7520, 1.4052, 1.5428, 2.0342};
  std::vector<double> cam, wind, other(8, 9.0);
  for (std::size_t g = 0; g < cam_cm.size(); ++g) {
    cam.push_back(cam_cm[g] * cam_cm[g]);
    wind.push_back(wind_cm[g] * wind_cm[g]);
  }
  // camera, wind, an insignificant distinguishable effect of larger shrink
  // than the wind (never the alternative), an insignificant one.
  const std::vector<EffectResult> e = {effect(true, true, 0.301), effect(true, false, 0.262),
                                       effect(false, false, 0.28), effect(false, true, 0.0)};
  {
    const IdentifiablePreference p = prefer_identifiable(e, 0, {cam, wind, other, other}, 0.01);
    EXPECT_EQ(p.verdict, 1);
    EXPECT_EQ(p.passed_over, 0);
    EXPECT_EQ(p.alternative, 1);
    EXPECT_NEAR(p.t, 1.0994, 1e-3);
    EXPECT_NEAR(p.t_critical, 2.9980, 1e-3);
  }
  {
    const std::vector<double> d = {5, 6, 4, 5, 7, 5, 6, 4};
    std::vector<double> worse;
    for (std::size_t g = 0; g < cam.size(); ++g) worse.push_back(cam[g] + d[g]);
    const IdentifiablePreference p = prefer_identifiable(e, 0, {cam, worse, other, other}, 0.01);
    EXPECT_EQ(p.verdict, 0);
    EXPECT_EQ(p.passed_over, -1);
    EXPECT_EQ(p.alternative, 1);
    EXPECT_NEAR(p.t, 14.3457, 1e-3);
  }
  {  // The best effect is distinguishable: it stays.
    const std::vector<EffectResult> f = {effect(true, false, 0.301), effect(true, false, 0.262)};
    const IdentifiablePreference p = prefer_identifiable(f, 0, {cam, wind}, 0.01);
    EXPECT_EQ(p.verdict, 0);
    EXPECT_EQ(p.passed_over, -1);
    EXPECT_EQ(p.alternative, -1);
  }
  {  // No other significant effect the coefficients cannot imitate.
    const std::vector<EffectResult> f = {effect(true, true, 0.301), effect(true, true, 0.262),
                                         effect(false, false, 0.2)};
    const IdentifiablePreference p = prefer_identifiable(f, 0, {cam, wind, other}, 0.01);
    EXPECT_EQ(p.verdict, 0);
    EXPECT_EQ(p.alternative, -1);
  }
  {  // Not significant itself: nothing to prefer over.
    const std::vector<EffectResult> f = {effect(false, true, 0.301), effect(true, false, 0.262)};
    EXPECT_EQ(prefer_identifiable(f, 0, {cam, wind}, 0.01).verdict, 0);
  }
  {  // One glider: no test possible, the best stays.
    const std::vector<EffectResult> f = {effect(true, true, 0.301), effect(true, false, 0.262)};
    const IdentifiablePreference p = prefer_identifiable(f, 0, {{1.0}, {2.0}}, 0.01);
    EXPECT_EQ(p.verdict, 0);
    EXPECT_EQ(p.passed_over, -1);
  }
  EXPECT_THROW(prefer_identifiable(e, 4, {cam, wind, other, other}, 0.01), InputError);
  EXPECT_THROW(prefer_identifiable(e, 0, {cam, wind}, 0.01), InputError);
  EXPECT_THROW(prefer_identifiable(e, 0, {cam, {1.0}, other, other}, 0.01), InputError);
  EXPECT_THROW(prefer_identifiable(e, 0, {cam, std::vector<double>(8, std::nan("")), other, other}, 0.01), InputError);
  EXPECT_THROW(prefer_identifiable(e, 0, {cam, wind, other, other}, 0.0), InputError);
}

// The passed-over effect never takes the verdict back in the second round:
// significant given the verdict's and making it superfluous, it would
// replace it (SecondRoundDecisionFollowsItsRule); passed over, it stays in `also`.
TEST(Diagnose, SecondRoundDoesNotHandTheVerdictBackToThePassedOverEffect) {
  EffectResult verdict;
  verdict.significant = true;
  EffectResult cam;
  cam.significant = true;
  cam.given_verdict.tested = cam.given_verdict.significant = cam.given_verdict.reverse_tested = true;
  cam.given_verdict.shrink = 0.08;
  cam.given_verdict.verdict_still_needed = false;
  const SecondRoundOutcome free = second_round_outcome({verdict, cam}, 0);
  EXPECT_EQ(free.verdict, 1);
  EXPECT_EQ(free.replaced, 0);
  const SecondRoundOutcome kept = second_round_outcome({verdict, cam}, 0, 1);
  EXPECT_EQ(kept.verdict, 0);
  EXPECT_EQ(kept.replaced, -1);
  EXPECT_EQ(kept.also, (std::vector<int>{1}));
  EXPECT_THROW(second_round_outcome({verdict, cam}, 0, 0), InputError);
  EXPECT_THROW(second_round_outcome({verdict, cam}, 0, 2), InputError);
}

// The summary's sentence on a glider that carries most of the held-out excess
// and that no candidate predicts better, on a `where` set by hand: the canard
// carries 6 of 9 units of excess (67 %) at 4.9 cm; a candidate that predicts
// it at 4.7 cm is not 10 % better (0.9 x 4.9 = 4.41 cm), so the sentence
// names it with the best candidate's 4.7 cm; one at 4.0 cm is, and so is no
// sentence. Neither a glider under half the excess nor a gap without excess
// gives one.
TEST(Diagnose, DominantGliderSentenceNamesOnlyAGliderNoCandidateHelps) {
  nlohmann::json where;
  where["all"]["excess_m2"] = 9.0;
  where["gliders"] = nlohmann::json::array();
  auto glider = [](const char* key, double rmse, double excess, double chi2) {
    return nlohmann::json{{"glider", key}, {"rmse_m", rmse}, {"excess_m2", excess}, {"chi2_ratio", chi2}};
  };
  where["gliders"].push_back(glider("t01", 0.015, 2.0, 1.4));
  where["gliders"].push_back(glider("t17", 0.049, 6.0, 13.0));
  where["gliders"].push_back(glider("t09", 0.020, 1.0, 2.8));
  auto candidate = [](double canard_rmse) {
    EffectResult e;
    e.glider_holdout_rmse_m = {{"t01", 0.010}, {"t17", canard_rmse}, {"t09", 0.012}};
    return e;
  };
  const std::string s = dominant_glider_sentence(where, {candidate(0.050), candidate(0.047)});
  EXPECT_NE(s.find("one glider, t17"), std::string::npos) << s;
  EXPECT_NE(s.find("(67 %)"), std::string::npos) << s;
  EXPECT_NE(s.find("at 4.9 cm held out"), std::string::npos) << s;
  EXPECT_NE(s.find("(best 4.7 cm)"), std::string::npos) << s;
  EXPECT_NE(s.find("13 times"), std::string::npos) << s;
  EXPECT_EQ(s.find("t01"), std::string::npos) << s;
  EXPECT_EQ(dominant_glider_sentence(where, {candidate(0.047), candidate(0.040)}), "");
  nlohmann::json spread = where;
  spread["gliders"][1]["excess_m2"] = 4.0;  // 4 of 9: under half
  EXPECT_EQ(dominant_glider_sentence(spread, {candidate(0.050)}), "");
  nlohmann::json none = where;
  none["all"]["excess_m2"] = 0.0;
  EXPECT_EQ(dominant_glider_sentence(none, {candidate(0.050)}), "");
  EXPECT_EQ(dominant_glider_sentence(nlohmann::json::object(), {}), "");
}

// The leave-one-glider-out shrink. By hand: four gliders at 1 unit of squared
// residual each, an effect that brings the fourth to 0.25 and leaves the
// rest: pooled 1 - sqrt(3.25 / 4) = 9.9 %, but 1 - sqrt(3 / 3) = 0 without
// the fourth glider (and 1 - sqrt(2.25 / 3) = 13.4 % without any other).
// The blind launch-rotation case (strength 2, seed 23) where the camera was
// the verdict, per-glider held-out RMSE in cm (baseline, camera; equal points
// per glider assumed): pooled 5.3 %, 3.05 % without t09 (by a separate
// computation in Python), under the 5 % margin. The smallest can never exceed
// the pooled shrink (if every leave-one-out ratio were below the pooled one,
// summing them would give (G-1) SSE_e < (G-1) SSE_e); checked on random sums.
TEST(Diagnose, LeaveOneGliderOutShrinkFindsAGainThatRestsOnOneGlider) {
  {
    const auto [s, g] = leave_one_glider_out_shrink({1, 1, 1, 1}, {1, 1, 1, 0.25});
    EXPECT_NEAR(s, 0.0, 1e-12);
    EXPECT_EQ(g, 3);
  }
  {
    const std::vector<double> base_cm = {1.90, 1.76, 2.31, 2.46, 8.38, 1.57, 1.36, 1.44};
    const std::vector<double> cam_cm = {1.76, 1.82, 2.38, 2.08, 7.87, 1.56, 1.41, 1.48};
    std::vector<double> b, e;
    for (std::size_t i = 0; i < base_cm.size(); ++i) {
      b.push_back(base_cm[i] * base_cm[i]);
      e.push_back(cam_cm[i] * cam_cm[i]);
    }
    const auto [s, g] = leave_one_glider_out_shrink(b, e);
    EXPECT_NEAR(s, 0.0305, 5e-4);
    EXPECT_EQ(g, 4);
  }
  {
    const auto [s, g] = leave_one_glider_out_shrink({4.0}, {1.0});
    EXPECT_NEAR(s, 0.5, 1e-12);  // one glider: nothing to leave out, the pooled shrink
    EXPECT_EQ(g, -1);
  }
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.01, 2.0);
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 2 + trial % 9;
    std::vector<double> b(n), e(n);
    double sb = 0, se = 0;
    for (int i = 0; i < n; ++i) {
      sb += b[i] = u(rng);
      se += e[i] = u(rng);
    }
    const auto [s, g] = leave_one_glider_out_shrink(b, e);
    ASSERT_GE(g, 0);
    EXPECT_LE(s, 1 - std::sqrt(se / sb) + 1e-12) << "trial " << trial;
  }
  EXPECT_THROW(leave_one_glider_out_shrink({1, 1}, {1}), InputError);
  EXPECT_THROW(leave_one_glider_out_shrink({1, -1}, {1, 1}), InputError);
  EXPECT_THROW(leave_one_glider_out_shrink({1, std::nan("")}, {1, 1}), InputError);
}

// The glider guard's decision (glider_guard_pass) by its definition: a gain
// whose leave-one-glider-out shrink stays at the margin passes; one that
// rests on a glider passes only when at least three quarters of the held-out
// gliders are predicted better. Blind finite span at 1, seed 29 (2026-11-29),
// where downwash was named: per-glider held-out RMSE in mm (baseline,
// downwash) and points, from its result file; pooled 7.07 %, 0.24 % without
// the canard (recomputed here), 5 of 8 improved: no longer significant.
// Finite span at strength 2 (seed 23): 3.4 % without the canard, 6 of 8:
// still passes; per-flight launch rotation on the 3-glider test data: 3 of 3.
TEST(DiagnoseStatistics, TheGliderGuardWantsThreeQuartersOfTheGlidersWhenTheGainRestsOnOne) {
  const std::vector<double> pts = {152, 130, 166, 142, 143, 155, 155, 150};
  const std::vector<double> base_mm = {14.46, 15.31, 17.63, 14.66, 15.68, 26.33, 14.25, 30.16};
  const std::vector<double> dw_mm = {14.91, 15.03, 17.69, 14.28, 15.50, 26.48, 13.87, 22.50};
  std::vector<double> b, e;
  int improved = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    b.push_back(pts[i] * base_mm[i] * base_mm[i]);
    e.push_back(pts[i] * dw_mm[i] * dw_mm[i]);
    improved += dw_mm[i] < base_mm[i];
  }
  const auto [rs, g] = leave_one_glider_out_shrink(b, e);
  EXPECT_NEAR(rs, 0.0024, 2e-4);
  EXPECT_EQ(g, 7);
  EXPECT_EQ(improved, 5);
  EXPECT_FALSE(glider_guard_pass(rs, 0.05, improved, 8));
  EXPECT_TRUE(glider_guard_pass(rs, 0.05, 6, 8));       // finite span at 2: 6 of 8
  EXPECT_TRUE(glider_guard_pass(0.022, 0.05, 3, 3));    // launch rotation per flight: 3 of 3
  EXPECT_FALSE(glider_guard_pass(0.022, 0.05, 2, 3));   // a bare majority is not enough
  EXPECT_FALSE(glider_guard_pass(0.0305, 0.05, 4, 8));  // the camera on launch rotation at 2
  EXPECT_TRUE(glider_guard_pass(0.05, 0.05, 0, 8));     // at the margin without any glider: passes
  EXPECT_TRUE(glider_guard_pass(0.2, 0.05, 1, 8));
  EXPECT_FALSE(glider_guard_pass(0.0, 0.05, 0, 0));     // no gliders: the shrink alone decides
  EXPECT_THROW(glider_guard_pass(0.1, 0.05, 9, 8), InputError);
  EXPECT_THROW(glider_guard_pass(0.1, 0.05, -1, 8), InputError);
}

// The bound guard (fold_bound_share): the share of the held-out gain that
// comes from folds whose fit ran to the outer tenth of the candidate's
// range. By its definition on blind pitch damping at 1, seed 26: added mass
// fitted 0, 2.879, 3, 3 (range 0 to 3) in the folds, whose held-out gains
// (points times mm squared, from the diagnosis's per-glider RMSEs) were 20,
// 21416, 6195, 13495: all but the first fold's 20 from folds at the edge.
// Finite span on seed 30 (0.415, 0, 0.806, 0.739) has none there; a
// strength's lower bound 0 is the baseline, not an edge; a signed
// parameter's edge is on either side.
TEST(DiagnoseStatistics, TheBoundGuardCountsTheGainOfFoldsFittedAtTheEdgeOfTheRange) {
  const std::vector<double> gains = {20, 21416, 6195, 13495};
  const double am = fold_bound_share(Effect::AddedMass, {{0.0}, {2.879}, {3.0}, {3.0}}, gains);
  EXPECT_NEAR(am, (21416.0 + 6195 + 13495) / (20.0 + 21416 + 6195 + 13495), 1e-12);
  EXPECT_GT(am, 0.5);
  EXPECT_DOUBLE_EQ(fold_bound_share(Effect::FiniteSpan, {{0.415}, {0.0}, {0.806}, {0.739}}, gains), 0.0);
  // 2.69 is under 0.9 of 3, 2.7 is not.
  EXPECT_DOUBLE_EQ(fold_bound_share(Effect::AddedMass, {{2.69}, {0}, {0}, {0}}, {1, 1, 1, 1}), 0.0);
  EXPECT_DOUBLE_EQ(fold_bound_share(Effect::AddedMass, {{2.7}, {0}, {0}, {0}}, {1, 1, 1, 1}), 0.25);
  // Folds that predict worse do not offset the others: positive parts only.
  EXPECT_DOUBLE_EQ(fold_bound_share(Effect::AddedMass, {{3}, {1}, {0}, {0}}, {2, 2, -10, 0}), 0.5);
  // Wind's range is -15 to 15 m/s: either side is an edge.
  EXPECT_DOUBLE_EQ(fold_bound_share(Effect::Wind, {{-14.0}, {1.0}}, {3, 1}), 0.75);
  EXPECT_DOUBLE_EQ(fold_bound_share(Effect::Wind, {{14.0}, {-1.0}}, {3, 1}), 0.75);
  // The camera: any of its two parameters (scale, roll in rad; range +-0.5).
  EXPECT_DOUBLE_EQ(fold_bound_share(Effect::Camera, {{0.01, 0.46}, {0.03, 0.03}}, {1, 1}), 0.5);
  EXPECT_DOUBLE_EQ(fold_bound_share(Effect::Camera, {{0.01, 0.02}, {0.03, 0.03}}, {1, 1}), 0.0);
  // No fold gains: no share.
  EXPECT_DOUBLE_EQ(fold_bound_share(Effect::AddedMass, {{3}, {3}}, {-1, 0}), 0.0);
  EXPECT_THROW(fold_bound_share(Effect::AddedMass, {{3}}, {1, 2}), InputError);
  EXPECT_THROW(fold_bound_share(Effect::Camera, {{0.01}}, {1}), InputError);
  EXPECT_THROW(fold_bound_share(Effect::AddedMass, {{std::nan("")}}, {1}), InputError);
  EXPECT_THROW(fold_bound_share(Effect::AddedMass, {{1}}, {std::numeric_limits<double>::infinity()}), InputError);
}

// The leader's start skips values at the bound guard's edge
// (values_at_range_edge): the same edge as the guard's, the outer tenth of a
// non-zero bound (ground effect's and added mass's strengths run 0 to 3, so
// 2.7 is at it; wind -15 to 15 m/s; the camera's two parameters +-0.5).
TEST(DiagnoseStatistics, ValuesAtTheEdgeOfTheRangeAreTheBoundGuardsEdge) {
  EXPECT_TRUE(values_at_range_edge(Effect::GroundEffect, {3.0}));
  EXPECT_TRUE(values_at_range_edge(Effect::AddedMass, {2.7}));
  EXPECT_FALSE(values_at_range_edge(Effect::AddedMass, {2.69}));
  EXPECT_FALSE(values_at_range_edge(Effect::FiniteSpan, {0.55}));
  EXPECT_FALSE(values_at_range_edge(Effect::PitchDamping, {0.0}));  // the lower bound 0 is the baseline
  EXPECT_TRUE(values_at_range_edge(Effect::Wind, {-14.0}));
  EXPECT_FALSE(values_at_range_edge(Effect::Wind, {-1.0}));
  EXPECT_TRUE(values_at_range_edge(Effect::Camera, {0.01, -0.46}));
  EXPECT_FALSE(values_at_range_edge(Effect::Camera, {0.01, 0.02}));
  // Agrees with the guard: a fold at such values counts all its gain.
  EXPECT_DOUBLE_EQ(fold_bound_share(Effect::GroundEffect, {{3.0}}, {1}), 1.0);
  EXPECT_THROW(values_at_range_edge(Effect::Camera, {0.01}), InputError);
  EXPECT_THROW(values_at_range_edge(Effect::AddedMass, {std::nan("")}), InputError);
}

// The likelihood ratios' reference: a candidate whose fit to all gliders
// ended with every parameter at 0 (the baseline model) but a smaller sum
// of squares than the baseline's fit is a better baseline fit (blind
// finite span s42: added mass at strength 0, RMSE 1.3985 against 1.4149
// cm, was named). Of two such, the lower sum; per-flight launch rotation
// never (its rates are per flight); at 0 but no better: -1.
TEST(DiagnoseStatistics, ACandidateFittedAtZeroThatBeatsTheBaselineIsTheLikelihoodReference) {
  const std::vector<Effect> fx = {Effect::AddedMass, Effect::FiniteSpan, Effect::LaunchRotation, Effect::Camera,
                                  Effect::PitchDamping};
  const std::vector<bool> pf = {false, false, true, false, false};
  // Sums in arbitrary units: the baseline 100.
  std::vector<std::vector<double>> par = {{0.0}, {0.94}, {0.0}, {0.017, -0.017}, {0.0}};
  std::vector<double> sse = {97.7, 95.9, 90.0, 97.2, 100.0};
  EXPECT_EQ(likelihood_reference(fx, par, sse, pf, 100.0), 0);
  // Pitch damping at 0 lower still: it is the reference.
  sse[4] = 96.0;
  EXPECT_EQ(likelihood_reference(fx, par, sse, pf, 100.0), 4);
  // Per-flight launch rotation with a mean rate of 0 is not the baseline model.
  sse = {101.0, 95.9, 90.0, 97.2, 100.0};
  EXPECT_EQ(likelihood_reference(fx, par, sse, pf, 100.0), -1);
  // A camera with one parameter at 0 is not at the baseline's values.
  par[3] = {0.0, 0.02};
  sse[3] = 80.0;
  EXPECT_EQ(likelihood_reference(fx, par, sse, pf, 100.0), -1);
  par[3] = {0.0, 0.0};
  EXPECT_EQ(likelihood_reference(fx, par, sse, pf, 100.0), 3);
  EXPECT_THROW(likelihood_reference(fx, par, {1.0}, pf, 100.0), InputError);
  par[1] = {0.5, 0.5};
  EXPECT_THROW(likelihood_reference(fx, par, sse, pf, 100.0), InputError);
  par[1] = {std::nan("")};
  EXPECT_THROW(likelihood_reference(fx, par, sse, pf, 100.0), InputError);
  par[1] = {0.94};
  EXPECT_THROW(likelihood_reference(fx, par, sse, pf, std::nan("")), InputError);
  // Better only by less than the gain asked for (the diagnosis: 0.2
  // chi-square units, a converged pass's; 20-glider finite span s41 had
  // pitch damping at 0 better by 1e-10 m of RMSE): not a better fit.
  sse = {101.0, 95.9, 90.0, 99.9, 100.0};
  EXPECT_EQ(likelihood_reference(fx, par, sse, pf, 100.0, 0.2), -1);
  EXPECT_EQ(likelihood_reference(fx, par, sse, pf, 100.0, 0.05), 3);
  EXPECT_THROW(likelihood_reference(fx, par, sse, pf, 100.0, -1.0), InputError);
  EXPECT_THROW(likelihood_reference(fx, par, sse, pf, 100.0, std::nan("")), InputError);
}

// A named effect's fitted size (on all gliders) draws a caution in the
// summary when an aerodynamic strength exceeds twice its theory (blind
// pitch damping s37 named added mass at 2.55, wrong; 1.9 passes) or any
// parameter lies in the outer tenth of its range: a 14 m/s wind of a range
// +-15; the camera's roll in degrees (0.46 rad = 26.4 deg, range +-28.6
// deg). Unremarkable sizes: "".
TEST(DiagnoseStatistics, AVerdictFittedFarBeyondItsTheoryOrNearItsRangesEndIsFlagged) {
  const auto has = [](const std::string& n, const std::string& part) { return n.find(part) != std::string::npos; };
  std::string n = range_edge_sentence(Effect::AddedMass, {2.55});
  EXPECT_TRUE(has(n, "strength 2.55, more than 2 times its theoretical size (range 0 to 3)")) << n;
  EXPECT_TRUE(has(n, "rather than measuring added_mass")) << n;
  EXPECT_EQ(range_edge_sentence(Effect::AddedMass, {1.9}), "");
  EXPECT_EQ(range_edge_sentence(Effect::PitchDamping, {0.6}), "");
  EXPECT_EQ(range_edge_sentence(Effect::AddedMass, {0.0}), "");
  // Fuselage drag's theory underestimates by construction (range 0 to 10).
  EXPECT_EQ(range_edge_sentence(Effect::FuselageDrag, {4.0}), "");
  EXPECT_TRUE(has(range_edge_sentence(Effect::FuselageDrag, {9.5}), "strength 9.5, near the end of the range"));
  n = range_edge_sentence(Effect::Wind, {-14.0});
  EXPECT_TRUE(has(n, "wind_m_s -14, near the end of the range allowed (-15 to 15)")) << n;
  EXPECT_EQ(range_edge_sentence(Effect::Wind, {-1.0}), "");
  n = range_edge_sentence(Effect::Camera, {0.01, 0.46});
  EXPECT_TRUE(has(n, "26.4, near the end of the range allowed (-28.6 to 28.6)")) << n;
  EXPECT_FALSE(has(n, " and ")) << n;  // the scale is inside
  EXPECT_EQ(range_edge_sentence(Effect::Camera, {0.03, 0.035}), "");
  EXPECT_THROW(range_edge_sentence(Effect::Camera, {0.01}), InputError);
  EXPECT_THROW(range_edge_sentence(Effect::Wind, {std::nan("")}), InputError);
}

TEST(DiagnoseStatistics, RmsesSetAgainstEachOtherReadDifferently) {
  // Blind finite span s42: added mass at 0 fitted 1.3985 cm, the baseline
  // 1.4149 cm; to one decimal both read 1.4.
  EXPECT_EQ(cm_against(0.013985, 0.014149), "1.40 against 1.41 cm");
  EXPECT_EQ(cm_against(0.0213, 0.0146), "2.1 against 1.5 cm");
  EXPECT_EQ(cm_against(0.0141493, 0.0141498), "1.4149 against 1.4150 cm");
  EXPECT_EQ(cm_against(0.014, 0.014), "1.4000 against 1.4000 cm");  // equal: the most decimals
  EXPECT_THROW(cm_against(std::nan(""), 0.014), InputError);
}

// The note a person reads when the bound guard stops a candidate gives the
// share of the held-out gain and every fold's fitted value against the
// correction's range. Figures of blind pitch damping s26: added mass 6.1 %
// held out, 99.95 % of its gain from folds fitted at 2.879, 3 and 3 of its
// range's 3 (rounded for a person: "100 %", "2.88"). The guard's reason
// comes before the likelihood-ratio test's; a candidate under the margin
// was not stopped by the guard and gets the margin's note.
TEST(DiagnoseStatistics, TheBoundGuardsNoteGivesTheFoldsValuesAgainstTheRange) {
  const DiagnoseOptions o;
  EffectResult r;
  r.effect = Effect::AddedMass;
  r.name = "added_mass";
  r.shrink = 0.061;
  r.bound_share = 0.9995;
  r.bound_pass = false;
  r.fold_parameters = {{0.0}, {2.879}, {3.0}, {3.0}};
  r.lr_pass = true;
  r.holdout_delta_chi2 = 50;
  r.holdout_threshold = 8;
  const auto has = [](const std::string& n, const std::string& part) { return n.find(part) != std::string::npos; };
  std::string n = effect_note(r, o, false);
  EXPECT_TRUE(has(n, "predicts held-out gliders better (shrink 6.1 %)")) << n;
  EXPECT_TRUE(has(n, "100 % of that gain comes from folds whose fit ran to the edge of the correction's range")) << n;
  EXPECT_TRUE(has(n, "(strength 0, 2.88, 3, 3 in the folds, range 0 to 3)")) << n;
  r.lr_pass = false;
  EXPECT_EQ(effect_note(r, o, false), n);
  // Under the 5 % margin the guard did not decide anything.
  r.lr_pass = true;
  r.shrink = 0.03;
  r.holdout_delta_chi2 = 1;
  n = effect_note(r, o, false);
  EXPECT_FALSE(has(n, "edge of the correction's range")) << n;
  EXPECT_TRUE(has(n, "barely carries over to held-out gliders (shrink 3.0 %)")) << n;
  // The camera's two parameters, roll reported in degrees: 0.46 rad is
  // 26.36 deg, 0.03 rad 1.72 deg, the range +-0.5 rad +-28.65 deg.
  EffectResult c;
  c.effect = Effect::Camera;
  c.shrink = 0.08;
  c.bound_share = 0.6;
  c.bound_pass = false;
  c.fold_parameters = {{0.01, 0.46}, {0.03, 0.03}};
  n = effect_note(c, o, false);
  EXPECT_TRUE(has(n, "60 % of that gain")) << n;
  EXPECT_TRUE(has(n, "scale_error 0.01, 0.03 in the folds, range -0.5 to 0.5; roll_deg 26.4, 1.72 in the folds, range "
                     "-28.6 to 28.6")) << n;
}

// The glider guard's note names the glider the gain rests on, the shrink
// without it and the count of held-out gliders improved.
TEST(DiagnoseStatistics, TheGliderGuardsNoteNamesTheGliderTheGainRestsOn) {
  const DiagnoseOptions o;
  EffectResult r;
  r.effect = Effect::Downwash;
  r.shrink = 0.071;
  r.lr_pass = true;
  r.holdout_delta_chi2 = 40;
  r.holdout_threshold = 8;
  r.robust_pass = false;
  r.robust_without = "t17-canard";
  r.robust_shrink = 0.0024;
  r.gliders_improved = 5;
  r.gliders_total = 8;
  const std::string n = effect_note(r, o, false);
  EXPECT_NE(n.find("without t17-canard the shrink is 0.2 %, less than the 5.0 % margin, and it improves only 5 of 8"),
            std::string::npos)
      << n;
  // Not decided on its own (under the held-out chi-square quantile), the
  // guard is not the reason given.
  r.holdout_delta_chi2 = 2;
  EXPECT_EQ(effect_note(r, o, false).find("rests on one glider"), std::string::npos);
}

// The guards in one call (held_out_guards), as both rounds make them: the
// glider guard's figures from the per-glider sums (the s29 downwash figures
// of the glider-guard test above: 5 of 8 improved, 0.24 % without the
// canard, the eighth glider), the bound guard's from the folds (the s26
// added-mass figures), and each guard switched off by its option while its
// figures are still given. A candidate that improves 6 of 8 gliders passes
// the glider guard even with its gain on one.
TEST(DiagnoseStatistics, BothGuardsInOneCallAsBothRoundsMakeThem) {
  const std::vector<double> pts = {152, 130, 166, 142, 143, 155, 155, 150};
  const std::vector<double> base_mm = {14.46, 15.31, 17.63, 14.66, 15.68, 26.33, 14.25, 30.16};
  const std::vector<double> dw_mm = {14.91, 15.03, 17.69, 14.28, 15.50, 26.48, 13.87, 22.50};
  std::vector<double> b, e;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    b.push_back(pts[i] * base_mm[i] * base_mm[i]);
    e.push_back(pts[i] * dw_mm[i] * dw_mm[i]);
  }
  const std::vector<std::vector<double>> at_edge = {{0.0}, {2.879}, {3.0}, {3.0}}, inside = {{0.4}, {0.5}, {0.6}, {0.5}};
  const std::vector<double> gains = {20, 21416, 6195, 13495};
  DiagnoseOptions o;
  HeldOutGuards h = held_out_guards(Effect::AddedMass, b, e, at_edge, gains, o);
  EXPECT_EQ(h.improved, 5);
  EXPECT_EQ(h.total, 8);
  EXPECT_NEAR(h.robust_shrink, 0.0024, 2e-4);
  EXPECT_EQ(h.robust_without, 7);
  EXPECT_FALSE(h.robust_pass);
  EXPECT_GT(h.bound_share, 0.99);
  EXPECT_FALSE(h.bound_pass);
  h = held_out_guards(Effect::AddedMass, b, e, inside, gains, o);
  EXPECT_DOUBLE_EQ(h.bound_share, 0.0);
  EXPECT_TRUE(h.bound_pass);
  EXPECT_FALSE(h.robust_pass);
  // A sixth glider improved (the first: 14.91 -> 14.0 mm).
  std::vector<double> e6 = e;
  e6[0] = pts[0] * 14.0 * 14.0;
  h = held_out_guards(Effect::AddedMass, b, e6, inside, gains, o);
  EXPECT_EQ(h.improved, 6);
  EXPECT_TRUE(h.robust_pass);
  // Switched off: they pass, and their figures are still filled in.
  o.glider_guard = false;
  o.bound_guard = false;
  h = held_out_guards(Effect::AddedMass, b, e, at_edge, gains, o);
  EXPECT_TRUE(h.robust_pass);
  EXPECT_TRUE(h.bound_pass);
  EXPECT_EQ(h.improved, 5);
  EXPECT_GT(h.bound_share, 0.99);
  EXPECT_THROW(held_out_guards(Effect::AddedMass, b, {1.0}, inside, gains, o), InputError);
  EXPECT_THROW(held_out_guards(Effect::AddedMass, b, e, inside, {1.0}, o), InputError);
}

// The note of a candidate given the verdict's effect (given_note) says what
// decided it, in the order the decision goes: the guards as in the first
// round (a gain resting on one glider, folds at the edge of the range),
// the likelihood-ratio test, the margin; nothing when it was not tested.
TEST(DiagnoseStatistics, TheSecondRoundsNoteSaysWhatDecidedGivenTheVerdict) {
  const DiagnoseOptions o;
  EffectResult r;
  r.effect = Effect::AddedMass;
  EXPECT_EQ(given_note(r, "wind", o), "");
  auto& g = r.given_verdict;
  g.tested = true;
  g.lr_pass = true;
  g.delta_chi2 = 37.9;
  g.p_value = 1.4e-9;
  g.shrink = 0.083;
  g.holdout_delta_chi2 = 60;
  g.holdout_threshold = 8;
  g.significant = true;
  std::string n = given_note(r, "wind", o);
  EXPECT_EQ(n.rfind("with wind in the model, significant", 0), 0u) << n;
  EXPECT_NE(n.find("8.3 % better still"), std::string::npos) << n;
  g.significant = false;
  g.robust_pass = false;
  g.robust_without = "t09-forward-swept-15";
  g.robust_shrink = 0.012;
  g.gliders_improved = 4;
  g.gliders_total = 8;
  n = given_note(r, "wind", o);
  EXPECT_NE(n.find("rests on one glider: without t09-forward-swept-15 it is 1.2 %, and it improves only 4 of 8"),
            std::string::npos)
      << n;
  g.bound_pass = false;
  g.bound_share = 0.9995;
  g.fold_parameters = {{0.0}, {2.879}, {3.0}, {3.0}};
  n = given_note(r, "wind", o);
  EXPECT_NE(n.find("100 % of that gain comes from folds whose fit ran to the edge"), std::string::npos) << n;
  EXPECT_NE(n.find("2.88"), std::string::npos) << n;
  g.bound_pass = true;
  g.robust_pass = true;
  g.lr_pass = false;
  g.p_value = 0.11;
  n = given_note(r, "wind", o);
  EXPECT_NE(n.find("not significant on the training gliders (p 0.11)"), std::string::npos) << n;
  g.lr_pass = true;
  g.shrink = 0.02;
  n = given_note(r, "wind", o);
  EXPECT_NE(n.find("2.0 % better, less than the 5.0 % margin"), std::string::npos) << n;
}

// Which guard alone stopped a candidate given the verdict
// (given_stopped_by): only one the three tests passed and that is not
// significant; the bound guard named first, as in the note. With the
// held-out chi-square test switched off (--no-holdout-test) a held-out
// delta chi2 under its quantile no longer keeps the guard from being the
// reason.
TEST(DiagnoseStatistics, TheGuardThatStoppedASecondEffectIsNamedOnlyWhenTheTestsPassed) {
  DiagnoseOptions o;
  EffectResult::Given g;
  EXPECT_EQ(given_stopped_by(g, o, Effect::Wind), "");  // not tested
  g.tested = true;
  g.lr_pass = true;
  g.shrink = 0.096;
  g.holdout_delta_chi2 = 512;
  g.holdout_threshold = 11.7;
  g.robust_pass = false;  // pitch damping given the wind, s42: 4.6 % without t09, 5 of 8
  EXPECT_EQ(given_stopped_by(g, o, Effect::Wind), "glider");
  g.bound_pass = false;
  EXPECT_EQ(given_stopped_by(g, o, Effect::Wind), "bound");
  g.significant = true;  // significant: nothing stopped it
  EXPECT_EQ(given_stopped_by(g, o, Effect::Wind), "");
  g.significant = false;
  g.robust_pass = g.bound_pass = true;  // both guards passed: something else stopped it
  EXPECT_EQ(given_stopped_by(g, o, Effect::Wind), "");
  g.robust_pass = false;
  g.lr_pass = false;  // a test failed: that is the reason, not the guard
  EXPECT_EQ(given_stopped_by(g, o, Effect::Wind), "");
  g.lr_pass = true;
  g.shrink = 0.03;
  EXPECT_EQ(given_stopped_by(g, o, Effect::Wind), "");
  g.shrink = 0.096;
  g.holdout_delta_chi2 = 5;
  EXPECT_EQ(given_stopped_by(g, o, Effect::Wind), "");
  o.holdout_chi2_test = false;
  EXPECT_EQ(given_stopped_by(g, o, Effect::Wind), "glider");
}

// The summary's launch caution (launch_caution): launch rotation passed its
// likelihood-ratio test but is not significant, and the verdict is another
// effect or `unexplained`. Figures of blind launch rotation s34 (the
// verdict wind; launch rotation p 3e-13, 63.8 deg/s, 1.65 % held out, "1.7 %") and
// s32 (`unexplained`). Nothing when it did not pass the test, when it is
// itself significant or the verdict, or for `none`.
namespace {
// Launch rotation and wind as blind launch rotation s34 gave them: launch
// rotation passed its likelihood-ratio test (p 3e-13) at 63.8 deg/s,
// 1.65 % held out, its per-flight rates' mean at p 0.0021, not significant;
// wind significant, the verdict.
EffectResult s34_launch_rotation() {
  EffectResult lr;
  lr.effect = Effect::LaunchRotation;
  lr.name = effect_name(Effect::LaunchRotation);
  lr.lr_pass = true;
  lr.p_value = 3e-13;
  lr.parameters = {deg2rad(63.8)};
  lr.shrink = 0.0165;
  lr.rate_test = true;
  lr.rate_mean = deg2rad(63.8);
  lr.rate_mean_p = 0.0021;
  return lr;
}
EffectResult s34_wind() {
  EffectResult wind;
  wind.effect = Effect::Wind;
  wind.name = "wind";
  wind.significant = true;
  wind.lr_pass = true;
  return wind;
}
}  // namespace

TEST(DiagnoseStatistics, TheSummaryCautionsWhenLaunchRotationFitsButIsNotTheVerdict) {
  const EffectResult lr = s34_launch_rotation(), wind = s34_wind();
  const std::vector<EffectResult> both = {wind, lr};
  std::string s = launch_caution(both, "wind", 0.05, 0.01);
  EXPECT_EQ(s.rfind(" launch_rotation also fits the training flights significantly better (p 3e-13; ", 0), 0u) << s;
  EXPECT_NE(s.find("63.8"), std::string::npos) << s;
  EXPECT_NE(s.find("closes only 1.7 % of the held-out error"), std::string::npos) << s;  // 1.65 % to one decimal
  EXPECT_NE(s.find("before taking wind as the cause"), std::string::npos) << s;
  s = launch_caution(both, "unexplained", 0.05, 0.01);
  EXPECT_EQ(s.rfind(" launch_rotation fits the training flights", 0), 0u) << s;
  EXPECT_NE(s.find("the gap may lie in the launches"), std::string::npos) << s;
  EXPECT_EQ(launch_caution(both, "none", 0.05, 0.01), "");
  EXPECT_EQ(launch_caution(both, "launch_rotation", 0.05, 0.01), "");
  std::vector<EffectResult> v = both;
  v[1].lr_pass = false;
  EXPECT_EQ(launch_caution(v, "wind", 0.05, 0.01), "");
  v[1].lr_pass = true;
  v[1].significant = true;
  EXPECT_EQ(launch_caution(v, "wind", 0.05, 0.01), "");
  EXPECT_EQ(launch_caution({wind}, "wind", 0.05, 0.01), "");
  // At or above the margin (stopped by something else) it is not "only".
  v[1].significant = false;
  v[1].shrink = 0.062;
  s = launch_caution(v, "wind", 0.05, 0.01);
  EXPECT_NE(s.find("but closes 6.2 % of the held-out error"), std::string::npos) << s;
  // Per-flight rates scattered both ways (mean's p over alpha) are no
  // launcher's rotation: no caution (pitch damping s34: p 0.45); a shared
  // rate (no per-flight rates, no rate test) is not asked for a direction.
  v[1].rate_mean_p = 0.45;
  EXPECT_EQ(launch_caution(v, "wind", 0.05, 0.01), "");
  EXPECT_EQ(launch_caution(v, "unexplained", 0.05, 0.01), "");
  v[1].rate_test = false;
  EXPECT_NE(launch_caution(v, "wind", 0.05, 0.01), "");
}

// The launch withhold (launch_withheld, withheld_sentence): beside a
// verdict of an effect applied alike to every flight (wind, the camera), a
// significant launch rotation takes the verdict, and one that only fits the
// training flights with rates turning one way (the caution's condition)
// makes it `unexplained`. Figures of blind launch rotation s34 (wind named,
// 0.6 m/s; launch rotation p 3e-13, 63.8 deg/s, 1.65 % held out, rates'
// mean p 0.0021). Nothing for an aerodynamic verdict, launch rotation
// itself, none or unexplained, nor when launch rotation failed its test or
// its rates scatter both ways.
TEST(DiagnoseStatistics, ASessionWideVerdictIsWithheldWhenLaunchRotationFitsTheLaunches) {
  const EffectResult lr = s34_launch_rotation();
  EffectResult wind = s34_wind();
  wind.shrink = 0.123;
  wind.parameters = {0.6};
  EffectResult camera = wind;
  camera.effect = Effect::Camera;
  camera.name = "camera";
  camera.parameters = {0.03, deg2rad(2.0)};
  EffectResult pd = wind;
  pd.effect = Effect::PitchDamping;
  pd.name = "pitch_damping";
  pd.parameters = {0.5};
  const std::vector<EffectResult> all = {wind, camera, pd, lr};
  EXPECT_EQ(launch_withheld(all, "wind", 0.01), "unexplained");
  EXPECT_EQ(launch_withheld(all, "camera", 0.01), "unexplained");
  EXPECT_EQ(launch_withheld(all, "pitch_damping", 0.01), "");  // depends on the geometry: not a launch habit
  EXPECT_EQ(launch_withheld(all, "launch_rotation", 0.01), "");
  EXPECT_EQ(launch_withheld(all, "none", 0.01), "");
  EXPECT_EQ(launch_withheld(all, "unexplained", 0.01), "");
  std::vector<EffectResult> v = all;
  v[3].lr_pass = false;
  EXPECT_EQ(launch_withheld(v, "wind", 0.01), "");
  EXPECT_EQ(withheld_sentence(v, "wind", 0.05, 0.01), "");
  v[3].lr_pass = true;
  v[3].rate_mean_p = 0.45;  // scattered both ways: no launcher's rotation
  EXPECT_EQ(launch_withheld(v, "wind", 0.01), "");
  EXPECT_EQ(launch_withheld({wind, camera}, "wind", 0.01), "");
  std::string s = withheld_sentence(all, "wind", 0.05, 0.01);
  EXPECT_EQ(s.rfind(" wind would cut it by 12 % (fitted wind_m_s 0.6)", 0), 0u) << s;  // 12.3 %: whole per cent above 10
  EXPECT_NE(s.find("launch_rotation fits the training flights"), std::string::npos) << s;
  EXPECT_NE(s.find("63.8"), std::string::npos) << s;
  EXPECT_NE(s.find("closes only 1.7 % of the held-out error"), std::string::npos) << s;
  EXPECT_NE(s.find("Check how the gliders were launched: if they left the hand without pitching, wind is the likely "
                   "cause (--no-launch-withhold names it)."),
            std::string::npos)
      << s;
  EXPECT_EQ(withheld_sentence(all, "camera", 0.05, 0.01).rfind(" camera would cut it by 12 %", 0), 0u);
  // Significant (its rates confirm it, launch_rates_confirm), launch
  // rotation takes the verdict from wind or the camera, not from an
  // aerodynamic effect; the sentence then says why wind is not named.
  v = all;
  v[3].significant = true;
  EXPECT_EQ(launch_withheld(v, "wind", 0.01), "launch_rotation");
  EXPECT_EQ(launch_withheld(v, "camera", 0.01), "launch_rotation");
  EXPECT_EQ(launch_withheld(v, "pitch_damping", 0.01), "");
  s = withheld_sentence(v, "wind", 0.05, 0.01);
  EXPECT_EQ(s.rfind(" wind predicts the held-out gliders better still (12 %, fitted wind_m_s 0.6) but is not named", 0),
            0u) << s;
  EXPECT_NE(s.find("rates share a direction (mean 63.8 deg/s, p 0.0021)"), std::string::npos) << s;
  EXPECT_NE(s.find("If the gliders left the hand without pitching, wind is the likely cause"), std::string::npos) << s;
}

// The launch withhold's exemption (launch_dominance,
// DiagnoseOptions::launch_withhold_dominance): a session-wide verdict whose
// all-glider fit closes more than K times launch rotation's share of the
// baseline's training misfit stands. Fit RMSEs of three stored blind runs
// (bench/diagnosis/runs); the shares worked out by hand, 1 - fit / baseline:
// wind s22 (ba2fc55, wind the truth): baseline 4.3998 cm, wind 1.5597 cm,
// launch rotation 4.3377 cm: 64.55 % and 1.411 %, 45.7 times;
// launch rotation s44 (06074dd): baseline 1.44419 cm, wind 1.3842 cm,
// launch rotation 1.41715 cm: 4.154 % and 1.872 %, 2.22 times;
// launch rotation s33 (ba2fc55): baseline 1.54752 cm, camera 1.5196 cm,
// launch rotation (significant) 1.51041 cm: 1.804 % and 2.398 %, 0.75 times.
TEST(DiagnoseStatistics, ASessionWideVerdictFarBetterThanLaunchRotationOnTheTrainingFlightsIsNotWithheld) {
  EffectResult lr = s34_launch_rotation();  // passed its test, not significant, rates' p 0.0021
  EffectResult wind = s34_wind();
  wind.shrink = 0.601;
  wind.parameters = {-0.92};
  double base = 0.043998;
  wind.fit_rmse_m = 0.015597;
  lr.fit_rmse_m = 0.043377;
  std::vector<EffectResult> v = {wind, lr};
  LaunchDominance d = launch_dominance(v, "wind", base, 5.0);
  EXPECT_TRUE(d.applies);
  EXPECT_NEAR(d.verdict_gain, 0.6455, 1e-4);
  EXPECT_NEAR(d.launch_gain, 0.01411, 1e-5);
  EXPECT_TRUE(d.dominates);
  EXPECT_EQ(launch_withheld(v, "wind", 0.01, base, 5.0), "");
  EXPECT_EQ(launch_withheld(v, "wind", 0.01, base, 45.0), "");
  EXPECT_EQ(launch_withheld(v, "wind", 0.01, base, 46.0), "unexplained");  // 45.7 times, not more than 46
  EXPECT_EQ(launch_withheld(v, "wind", 0.01, base, 0.0), "unexplained");   // 0: the rule of 2026-11-30
  EXPECT_EQ(launch_withheld(v, "wind", 0.01), "unexplained");
  EXPECT_EQ(launch_withheld(v, "wind", 0.01, 0.0, 5.0), "unexplained");  // no baseline RMSE: no exemption
  std::string s = launch_dominance_sentence(v, "wind", 0.01, base, 5.0);
  EXPECT_EQ(s.rfind(" wind is named though launch rotation fits the training flights too: fitted to all gliders it "
                    "closes 65 % of the baseline's misfit there, launch rotation 1.4 %, more than 5 times as much.",
                    0),
            0u)
      << s;
  EXPECT_NE(s.find("--launch-withhold-dominance 0 withholds it"), std::string::npos) << s;
  EXPECT_EQ(launch_dominance_sentence(v, "wind", 0.01, base, 46.0), "");  // withheld: no such sentence
  // An aerodynamic verdict is never withheld, so nothing is said of it.
  EffectResult pd = wind;
  pd.effect = Effect::PitchDamping;
  pd.name = "pitch_damping";
  EXPECT_EQ(launch_dominance_sentence({pd, lr}, "pitch_damping", 0.01, base, 5.0), "");
  // Launch rotation's rates scattered both ways: the withhold does not apply,
  // so neither does the sentence.
  v[1].rate_mean_p = 0.45;
  EXPECT_EQ(launch_dominance_sentence(v, "wind", 0.01, base, 5.0), "");

  // The two shares (to 1e-5) and the decision at 5 of a stored run.
  const auto expect_shares = [](const std::vector<EffectResult>& runs, const std::string& verdict, double baseline,
                                double verdict_share, double launch_share) {
    const LaunchDominance e = launch_dominance(runs, verdict, baseline, 5.0);
    EXPECT_NEAR(e.verdict_gain, verdict_share, 1e-5) << verdict;
    EXPECT_NEAR(e.launch_gain, launch_share, 1e-5) << verdict;
    EXPECT_FALSE(e.dominates) << verdict;
  };

  // Launch rotation s44: the wind only 2.2 times: withheld at 5, not at 2.
  base = 0.0144419;
  wind.fit_rmse_m = 0.013842;
  lr.fit_rmse_m = 0.0141715;
  v = {wind, lr};
  expect_shares(v, "wind", base, 0.04154, 0.01872);
  EXPECT_EQ(launch_withheld(v, "wind", 0.01, base, 5.0), "unexplained");
  EXPECT_EQ(launch_dominance_sentence(v, "wind", 0.01, base, 5.0), "");
  EXPECT_EQ(launch_withheld(v, "wind", 0.01, base, 2.0), "");

  // Launch rotation s33: significant and fitting better than the camera:
  // it takes the verdict.
  base = 0.0154752;
  EffectResult camera = s34_wind();
  camera.effect = Effect::Camera;
  camera.name = "camera";
  camera.fit_rmse_m = 0.0151960;
  lr.fit_rmse_m = 0.0151041;
  lr.significant = true;
  v = {camera, lr};
  expect_shares(v, "camera", base, 0.01804, 0.02398);
  EXPECT_EQ(launch_withheld(v, "camera", 0.01, base, 5.0), "launch_rotation");
  // Without launch rotation among the candidates there is nothing to compare.
  EXPECT_FALSE(launch_dominance({camera}, "camera", base, 5.0).applies);
}

// The shrink margin (shrink_margin): every effect is held to
// DiagnoseOptions::min_shrink except per-flight launch rotation while its
// rates confirm it (launch_rates_confirm); a launch rotation common to the
// session (one strength) is held to it as every effect.
TEST(DiagnoseStatistics, PerFlightLaunchRotationIsConfirmedByItsRatesNotTheMargin) {
  DiagnoseOptions o;
  EXPECT_EQ(shrink_margin(o, Effect::LaunchRotation), 0.0);
  EXPECT_EQ(shrink_margin(o, Effect::Wind), o.min_shrink);
  EXPECT_EQ(shrink_margin(o, Effect::PitchDamping), o.min_shrink);
  o.launch_rotation_per_flight = false;
  EXPECT_EQ(shrink_margin(o, Effect::LaunchRotation), o.min_shrink);
  o.launch_rotation_per_flight = true;
  o.launch_rates_confirm = false;
  EXPECT_EQ(shrink_margin(o, Effect::LaunchRotation), o.min_shrink);
  // The note of a significant launch rotation under the margin says what
  // confirmed it (s34's figures).
  o.launch_rates_confirm = true;
  EffectResult lr;
  lr.effect = Effect::LaunchRotation;
  lr.name = "launch_rotation";
  lr.significant = true;
  lr.lr_pass = true;
  lr.shrink = 0.016;
  lr.rate_test = true;
  lr.rate_mean = deg2rad(63.8);
  lr.rate_mean_p = 7.2e-4;
  const std::string n = effect_note(lr, o, false);
  EXPECT_NE(n.find("shrink 1.6 %), under the 5.0 % margin, which a launch value is not held to"), std::string::npos)
      << n;
  EXPECT_NE(n.find("mean 63.8 deg/s, p 0.00072"), std::string::npos) << n;
  // Over the margin it is not said to be under it.
  lr.shrink = 0.062;
  EXPECT_EQ(effect_note(lr, o, false).find("under the"), std::string::npos) << effect_note(lr, o, false);
  // Stopped by the bound guard with a shrink under the 5 % margin but over
  // its own (0): the note names the guard, as for any effect over its margin.
  lr.significant = false;
  lr.shrink = 0.02;
  lr.bound_pass = false;
  lr.bound_share = 0.8;
  lr.fold_parameters = {{19.0}, {19.5}, {0.5}, {0.4}};
  EXPECT_NE(effect_note(lr, o, false).find("edge of the correction's range"), std::string::npos)
      << effect_note(lr, o, false);
}

// A linearised step that overshoots is given up after its first fit and
// damped (kGiveUpFactor, kStepFractions in src/diagnose.cpp): with a 2 m/s
// head wind (2 mm noise) the linearisation on all gliders points far past
// the truth, and the full step's first fit misfits worse than the baseline
// (and so worse than the fixed-coefficient candidate fit it must beat; seen
// 7.2 cm against 4.6 cm): it is not settled further, the half step is tried,
// and the joint refit from the better of the two reaches the truth (2 m/s
// within 0.05) and the tracking noise. With the damped steps removed
// (kStepFractions = {1}) the test fails on the missing half step (the joint
// refit from the full step's first fit still reaches the truth here: the
// damping is a safeguard for fits that do not, e.g. wind on blind data).
TEST(Diagnose, AnOvershootingStepIsGivenUpAndDamped) {
  EffectValues truth;
  truth.wind = -2.0;
  const Dataset d = corrected_flights(truth, 0.002, 5);
  const DiagnoseOptions o = profiled_diagnosis({Effect::Wind});
  std::vector<std::string> lines;
  const DiagnoseResult r = diagnose(d, o, [&](const DiagnoseProgress& p) { lines.push_back(p.message); });
  ASSERT_EQ(r.verdict, "wind") << r.summary;
  // A wind in m/s has no theoretical size to compare it with.
  EXPECT_EQ(r.summary.find("theoretical size"), std::string::npos) << r.summary;
  // "all gliders: wind from 0.5 of the linearised step (...): RMSE a cm (the full step: b cm)"
  const std::regex damped(R"(^all gliders: wind from 0\.5 of the linearised step .*: RMSE ([0-9.]+) cm \(the full step: ([0-9.]+) cm\))");
  int seen = 0;
  for (const auto& l : lines) {
    std::smatch m;
    if (!std::regex_search(l, m, damped)) continue;
    ++seen;
    const double half = std::stod(m[1]) / 100, full = std::stod(m[2]) / 100;
    EXPECT_GT(full, r.fit_rmse_m) << "the full step was not worse than the baseline: " << l;
    EXPECT_LT(half, full) << l;
  }
  EXPECT_EQ(seen, 1) << "no damped step on all gliders";
  for (const auto& e : r.effects)
    if (e.effect == Effect::Wind) {
      ASSERT_EQ(e.parameters.size(), 1u);
      EXPECT_NEAR(e.parameters[0], -2.0, 0.05);
      EXPECT_LT(e.fit_rmse_m, 2 * 0.002);
    }
}

// Held-out-led steps (DiagnoseOptions::heldout_steps): which candidates are
// refitted from their step on all gliders. A candidate the held-out gliders
// confirm by every held-out part of the decision rule (the margin, the
// held-out chi-square, the glider guard) with a plausible fit is, whatever
// its likelihood ratio; one that fails any of them, one already stepped
// and a per-flight one are not.
TEST(Diagnose, HeldOutLedStepsTakeOnlyCandidatesTheHeldOutGlidersConfirm) {
  DiagnoseOptions o;  // margin 5 %, held-out chi-square test on
  EffectResult r;
  r.shrink = 0.154;  // blind finite span at 1, seed 28
  r.holdout_delta_chi2 = 842;
  r.holdout_threshold = 10.6;
  r.robust_pass = true;
  r.plausible = true;
  r.lr_pass = false;
  r.delta_chi2 = 0;
  EXPECT_TRUE(heldout_step_eligible(r, o, false, false));
  EXPECT_FALSE(heldout_step_eligible(r, o, true, false));   // stepped already
  EXPECT_FALSE(heldout_step_eligible(r, o, false, true));   // per-flight launch rotation
  EffectResult under = r;
  under.shrink = 0.049;
  EXPECT_FALSE(heldout_step_eligible(under, o, false, false));
  EffectResult noise = r;
  noise.holdout_delta_chi2 = 10.5;
  EXPECT_FALSE(heldout_step_eligible(noise, o, false, false));
  DiagnoseOptions no_test = o;
  no_test.holdout_chi2_test = false;
  EXPECT_TRUE(heldout_step_eligible(noise, no_test, false, false));
  EffectResult one_glider = r;
  one_glider.robust_pass = false;
  EXPECT_FALSE(heldout_step_eligible(one_glider, o, false, false));
  EffectResult implausible = r;
  implausible.plausible = false;
  EXPECT_FALSE(heldout_step_eligible(implausible, o, false, false));
  EffectResult at_edge = r;  // added mass on pitch damping s26: folds at its range's edge
  at_edge.bound_share = 0.9995;
  at_edge.bound_pass = false;
  EXPECT_FALSE(heldout_step_eligible(at_edge, o, false, false));
  DiagnoseOptions wide = o;
  wide.min_shrink = 0.2;
  EXPECT_FALSE(heldout_step_eligible(r, wide, false, false));
}

// Theoretical-size starts (DiagnoseOptions::theory_starts): with no
// candidate refitted from its linearised step (profiled_candidates = 0) the
// folds' pitch-damping fits keep the baseline's centre values, which took
// part of the damping. Started at strength 1 (the correction's theoretical
// size, which made these flights, reached in quarter steps) with the
// centre values refitted, every
// fold's training fit finds the truth: fold strengths within 0.1 of 1 and
// held-out gliders predicted to within twice the 2 mm noise. The progress
// names the start in every fit (three folds and all gliders).
TEST(Diagnose, TheoreticalSizeStartsRefitTheCentreValuesWithTheCorrection) {
  auto [d, p] = profiled_pitch_damping_case();
  DiagnoseOptions o = unstepped(p);
  o.theory_starts = true;
  o.hold_theory = true;  // the held strength's marks, checked at the end
  std::vector<std::string> lines;
  const DiagnoseResult r = diagnose(d, o, [&](const DiagnoseProgress& p) { lines.push_back(p.message); });
  ASSERT_EQ(r.verdict, "pitch_damping") << r.summary;
  // all gliders and three folds (more when the baseline improves)
  EXPECT_GE(lines_with(lines, "pitch_damping from its theoretical size with the centre values"), 4);
  // reached in quarter steps, as the oracle's effects are, in each of those fits
  EXPECT_GE(lines_with(lines, "pitch_damping switched on to its theoretical size in 4 steps"), 4);
  for (const auto& l : lines) EXPECT_EQ(l.find("wind from its theoretical size"), std::string::npos) << l;  // a session effect
  bool seen = false;
  for (const auto& e : r.effects)
    if (e.effect == Effect::PitchDamping) {
      seen = true;
      ASSERT_EQ(e.fold_parameters.size(), 3u);
      for (const auto& f : e.fold_parameters) EXPECT_NEAR(f.at(0), 1.0, 0.1);
      EXPECT_LT(e.holdout_rmse_m, 2 * 0.002);
    }
  EXPECT_TRUE(seen);
  // freed, the strength did not fit the training flights significantly
  // better than the theoretical size that made them
  EXPECT_GE(lines_with(lines, "pitch_damping freed from its theoretical size"), 4);
  EXPECT_GE(lines_with(lines, ": held at its theoretical size"), 1);
  // a held strength is exactly the theoretical size, and the result says so
  for (const auto& e : r.effects) {
    ASSERT_EQ(e.fold_strength_held.size(), e.fold_parameters.size());
    for (std::size_t k = 0; k < e.fold_parameters.size(); ++k)
      if (e.fold_strength_held[k]) EXPECT_EQ(e.fold_parameters[k].at(0), 1.0) << e.name << " fold " << k;
    if (e.strength_held) EXPECT_EQ(e.parameters.at(0), 1.0) << e.name;
    EXPECT_EQ(e.strength_held, e.note.find("held at its theoretical size") != std::string::npos) << e.note;
  }
}

// (DiagnoseOptions::hold_theory) A theoretical-size start is held at strength 1 only while the training
// flights do not reject it: on flights made with pitch damping at twice
// its theoretical size (2 mm noise), the strength freed from 1 fits them
// better by far more than the chi-square quantile, so the fits keep the
// freed strength, near the 2 that made the flights, in every fold.
TEST(Diagnose, ATheoreticalSizeTheFlightsRejectIsFreed) {
  EffectValues truth;
  truth.pitch_damping = 2.0;
  const Dataset d = corrected_flights(truth, 0.002, 5);
  DiagnoseOptions o = unstepped(profiled_diagnosis({Effect::PitchDamping, Effect::Wind}));
  o.theory_starts = true;
  o.hold_theory = true;
  std::vector<std::string> lines;
  const DiagnoseResult r = diagnose(d, o, [&](const DiagnoseProgress& p) { lines.push_back(p.message); });
  EXPECT_GE(lines_with(lines, "pitch_damping freed from its theoretical size"), 4);
  EXPECT_GE(lines_with(lines, ": the theoretical size is rejected"), 4);
  ASSERT_EQ(r.verdict, "pitch_damping") << r.summary;
  for (const auto& e : r.effects)
    if (e.effect == Effect::PitchDamping) {
      std::cout << "pitch damping: strength " << e.parameters.at(0) << std::endl;
      EXPECT_FALSE(e.strength_held);
      EXPECT_NEAR(e.parameters.at(0), 2.0, 0.3);
      for (const auto& f : e.fold_parameters) EXPECT_NEAR(f.at(0), 2.0, 0.3);
    }
}

// The second search's verdict is also measured against the first search's
// baseline (second_search_against_first). Worked by hand: the second
// search's baseline predicts the held-out gliders at 1.88 cm, pitch damping
// at 1.58 cm (1 - 1.58/1.88 = 16.0 %); against a first baseline of 1.67 cm
// it closes 1 - 1.58/1.67 = 5.39 %: over the 5 % margin, it stands; against
// 1.62 cm, 2.47 %: under it, demoted, and the sentence gives both figures.
// `none`, `unexplained` and launch rotation are not measured.
// A second search that named pitch damping at 1.58 cm held out against its
// own baseline's 1.88 cm (blind pitch damping s47's figures).
namespace {
DiagnoseResult pitch_damping_second_search() {
  DiagnoseResult r;
  r.verdict = "pitch_damping";
  r.holdout_rmse_m = 0.0188;
  EffectResult e;
  e.name = "pitch_damping";
  e.holdout_rmse_m = 0.0158;
  e.shrink = 1 - 0.0158 / 0.0188;
  r.effects = {e};
  return r;
}
}  // namespace

TEST(Diagnose, TheSecondSearchsEffectMustAlsoBeatTheFirstSearchsBaseline) {
  DiagnoseOptions o;
  o.min_shrink = 0.05;
  DiagnoseResult r = pitch_damping_second_search();
  EffectResult w;
  w.name = "wind";
  w.holdout_rmse_m = 0.0100;  // not the verdict: not looked at
  r.effects.insert(r.effects.begin(), w);
  EXPECT_EQ(second_search_against_first(r, 0.0167, o), "");
  EXPECT_NEAR(r.escalation.shrink_against_first, 1 - 1.58 / 1.67, 1e-12);
  EXPECT_EQ(r.escalation.first_holdout_rmse_m, 0.0167);
  EXPECT_EQ(r.escalation.demoted, "");
  const std::string why = second_search_against_first(r, 0.0162, o);
  EXPECT_NEAR(r.escalation.shrink_against_first, 1 - 1.58 / 1.62, 1e-12);
  EXPECT_EQ(r.escalation.demoted, "pitch_damping");
  for (const char* s : {"pitch_damping", "16 %", "1.88 cm", "2.5 %", "1.62 cm", "5.0 % margin", "unexplained"})
    EXPECT_NE(why.find(s), std::string::npos) << s << " not in: " << why;
  for (const char* v : {"none", "unexplained", "launch_rotation"}) {
    DiagnoseResult n = r;
    n.verdict = v;
    EXPECT_EQ(second_search_against_first(n, 0.0162, o), "") << v;
    EXPECT_TRUE(std::isnan(n.escalation.shrink_against_first)) << v;
    EXPECT_EQ(n.escalation.demoted, "") << v;
  }
}

// When the second search's effect falls under the margin against the first
// search's baseline, the first result stands (first_result_stands, what
// diagnose() with --escalate returns then): its verdict, effects and
// baseline unchanged, the second search's escalation record (the demoted
// effect), the sentence before its summary and the pointer to a second
// search gone from it, timed over both searches.
TEST(Diagnose, WhenTheSecondSearchsEffectFallsTheFirstResultStands) {
  DiagnoseOptions o;
  o.min_shrink = 0.05;
  DiagnoseResult first;
  first.verdict = "unexplained";
  first.holdout_rmse_m = 0.0162;
  first.summary = std::string("The gap stays.") + kSecondSearchHint;
  first.seconds = 400;
  first.timings = {{"folds_s", 300.0}, {"total_s", 400.0}};
  EffectResult a;
  a.name = "added_mass";
  a.holdout_rmse_m = 0.0160;
  first.effects = {a};
  DiagnoseResult second = pitch_damping_second_search();
  second.seconds = 900;
  const std::string fell = conclude_second_search(second, "unexplained", "added_mass", 0.01, 400, 0.0162, o);
  ASSERT_FALSE(fell.empty());
  first_result_stands(first, second, fell, 400, 1305);
  EXPECT_EQ(first.verdict, "unexplained");
  ASSERT_EQ(first.effects.size(), 1u);
  EXPECT_EQ(first.effects[0].name, "added_mass");
  EXPECT_EQ(first.holdout_rmse_m, 0.0162);
  EXPECT_TRUE(first.escalation.ran);
  EXPECT_EQ(first.escalation.demoted, "pitch_damping");
  EXPECT_EQ(first.escalation.first_best, "added_mass");
  EXPECT_NEAR(first.escalation.shrink_against_first, 1 - 1.58 / 1.62, 1e-12);
  EXPECT_EQ(first.summary, fell + "The gap stays.");
  EXPECT_EQ(first.summary.find("--escalate"), std::string::npos);
  EXPECT_EQ(first.seconds, 1305);
  EXPECT_EQ(first.timings.at("first_search_s").get<double>(), 400);
  EXPECT_EQ(first.timings.at("second_search_s").get<double>(), 900);
  EXPECT_EQ(first.timings.at("total_s").get<double>(), 1305);
  EXPECT_EQ(first.timings.at("folds_s").get<double>(), 300);  // the first search's own stay
  EXPECT_THROW(first_result_stands(first, second, "", 400, 1305), std::logic_error);
}

// The second search (DiagnoseOptions::escalate): flights made with the
// finite-span correction at strength 1; with no candidate refitted from its
// linearised step and no steps carried into the folds, the first search
// keeps finite span at strength 0 in every fit (the centre values absorb it
// to first order) and leaves the gap unexplained. Searched again with the
// correction also started at its theoretical size, finite span is named,
// fitted near the strength that made the flights. The progress says so,
// and the last report ("done") comes once, at the very end. Without the
// second search the summary points to it.
TEST(Diagnose, AnUnexplainedGapIsSearchedAgainFromTheoreticalSizes) {
  EffectValues truth;
  truth.finite_span = 1.0;
  const Dataset d = corrected_flights(truth, 0.002, 5);
  DiagnoseOptions o = unstepped(profiled_diagnosis({Effect::FiniteSpan, Effect::Wind}));
  {
    // without the second search: the gap stays unexplained, and the
    // summary says what could still find it
    const DiagnoseResult r1 = diagnose(d, o, {});
    EXPECT_EQ(r1.verdict, "unexplained") << r1.summary;
    EXPECT_FALSE(r1.escalation.ran);
    EXPECT_NE(r1.summary.find("--escalate"), std::string::npos) << r1.summary;
  }
  o.escalate = true;
  std::vector<DiagnoseProgress> lines;
  const DiagnoseResult r = diagnose(d, o, [&](const DiagnoseProgress& p) { lines.push_back(p); });
  ASSERT_TRUE(r.escalation.ran) << r.verdict << ": " << r.summary;
  EXPECT_EQ(r.escalation.first_verdict, "unexplained");
  EXPECT_EQ(r.verdict, "finite_span") << r.summary;
  ASSERT_FALSE(lines.empty());
  int done = 0, second = 0;
  for (const auto& p : lines) {
    done += p.stage == "done" ? 1 : 0;
    second += p.message.rfind("second search: ", 0) == 0 ? 1 : 0;
  }
  EXPECT_EQ(done, 1);
  EXPECT_EQ(lines.back().stage, "done");
  // the final report carries the concluded summary (with its "Searched
  // from the baseline..." opening), timed over both searches
  EXPECT_EQ(lines.back().message, r.verdict + ": " + r.summary);
  EXPECT_GE(lines.back().elapsed_s, r.timings.at("first_search_s").get<double>());
  EXPECT_GE(second, 4);
  EXPECT_NE(r.summary.find("theoretical sizes"), std::string::npos) << r.summary;
  for (const auto& e : r.effects)
    if (e.effect == Effect::FiniteSpan) {
      std::cout << "finite span: shrink " << e.shrink << ", strength " << e.parameters.at(0) << std::endl;
      EXPECT_NEAR(e.parameters.at(0), 1.0, 0.15);
    }
}

// A theoretical-size start far from the flights ends its ramp early: on
// flights of the baseline model (no correction, 2 mm noise) pitch damping
// switched on misfits more than four times the baseline's squared error
// before strength 1, so the ramp stops there and no centre-value refit
// starts from it; the verdict stays `none`.
TEST(Diagnose, ATheoreticalSizeStartFarFromTheFlightsEndsItsRampEarly) {
  const Dataset d = corrected_flights(EffectValues{}, 0.002, 5);
  DiagnoseOptions o = profiled_diagnosis({Effect::PitchDamping, Effect::Wind});
  o.theory_starts = true;
  std::vector<std::string> lines;
  const DiagnoseResult r = diagnose(d, o, [&](const DiagnoseProgress& p) { lines.push_back(p.message); });
  EXPECT_EQ(r.verdict, "none") << r.summary;
  EXPECT_GE(lines_with(lines, "pitch_damping switched on: at "), 4);
  for (const auto& l : lines) {
    if (l.find("pitch_damping switched on: at ") == std::string::npos) continue;
    EXPECT_NE(l.find("of its theoretical size already RMSE"), std::string::npos) << l;
    EXPECT_EQ(l.find("at 4/4"), std::string::npos) << l;  // ended before full size
  }
  EXPECT_EQ(lines_with(lines, "pitch_damping from its theoretical size with the centre values"), 0);
}

// Stability checks (check_stability): the re-runs' steps go 5 % finer, 5 %
// coarser, then 10 % either way, ..., the first run's step first; 2 to 7
// runs in all, anything else refused.
TEST(Diagnose, StabilityChecksStepFivePercentEitherWayInTurn) {
  const auto f3 = stability_factors(3);
  ASSERT_EQ(f3.size(), 3u);
  EXPECT_DOUBLE_EQ(f3[0], 1.0);
  EXPECT_DOUBLE_EQ(f3[1], 0.95);
  EXPECT_DOUBLE_EQ(f3[2], 1.05);
  const auto f7 = stability_factors(7);
  const std::vector<double> want{1.0, 0.95, 1.05, 0.90, 1.10, 0.85, 1.15};
  ASSERT_EQ(f7.size(), want.size());
  for (std::size_t i = 0; i < want.size(); ++i) EXPECT_NEAR(f7[i], want[i], 1e-15) << i;
  EXPECT_EQ(stability_factors(2).size(), 2u);
  EXPECT_THROW(stability_factors(1), InputError);
  EXPECT_THROW(stability_factors(8), InputError);
  EXPECT_THROW(stability_factors(0), InputError);
}

// A stability re-run of a result that came from a second search makes both
// searches again, so its verdict meets the test against its own first
// search's baseline; any other result is re-run with its own options, only
// the step changed.
TEST(Diagnose, AStabilityReRunOfASecondSearchsResultSearchesTwiceAgain) {
  DiagnoseOptions o;
  o.sim.dt = 0.002;
  DiagnoseResult plain;
  plain.verdict = "camera";
  const DiagnoseOptions a = stability_rerun_options(o, plain, 0.95);
  EXPECT_DOUBLE_EQ(a.sim.dt, 0.0019);
  EXPECT_FALSE(a.escalate);
  EXPECT_FALSE(a.theory_starts);
  // the FreeCAD command's second search: theory_starts with a first result
  DiagnoseOptions t = o;
  t.theory_starts = true;
  DiagnoseResult second = plain;
  second.escalation.ran = true;
  const DiagnoseOptions b = stability_rerun_options(t, second, 1.05);
  EXPECT_DOUBLE_EQ(b.sim.dt, 0.0021);
  EXPECT_TRUE(b.escalate);
  EXPECT_FALSE(b.theory_starts);
  // theory_starts alone (no first search recorded) stays as it was asked
  const DiagnoseOptions c = stability_rerun_options(t, plain, 1.05);
  EXPECT_TRUE(c.theory_starts);
  EXPECT_FALSE(c.escalate);
  // --escalate: unchanged but for the step
  DiagnoseOptions e = o;
  e.escalate = true;
  const DiagnoseOptions d = stability_rerun_options(e, second, 0.9);
  EXPECT_TRUE(d.escalate);
  EXPECT_FALSE(d.theory_starts);
  EXPECT_DOUBLE_EQ(d.sim.dt, 0.0018);
  EXPECT_THROW(stability_rerun_options(o, plain, 0.0), InputError);
  EXPECT_THROW(stability_rerun_options(o, plain, std::nan("")), InputError);
}

// A second search after a first result compares the two results' `options`
// key by key, so every option that shapes the baseline must be there: the
// element spacing, the solver's iterations and the start model (a model that
// differs in one centre value by 0.001, or a flat-plate prior with another
// stall angle, gives another fingerprint; the same model gives the same).
TEST(Diagnose, OptionsRecordTheSpacingIterationsAndStartModel) {
  const DiagnoseOptions a;
  const nlohmann::json ja = diagnosis_options_json(a);
  EXPECT_EQ(ja, diagnosis_options_json(a));
  EXPECT_EQ(ja["dz_m"], a.sim.aero.dz);
  EXPECT_EQ(ja["iterations"], a.sim.max_iterations);
  EXPECT_EQ(ja["model"]["type"], "flat_plate");
  EXPECT_TRUE(std::regex_match(ja["model"]["fingerprint"].get<std::string>(), std::regex("[0-9a-f]{16}")));

  DiagnoseOptions b = a;
  b.sim.aero.dz = 0.01;
  EXPECT_EQ(diagnosis_options_json(b)["dz_m"], 0.01);
  b = a;
  b.sim.max_iterations = 9;
  EXPECT_EQ(diagnosis_options_json(b)["iterations"], 9);
  b = a;
  b.fit.prior.stall_deg = 11.0;
  EXPECT_NE(diagnosis_options_json(b)["model"], ja["model"]);

  const nlohmann::json fitted = nlohmann::json::parse(read_file(test::source_path("engine/models/fitted.model.json")));
  DiagnoseOptions c = a;
  c.start = std::dynamic_pointer_cast<const RbfModel>(model_from_json(fitted));
  ASSERT_TRUE(c.start);
  const nlohmann::json jc = diagnosis_options_json(c);
  EXPECT_EQ(jc["model"]["type"], "rbf");
  EXPECT_NE(jc["model"]["fingerprint"], ja["model"]["fingerprint"]);
  DiagnoseOptions same = a;
  same.start = std::dynamic_pointer_cast<const RbfModel>(model_from_json(fitted));
  EXPECT_EQ(diagnosis_options_json(same)["model"], jc["model"]);
  nlohmann::json nudged = fitted;
  ASSERT_FALSE(nudged["centres"].empty());
  nudged["centres"][0]["cl"] = nudged["centres"][0]["cl"].get<double>() + 1e-3;
  DiagnoseOptions d = a;
  d.start = std::dynamic_pointer_cast<const RbfModel>(model_from_json(nudged));
  ASSERT_TRUE(d.start);
  EXPECT_NE(diagnosis_options_json(d)["model"]["fingerprint"], jc["model"]["fingerprint"]);
}

// Each candidate once: the command's --effects and diagnose() share the
// check, which names the repeated effect after the caller's prefix.
TEST(Diagnose, ACandidateNamedTwiceIsRefused) {
  EXPECT_NO_THROW(check_candidate_effects({Effect::Wind, Effect::Camera}));
  EXPECT_NO_THROW(check_candidate_effects({}));
  try {
    check_candidate_effects({Effect::Wind, Effect::Camera, Effect::Wind}, "--effects: ");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "--effects: candidate effect 'wind' is listed twice");
  }
  DiagnoseOptions o;
  o.effects = {Effect::Camera, Effect::Camera};
  try {
    diagnose(Dataset{}, o);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "candidate effect 'camera' is listed twice");
  }
}
