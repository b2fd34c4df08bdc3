// Bindings: flight capture (capture.hpp, capture_render.hpp, track.hpp). The
// documented Python API is pteromys/capture.py; these are its thin parts.
#include <cstring>
#include <map>
#include <mutex>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "pteromys/capture.hpp"
#include "pteromys/capture_render.hpp"
#include "pteromys/io.hpp"
#include "pteromys/mass.hpp"
#include "pteromys/track.hpp"

namespace pteromys::python {
namespace {

using namespace pteromys::capture;
using nlohmann::json;

json to_json_obj(const py::object& o) {
  const std::string text = py::module_::import("json").attr("dumps")(o).cast<std::string>();
  return parse_json(text, "the given object");
}

py::array_t<double> as_points(const py::object& o, int cols, const char* what) {
  auto a = py::module_::import("numpy").attr("asarray")(o, "float64").cast<py::array_t<double, py::array::c_style | py::array::forcecast>>();
  if (a.ndim() == 1 && a.shape(0) == cols) a = a.reshape({static_cast<py::ssize_t>(1), static_cast<py::ssize_t>(cols)});
  if (a.ndim() != 2 || a.shape(1) != cols)
    throw InputError(std::string(what) + " must be an (n, " + std::to_string(cols) + ") array");
  return a;
}

py::array_t<double> map_points(const py::object& pts, int cols, const std::function<Vec2(const double*)>& f, const char* what) {
  const auto a = as_points(pts, cols, what);
  py::array_t<double> out({a.shape(0), static_cast<py::ssize_t>(2)});
  auto r = a.unchecked<2>();
  auto w = out.mutable_unchecked<2>();
  for (py::ssize_t i = 0; i < a.shape(0); ++i) {
    double v[3] = {r(i, 0), r(i, 1), cols > 2 ? r(i, 2) : 0.0};
    const Vec2 q = f(v);
    w(i, 0) = q.x;
    w(i, 1) = q.y;
  }
  return out;
}

std::map<int, Correction> corrections_of(const py::object& o) {
  if (o.is_none()) return {};
  if (py::isinstance<py::str>(o)) return load_corrections(o.cast<std::string>());
  // {frame: (u, v) or None}
  json j = json::object();
  for (auto item : o.cast<py::dict>()) {
    const std::string k = py::str(item.first).cast<std::string>();
    if (item.second.is_none()) j[k] = nullptr;
    else {
      auto seq = item.second.cast<std::vector<double>>();
      j[k] = seq;
    }
  }
  return corrections_from_json(j, "corrections");
}

py::dict track_point_arrays(const FlightTrack& f) {
  const auto n = static_cast<py::ssize_t>(f.points.size());
  py::array_t<double> t(n), u(n), v(n), xt(n), yt(n), x(n), y(n), pitch(n), conf(n), area(n);
  py::array_t<int> frame(n);
  py::array_t<bool> manual(n);
  for (py::ssize_t i = 0; i < n; ++i) {
    const auto& p = f.points[i];
    frame.mutable_at(i) = p.frame;
    t.mutable_at(i) = p.t;
    u.mutable_at(i) = p.px.x;
    v.mutable_at(i) = p.px.y;
    xt.mutable_at(i) = p.tracked.x;
    yt.mutable_at(i) = p.tracked.y;
    x.mutable_at(i) = p.cg.x;
    y.mutable_at(i) = p.cg.y;
    pitch.mutable_at(i) = p.pitch_deg;
    conf.mutable_at(i) = p.confidence;
    manual.mutable_at(i) = p.manual;
    area.mutable_at(i) = p.area_px;
  }
  py::dict d;
  d["name"] = f.name;
  d["first_frame"] = f.first_frame;
  d["last_frame"] = f.last_frame;
  d["end"] = f.end;
  d["noise_sigma_m"] = f.noise_sigma_m;
  d["sigma_m"] = f.sigma_m;
  d["mean_speed_m_s"] = f.mean_speed_m_s;
  d["missed"] = f.missed;
  d["frame"] = frame;
  d["t_s"] = t;
  d["u_px"] = u;
  d["v_px"] = v;
  d["x_tracked_m"] = xt;
  d["y_tracked_m"] = yt;
  d["x_m"] = x;
  d["y_m"] = y;
  d["pitch_deg"] = pitch;
  d["confidence"] = conf;
  d["manual"] = manual;
  d["area_px"] = area;
  return d;
}

/// A tracking result with what produced it (for the summary and writing).
struct PyTrack {
  TrackResult result;
  TrackOptions options;
};

/// Random access to the frames of a video (for the GUI): RGB uint8 arrays.
class VideoFrames {
 public:
  explicit VideoFrames(const std::string& path) : path_(path) {
    cap_.open(path, cv::CAP_FFMPEG);
    if (!cap_.isOpened()) throw InputError("cannot read video '" + path + "': not a video file FFmpeg (through OpenCV) can decode");
    count_ = static_cast<int>(cap_.get(cv::CAP_PROP_FRAME_COUNT));
    fps_ = cap_.get(cv::CAP_PROP_FPS);
    width_ = static_cast<int>(cap_.get(cv::CAP_PROP_FRAME_WIDTH));
    height_ = static_cast<int>(cap_.get(cv::CAP_PROP_FRAME_HEIGHT));
  }
  py::array_t<uint8_t> get(int i) {
    if (i < 0 || (count_ > 0 && i >= count_))
      throw InputError("frame " + std::to_string(i) + " is outside the video (0 to " + std::to_string(count_ - 1) + ")");
    cv::Mat f;
    {
      py::gil_scoped_release nogil;
      std::lock_guard<std::mutex> l(m_);
      if (i != next_) {
        cap_.set(cv::CAP_PROP_POS_FRAMES, i);
        next_ = i;
      }
      if (!cap_.read(f) || f.empty()) throw InputError("cannot decode frame " + std::to_string(i) + " of '" + path_ + "'");
      ++next_;
    }
    cv::Mat rgb;
    cv::cvtColor(f, rgb, f.channels() == 1 ? cv::COLOR_GRAY2RGB : cv::COLOR_BGR2RGB);
    py::array_t<uint8_t> out({rgb.rows, rgb.cols, 3});
    for (int y = 0; y < rgb.rows; ++y) std::memcpy(out.mutable_data(y, 0, 0), rgb.ptr(y), static_cast<std::size_t>(rgb.cols) * 3);
    return out;
  }
  int count() const { return count_; }
  double fps() const { return fps_; }
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  std::string path_;
  cv::VideoCapture cap_;
  int count_ = 0, width_ = 0, height_ = 0, next_ = 0;
  double fps_ = 0;
  std::mutex m_;
};

void bind_capture(py::module_& m) {
  py::class_<Calibration>(m, "CameraCalibration",
                          "A calibrated side camera: image <-> flight plane (pteromys.capture.calibrate).")
      .def_readonly("width", &Calibration::width)
      .def_readonly("height", &Calibration::height)
      .def_readonly("distortion_model", &Calibration::distortion_model)
      .def_readonly("rms_px", &Calibration::rms_px)
      .def_readonly("max_px", &Calibration::max_px)
      .def_readonly("rms_m", &Calibration::rms_m)
      .def_readonly("max_m", &Calibration::max_m)
      .def_readonly("loo_rms_m", &Calibration::loo_rms_m)
      .def_readonly("warnings", &Calibration::warnings)
      .def_property_readonly("pose_known", [](const Calibration& c) { return c.pose.known; })
      .def_property_readonly("camera_distance_m", [](const Calibration& c) { return c.pose.known ? py::object(py::float_(c.pose.distance_m)) : py::object(py::none()); })
      .def_property_readonly("camera_position_m", [](const Calibration& c) {
        return c.pose.known ? py::object(py::make_tuple(c.pose.centre.x, c.pose.centre.y, c.pose.centre.z)) : py::object(py::none());
      })
      .def_property_readonly("focal_px", [](const Calibration& c) { return c.pose.known ? py::object(py::float_(c.pose.focal_px)) : py::object(py::none()); })
      .def_property_readonly("lens", [](const Calibration& c) {
        py::dict d;
        d["fx"] = c.lens.fx;
        d["fy"] = c.lens.fy;
        d["cx"] = c.lens.cx;
        d["cy"] = c.lens.cy;
        d["dist"] = std::vector<double>(c.lens.dist.begin(), c.lens.dist.end());
        d["intrinsics_known"] = c.lens.intrinsics_known;
        return d;
      })
      .def_property_readonly("residuals", [](const Calibration& c) {
        py::list l;
        for (const auto& r : c.residuals) {
          py::dict d;
          d["name"] = r.name;
          d["du_px"] = r.du_px;
          d["dv_px"] = r.dv_px;
          d["dx_m"] = r.dx_m;
          d["dy_m"] = r.dy_m;
          d["loo_m"] = r.loo_m >= 0 ? py::object(py::float_(r.loo_m)) : py::object(py::none());
          l.append(d);
        }
        return l;
      })
      .def_property_readonly("points", [](const Calibration& c) {
        py::list l;
        for (const auto& p : c.input.points) l.append(py::make_tuple(p.name, py::make_tuple(p.world.x, p.world.y), py::make_tuple(p.image.x, p.image.y)));
        return l;
      })
      .def("image_to_world", [](const Calibration& c, const py::object& px) {
        return map_points(px, 2, [&](const double* v) { return image_to_world(c, {v[0], v[1]}); }, "pixels");
      }, py::arg("px"), "World points (n, 2) [m] of distorted pixels (n, 2).")
      .def("world_to_image", [](const Calibration& c, const py::object& w) {
        return map_points(w, 2, [&](const double* v) { return world_to_image(c, {v[0], v[1]}); }, "world points");
      }, py::arg("world"), "Distorted pixels (n, 2) of flight-plane points (n, 2) [m].")
      .def("project", [](const Calibration& c, const py::object& p) {
        return map_points(p, 3, [&](const double* v) { return project_point(c, {v[0], v[1], v[2]}); }, "points");
      }, py::arg("points"), "Distorted pixels (n, 2) of points in space (n, 3) [m] (needs the camera pose).")
      .def("to_json", [](const Calibration& c) { return calibration_to_json(c).dump(2); })
      .def("save", [](const Calibration& c, const std::string& p) { save_calibration(c, p); }, py::arg("path"));

  m.def("capture_calibrate", [](const std::string& text) {
    const CalibrationInput in = calibration_input_from_json(parse_json(text, "calibration points"), "calibration points");
    py::gil_scoped_release nogil;
    return calibrate(in);
  }, py::arg("points_json"));
  m.def("capture_calibration_from_json", [](const std::string& text) {
    return calibration_from_json(parse_json(text, "calibration"), "calibration");
  }, py::arg("text"));
  m.def("capture_load_calibration", [](const std::string& path) {
    const json j = parse_json(read_file(path), "calibration file '" + path + "'");
    if (j.is_object() && j.contains("format") && j["format"] == "pteromys-calib-points/1")
      return calibrate(calibration_input_from_json(j, "calibration points file '" + path + "'"));
    return calibration_from_json(j, "calibration file '" + path + "'");
  }, py::arg("path"));

  py::class_<Detections>(m, "Detections", "Per-frame candidate blobs of a video (pteromys.capture.detect).")
      .def_readonly("video", &Detections::video)
      .def_readonly("width", &Detections::width)
      .def_readonly("height", &Detections::height)
      .def_readonly("fps", &Detections::fps)
      .def_readonly("frame_count", &Detections::frame_count)
      .def_readonly("seconds", &Detections::seconds)
      .def_property_readonly("detector", [](const Detections& d) { return d.detector == Detector::Background ? "background" : "marker"; })
      .def_property_readonly("frames_processed", [](const Detections& d) { return d.frames.size(); })
      .def("candidates", [](const Detections& d) {
        // dict frame -> (k, 11) array: u, v, area, contrast, angle_deg, elongation, x0, y0, x1, y1, clipped
        py::dict out;
        for (const auto& f : d.frames) {
          py::array_t<double> a({static_cast<py::ssize_t>(f.candidates.size()), static_cast<py::ssize_t>(11)});
          auto w = a.mutable_unchecked<2>();
          for (std::size_t i = 0; i < f.candidates.size(); ++i) {
            const auto& c = f.candidates[i];
            const double row[11] = {c.px.x, c.px.y, c.area_px, c.contrast, c.angle_deg, c.elongation,
                                    double(c.x0), double(c.y0), double(c.x1), double(c.y1), c.clipped ? 1.0 : 0.0};
            for (int k = 0; k < 11; ++k) w(i, k) = row[k];
          }
          out[py::int_(f.frame)] = a;
        }
        return out;
      }, "dict frame -> (k, 11) array: u, v, area_px, contrast, angle_deg, elongation, x0, y0, x1, y1, clipped");

  m.def("capture_detect", [](const std::string& video, const std::string& detector, const std::string& frames,
                             double fps, const std::vector<int>& marker_bgr, double threshold, int min_area,
                             const py::object& progress) {
    DetectOptions o;
    if (detector == "background") o.detector = Detector::Background;
    else if (detector == "marker") o.detector = Detector::Marker;
    else throw InputError("detector must be 'background' or 'marker'");
    if (!frames.empty()) o.ranges = parse_frame_ranges(frames);
    o.fps = fps;
    if (marker_bgr.size() == 3) o.marker_bgr = {marker_bgr[0], marker_bgr[1], marker_bgr[2]};
    o.threshold_sigma = threshold;
    o.min_area_px = min_area;
    std::function<void(int, int)> cb;
    if (!progress.is_none()) {
      py::function pf = progress.cast<py::function>();
      o.progress = [pf](int a, int b) {
        py::gil_scoped_acquire g;
        pf(a, b);
      };
    }
    py::gil_scoped_release nogil;
    return detect(video, o);
  }, py::arg("video"), py::arg("detector") = "background", py::arg("frames") = "", py::arg("fps") = 0.0,
     py::arg("marker_bgr") = std::vector<int>{}, py::arg("threshold") = 6.0, py::arg("min_area") = 4,
     py::arg("progress") = py::none());

  py::class_<PyTrack>(m, "TrackResult", "Flights tracked in a video (pteromys.capture.track_flights).")
      .def_property_readonly("flights", [](const PyTrack& t) {
        py::list l;
        for (const auto& f : t.result.flights) l.append(track_point_arrays(f));
        return l;
      })
      .def_property_readonly("notes", [](const PyTrack& t) { return t.result.notes; })
      .def_property_readonly("tracking_sigma_m", [](const PyTrack& t) { return t.result.tracking_sigma_m; })
      .def_property_readonly("sigma_components_m", [](const PyTrack& t) {
        py::dict d;
        d["noise"] = t.result.sigma_noise_m;
        d["calibration"] = t.result.sigma_calibration_m;
        d["cg_offset"] = t.result.sigma_cg_m;
        d["silhouette_model"] = t.result.sigma_model_m;
        return d;
      })
      .def_property_readonly("pitch_source", [](const PyTrack& t) { return t.result.pitch_source; })
      .def_property_readonly("perspective_model", [](const PyTrack& t) { return t.result.perspective_model; })
      .def("summary_json", [](const PyTrack& t, const Detections& d, const Calibration& c, const std::string& key) {
        return track_summary_json(t.result, d, c, t.options, key).dump(2);
      }, py::arg("detections"), py::arg("calibration"), py::arg("key") = "glider");

  m.def("capture_track_flights", [](const Detections& d, const Calibration& c, const py::object& go,
                                    const py::object& corrections, const std::string& frames, const std::string& pitch,
                                    double aoa_deg, const py::object& marker_at, const std::string& name,
                                    double gate, int max_missed, int min_points) {
    PyTrack t;
    TrackOptions& o = t.options;
    const Glider g = to_glider(go);
    validate(g);
    o.corrections = corrections_of(corrections);
    if (!frames.empty()) o.ranges = parse_frame_ranges(frames);
    if (pitch == "auto") o.pitch = PitchSource::Auto;
    else if (pitch == "silhouette") o.pitch = PitchSource::Silhouette;
    else if (pitch == "path") o.pitch = PitchSource::Path;
    else if (pitch == "none") o.pitch = PitchSource::None;
    else throw InputError("pitch must be 'auto', 'silhouette', 'path' or 'none'");
    o.aoa_deg = aoa_deg;
    if (!marker_at.is_none()) {
      const auto v = marker_at.cast<std::vector<double>>();
      if (v.size() != 2) throw InputError("marker_at must be (x, y) in the glider frame [m]");
      o.tracked_point_given = true;
      o.tracked_point_m = {v[0], v[1]};
    }
    o.name_prefix = name;
    o.gate_sigma = gate;
    o.max_missed = max_missed;
    o.min_points = min_points;
    {
      py::gil_scoped_release nogil;
      t.result = track_flights(d, c, g, o);
    }
    return t;
  }, py::arg("detections"), py::arg("calibration"), py::arg("glider"), py::arg("corrections") = py::none(),
     py::arg("frames") = "", py::arg("pitch") = "auto", py::arg("aoa_deg") = 0.0, py::arg("marker_at") = py::none(),
     py::arg("name") = "flight", py::arg("gate") = 5.0, py::arg("max_missed") = 3, py::arg("min_points") = 6);

  m.def("capture_write_dataset", [](const std::string& dir, const PyTrack& t, const Detections& d, const Calibration& c,
                                    const py::object& go, const std::string& key, bool append, bool replace) {
    const Glider g = to_glider(go);
    const Dataset ds = write_capture_dataset(dir, t.result, d, c, t.options, g, key, append, replace);
    return ds.flights.size();
  }, py::arg("dir"), py::arg("track"), py::arg("detections"), py::arg("calibration"), py::arg("glider"),
     py::arg("key"), py::arg("append") = false, py::arg("replace") = false);

  m.def("capture_load_corrections", [](const std::string& path) {
    py::dict d;
    for (const auto& [f, c] : load_corrections(path))
      d[py::int_(f)] = c.absent ? py::object(py::none()) : py::object(py::make_tuple(c.px.x, c.px.y));
    return d;
  }, py::arg("path"));
  m.def("capture_corrections_json", [](const py::object& corrections, const std::string& video) {
    return corrections_to_json(corrections_of(corrections), video).dump(2);
  }, py::arg("corrections"), py::arg("video") = "");
  m.def("capture_silhouette_centroid", [](const py::object& go) {
    const Vec2 c = silhouette_centroid_glider(to_glider(go));
    return py::make_tuple(c.x, c.y);
  }, py::arg("glider"));

  // ------------------------------------------------------- synthetic videos
  m.def("capture_synthetic_camera", [](int width, int height, double hfov_deg, double k1, double k2,
                                       const std::vector<double>& position, double yaw, double tilt, double roll,
                                       double cx_offset, double cy_offset) {
    SyntheticCamera s;
    s.width = width;
    s.height = height;
    s.hfov_deg = hfov_deg;
    s.k1 = k1;
    s.k2 = k2;
    if (position.size() != 3) throw InputError("position must be (x, y, z) [m]");
    s.position = {position[0], position[1], position[2]};
    s.yaw_deg = yaw;
    s.tilt_deg = tilt;
    s.roll_deg = roll;
    s.cx_offset_px = cx_offset;
    s.cy_offset_px = cy_offset;
    return synthetic_calibration(s);
  }, py::arg("width") = 1280, py::arg("height") = 720, py::arg("hfov_deg") = 66.0, py::arg("k1") = -0.10,
     py::arg("k2") = 0.02, py::arg("position") = std::vector<double>{4.0, 1.2, 4.0}, py::arg("yaw_deg") = 0.0,
     py::arg("tilt_deg") = 0.0, py::arg("roll_deg") = 0.0, py::arg("cx_offset_px") = 5.0, py::arg("cy_offset_px") = -3.0);
  m.def("capture_synthetic_points", [](const Calibration& truth, int nx, int ny, double click_sigma, std::uint64_t seed,
                                       double distance_m) {
    return calibration_input_to_json(synthetic_reference_points(truth, nx, ny, click_sigma, seed, 0.001, distance_m)).dump(2);
  }, py::arg("truth"), py::arg("nx") = 4, py::arg("ny") = 3, py::arg("click_sigma_px") = 0.3, py::arg("seed") = 1,
     py::arg("distance_m") = 0.0);
  m.def("capture_render_video", [](const std::string& path, const Calibration& cam, const py::object& go,
                                   const py::list& flights, double fps, double exposure_s, int blur_samples,
                                   double noise_sigma, int quality, std::uint64_t seed, bool marker,
                                   const py::object& marker_at, double marker_radius, int lead, int gap, int tail,
                                   const py::object& progress, double wing_shade) {
    const Glider g = to_glider(go);
    std::vector<KnownFlight> fl;
    for (auto item : flights) {
      const auto a = as_points(py::reinterpret_borrow<py::object>(item), 4, "each flight (t_s, x_m, y_m, pitch_deg)");
      auto r = a.unchecked<2>();
      KnownFlight k;
      for (py::ssize_t i = 0; i < a.shape(0); ++i) {
        k.t.push_back(r(i, 0));
        k.x.push_back(r(i, 1));
        k.y.push_back(r(i, 2));
        k.pitch.push_back(deg2rad(r(i, 3)));
      }
      fl.push_back(std::move(k));
    }
    RenderOptions o;
    o.fps = fps;
    o.exposure_s = exposure_s;
    o.blur_samples = blur_samples;
    o.noise_sigma = noise_sigma;
    o.quality = quality;
    o.seed = seed;
    o.marker = marker;
    if (!marker_at.is_none()) {
      const auto v = marker_at.cast<std::vector<double>>();
      if (v.size() != 2) throw InputError("marker_at must be (x, y) in the glider frame [m]");
      o.marker_glider_m = {v[0], v[1]};
    } else {
      o.marker_glider_m = mass_properties(g).cg;
    }
    o.marker_radius_m = marker_radius;
    o.lead_frames = lead;
    o.gap_frames = gap;
    o.tail_frames = tail;
    o.wing_shade = wing_shade;
    if (!progress.is_none()) {
      py::function pf = progress.cast<py::function>();
      o.progress = [pf](int a, int b) {
        py::gil_scoped_acquire gg;
        pf(a, b);
      };
    }
    RenderResult rr;
    {
      py::gil_scoped_release nogil;
      rr = render_video(path, cam, g, fl, o);
    }
    const auto n = static_cast<py::ssize_t>(rr.truth.size());
    py::array_t<double> truth({n, static_cast<py::ssize_t>(12)});
    auto w = truth.mutable_unchecked<2>();
    for (py::ssize_t i = 0; i < n; ++i) {
      const auto& t = rr.truth[i];
      const double row[12] = {double(t.flight), double(t.frame), t.t_video, t.x, t.y, rad2deg(t.pitch), t.speed,
                              t.cg_px.x, t.cg_px.y, t.marker_world.x, t.marker_world.y, t.visible ? 1.0 : 0.0};
      for (int k = 0; k < 12; ++k) w(i, k) = row[k];
    }
    py::dict d;
    d["truth"] = truth;
    d["columns"] = std::vector<std::string>{"flight", "frame", "t_s", "x_m", "y_m", "pitch_deg", "speed_m_s", "u_px",
                                            "v_px", "marker_x_m", "marker_y_m", "visible"};
    d["frames"] = rr.frames;
    d["flight_frames"] = rr.flight_frames;
    d["seconds"] = rr.seconds;
    return d;
  }, py::arg("path"), py::arg("camera"), py::arg("glider"), py::arg("flights"), py::arg("fps") = 30.0,
     py::arg("exposure_s") = 1.0 / 250, py::arg("blur_samples") = 5, py::arg("noise_sigma") = 2.0,
     py::arg("quality") = 90, py::arg("seed") = 1, py::arg("marker") = true, py::arg("marker_at") = py::none(),
     py::arg("marker_radius_m") = 0.012, py::arg("lead_frames") = 12, py::arg("gap_frames") = 24,
     py::arg("tail_frames") = 12, py::arg("progress") = py::none(), py::arg("wing_shade") = 0.82);

  py::class_<VideoFrames>(m, "VideoFrames", "Random access to the frames of a video as RGB arrays (height, width, 3).")
      .def(py::init<const std::string&>(), py::arg("path"))
      .def("__getitem__", &VideoFrames::get)
      .def("get", &VideoFrames::get, py::arg("index"))
      .def("__len__", &VideoFrames::count)
      .def_property_readonly("fps", &VideoFrames::fps)
      .def_property_readonly("width", &VideoFrames::width)
      .def_property_readonly("height", &VideoFrames::height);
}

const bool registered = register_binder(80, bind_capture);
}  // namespace

}  // namespace pteromys::python
