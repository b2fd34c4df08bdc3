// Tests of src/fit.cpp: coefficient fit (eq. 6), interleaving with the launch
// fits, greedy centre insertion, stopping rule; and of the report.
//
// The reference ("truth") throughout is a known RBF model: flights are
// simulated with it (random hand launches, optional Gaussian noise), and the
// fit must recover the flights. The yardstick for noisy data is independent
// of the fitter: the truth model itself with launches fitted to the same
// points (predict_flights), i.e. the best any model can do on that noise.
#include <cmath>

#include <gtest/gtest.h>

#include "pteromys/fit.hpp"
#include "pteromys/io.hpp"
#include "test_support.hpp"

using namespace pteromys;

namespace {

std::map<std::string, Glider> gliders(std::initializer_list<const char*> names) {
  std::map<std::string, Glider> out;
  for (const char* n : names) out[n] = load_glider(test::source_path(std::string("examples/training/") + n + ".glider.json"));
  return out;
}

RbfCentre centre(double alpha_deg, double re, double xl_deg, double xt_deg) {
  RbfCentre c;
  c.alpha = deg2rad(alpha_deg);
  c.re = re;
  c.xi_l = deg2rad(xl_deg);
  c.xi_t = deg2rad(xt_deg);
  return c;
}

/// The known model: flat-plate prior plus two centres whose values depart
/// from it (more lift and drag on unswept elements, less lift on swept ones).
std::shared_ptr<RbfModel> truth_model(bool at_prior_values = false) {
  auto prior = std::make_shared<FlatPlateModel>();
  std::vector<RbfCentre> cs = {centre(4, 2.0e4, 0, 0), centre(4, 1.5e4, 30, 15)};
  for (auto& c : cs) c.value = prior->eval({c.alpha, c.re, c.xi_l, c.xi_t});
  if (!at_prior_values) {
    cs[0].value.cl *= 1.4;
    cs[0].value.cd += 0.03;
    cs[0].value.cm -= 0.01;
    cs[1].value.cl *= 0.75;
    cs[1].value.cd += 0.02;
  }
  return std::make_shared<RbfModel>(cs, RbfScales{}, deg2rad(40), prior);
}

SyntheticOptions synth(double noise, int per_glider, unsigned seed) {
  SyntheticOptions o;
  o.noise_m = noise;
  o.flights_per_glider = per_glider;
  o.seed = seed;
  return o;
}

FitOptions quick(int centres) {
  FitOptions o;
  o.max_centres = centres;
  o.threads = 2;
  return o;
}

}  // namespace

TEST(FitCoefficients, RecoversTheValuesOfAKnownModelFromExactFlights) {
  // Exact flights (no noise, tracked from the release) of the truth; the
  // centres of the truth are given and their values start at the prior's.
  // Without the pull toward the prior the least-squares optimum is the truth
  // itself: flights to 1e-6 m and every value to 1e-5 (solver tolerance).
  const auto g = gliders({"t01-rectangular", "t07-swept-30", "t10-forward-swept-30", "t11-delta"});
  const auto truth = truth_model();
  SyntheticOptions so = synth(0.0, 4, 11);
  so.delay_max_s = 0.0;
  const Dataset d = synthetic_dataset(g, truth, so);
  FitOptions o = quick(2);
  o.start = truth_model(true);
  o.regularisation_m = 0.0;
  const FitResult r = fit_coefficients(d, o);
  EXPECT_GT(r.prior_rmse_m, 0.01) << "the truth must differ visibly from the prior for this test to mean anything";
  EXPECT_LT(r.rmse_m, 1e-6);
  ASSERT_EQ(r.model->centres().size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    const Coefficients& f = r.model->centres()[k].value;
    const Coefficients& t = truth->centres()[k].value;
    EXPECT_NEAR(f.cd, t.cd, 1e-5) << k;
    EXPECT_NEAR(f.cl, t.cl, 1e-5) << k;
    EXPECT_NEAR(f.cm, t.cm, 1e-5) << k;
  }

  // Generalisation within the training gliders: new launches, not in the
  // dataset, flown with the fitted and the true model agree.
  const Dataset fresh = synthetic_dataset(g, truth, synth(0.0, 3, 99));
  FitOptions po;
  po.launch.points = 10;
  const auto pf = predict_flights(fresh, r.model, po);
  const auto pt = predict_flights(fresh, truth, po);
  for (std::size_t i = 0; i < pf.size(); ++i) EXPECT_NEAR(pf[i].rmse_m, pt[i].rmse_m, 1e-5) << pf[i].flight;
}

TEST(FitCoefficients, GreedyFitOfExactFlightsComesWithinMillimetres) {
  // The same truth, but the fit knows nothing of its centres: greedy
  // insertion from one centre at the mean element, default regularisation,
  // tracking that starts up to 50 ms after release (a small launch-model
  // mismatch: the truth model itself then scores ~0.7 mm). The prior misses
  // by centimetres; the fit must come within 3 mm.
  const auto g = gliders({"t01-rectangular", "t07-swept-30", "t10-forward-swept-30", "t11-delta"});
  const Dataset d = synthetic_dataset(g, truth_model(), synth(0.0, 4, 11));
  const FitResult r = fit_coefficients(d, quick(4));
  EXPECT_GT(r.prior_rmse_m, 0.01);
  EXPECT_LT(r.rmse_m, 0.003);
}

