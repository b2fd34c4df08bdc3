// Flight capture, part 3: synthetic side-view videos of known flights, to
// test and measure the tracker (docs/capture.md, "Test videos").
//
// A flight (CG trajectory and pitch in the world frame of spec/formats.md) is
// drawn as the glider's flat plates in 3D - the fuselage in the plane of
// symmetry, each wing plate turned by its mounting angle, split into the half
// toward the camera and the half away from it - seen by a pinhole camera with
// OpenCV lens distortion, over a textured background, with motion blur over
// the exposure, sensor noise, a slight flicker, and the lossy codec of the
// video file. The true position of every frame is returned.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "pteromys/capture.hpp"
#include "pteromys/glider.hpp"

namespace pteromys::capture {

/// A camera for synthetic videos, looking at the flight plane from +z.
struct SyntheticCamera {
  int width = 1280, height = 720;   ///< [px]
  double hfov_deg = 66.0;           ///< horizontal field of view of the pinhole (undistorted) [deg]
  double k1 = -0.10, k2 = 0.02;     ///< OpenCV radial distortion (on (p - c) / f); k1 < 0 is barrel
  double cx_offset_px = 5.0, cy_offset_px = -3.0;  ///< principal point minus the image centre [px]
  Point3 position = {4.0, 1.2, 4.0};  ///< camera centre [m]; z is the distance to the flight plane
  /// Small turns away from looking straight along -z [deg]: yaw (about the
  /// camera's vertical axis, positive turns the view toward +x), tilt
  /// (positive looks up), roll (positive turns the image counter-clockwise).
  double yaw_deg = 0.0, tilt_deg = 0.0, roll_deg = 0.0;
};

/// The camera as a Calibration with known intrinsics and pose (the truth the
/// tracker is measured against): lens (focal, principal point, k1, k2), pose
/// and the plane homography.
Calibration synthetic_calibration(const SyntheticCamera& cam);

/// Reference points as a person would measure and click them: an nx x ny
/// grid over the image (8 % margins), world positions rounded to `round_m`,
/// image positions projected by the true camera plus Gaussian click noise of
/// `click_sigma_px` per coordinate. `distance_m` (if > 0) is written as the
/// measured camera distance.
CalibrationInput synthetic_reference_points(const Calibration& truth, int nx, int ny, double click_sigma_px,
                                            std::uint64_t seed, double round_m = 0.001, double distance_m = 0);

/// A glider plate in 3D, glider frame [m] (x toward the nose, y up, z along
/// the span). side: 0 for the fuselage, +1 / -1 for the half wing at z > 0 / z < 0.
struct Plate3 {
  std::vector<Point3> outline;
  int wing = -1;  ///< index into Glider::wings, -1 for the fuselage
  int side = 0;
};
/// The fuselage and the wing halves (each wing outline clipped at z = 0).
std::vector<Plate3> glider_plates(const Glider& g);

/// World point of glider-frame point p when the glider's CG (glider frame
/// `cg_glider`) is at world `cg_world` with pitch `beta` [rad] (nose up positive).
Point3 glider_to_world(Point3 p, Vec2 cg_glider, Vec2 cg_world, double beta);

/// A known flight: CG positions [m] and pitch [rad] at times [s] (strictly increasing).
struct KnownFlight {
  std::vector<double> t, x, y, pitch;
};

struct RenderOptions {
  double fps = 30.0;
  double exposure_s = 1.0 / 250;   ///< shutter time; frames are stamped at the middle of the exposure
  int blur_samples = 5;            ///< renders averaged over the exposure
  double noise_sigma = 2.0;        ///< Gaussian sensor noise [grey levels of 255]
  double flicker = 0.01;           ///< relative brightness oscillation (mains lighting)
  std::string fourcc = "MJPG";     ///< codec (MJPG in .avi is written by OpenCV itself)
  int quality = 90;                ///< JPEG quality for MJPG
  std::uint64_t seed = 1;          ///< background texture and noise
  std::array<int, 3> glider_bgr = {245, 245, 240};   ///< plate colour (white foam board)
  double wing_shade = 0.82;        ///< wings are drawn at this fraction of the plate colour (seen at a slant)
  bool marker = true;              ///< a coloured disc on both faces of the fuselage
  Vec2 marker_glider_m = {0, 0};   ///< marker centre, glider frame [m]
  double marker_radius_m = 0.012;
  std::array<int, 3> marker_bgr = {30, 30, 220};     ///< red
  int lead_frames = 12;            ///< frames before the first flight
  int gap_frames = 24;             ///< frames between flights (glider out of view)
  int tail_frames = 12;            ///< frames after the last flight
  double phase_s = 0.0113;         ///< flight time of a flight's first frame (not on a simulator step)
  /// Called after each frame with (frames done, frames total).
  std::function<void(int, int)> progress;
};

/// Truth of one frame in which a flight is under way.
struct TruthFrame {
  int flight = 0;       ///< index into the flights given
  int frame = 0;        ///< frame index in the video
  double t_video = 0;   ///< frame / fps [s]
  double t_flight = 0;  ///< time on the flight's own clock [s]
  double x = 0, y = 0;  ///< CG, world [m]
  double pitch = 0;     ///< [rad]
  double speed = 0;     ///< [m/s]
  Vec2 cg_px;           ///< where the CG is seen (distorted pixels)
  Vec2 marker_world;    ///< marker centre in the flight plane [m]
  bool visible = false; ///< the CG is inside the image
};

struct RenderResult {
  int frames = 0;
  int width = 0, height = 0;
  double fps = 30;
  std::vector<TruthFrame> truth;
  std::vector<std::pair<int, int>> flight_frames;  ///< first and last frame of each flight
  double seconds = 0;
};

/// Renders the flights one after the other into a video file. Throws
/// InputError when the file cannot be written or a flight is empty.
RenderResult render_video(const std::string& path, const Calibration& camera, const Glider& g,
                          const std::vector<KnownFlight>& flights, const RenderOptions& opt);

}  // namespace pteromys::capture
