// Tests of src/fit_data.cpp: synthetic datasets and held-out predictions.
#include <cmath>
#include <cstdlib>
#include <unistd.h>

#include <gtest/gtest.h>

#include "pteromys/fit.hpp"
#include "pteromys/io.hpp"
#include "test_support.hpp"

using namespace pteromys;

namespace {

std::map<std::string, Glider> two_gliders() {
  std::map<std::string, Glider> g;
  g["a"] = load_glider(test::source_path("examples/training/t01-rectangular.glider.json"));
  g["b"] = load_glider(test::source_path("examples/training/t08-swept-45.glider.json"));
  return g;
}

}  // namespace

TEST(SyntheticDataset, FlightsLookLikeTheSpecsTrackingAndCarryTheirTruth) {
  SyntheticOptions o;
  o.flights_per_glider = 6;
  o.noise_m = 0.05;
  o.seed = 12;
  const Dataset d = synthetic_dataset(two_gliders(), std::make_shared<FlatPlateModel>(), o);
  ASSERT_EQ(d.flights.size(), 12u);
  EXPECT_TRUE(dataset_problems(d).empty());
  EXPECT_DOUBLE_EQ(d.tracking_sigma_m, 0.05);
  for (const auto& f : d.flights) {
    EXPECT_GE(f.points.size(), 15u);
    EXPECT_LE(f.points.size(), 20u);
    for (std::size_t i = 1; i < f.points.size(); ++i) EXPECT_NEAR(f.points[i].t - f.points[i - 1].t, 1 / 30.0, 1e-9);
    const double v = std::stod(f.extra.at("release_speed_m_s"));
    EXPECT_GE(v, 5.0);
    EXPECT_LE(v, 9.0);
    EXPECT_LE(std::stod(f.extra.at("release_t_s")), f.points[0].t);
  }
}

TEST(SyntheticDataset, NoiseHasTheRequestedStandardDeviation) {
  // The same seed draws the same launches and noise samples; with noise 0
  // the points are exact, so the difference is the noise itself. Its sample
  // standard deviation over ~700 values must be within 10 % of 5 cm
  // (the standard error of a standard deviation is sigma / sqrt(2n) ~ 2.7 %).
  SyntheticOptions o;
  o.flights_per_glider = 10;
  o.seed = 3;
  o.noise_m = 0.05;
  const Dataset noisy = synthetic_dataset(two_gliders(), std::make_shared<FlatPlateModel>(), o);
  o.noise_m = 0.0;
  const Dataset clean = synthetic_dataset(two_gliders(), std::make_shared<FlatPlateModel>(), o);
  ASSERT_EQ(noisy.flights.size(), clean.flights.size());
  double s = 0, s2 = 0;
  int n = 0;
  for (std::size_t i = 0; i < noisy.flights.size(); ++i) {
    ASSERT_EQ(noisy.flights[i].points.size(), clean.flights[i].points.size());
    for (std::size_t j = 0; j < noisy.flights[i].points.size(); ++j)
      for (double e : {noisy.flights[i].points[j].x - clean.flights[i].points[j].x,
                       noisy.flights[i].points[j].y - clean.flights[i].points[j].y}) {
        s += e;
        s2 += e * e;
        ++n;
      }
  }
  const double mean = s / n, sd = std::sqrt(s2 / n - mean * mean);
  EXPECT_GT(n, 500);
  EXPECT_NEAR(sd, 0.05, 0.005);
  EXPECT_NEAR(mean, 0.0, 4 * 0.05 / std::sqrt(n));
}

TEST(SyntheticDataset, SavesAndLoadsBackThroughTheDatasetFiles) {
  SyntheticOptions o;
  o.flights_per_glider = 2;
  const Dataset d = synthetic_dataset(two_gliders(), std::make_shared<FlatPlateModel>(), o);
  char tmpl[] = "/tmp/pteromys-fit-XXXXXX";
  const std::string dir = mkdtemp(tmpl);
  save_dataset(d, dir);
  const Dataset back = load_dataset(dir + "/dataset.json");
  ASSERT_EQ(back.flights.size(), d.flights.size());
  EXPECT_EQ(back.flights[0].extra.at("release_speed_m_s"), d.flights[0].extra.at("release_speed_m_s"));
  EXPECT_NEAR(back.flights[1].points[3].y, d.flights[1].points[3].y, 1e-6);  // CSV keeps micrometres
  std::system(("rm -rf " + dir).c_str());
}

TEST(PredictFlights, TheTrueModelPredictsItsOwnFlightsAndBallisticMotionDoesNot) {
  // Noise-free flights of the flat-plate element tracked from the release
  // (no delay), launches fitted to the first 10 points: the same model
  // predicts the remaining points to solver precision; ballistic motion (no
  // lift) misses them by decimetres.
  SyntheticOptions o;
  o.flights_per_glider = 3;
  o.noise_m = 0.0;
  o.delay_max_s = 0.0;
  const auto model = std::make_shared<FlatPlateModel>();
  const Dataset d = synthetic_dataset(two_gliders(), model, o);
  FitOptions fo;
  fo.launch.points = 10;
  const auto same = predict_flights(d, model, fo);
  const auto ballistic = predict_flights(d, nullptr, fo);
  ASSERT_EQ(same.size(), d.flights.size());
  for (const auto& p : same) {
    EXPECT_EQ(p.launch_points, 10);
    EXPECT_LT(p.rmse_m, 1e-4) << p.flight;
    EXPECT_GT(p.rmse_after_m, 0.0);
  }
  EXPECT_GT(predictions_rmse(ballistic, true), 0.1);
  EXPECT_GT(predictions_rmse(ballistic, true), predictions_rmse(ballistic));  // errors grow after the fitted part
}

TEST(PredictFlights, TrackingThatStartsAfterReleaseNeedsThePitchRate) {
  // Tracking starts up to 0.1 s after release: at the first tracked point the
  // glider already turns, which a launch with zero pitch rate (the paper's
  // sigma) cannot express; fitting the pitch rate too recovers the flights.
  SyntheticOptions o;
  o.flights_per_glider = 3;
  o.noise_m = 0.0;
  o.delay_max_s = 0.1;
  const auto model = std::make_shared<FlatPlateModel>();
  const Dataset d = synthetic_dataset(two_gliders(), model, o);
  FitOptions fo;
  fo.launch.points = 0;
  const double without = predictions_rmse(predict_flights(d, model, fo));
  fo.launch.fit_pitch_rate = true;
  const double with = predictions_rmse(predict_flights(d, model, fo));
  EXPECT_LT(with, 1e-4);
  EXPECT_GT(without, 10 * with);
}