TEST(FitCoefficients, NoisyFlightsAreFittedDownToTheNoise) {
  // 1 cm tracking noise (the truth's departure from the prior is about
  // 1.5 cm, so the prior is visibly worse). Yardstick: the truth model with
  // launches fitted to all points of the same flights (predict_flights,
  // M = all). The greedy fit from a single centre must come within 5 % of
  // it, while the prior stays clearly above it.
  const auto g = gliders({"t01-rectangular", "t07-swept-30", "t10-forward-swept-30", "t11-delta"});
  const auto truth = truth_model();
  const Dataset d = synthetic_dataset(g, truth, synth(0.01, 5, 5));
  FitOptions po;
  po.launch.points = 0;
  const double oracle = predictions_rmse(predict_flights(d, truth, po));
  const FitResult r = fit_coefficients(d, quick(4));
  EXPECT_GT(r.prior_rmse_m, 1.2 * oracle);
  EXPECT_LT(r.rmse_m, 1.05 * oracle);
  EXPECT_GT(r.rmse_m, 0.8 * oracle) << "fitting far below the noise would mean overfitting";
  EXPECT_EQ(r.points, [&] {
    int n = 0;
    for (const auto& f : d.flights) n += static_cast<int>(f.points.size());
    return n;
  }());
}

TEST(FitCoefficients, GreedyInsertionLowersTheErrorStageByStage) {
  const auto g = gliders({"t01-rectangular", "t07-swept-30", "t10-forward-swept-30", "t11-delta"});
  const Dataset d = synthetic_dataset(g, truth_model(), synth(0.0, 4, 3));
  FitOptions o = quick(3);
  o.information_criterion = false;  // keep every centre that does not raise the error
  const FitResult r = fit_coefficients(d, o);
  ASSERT_GE(r.history.size(), 2u);
  EXPECT_EQ(r.history.front().centres, 0);
  EXPECT_DOUBLE_EQ(r.history.front().rmse_m, r.prior_rmse_m);
  double prev = r.history.front().rmse_m;
  for (std::size_t i = 1; i < r.history.size(); ++i) {
    if (!r.history[i].accepted) continue;
    EXPECT_LE(r.history[i].rmse_m, prev * (1 + 1e-9)) << "stage " << i;
    EXPECT_TRUE(r.history[i].has_added);
    prev = r.history[i].rmse_m;
  }
  EXPECT_LT(r.rmse_m, 0.5 * r.prior_rmse_m);
  EXPECT_EQ(r.model->centres().size(), static_cast<std::size_t>(r.history.back().accepted ? r.history.back().centres
                                                                                          : r.history.back().centres - 1));
}

TEST(FitCoefficients, StopsWhenTheErrorStopsFallingAndKeepsThePrior) {
  // Flights of the flat-plate element itself with 3 cm noise: the prior is
  // already right, so a centre can only fit noise (about 3 sigma^2 of squared
  // error for three values, far below the information criterion's
  // 3 ln(n) sigma^2) and the fit stops with the prior's coefficients.
  const auto g = gliders({"t01-rectangular", "t07-swept-30", "t11-delta"});
  const auto prior = std::make_shared<FlatPlateModel>();
  const Dataset d = synthetic_dataset(g, prior, synth(0.03, 4, 8));
  const FitResult r = fit_coefficients(d, quick(10));
  EXPECT_LE(r.model->centres().size(), 2u);
  EXPECT_NE(r.stop_reason.find("stopped falling"), std::string::npos) << r.stop_reason;
  EXPECT_LE(r.rmse_m, r.prior_rmse_m * (1 + 1e-9));
  for (double a : {2.0, 5.0, 8.0}) {
    const ElementState e{deg2rad(a), 2e4, 0, 0};
    EXPECT_NEAR(r.model->eval(e).cl, prior->eval(e).cl, 0.02) << a;
    EXPECT_NEAR(r.model->eval(e).cd, prior->eval(e).cd, 0.005) << a;
  }
  // Every kept stage lowered the information criterion; the dropped one did not.
  double bic = r.history.front().bic;
  for (std::size_t i = 1; i < r.history.size(); ++i) {
    if (r.history[i].accepted) {
      EXPECT_LT(r.history[i].bic, bic);
      bic = r.history[i].bic;
    } else {
      EXPECT_GE(r.history[i].bic, bic);
    }
  }
}

