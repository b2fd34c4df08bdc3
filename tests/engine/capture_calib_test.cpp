// Camera calibration (src/capture_calib.cpp, src/capture_io.cpp). The truth is
// a synthetic pinhole camera (capture_render.hpp) whose projection is the
// plain pinhole formula with OpenCV's distortion polynomial, independent of
// the homography fit under test.
#include "pteromys/capture.hpp"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "pteromys/capture_render.hpp"
#include "pteromys/io.hpp"

using namespace pteromys;
using namespace pteromys::capture;

namespace {

SyntheticCamera camera(double k1 = 0.0, double k2 = 0.0, double distance = 4.0) {
  SyntheticCamera c;
  c.k1 = k1;
  c.k2 = k2;
  c.position = {2.0, 1.2, distance};
  c.tilt_deg = 4.0;
  c.yaw_deg = -3.0;
  c.roll_deg = 1.5;
  return c;
}

// Largest distance in the plane between the calibration's and the truth's
// world point over a 21 x 13 grid of pixels covering the image.
double max_world_error(const Calibration& fit, const Calibration& truth, double margin = 0.03) {
  double e = 0;
  for (int j = 0; j <= 12; ++j)
    for (int i = 0; i <= 20; ++i) {
      const Vec2 px{truth.width * (margin + (1 - 2 * margin) * i / 20.0), truth.height * (margin + (1 - 2 * margin) * j / 12.0)};
      const Vec2 a = image_to_world(fit, px), b = image_to_world(truth, px);
      e = std::max(e, std::hypot(a.x - b.x, a.y - b.y));
    }
  return e;
}

std::string error_of(const CalibrationInput& in) {
  try {
    calibrate(in);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(CaptureLens, DistortAndUndistortAreInverseOverTheImage) {
  const Calibration cam = synthetic_calibration(camera(-0.12, 0.03));
  Lens lens = cam.lens;
  lens.dist[2] = 0.001;  // tangential terms too
  lens.dist[3] = -0.0015;
  double worst = 0;
  for (int j = 0; j <= 20; ++j)
    for (int i = 0; i <= 30; ++i) {
      const Vec2 d{cam.width * i / 30.0, cam.height * j / 20.0};
      const Vec2 u = undistort(lens, d);
      const Vec2 back = distort(lens, u);
      worst = std::max(worst, std::hypot(back.x - d.x, back.y - d.y));
    }
  EXPECT_LT(worst, 1e-8);  // Newton to 1e-14 in normalised units
}

TEST(CaptureCalib, FourExactPointsGiveTheExactPlaneMapping) {
  // Reference: the synthetic pinhole without distortion; a homography is exact for it.
  const Calibration truth = synthetic_calibration(camera());
  CalibrationInput in = synthetic_reference_points(truth, 2, 2, 0.0, 1, 0.0);
  in.distortion = "none";
  const Calibration c = calibrate(in);
  EXPECT_EQ(c.distortion_model, "none");
  EXPECT_LT(max_world_error(c, truth), 1e-6);
  EXPECT_LT(c.rms_px, 1e-6);
  EXPECT_LT(c.loo_rms_m, 0);  // not available with 4 points
  ASSERT_FALSE(c.warnings.empty());
  EXPECT_NE(c.warnings.front().find("exact"), std::string::npos);
}

TEST(CaptureCalib, RadialDistortionIsRecoveredFromTwelvePoints) {
  // True lens: k1 = -0.10, k2 = 0.02 on (p - c) / f, principal point 5 px
  // right and 3 px above the centre (the fit assumes the centre). Without
  // distortion the plane mapping is off by centimetres at the corners.
  const Calibration truth = synthetic_calibration(camera(-0.10, 0.02));
  CalibrationInput in = synthetic_reference_points(truth, 4, 3, 0.0, 1, 0.0);
  in.distortion = "none";
  const double err_none = max_world_error(calibrate(in), truth);
  in.distortion = "auto";
  const Calibration c = calibrate(in);
  EXPECT_NE(c.distortion_model, "none");
  const double err = max_world_error(c, truth, 0.08);  // inside the points' hull
  EXPECT_GT(err_none, 0.02);
  // 1 mm at 4 m is 0.25 px; the fixed principal point (5 px off) costs a few tenths of a pixel
  EXPECT_LT(err, 0.0015) << "without distortion: " << err_none;
  EXPECT_GE(c.model_loo_m.size(), 2u);
}

TEST(CaptureCalib, ResidualsMatchTheClickingNoise) {
  // 20 points with Gaussian noise of 0.5 px per coordinate: the RMS distance
  // residual of a fit with p = 9 parameters is 0.5 * sqrt(2) * sqrt(1 - p / 2n)
  // = 0.63 px; allow the sampling spread of 40 residuals (+-25 %).
  const Calibration truth = synthetic_calibration(camera(-0.10, 0.02));
  CalibrationInput in = synthetic_reference_points(truth, 5, 4, 0.5, 7, 0.0);
  in.distortion = "k1";
  const Calibration c = calibrate(in);
  EXPECT_NEAR(c.rms_px, 0.63, 0.16);
  // metres: about rms_px times the scale (4 m / 985 px = 4.1 mm/px)
  EXPECT_NEAR(c.rms_m / c.rms_px, 4.0 / 985.5, 0.6e-3);
  EXPECT_GT(c.loo_rms_m, c.rms_m);  // left-out points are predicted less well than fitted ones
  EXPECT_LT(c.loo_rms_m, 0.006);
  ASSERT_EQ(c.residuals.size(), 20u);
  for (const auto& r : c.residuals) EXPECT_GE(r.loo_m, 0.0);
}

TEST(CaptureCalib, CameraPoseFollowsFromTheMeasuredDistance) {
  const Calibration truth = synthetic_calibration(camera(-0.10, 0.02, 5.0));
  CalibrationInput in = synthetic_reference_points(truth, 4, 3, 0.2, 3, 0.001, 5.0);
  const Calibration c = calibrate(in);
  ASSERT_TRUE(c.pose.known);
  EXPECT_NEAR(c.pose.distance_m, 5.0, 1e-6);  // imposed
  // the true centre (2, 1.2, 5); the focal length 985.5 px (66 deg over 1280 px)
  EXPECT_NEAR(c.pose.centre.x, 2.0, 0.05);
  EXPECT_NEAR(c.pose.centre.y, 1.2, 0.05);
  EXPECT_NEAR(c.pose.focal_px, 985.5, 985.5 * 0.02);
  // a point off the plane (a wing tip 0.2 m toward the camera) lands where the truth sees it, within 1 px
  const Point3 p{2.3, 1.0, 0.2};
  const Vec2 a = project_point(c, p), b = project_point(truth, p);
  EXPECT_LT(std::hypot(a.x - b.x, a.y - b.y), 1.0);
}

TEST(CaptureCalib, FileRoundTripKeepsTheMapping) {
  const Calibration truth = synthetic_calibration(camera(-0.10, 0.02));
  CalibrationInput in = synthetic_reference_points(truth, 4, 3, 0.3, 5, 0.001, 4.0);
  const Calibration c = calibrate(in);
  const Calibration r = calibration_from_json(parse_json(calibration_to_json(c).dump(), "test"), "test");
  EXPECT_LT(max_world_error(c, r), 1e-9);
  EXPECT_EQ(r.distortion_model, c.distortion_model);
  EXPECT_TRUE(r.pose.known);
  EXPECT_NEAR(r.loo_rms_m, c.loo_rms_m, 1e-12);
  const CalibrationInput back = calibration_input_from_json(calibration_input_to_json(in), "test");
  ASSERT_EQ(back.points.size(), in.points.size());
  EXPECT_EQ(back.points[3].name, in.points[3].name);
  EXPECT_DOUBLE_EQ(back.points[3].image.x, in.points[3].image.x);
}

TEST(CaptureCalib, RefusesTooFewOrDegeneratePointsWithAClearMessage) {
  const Calibration truth = synthetic_calibration(camera());
  const CalibrationInput good = synthetic_reference_points(truth, 3, 3, 0.0, 1, 0.0);
  ASSERT_EQ(error_of(good), "");

  CalibrationInput in = good;
  in.points.resize(3);
  EXPECT_NE(error_of(in).find("at least 4 reference points"), std::string::npos) << error_of(in);

  in = good;  // all on one line (the middle row)
  in.points = {good.points[3], good.points[4], good.points[5], good.points[4]};
  in.points[3].world.x += 0.5;
  in.points[3].image = world_to_image(truth, in.points[3].world);
  EXPECT_NE(error_of(in).find("one line"), std::string::npos) << error_of(in);

  in = good;  // four points, three of them aligned
  in.points = {good.points[0], good.points[1], good.points[2], good.points[7]};
  EXPECT_NE(error_of(in).find("lie (nearly) on one line"), std::string::npos) << error_of(in);

  in = good;
  in.points[2].world.y = std::nan("");
  EXPECT_NE(error_of(in).find("not a finite number"), std::string::npos) << error_of(in);

  in = good;
  in.points[4].world = in.points[1].world;
  EXPECT_NE(error_of(in).find("same world position"), std::string::npos) << error_of(in);

  in = good;
  in.points[0].image.x = -40;
  EXPECT_NE(error_of(in).find("outside"), std::string::npos) << error_of(in);

  in = good;
  in.points.resize(5);
  in.distortion = "k1";
  EXPECT_NE(error_of(in).find("needs at least 6"), std::string::npos) << error_of(in);

  in = good;  // two points' world coordinates swapped: no camera explains them
  std::swap(in.points[0].world, in.points[8].world);
  EXPECT_NE(error_of(in).find("not consistent"), std::string::npos) << error_of(in);
}

TEST(CaptureCalib, RefusesDistortionThePointsCannotConstrain) {
  // 9 points bunched in the middle tenth of the image say nothing about the corners.
  const Calibration truth = synthetic_calibration(camera(-0.10, 0.02));
  CalibrationInput in;
  in.width = truth.width;
  in.height = truth.height;
  std::mt19937 gen(2);
  std::normal_distribution<double> n(0.0, 0.5);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      const Vec2 px{truth.width * (0.46 + 0.04 * i), truth.height * (0.46 + 0.04 * j)};
      const Vec2 w = image_to_world(truth, px);
      in.points.push_back({"p" + std::to_string(3 * j + i), w, {px.x + n(gen), px.y + n(gen)}});
    }
  in.distortion = "k1k2";
  const std::string e = error_of(in);
  EXPECT_NE(e.find("do not constrain lens distortion"), std::string::npos) << e;
  in.distortion = "auto";
  const Calibration c = calibrate(in);
  EXPECT_EQ(c.distortion_model, "none");
}

TEST(CaptureCalib, PointsFileErrorsNameTheProblem) {
  auto err = [](const std::string& text) {
    try {
      calibration_input_from_json(parse_json(text, "f"), "f");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(err(R"({"format": "x"})").find("unknown format"), std::string::npos);
  EXPECT_NE(err(R"({"format": "pteromys-calib-points/1", "points": []})").find("image_size_px"), std::string::npos);
  EXPECT_NE(err(R"({"format": "pteromys-calib-points/1", "image_size_px": [1280, 720],
                    "points": [{"world_m": [0, 1], "image_px": [3]}]})")
                .find("points[0].image_px"),
            std::string::npos);
  EXPECT_NE(err(R"({"format": "pteromys-calib-points/1", "image_size_px": [1280, 720], "distortion": "k3", "points": []})")
                .find("distortion"),
            std::string::npos);
  try {
    parse_json(R"({"format": "pteromys-calib-points/1", "x": NaN})", "points file");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("NaN"), std::string::npos);
  }
}
