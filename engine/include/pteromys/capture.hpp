// Flight capture, part 1: the camera. Calibration of a side-view camera from
// reference points of known position in the flight plane (paper section 5.1),
// the image <-> flight-plane mapping, lens distortion, and the camera pose
// when the focal length or the camera distance is known (docs/capture.md).
//
// Frames and units
// - World frame of a flight (spec/formats.md): x horizontal along the flight,
//   y up, the flight plane is z = 0; +z points from the plane toward the
//   camera side that is in use (a right-handed frame). Metres.
// - Image: pixels, u to the right, v down, origin at the centre of the top-left
//   pixel (OpenCV's convention). "Distorted" pixels are where things appear in
//   the video; "undistorted" pixels are where an ideal pinhole camera with the
//   same principal point and scale would show them.
// - Lens model: OpenCV's (k1, k2, p1, p2, k3) acting on (p - c) / f with the
//   camera matrix [[fx, 0, cx], [0, fy, cy], [0, 0, 1]]. When the intrinsics
//   are not known, fx = fy = s is a normalising scale (half the image
//   diagonal: r = 1 at the corners) and not the focal length; only k1 (and k2)
//   are estimated and the principal point is the image centre.
// - Homography H (3 x 3, row-major): world (x, y, 1) -> undistorted pixel
//   (homogeneous), defined up to scale.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pteromys/types.hpp"