TEST(FitCoefficients, InformationCriterionKeepsCentresThatExplainRealDepartures) {
  // The truth departs from the prior by about 1.5 cm; with 1 cm noise the
  // first centres lower the error far more than noise could, so the
  // criterion keeps at least two.
  const auto g = gliders({"t01-rectangular", "t07-swept-30", "t10-forward-swept-30", "t11-delta"});
  const Dataset d = synthetic_dataset(g, truth_model(), synth(0.01, 5, 5));
  const FitResult r = fit_coefficients(d, quick(4));
  EXPECT_GE(r.model->centres().size(), 2u) << r.stop_reason;
  EXPECT_TRUE(r.history[1].accepted);
}

TEST(FitCoefficients, FittedModelKeepsExactParity) {
  const auto g = gliders({"t01-rectangular", "t10-forward-swept-30"});
  const Dataset d = synthetic_dataset(g, truth_model(), synth(0.02, 3, 4));
  const FitResult r = fit_coefficients(d, quick(3));
  for (double a : {0.5, 3.0, 7.0, 15.0, 35.0})
    for (double re : {8e3, 2e4, 4e4}) {
      const Coefficients p = r.model->eval({deg2rad(a), re, 0.2, -0.1});
      const Coefficients n = r.model->eval({-deg2rad(a), re, 0.2, -0.1});
      EXPECT_EQ(p.cd, n.cd);
      EXPECT_EQ(p.cl, -n.cl);
      EXPECT_EQ(p.cm, -n.cm);
    }
}

TEST(FitCoefficients, PaperSchemeWithTenLaunchPointsAlsoRuns) {
  // The paper's M = 10: launches fitted to the first ten points only.
  const auto g = gliders({"t01-rectangular", "t07-swept-30"});
  const Dataset d = synthetic_dataset(g, truth_model(), synth(0.0, 3, 21));
  FitOptions o = quick(2);
  o.launch.points = 10;
  const FitResult r = fit_coefficients(d, o);
  EXPECT_LT(r.rmse_m, r.prior_rmse_m);
  for (const auto& f : r.flights) EXPECT_GE(f.points, 15);
}

TEST(FitCoefficients, RejectsDatasetsItCannotFit) {
  const auto g = gliders({"t01-rectangular"});
  Dataset d = synthetic_dataset(g, std::make_shared<FlatPlateModel>(), synth(0.0, 2, 1));
  Dataset empty = d;
  empty.flights.clear();
  EXPECT_THROW(fit_coefficients(empty), InputError);

  Dataset backwards = d;
  for (auto& p : backwards.flights[1].points) p.x = -p.x;
  try {
    fit_coefficients(backwards);
    FAIL() << "a flight moving along -x must be rejected";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(backwards.flights[1].name), std::string::npos) << e.what();
  }

  Dataset unknown = d;
  unknown.flights[0].glider = "nope";
  EXPECT_THROW(fit_coefficients(unknown), InputError);

  FitOptions bad;
  bad.max_centres = 0;
  EXPECT_THROW(fit_coefficients(d, bad), InputError);
  bad = FitOptions{};
  bad.launch.points = 2;
  EXPECT_THROW(fit_coefficients(d, bad), InputError);
}

TEST(FitReport, HasTheSpecKeysAndConsistentCounts) {
  const auto g = gliders({"t01-rectangular", "t07-swept-30"});
  const Dataset d = synthetic_dataset(g, truth_model(), synth(0.02, 3, 2));
  std::vector<FitProgress> seen;
  const FitOptions o = quick(2);
  const FitResult r = fit_coefficients(d, o, [&](const FitProgress& p) { seen.push_back(p); });
  const nlohmann::json j = fit_report_json(r, o);
  EXPECT_EQ(j.at("format"), "pteromys-fit/1");
  EXPECT_DOUBLE_EQ(j.at("fit_rmse_m").get<double>(), r.rmse_m);
  EXPECT_EQ(j.at("centres").get<int>(), static_cast<int>(r.model->centres().size()));
  EXPECT_EQ(j.at("flights").get<int>(), static_cast<int>(d.flights.size()));
  EXPECT_EQ(j.at("per_flight").size(), d.flights.size());
  EXPECT_EQ(j.at("history").size(), r.history.size());
  // fit_rmse_m is the RMS over all points of the per-flight errors.
  double s = 0;
  int n = 0;
  for (const auto& f : j.at("per_flight")) {
    s += std::pow(f.at("rmse_m").get<double>(), 2) * f.at("points").get<int>();
    n += f.at("points").get<int>();
  }
  EXPECT_NEAR(std::sqrt(s / n), r.rmse_m, 1e-12);
  // Progress: every solver iteration is reported, the last message is "done".
  ASSERT_FALSE(seen.empty());
  EXPECT_EQ(seen.back().stage, "done");
  int iterations = 0;
  for (const auto& p : seen) iterations += p.stage == "coefficients" ? 1 : 0;
  int expected = 0;
  for (const auto& h : r.history) expected += h.iterations;
  EXPECT_EQ(iterations, expected);
  // The model round-trips through its file format.
  const auto back = model_from_json(model_to_json(*r.model));
  const ElementState e{deg2rad(5), 2e4, 0.1, 0.0};
  EXPECT_NEAR(back->eval(e).cl, r.model->eval(e).cl, 1e-12);
}
