// Flight capture, part 2: tracking a glider in a side-view video and turning
// the tracks into a flight dataset (spec/formats.md "Flight dataset";
// docs/capture.md has the method, its accuracy and the files).
//
// Two stages, so that manual corrections re-run only the cheap one:
//  1. detect():  video -> per-frame candidate blobs with sub-pixel centroids
//     (background subtraction against a per-chunk median background, or a
//     coloured marker), their area and orientation. Independent of the glider.
//  2. track_flights(): candidates + calibration + glider + corrections ->
//     flights: launch detection (or given frame ranges), a constant-velocity
//     Kalman filter in the flight plane gating the candidates, manual
//     corrections overriding frames, the pitch (silhouette orientation or
//     track direction), the tracked point moved to the centre of gravity,
//     and the tracking uncertainty.
//
// Units and frames as in capture.hpp: pixels (u right, v down) for the image,
// metres in the flight plane (x along the flight, y up), seconds; the time of
// a frame is frame_index / fps (the middle of its exposure).
#pragma once

#include <array>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pteromys/capture.hpp"
#include "pteromys/dataset.hpp"
#include "pteromys/glider.hpp"

namespace pteromys::capture {

enum class Detector {
  Background,  ///< moving silhouette against a median background (no preparation of the glider)
  Marker       ///< a coloured disc stuck on the fuselage (more precise, needs a marker)
};

/// Inclusive range of frame indices.
using FrameRange = std::pair<int, int>;

struct DetectOptions {
  Detector detector = Detector::Background;
  // -- background subtraction
  int chunk_frames = 150;        ///< frames sharing one median background
  int background_samples = 15;   ///< frames sampled (evenly) for each median
  int background_pad = 45;       ///< frames beyond a range also used for its background
  double threshold_sigma = 6.0;  ///< foreground seed: |I - B| > threshold_sigma x robust noise sigma
  double min_contrast = 12.0;    ///< floor of that threshold [grey levels of 255]
  // -- marker
  std::array<int, 3> marker_bgr = {30, 30, 220};  ///< marker colour, blue-green-red 0..255
  double marker_hue_tolerance_deg = 20.0;   ///< hue distance accepted (hue in degrees, 0..360)
  double marker_min_saturation = 0.35;      ///< 0..1; half of it (x 255) is the floor of the threshold
  double marker_min_value = 0.15;           ///< 0..1
  // -- both
  int min_area_px = 4;           ///< smaller blobs are ignored
  int max_candidates = 12;       ///< strongest blobs (sum of the difference) kept per frame
  bool marker_silhouettes = true;  ///< marker detector: also find the silhouettes (pitch; about 1.6x the time)
  std::vector<FrameRange> ranges;  ///< frames to process; empty: the whole video
  double fps = 0;                ///< frame rate [1/s]; 0: as the file says
  /// Called now and then with (frames done, frames to do).
  std::function<void(int, int)> progress;
};

/// A blob that may be the glider (or its marker).
struct Candidate {
  Vec2 px;                 ///< sub-pixel centroid, distorted image [px]
  double area_px = 0;      ///< coverage-weighted pixel count
  double contrast = 0;     ///< mean difference from the background: grey levels, or marker score (saturation x 255)
  double angle_deg = 0;    ///< principal axis in the image, counter-clockwise on screen from +u, in (-90, 90]
  double elongation = 1;   ///< sqrt(major / minor second moment), >= 1
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  ///< bounding box [px], inclusive
  bool clipped = false;    ///< the blob touches the image border (partly outside: its centroid is biased)
};

struct FrameCandidates {
  int frame = 0;
  double t = 0;         ///< frame / fps [s]
  double noise = 0;     ///< robust noise sigma of the difference image [grey levels or score]
  std::vector<Candidate> candidates;  ///< strongest first
  /// Marker detector only: the moving silhouettes of the frame (grey-level
  /// background subtraction), whose orientation gives the pitch.
  std::vector<Candidate> silhouettes;
};

struct Detections {
  std::string video;
  int width = 0, height = 0;
  double fps = 30;
  int frame_count = 0;          ///< frames in the video (as read)
  Detector detector = Detector::Background;
  std::vector<FrameCandidates> frames;  ///< every processed frame, in order
  double seconds = 0;           ///< wall time of detection (decoding included) [s]
};

/// Stage 1. Throws InputError for a file that cannot be opened or decoded,
/// an empty video, frame ranges outside the video or malformed options.
Detections detect(const std::string& video, const DetectOptions& opt);

/// A manual correction of one frame (from the corrections file or the GUI).
struct Correction {
  bool absent = false;  ///< true: the glider is not (visibly) in this frame
  Vec2 px;              ///< where the tracked point is [px] (distorted image)
};

enum class PitchSource {
  Auto,        ///< silhouette when silhouettes were detected, else path
  Silhouette,  ///< principal axis of the silhouette, against the glider's own (projected) silhouette
  Path,        ///< direction of the track plus `aoa_deg`
  None         ///< no pitch: the tracked point is taken as the CG (a marker on the CG)
};

struct TrackOptions {
  // -- association
  double gate_sigma = 5.0;           ///< Mahalanobis gate of the Kalman prediction
  double accel_sigma_m_s2 = 20.0;    ///< white-acceleration process noise [m/s^2]
  double pixel_sigma = 0.7;          ///< centroid noise assumed for gating [px]
  double min_speed_m_s = 1.5, max_speed_m_s = 35.0;  ///< speeds accepted when a flight starts
  int max_missed = 3;                ///< a flight ends after this many frames without the glider
  double stop_speed_m_s = 1.2;       ///< slower than this for 3 frames: the glider has landed
  double area_ratio_max = 5.0;       ///< blob area within [1/r, r] x the glider's expected area
  int min_points = 6;                ///< shorter flights are left out (spec: at least 6 points)
  std::vector<FrameRange> ranges;    ///< one flight per range; empty: launches found automatically
  std::map<int, Correction> corrections;  ///< frame -> correction
  // -- centre of gravity
  PitchSource pitch = PitchSource::Auto;
  double aoa_deg = 0.0;              ///< angle of attack added to the path direction (Path) [deg]
  /// The glider-frame point that is tracked [m] (the marker's centre). When
  /// not given: the CG for the marker detector, the silhouette's centroid
  /// (computed from the glider) for the background detector.
  bool tracked_point_given = false;
  Vec2 tracked_point_m;
  double pitch_sigma_deg = -1;       ///< uncertainty of the pitch used for sigma; <0: 3 (silhouette) or 5 (path)
  int smooth_half_window = 4;        ///< local quadratic fit over 2k+1 frames (noise estimate, path pitch)
  std::string name_prefix = "flight";  ///< flights are named <prefix>-01, -02, ...
};

struct TrackPoint {
  int frame = 0;
  double t = 0;             ///< [s]
  Vec2 px;                  ///< tracked point, distorted image [px]
  Vec2 tracked;             ///< tracked point in the flight plane [m]
  Vec2 cg;                  ///< centre of gravity in the flight plane [m]
  double pitch_deg = 0;     ///< pitch used for the CG offset [deg], nose up positive
  double confidence = 0;    ///< 0..1 (1 for manual points; see docs/capture.md)
  bool manual = false;
  double area_px = 0;
};

struct FlightTrack {
  std::string name;
  int first_frame = 0, last_frame = 0;
  std::vector<TrackPoint> points;
  double noise_sigma_m = 0;   ///< per coordinate, from the residual of the local quadratic fit [m]
  double sigma_m = 0;         ///< total per-coordinate uncertainty of this flight [m]
  double mean_speed_m_s = 0;
  int missed = 0;             ///< frames inside the flight without a point
  std::string end;            ///< why it ends: lost, left the image, landed, range end, video end
};

struct TrackResult {
  std::vector<FlightTrack> flights;
  std::vector<std::string> notes;  ///< flights left out and why, frames with doubtful points
  // per-coordinate uncertainty components [m] (docs/capture.md)
  double sigma_noise_m = 0;        ///< centroid jitter (pooled over flights)
  double sigma_calibration_m = 0;  ///< calibration error in the plane
  double sigma_cg_m = 0;           ///< CG offset through the pitch uncertainty
  double sigma_model_m = 0;        ///< silhouette model without camera distance
  double tracking_sigma_m = 0;     ///< their root sum of squares
  std::string pitch_source;        ///< "silhouette", "path" or "none"
  Vec2 tracked_point_m;            ///< glider-frame point that was tracked
  Vec2 cg_glider_m;                ///< CG in the glider frame
  bool perspective_model = false;  ///< silhouette model projected with the camera pose
};

/// Whether `prefix` can name flights (<prefix>-01, ...) in a flights.csv:
/// 1-100 ASCII letters, digits, '-', '_' or '.' (no comma, quote or line end).
bool valid_flight_prefix(const std::string& prefix);

/// Stage 2. Throws InputError for corrections or ranges outside the video,
/// an image size that differs from the calibration, bad options.
TrackResult track_flights(const Detections& d, const Calibration& c, const Glider& g, const TrackOptions& opt);

/// The flights as a dataset (spec format): glider `key`, frame rate of the
/// video, tracking_sigma_m of the result.
Dataset tracks_to_dataset(const TrackResult& r, const Glider& g, const std::string& key, double fps);

/// Corrections file (format pteromys-corrections/1, or a bare object
/// {"frame": [u, v] or null}); docs/capture.md.
std::map<int, Correction> corrections_from_json(const nlohmann::json& j, const std::string& what);
nlohmann::json corrections_to_json(const std::map<int, Correction>& c, const std::string& video);
std::map<int, Correction> load_corrections(const std::string& path);

/// "10-40,55-90" -> {(10, 40), (55, 90)}; throws InputError on malformed text.
std::vector<FrameRange> parse_frame_ranges(const std::string& text);

/// Per-point details (tracks.csv) and the run summary (capture.json).
std::string tracks_csv(const TrackResult& r, const std::string& video);
nlohmann::json track_summary_json(const TrackResult& r, const Detections& d, const Calibration& c,
                                  const TrackOptions& o, const std::string& glider_key);

/// Writes a tracking run as a dataset directory: dataset.json, flights.csv,
/// gliders/KEY.glider.json (spec format), tracks.csv (every point: pixel,
/// tracked point, CG, pitch, confidence, manual or automatic) and
/// capture.json (runs, uncertainty budget, notes). With `append`, the flights
/// join the dataset already in `dir` (same frame rate; a key already used
/// must name the same glider; flight names must be new) and
/// tracking_sigma_m becomes the RMS over all points; otherwise an existing
/// dataset is refused unless `replace`. Everything is checked before the
/// first file is written; each file is written atomically, dataset.json last.
/// Returns the dataset as written.
Dataset write_capture_dataset(const std::string& dir, const TrackResult& r, const Detections& d, const Calibration& c,
                              const TrackOptions& o, const Glider& g, const std::string& key, bool append, bool replace);

/// Where the glider's silhouette centroid lies in the glider frame for a
/// view straight from the side (fuselage plate; wings seen edge-on) [m].
Vec2 silhouette_centroid_glider(const Glider& g);

}  // namespace pteromys::capture