namespace pteromys::capture {

/// A point in space, world frame [m].
struct Point3 {
  double x = 0, y = 0, z = 0;
};

/// Row-major 3 x 3 matrix.
using Mat3 = std::array<double, 9>;

/// Lens of a camera: OpenCV camera matrix entries [px] and distortion
/// coefficients (k1, k2, p1, p2, k3) [dimensionless].
struct Lens {
  double fx = 1, fy = 1, cx = 0, cy = 0;
  std::array<double, 5> dist = {0, 0, 0, 0, 0};
  /// True when fx, fy are the real focal length (intrinsics given by the
  /// person); false when they are a normalising scale (see file comment).
  bool intrinsics_known = false;
};

/// Distorted pixel of an undistorted pixel (exact, closed form).
Vec2 distort(const Lens& lens, Vec2 undistorted_px);
/// Undistorted pixel of a distorted pixel (Newton iteration to 1e-10 px).
/// Throws InputError when the lens model cannot be inverted there (a pixel
/// far outside the range where the polynomial is monotonic).
Vec2 undistort(const Lens& lens, Vec2 distorted_px);

/// Camera pose: world -> camera x_c = R x_w + t (OpenCV camera axes: x right,
/// y down, z forward), with an ideal pinhole of focal length focal_px and
/// principal point (cx, cy) of the lens, in undistorted pixels.
struct Pose {
  bool known = false;
  double focal_px = 0;    ///< fx [px]
  double focal_y_px = 0;  ///< fy [px] (equal to focal_px unless the intrinsics say otherwise)
  Mat3 R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  std::array<double, 3> t = {0, 0, 0};  ///< [m]
  Point3 centre;                        ///< camera centre in the world [m]
  double distance_m = 0;                ///< perpendicular distance camera - flight plane [m]
  std::string source;                   ///< "focal_px", "distance_m" or "intrinsics"
};

/// One reference point: its known place in the flight plane and where it is
/// seen in the video (as clicked: distorted pixels).
struct CalibrationPoint {
  std::string name;
  Vec2 world;  ///< (x, y) in the flight plane [m]
  Vec2 image;  ///< (u, v) [px]
};

/// What `calibrate` is given (file format pteromys-calib-points/1, docs/capture.md).
struct CalibrationInput {
  int width = 0, height = 0;                 ///< image size [px]
  std::vector<CalibrationPoint> points;
  /// "auto" (choose by leave-one-out error among those the points allow),
  /// "none", "k1" (>= 6 points), "k1k2" (>= 8 points). Ignored when
  /// `lens.intrinsics_known` (the given distortion is used as it is).
  std::string distortion = "auto";
  Lens lens;                   ///< used when lens.intrinsics_known
  double focal_px = 0;         ///< optional: focal length [px] (pose from H)
  double distance_m = 0;       ///< optional: camera-to-flight-plane distance [m] (focal from H)
  double click_sigma_px = 0.5; ///< expected accuracy of the clicked image points [px]
  nlohmann::json extra;        ///< keys of the points file kept as they are (video, frame)
};

struct PointResidual {
  std::string name;
  double du_px = 0, dv_px = 0;  ///< observed - predicted image position [px]
  double dx_m = 0, dy_m = 0;    ///< world position of the observed pixel - known position [m]
  double loo_m = -1;            ///< error at this point when it is left out of the fit [m] (-1: not available)
};

/// A calibrated side camera (file format pteromys-calibration/1).
struct Calibration {
  int width = 0, height = 0;
  Lens lens;
  std::string distortion_model;  ///< "none", "k1", "k1k2" or "known"
  Mat3 H{};                      ///< world (x, y, 1) -> undistorted pixel
  Mat3 H_inv{};                  ///< undistorted pixel -> world (x, y, 1)
  Pose pose;
  std::vector<PointResidual> residuals;
  double rms_px = 0, max_px = 0;  ///< reprojection residual [px]
  double rms_m = 0, max_m = 0;    ///< residual in the flight plane [m] (distance per point)
  /// Leave-one-out RMS distance in the flight plane [m]: the error to expect
  /// at a point that took no part in the fit; -1 when there are too few
  /// points (the fit is then exact and rms_m says nothing).
  double loo_rms_m = -1;
  double click_sigma_px = 0.5;
  /// Per-model leave-one-out RMS [m] that "auto" compared ("none", "k1", ...).
  std::vector<std::pair<std::string, double>> model_loo_m;
  std::vector<std::string> warnings;
  CalibrationInput input;  ///< the points it was made from
};

/// Calibrates from reference points. Throws InputError with a one-line
/// message for: fewer than 4 points, non-finite coordinates, repeated points,
/// points (nearly) on one line in the world or in the image, configurations
/// that do not determine a homography (three of four points on a line),
/// points outside the image, a requested distortion model the points cannot
/// support or constrain, and points inconsistent with any camera (residual
/// larger than 2 % of the image diagonal; the worst point is named).
Calibration calibrate(const CalibrationInput& in);

/// World point (flight plane, [m]) seen at distorted pixel `px`.
Vec2 image_to_world(const Calibration& c, Vec2 px);
/// Distorted pixel where world point `w` (flight plane, [m]) is seen.
Vec2 world_to_image(const Calibration& c, Vec2 w);
/// Distorted pixel of a point anywhere in space (needs c.pose.known; throws
/// InputError otherwise). Points behind the camera give NaN.
Vec2 project_point(const Calibration& c, Point3 p);
/// Jacobian d(world)/d(pixel) at distorted pixel `px`: 2 x 2 row-major
/// [dx/du, dx/dv, dy/du, dy/dv] [m/px] (numerical, central differences).
std::array<double, 4> world_per_pixel(const Calibration& c, Vec2 px);

/// Files. Points: format "pteromys-calib-points/1"; calibration:
/// "pteromys-calibration/1" (docs/capture.md). Readers throw InputError
/// naming the file and the problem.
CalibrationInput calibration_input_from_json(const nlohmann::json& j, const std::string& what);
nlohmann::json calibration_input_to_json(const CalibrationInput& in);
CalibrationInput load_calibration_points(const std::string& path);
nlohmann::json calibration_to_json(const Calibration& c);
Calibration calibration_from_json(const nlohmann::json& j, const std::string& what);
Calibration load_calibration(const std::string& path);
void save_calibration(const Calibration& c, const std::string& path);

/// Homography of an exact pinhole camera (for tests and rendering): world
/// plane z = 0 -> undistorted pixel for pose (R, t), focal f, principal point (cx, cy).
Mat3 plane_homography(const Mat3& R, const std::array<double, 3>& t, double f, double cx, double cy);

}  // namespace pteromys::capture
