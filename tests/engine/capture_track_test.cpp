// Tracking (src/track_detect.cpp, src/track_flights.cpp, src/track_io.cpp)
// on synthetic videos written to disk and read back (src/capture_render.cpp).
// The reference is the flight the video was rendered from: the baseline
// simulator's CG trajectory, known independently of the tracker. The camera
// is calibrated from clicked reference points (0.3 px noise), not given.
#include "pteromys/track.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "pteromys/capture_render.hpp"
#include "pteromys/dataset.hpp"
#include "pteromys/flight.hpp"
#include "pteromys/io.hpp"
#include "pteromys/mass.hpp"
#include "test_support.hpp"

using namespace pteromys;
using namespace pteromys::capture;

namespace {

std::string temp_dir() {
  char tmpl[] = "/tmp/pteromys-track-XXXXXX";
  return mkdtemp(tmpl);
}

const Glider& glider() {
  static const Glider g = load_glider(test::source_path("examples/training/t04-tapered-mild.glider.json"));
  return g;
}

// A hand launch of the glider simulated by the baseline model (2 ms steps).
KnownFlight launch(double speed, double climb_deg, double t_max = 2.0) {
  const MountedGlider mg = mount(glider(), default_model());
  Launch l;
  l.speed = speed;
  l.climb_deg = climb_deg;
  SimOptions so;
  so.t_max = t_max;
  const Flight f = simulate(QuasiStaticAero(mg), {mg.mass().mass, mg.mass().inertia}, l, so);
  KnownFlight k;
  for (const auto& s : f.samples) k.t.push_back(s.t), k.x.push_back(s.x), k.y.push_back(s.y), k.pitch.push_back(s.pitch);
  return k;
}

// A camera at `distance` that sees the flight from its start across about
// 80 % of the image width, centred on the heights flown there.
SyntheticCamera framing(const KnownFlight& f, double distance) {
  SyntheticCamera c;
  const double width = 2 * distance * std::tan(deg2rad(c.hfov_deg) / 2);
  const double x0 = f.x.front();
  double ysum = 0;
  int n = 0;
  for (std::size_t i = 0; i < f.t.size(); ++i)
    if (f.x[i] < x0 + 0.8 * width) ysum += f.y[i], ++n;
  c.position = {x0 + 0.42 * width, ysum / n, distance};
  c.tilt_deg = 1.5;
  c.roll_deg = -0.8;
  return c;
}

struct Scene {
  std::string dir, video;
  Calibration truth, calib;
  RenderResult render;
  Vec2 marker;
};

const Vec2 kNoseMarker{-0.03, 0.001};  // on the fuselage, clear of the wings

Scene make_scene(const std::vector<KnownFlight>& flights, double distance, std::uint64_t seed) {
  Scene s;
  s.dir = temp_dir();
  s.video = s.dir + "/launches.avi";
  s.truth = synthetic_calibration(framing(flights.front(), distance));
  RenderOptions ro;
  ro.seed = seed;
  ro.marker_glider_m = kNoseMarker;
  ro.marker_radius_m = 0.008;
  s.marker = kNoseMarker;
  s.render = render_video(s.video, s.truth, glider(), flights, ro);
  s.calib = calibrate(synthetic_reference_points(s.truth, 4, 3, 0.3, seed, 0.001, distance));
  return s;
}

const Scene& scene(double distance) {
  static std::map<double, Scene> scenes;
  auto it = scenes.find(distance);
  if (it == scenes.end()) it = scenes.emplace(distance, make_scene({launch(8.0, 4.0)}, distance, 7)).first;
  return it->second;
}

// RMS distance between tracked CG points and the truth of the same frames [m].
double rms_error(const TrackResult& r, const RenderResult& render, int* n = nullptr) {
  std::map<int, const TruthFrame*> truth;
  for (const auto& t : render.truth) truth[t.frame] = &t;
  double s = 0;
  int k = 0;
  for (const auto& f : r.flights)
    for (const auto& p : f.points) {
      if (!truth.count(p.frame)) {
        ADD_FAILURE() << "a point in frame " << p.frame << ", where no glider was drawn";
        continue;
      }
      const TruthFrame* t = truth.at(p.frame);
      s += std::pow(p.cg.x - t->x, 2) + std::pow(p.cg.y - t->y, 2);
      ++k;
    }
  if (n) *n = k;
  return k ? std::sqrt(s / k) : 1e9;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

// The issue's target: RMS error <= 1 cm in the flight plane at 30 fps,
// 1280 x 720, glider 3 to 6 m from the camera (issue 8, deliverable 5).
TEST(CaptureTrack, SilhouetteTrackingIsWithinOneCentimetreFromThreeToSixMetres) {
  for (double d : {3.0, 6.0}) {
    const Scene& s = scene(d);
    const Detections det = detect(s.video, {});
    EXPECT_EQ(det.width, 1280);
    EXPECT_EQ(det.height, 720);
    EXPECT_DOUBLE_EQ(det.fps, 30.0);
    const TrackResult r = track_flights(det, s.calib, glider(), {});
    ASSERT_EQ(r.flights.size(), 1u) << "at " << d << " m";
    EXPECT_TRUE(r.perspective_model);
    int n = 0;
    const double e = rms_error(r, s.render, &n);
    EXPECT_GE(n, 10) << "at " << d << " m";
    EXPECT_LE(e, 0.010) << "at " << d << " m";
    // the reported per-coordinate sigma is of the size of the error made
    EXPECT_LT(e / std::sqrt(2.0), 3 * r.tracking_sigma_m) << "at " << d << " m";
    EXPECT_LT(r.tracking_sigma_m, 0.02);
  }
}

TEST(CaptureTrack, MarkerTrackingIsWithinOneCentimetreFromThreeToSixMetres) {
  for (double d : {3.0, 6.0}) {
    const Scene& s = scene(d);
    DetectOptions o;
    o.detector = Detector::Marker;
    const Detections det = detect(s.video, o);
    TrackOptions to;
    to.tracked_point_given = true;
    to.tracked_point_m = s.marker;
    const TrackResult r = track_flights(det, s.calib, glider(), to);
    ASSERT_EQ(r.flights.size(), 1u) << "at " << d << " m";
    EXPECT_EQ(r.pitch_source, "silhouette");  // the moving silhouette around the marker
    int n = 0;
    const double e = rms_error(r, s.render, &n);
    EXPECT_GE(n, 10) << "at " << d << " m";
    EXPECT_LE(e, 0.010) << "at " << d << " m";
  }
}

TEST(CaptureTrack, EachLaunchInAVideoBecomesOneFlight) {
  const Scene s = make_scene({launch(7.5, 6.0), launch(10.0, 0.0)}, 4.5, 3);
  const Detections det = detect(s.video, {});
  TrackOptions o;
  o.name_prefix = "g01-v";
  const TrackResult r = track_flights(det, s.calib, glider(), o);
  ASSERT_EQ(r.flights.size(), 2u);
  EXPECT_EQ(r.flights[0].name, "g01-v-01");
  EXPECT_EQ(r.flights[1].name, "g01-v-02");
  // each flight lies inside the frames of its launch
  for (int k = 0; k < 2; ++k) {
    EXPECT_GE(r.flights[k].first_frame, s.render.flight_frames[k].first);
    EXPECT_LE(r.flights[k].last_frame, s.render.flight_frames[k].second);
    EXPECT_GE(r.flights[k].points.size(), 8u);
  }
  EXPECT_LE(rms_error(r, s.render), 0.010);
  // given frame ranges, one flight per range whatever the automatic split says
  TrackOptions ro;
  ro.ranges = {s.render.flight_frames[0], s.render.flight_frames[1]};
  const TrackResult rr = track_flights(det, s.calib, glider(), ro);
  ASSERT_EQ(rr.flights.size(), 2u);
  EXPECT_EQ(rr.flights[0].first_frame, s.render.flight_frames[0].first);
  EXPECT_EQ(rr.flights[1].last_frame, s.render.flight_frames[1].second);
  EXPECT_EQ(rr.flights[0].end, "range end");
}

TEST(CaptureTrack, ManualCorrectionsReplaceAddAndRemovePoints) {
  const Scene& s = scene(3.0);
  DetectOptions dopt;
  dopt.detector = Detector::Marker;
  const Detections det = detect(s.video, dopt);
  TrackOptions o;
  o.tracked_point_given = true;
  o.tracked_point_m = s.marker;
  const TrackResult auto_r = track_flights(det, s.calib, glider(), o);
  ASSERT_EQ(auto_r.flights.size(), 1u);
  const auto& pts = auto_r.flights[0].points;
  ASSERT_GE(pts.size(), 8u);
  // replace the 4th point by a click 6 px away, remove the 6th
  const int f_moved = pts[3].frame, f_removed = pts[5].frame;
  const Vec2 click{pts[3].px.x + 6.0, pts[3].px.y - 2.0};
  o.corrections[f_moved] = {false, click};
  o.corrections[f_removed] = {true, {}};
  const TrackResult r = track_flights(det, s.calib, glider(), o);
  ASSERT_EQ(r.flights.size(), 1u);
  const auto& q = r.flights[0].points;
  EXPECT_EQ(q.size(), pts.size() - 1);
  bool seen = false;
  for (const auto& p : q) {
    EXPECT_NE(p.frame, f_removed);
    if (p.frame == f_moved) {
      seen = true;
      EXPECT_TRUE(p.manual);
      EXPECT_DOUBLE_EQ(p.confidence, 1.0);
      const Vec2 w = image_to_world(s.calib, click);  // the clicked pixel in the plane, exactly
      EXPECT_NEAR(p.tracked.x, w.x, 1e-9);
      EXPECT_NEAR(p.tracked.y, w.y, 1e-9);
    }
  }
  EXPECT_TRUE(seen);
  // a click in a frame the detector did not process adds a point there
  DetectOptions part = dopt;
  part.ranges = {{0, pts[6].frame}};
  const Detections det2 = detect(s.video, part);
  TrackOptions o2;
  o2.tracked_point_given = true;
  o2.tracked_point_m = s.marker;
  o2.corrections[pts[7].frame] = {false, pts[7].px};
  const TrackResult r2 = track_flights(det2, s.calib, glider(), o2);
  ASSERT_EQ(r2.flights.size(), 1u);
  EXPECT_EQ(r2.flights[0].points.back().frame, pts[7].frame);
  EXPECT_TRUE(r2.flights[0].points.back().manual);
}

TEST(CaptureTrack, DatasetIsWrittenInTheSpecFormatAndAppended) {
  const Scene& s = scene(3.0);
  const Detections det = detect(s.video, {});
  TrackOptions o;
  o.name_prefix = "g01-a";
  const TrackResult r = track_flights(det, s.calib, glider(), o);
  const std::string dir = s.dir + "/dataset";
  write_capture_dataset(dir, r, det, s.calib, o, glider(), "g01", false, false);
  Dataset d = load_dataset(dir + "/dataset.json");  // the spec reader, with its validation
  ASSERT_EQ(d.flights.size(), 1u);
  EXPECT_EQ(d.flights[0].glider, "g01");
  EXPECT_DOUBLE_EQ(d.frame_rate_hz, 30.0);
  EXPECT_NEAR(d.tracking_sigma_m, r.tracking_sigma_m, 1e-9);
  ASSERT_EQ(d.flights[0].points.size(), r.flights[0].points.size());
  EXPECT_NEAR(d.flights[0].points[2].x, r.flights[0].points[2].cg.x, 1e-8);
  EXPECT_EQ(d.flights[0].extra.at("first_frame"), std::to_string(r.flights[0].first_frame));
  // the same run again is refused (names taken), a renamed one is appended
  EXPECT_NE(error_of([&] { write_capture_dataset(dir, r, det, s.calib, o, glider(), "g01", false, false); }).find("already holds"),
            std::string::npos);
  EXPECT_NE(error_of([&] { write_capture_dataset(dir, r, det, s.calib, o, glider(), "g01", true, false); }).find("already in"),
            std::string::npos);
  TrackOptions o2 = o;
  o2.name_prefix = "g01-b";
  const TrackResult r2 = track_flights(det, s.calib, glider(), o2);
  write_capture_dataset(dir, r2, det, s.calib, o2, glider(), "g01", true, false);
  d = load_dataset(dir + "/dataset.json");
  EXPECT_EQ(d.flights.size(), 2u);
  // a different glider under the same key is refused, and nothing changes
  Glider other = glider();
  other.ballast.front().mass_kg *= 1.5;
  EXPECT_NE(error_of([&] { write_capture_dataset(dir, r2, det, s.calib, o2, other, "g01", true, false); }).find("different glider"),
            std::string::npos);
  EXPECT_EQ(load_dataset(dir + "/dataset.json").flights.size(), 2u);
  // tracks.csv holds every point of both runs
  std::ifstream t(dir + "/tracks.csv");
  int lines = 0;
  for (std::string l; std::getline(t, l);) ++lines;
  EXPECT_EQ(lines, 1 + 2 * static_cast<int>(r.flights[0].points.size()));
}

TEST(CaptureTrack, BadInputIsRefusedWithAMessage) {
  const Scene& s = scene(3.0);
  EXPECT_NE(error_of([&] { detect(s.dir + "/missing.avi", {}); }).find("no such file"), std::string::npos);
  const std::string text = s.dir + "/not-a-video.avi";
  std::ofstream(text) << "this is not a video\n";
  EXPECT_NE(error_of([&] { detect(text, {}); }).find("cannot read video"), std::string::npos);
  DetectOptions beyond;
  beyond.ranges = {{10, 100000}};
  EXPECT_NE(error_of([&] { detect(s.video, beyond); }).find("beyond the video"), std::string::npos);
  const Detections det = detect(s.video, {});
  TrackOptions o;
  o.corrections[100000] = {false, {10, 10}};
  EXPECT_NE(error_of([&] { track_flights(det, s.calib, glider(), o); }).find("frame 100000"), std::string::npos);
  o.corrections = {{5, {false, {-50, 10}}}};
  EXPECT_NE(error_of([&] { track_flights(det, s.calib, glider(), o); }).find("outside the image"), std::string::npos);
  Calibration small = s.calib;
  small.width = 640;
  EXPECT_NE(error_of([&] { track_flights(det, small, glider(), {}); }).find("calibration was made for 640x720"),
            std::string::npos);
  EXPECT_NE(error_of([] { parse_frame_ranges("12-5"); }).find("ends before"), std::string::npos);
  EXPECT_NE(error_of([] { parse_frame_ranges("1-5,4-9"); }).find("overlap"), std::string::npos);
  EXPECT_NE(error_of([] { corrections_from_json(nlohmann::json::parse(R"({"x": [1, 2]})"), "c"); }).find("not a frame number"),
            std::string::npos);
  EXPECT_NE(error_of([] { corrections_from_json(nlohmann::json::parse(R"({"3": [1]})"), "c"); }).find("frame 3"),
            std::string::npos);
}
