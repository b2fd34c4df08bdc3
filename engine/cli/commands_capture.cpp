// pteromys calibrate, pteromys track, pteromys render-video (flight capture, docs/capture.md).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <sys/stat.h>
#include <unistd.h>

#include <opencv2/core.hpp>

#include "commands.hpp"
#include "common.hpp"
#include "pteromys/capture.hpp"
#include "pteromys/capture_render.hpp"
#include "pteromys/dataset.hpp"
#include "pteromys/flight.hpp"
#include "pteromys/io.hpp"
#include "pteromys/mass.hpp"
#include "pteromys/track.hpp"

namespace pteromys::cli {
namespace {

using namespace pteromys::capture;
using nlohmann::json;

std::string fmt(double v, int prec = 3) {
  std::ostringstream s;
  s.precision(prec);
  s << v;
  return s.str();
}

/// A file's stem as part of a flight's name or a glider key ("video" if empty).
std::string stem(const std::string& path) {
  const std::string b = safe_name(file_stem(path));
  return b.empty() ? "video" : b;
}

Vec2 pair_option(const Args& a, const std::string& key) {
  const std::string v = a.get(key);
  const auto c = v.find(',');
  if (c == std::string::npos) throw InputError(key + " needs two numbers X,Y");
  char* e1 = nullptr;
  char* e2 = nullptr;
  const std::string s1 = v.substr(0, c), s2 = v.substr(c + 1);
  const double x = std::strtod(s1.c_str(), &e1), y = std::strtod(s2.c_str(), &e2);
  if (s1.empty() || s2.empty() || *e1 || *e2 || !std::isfinite(x) || !std::isfinite(y))
    throw InputError(key + " needs two numbers X,Y, got '" + v + "'");
  return {x, y};
}

std::array<int, 3> colour_option(const std::string& text) {
  // #RRGGBB or R,G,B
  std::string s = text;
  if (!s.empty() && s[0] == '#' && s.size() == 7) {
    char* end = nullptr;
    const long v = std::strtol(s.c_str() + 1, &end, 16);
    if (*end) throw InputError("colour '" + text + "' must be #RRGGBB or R,G,B");
    return {static_cast<int>(v & 255), static_cast<int>((v >> 8) & 255), static_cast<int>((v >> 16) & 255)};
  }
  int r, g, b;
  char extra;
  if (std::sscanf(s.c_str(), "%d,%d,%d%c", &r, &g, &b, &extra) == 3 && r >= 0 && r < 256 && g >= 0 && g < 256 && b >= 0 && b < 256)
    return {b, g, r};
  throw InputError("colour '" + text + "' must be #RRGGBB or R,G,B (0-255)");
}

// Progress on stderr: a rewritten line on a terminal, a few lines otherwise.
struct Progress {
  std::string what;
  bool quiet = false;
  bool tty = ::isatty(2);
  int last_pct = -100;
  std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
  void operator()(int done, int total) {
    if (quiet || total <= 0) return;
    const int pct = static_cast<int>(100.0 * done / total);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (tty) {
      std::fprintf(stderr, "\r%s: %3d %% (%d/%d frames, %.0f frames/s)   ", what.c_str(), std::min(pct, 100), done, total,
                   s > 0 ? done / s : 0.0);
      if (done >= total) std::fprintf(stderr, "\n");
    } else if (pct >= last_pct + 25 || done >= total) {
      std::fprintf(stderr, "%s: %d %% (%d/%d frames)\n", what.c_str(), std::min(pct, 100), done, total);
      last_pct = pct;
    }
  }
};

std::string calibration_summary(const Calibration& c) {
  std::ostringstream s;
  s << "calibration: " << c.input.points.size() << " points, lens distortion '" << c.distortion_model << "'";
  if (c.distortion_model == "k1" || c.distortion_model == "k1k2")
    s << " (k1 " << fmt(c.lens.dist[0], 4) << ", k2 " << fmt(c.lens.dist[1], 4) << " on radius / half diagonal)";
  s << "\n  residual: " << fmt(c.rms_px) << " px rms (max " << fmt(c.max_px) << "), " << fmt(c.rms_m * 1000) << " mm rms in the plane (max "
    << fmt(c.max_m * 1000) << ")\n";
  if (c.loo_rms_m >= 0) s << "  leave-one-out error: " << fmt(c.loo_rms_m * 1000) << " mm rms (the accuracy to expect)\n";
  if (c.pose.known)
    s << "  camera: " << fmt(c.pose.distance_m) << " m from the flight plane at (" << fmt(c.pose.centre.x) << ", "
      << fmt(c.pose.centre.y) << ") m, focal length " << fmt(c.pose.focal_px, 5) << " px\n";
  for (const auto& w : c.warnings) s << "  warning: " << w << "\n";
  return s.str();
}

Calibration calibration_from_file(const std::string& path) {
  const json j = parse_json(read_file(path), "calibration file '" + path + "'");
  if (j.is_object() && j.contains("format") && j["format"] == "pteromys-calib-points/1")
    return calibrate(calibration_input_from_json(j, "calibration points file '" + path + "'"));
  return calibration_from_json(j, "calibration file '" + path + "'");
}

// ------------------------------------------------------------- calibrate

int run_calibrate(const std::vector<std::string>& argv) {
  const Args a = parse_args(argv, {"-o", "--distortion", "--distance", "--focal"}, {"--quiet"});
  if (a.positional.empty()) throw InputError("missing POINTS.json (see --help)");
  if (a.positional.size() > 1) throw InputError("unexpected argument '" + a.positional[1] + "'");
  if (!a.has("-o")) throw InputError("missing -o CALIB.json (see --help)");
  check_writable(a.get("-o"), "calibration");
  CalibrationInput in = load_calibration_points(a.positional[0]);
  if (a.has("--distortion")) {
    in.distortion = a.get("--distortion");
    if (in.distortion != "auto" && in.distortion != "none" && in.distortion != "k1" && in.distortion != "k1k2")
      throw InputError("--distortion must be auto, none, k1 or k1k2");
  }
  if (a.has("--distance")) {
    in.distance_m = a.number("--distance", 0);
    if (!(in.distance_m > 0) || in.distance_m > 1000) throw InputError("--distance must be a positive number of metres");
  }
  if (a.has("--focal")) {
    in.focal_px = a.number("--focal", 0);
    if (!(in.focal_px > 0) || in.focal_px > 1e6) throw InputError("--focal must be a positive number of pixels");
  }
  const auto t0 = std::chrono::steady_clock::now();
  const Calibration c = calibrate(in);
  const double ms = 1000 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  save_calibration(c, a.get("-o"));
  if (!a.flag("--quiet")) {
    std::cout << calibration_summary(c);
    std::cout << "  per point (du, dv px; dx, dy mm; left out mm):\n";
    for (const auto& r : c.residuals) {
      char buf[200];
      std::snprintf(buf, sizeof buf, "    %-12s %7.2f %7.2f   %7.1f %7.1f   %s\n", r.name.c_str(), r.du_px, r.dv_px,
                    r.dx_m * 1000, r.dy_m * 1000, r.loo_m >= 0 ? fmt(r.loo_m * 1000, 3).c_str() : "-");
      std::cout << buf;
    }
    std::cout << "  (" << fmt(ms, 3) << " ms)\n";
  }
  return 0;
}

// ----------------------------------------------------------------- track

int run_track(const std::vector<std::string>& argv) {
  const std::set<std::string> valued = {"--calib", "--glider", "-o", "--glider-key", "--corrections", "--frames",
                                        "--detector", "--marker-colour", "--marker-color", "--marker-at", "--pitch",
                                        "--aoa", "--fps", "--min-points", "--name", "--threshold", "--gate",
                                        "--max-missed", "--ground-y"};
  const Args a = parse_args(argv, valued, {"--append", "--force", "--quiet"});
  if (a.positional.empty()) throw InputError("missing VIDEO (see --help)");
  if (a.positional.size() > 1) throw InputError("unexpected argument '" + a.positional[1] + "'");
  if (!a.has("--calib")) throw InputError("missing --calib CALIB.json (see --help)");
  if (!a.has("--glider")) throw InputError("missing --glider GLIDER.glider.json (see --help)");
  if (!a.has("-o")) throw InputError("missing -o DATASET_DIR (see --help)");
  const std::string video = a.positional[0];
  const std::string out = a.get("-o");
  if (a.flag("--append") && a.flag("--force")) throw InputError("--append and --force cannot be used together");
  {
    const std::string parent = directory_of(strip_slash(out));
    if (!is_dir(parent)) throw InputError("cannot write the dataset '" + out + "': directory '" + parent + "' does not exist");
    if (is_file(out)) throw InputError("cannot write the dataset '" + out + "': it is a file, not a directory");
  }
  const bool exists = is_file(out + "/dataset.json");
  if (exists && !a.flag("--append") && !a.flag("--force"))
    throw InputError("'" + out + "' already holds a dataset: add --append to add these flights, or --force to replace it");
  if (!is_file(video)) throw InputError("cannot read video '" + video + "': no such file");

  const Calibration cal = calibration_from_file(a.get("--calib"));
  const Glider glider = load_glider(a.get("--glider"));
  std::string key = a.get("--glider-key", stem(a.get("--glider")));
  for (char c : key)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_'))
      throw InputError("--glider-key may hold only letters, digits, '-' and '_'");

  DetectOptions dopt;
  TrackOptions topt;
  const std::string det = a.get("--detector", "background");
  if (det == "background") dopt.detector = Detector::Background;
  else if (det == "marker") dopt.detector = Detector::Marker;
  else throw InputError("--detector must be background or marker");
  if (a.has("--marker-colour") || a.has("--marker-color"))
    dopt.marker_bgr = colour_option(a.has("--marker-colour") ? a.get("--marker-colour") : a.get("--marker-color"));
  if (a.has("--marker-at")) {
    topt.tracked_point_given = true;
    topt.tracked_point_m = pair_option(a, "--marker-at");
  }
  if (a.has("--threshold")) {
    dopt.threshold_sigma = a.number("--threshold", dopt.threshold_sigma);
    if (!(dopt.threshold_sigma > 0) || dopt.threshold_sigma > 100) throw InputError("--threshold must be in (0, 100]");
  }
  if (a.has("--fps")) {
    dopt.fps = a.number("--fps", 0);
    if (!(dopt.fps > 0) || dopt.fps > 10000) throw InputError("--fps must be a positive frame rate");
  }
  if (a.has("--frames")) {
    dopt.ranges = parse_frame_ranges(a.get("--frames"));
    topt.ranges = dopt.ranges;
  }
  if (a.has("--corrections")) topt.corrections = load_corrections(a.get("--corrections"));
  const std::string pitch = a.get("--pitch", "auto");
  if (pitch == "auto") topt.pitch = PitchSource::Auto;
  else if (pitch == "silhouette") topt.pitch = PitchSource::Silhouette;
  else if (pitch == "path") topt.pitch = PitchSource::Path;
  else if (pitch == "none") topt.pitch = PitchSource::None;
  else throw InputError("--pitch must be auto, silhouette, path or none");
  topt.aoa_deg = a.number("--aoa", 0.0);
  if (a.has("--gate")) {
    topt.gate_sigma = a.number("--gate", topt.gate_sigma);
    if (!(topt.gate_sigma > 0) || topt.gate_sigma > 100) throw InputError("--gate must be in (0, 100]");
  }
  if (a.has("--max-missed")) {
    const double m = a.number("--max-missed", 3);
    if (m < 0 || m > 1000 || m != std::floor(m)) throw InputError("--max-missed must be a whole number from 0");
    topt.max_missed = static_cast<int>(m);
  }
  if (a.has("--min-points")) {
    const double m = a.number("--min-points", 6);
    if (m < 6 || m > 100000 || m != std::floor(m)) throw InputError("--min-points must be a whole number of at least 6 (the spec's minimum)");
    topt.min_points = static_cast<int>(m);
  }
  if (a.has("--name")) {
    topt.name_prefix = a.get("--name");
    if (!valid_flight_prefix(topt.name_prefix))
      throw InputError("--name must be 1-100 letters, digits, '-', '_' or '.' (it names the flights in flights.csv)");
  } else {
    topt.name_prefix = (key + "-" + stem(video)).substr(0, 100);  // both parts are safe; a long file name is cut
  }

  Progress prog{"detect"};
  prog.quiet = a.flag("--quiet");
  dopt.progress = [&](int d, int t) { prog(d, t); };
  Detections d;
  try {
    d = detect(video, dopt);
  } catch (const cv::Exception& e) {
    throw InputError("cannot read video '" + video + "': OpenCV failed to decode it (" + std::string(e.err) + ")");
  }
  const TrackResult r = track_flights(d, cal, glider, topt);
  if (r.flights.empty())
    throw InputError("no flight was found in '" + video + "'" + (r.notes.empty() ? "" : " (" + r.notes.front() + ")") +
                     ": check the calibration, give --frames, or add corrections");

  const Dataset ds = write_capture_dataset(out, r, d, cal, topt, glider, key, a.flag("--append"), a.flag("--force"));
  if (!a.flag("--quiet")) {
    std::cout << "tracked " << r.flights.size() << " flight(s) in " << video << " (" << d.frames.size() << " frames, "
              << fmt(d.seconds > 0 ? d.frames.size() / d.seconds : 0, 3) << " frames/s)\n";
    for (const auto& f : r.flights)
      std::cout << "  " << f.name << ": frames " << f.first_frame << "-" << f.last_frame << ", " << f.points.size()
                << " points, " << fmt(f.mean_speed_m_s) << " m/s, noise " << fmt(f.noise_sigma_m * 1000) << " mm, ends: " << f.end
                << "\n";
    std::cout << "tracking sigma " << fmt(r.tracking_sigma_m * 1000) << " mm per coordinate (noise "
              << fmt(r.sigma_noise_m * 1000) << ", calibration " << fmt(r.sigma_calibration_m * 1000) << ", CG offset "
              << fmt(r.sigma_cg_m * 1000) << ", silhouette model " << fmt(r.sigma_model_m * 1000) << ")\n";
    for (const auto& n : r.notes) std::cout << "note: " << n << "\n";
    std::cout << "wrote " << out << "/dataset.json (" << ds.flights.size() << " flights)\n";
  }
  return 0;
}

// ---------------------------------------------------------- render-video

std::vector<KnownFlight> trajectories_from_csv(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw InputError("cannot read trajectory file '" + path + "'");
  std::string line;
  if (!std::getline(f, line)) throw InputError("trajectory file '" + path + "' is empty");
  const std::vector<std::string> cols = split_csv_line(line);
  auto col = [&](const std::string& n) {
    for (std::size_t i = 0; i < cols.size(); ++i)
      if (cols[i] == n) return static_cast<int>(i);
    return -1;
  };
  const int it = col("t_s"), ix = col("x_m"), iy = col("y_m"), ip = col("pitch_deg");
  int ig = col("launch");
  if (ig < 0) ig = col("flight");
  if (it < 0 || ix < 0 || iy < 0)
    throw InputError("trajectory file '" + path + "' needs the columns t_s, x_m, y_m (and optionally pitch_deg, launch or flight)");
  std::vector<KnownFlight> out;
  std::vector<std::string> keys;
  int ln = 1;
  while (std::getline(f, line)) {
    ++ln;
    if (line.empty() || line == "\r") continue;
    const std::vector<std::string> v = split_csv_line(line);
    auto num = [&](int i) {
      const std::string where = "trajectory file '" + path + "' line " + std::to_string(ln);
      if (i >= static_cast<int>(v.size())) throw InputError(where + ": too few columns");
      return parse_decimal(v[i], where);
    };
    const std::string k = ig >= 0 && ig < static_cast<int>(v.size()) ? v[ig] : "";
    if (keys.empty() || keys.back() != k) {
      keys.push_back(k);
      out.emplace_back();
    }
    KnownFlight& kf = out.back();
    kf.t.push_back(num(it));
    kf.x.push_back(num(ix));
    kf.y.push_back(num(iy));
    kf.pitch.push_back(ip >= 0 ? deg2rad(num(ip)) : std::nan(""));
  }
  for (auto& kf : out) {
    for (std::size_t i = 1; i < kf.t.size(); ++i)
      if (!(kf.t[i] > kf.t[i - 1])) throw InputError("trajectory file '" + path + "': times of a flight must increase");
    if (kf.t.size() < 2) throw InputError("trajectory file '" + path + "': a flight needs at least two rows");
    // no pitch column: the nose along the path
    for (std::size_t i = 0; i < kf.t.size(); ++i)
      if (!std::isfinite(kf.pitch[i])) {
        const std::size_t a = i == 0 ? 0 : i - 1, b = i + 1 < kf.t.size() ? i + 1 : i;
        kf.pitch[i] = std::atan2(kf.y[b] - kf.y[a], kf.x[b] - kf.x[a]);
      }
  }
  if (out.empty()) throw InputError("trajectory file '" + path + "' has no rows");
  return out;
}

int run_render(const std::vector<std::string>& argv) {
  const std::set<std::string> valued = {"-o", "--truth", "--points", "--camera", "--launches", "--trajectory",
                                        "--distance", "--camera-x", "--camera-y", "--hfov", "--k1", "--k2", "--noise",
                                        "--exposure", "--blur-samples", "--fps", "--size", "--marker-at", "--seed",
                                        "--click-sigma", "--grid", "--height", "--model", "--max-time", "--quality",
                                        "--marker-colour", "--marker-radius", "--tilt", "--roll", "--yaw"};
  const Args a = parse_args(argv, valued, {"--no-marker", "--quiet"});
  if (a.positional.empty()) throw InputError("missing GLIDER file (see --help)");
  if (a.positional.size() > 1) throw InputError("unexpected argument '" + a.positional[1] + "'");
  if (!a.has("-o")) throw InputError("missing -o VIDEO.avi (see --help)");
  for (const char* k : {"-o", "--truth", "--points", "--camera"})
    if (a.has(k)) check_writable(a.get(k), k);
  const Glider g = load_glider(a.positional[0]);
  const MassProperties mp = mass_properties(g);
  // flights
  std::vector<KnownFlight> flights;
  const double max_time = a.number("--max-time", 1.5);
  if (!(max_time > 0.1) || max_time > 60) throw InputError("--max-time must be between 0.1 and 60 s");
  if (a.has("--trajectory")) {
    flights = trajectories_from_csv(a.get("--trajectory"));
  } else {
    std::vector<std::pair<double, double>> launches;
    std::stringstream ss(a.get("--launches", "9,5"));
    std::string item;
    while (std::getline(ss, item, ';')) {
      double sp, cl;
      char extra;
      if (std::sscanf(item.c_str(), "%lf,%lf%c", &sp, &cl, &extra) != 2 || !(sp > 0.5 && sp < 40) || !(std::abs(cl) < 80))
        throw InputError("--launches must be SPEED,CLIMB_DEG[;SPEED,CLIMB_DEG...] with speeds in (0.5, 40) m/s, got '" + item + "'");
      launches.push_back({sp, cl});
    }
    if (launches.empty()) throw InputError("--launches is empty");
    const auto model = a.has("--model") ? load_model(a.get("--model")) : default_model();
    const MountedGlider mg = mount(g, model);
    const RigidBody body{mg.mass().mass, mg.mass().inertia};
    for (const auto& [sp, cl] : launches) {
      Launch l;
      l.speed = sp;
      l.climb_deg = cl;
      l.height = a.number("--height", 1.5);
      SimOptions so;
      so.dt = 0.002;
      so.t_max = max_time;
      const Flight f = simulate(QuasiStaticAero(mg), body, l, so, mg.aero().environment().gravity);
      KnownFlight k;
      for (const auto& s : f.samples) {
        k.t.push_back(s.t);
        k.x.push_back(s.x);
        k.y.push_back(s.y);
        k.pitch.push_back(s.pitch);
      }
      if (k.t.size() < 2) throw InputError("the simulated launch " + fmt(sp) + " m/s, " + fmt(cl) + " deg ends at once");
      flights.push_back(k);
    }
  }
  for (auto& f : flights) {  // clip to the time limit
    const double t_end = f.t.front() + max_time;
    std::size_t n = 0;
    while (n < f.t.size() && f.t[n] <= t_end) ++n;
    n = std::max<std::size_t>(n, 2);
    f.t.resize(n), f.x.resize(n), f.y.resize(n), f.pitch.resize(n);
  }
  // camera
  SyntheticCamera sc;
  if (a.has("--size")) {
    int w, h;
    char extra;
    if (std::sscanf(a.get("--size").c_str(), "%dx%d%c", &w, &h, &extra) != 2 || w < 16 || h < 16 || w > 8192 || h > 8192)
      throw InputError("--size must be WIDTHxHEIGHT, for example 1280x720");
    sc.width = w, sc.height = h;
  }
  sc.hfov_deg = a.number("--hfov", sc.hfov_deg);
  sc.k1 = a.number("--k1", sc.k1);
  sc.k2 = a.number("--k2", sc.k2);
  sc.tilt_deg = a.number("--tilt", 0);
  sc.roll_deg = a.number("--roll", 0);
  sc.yaw_deg = a.number("--yaw", 0);
  sc.position.z = a.number("--distance", 4.0);
  if (!(sc.position.z > 0.2) || sc.position.z > 200) throw InputError("--distance must be between 0.2 and 200 m");
  {
    // default: centred on the first flight's path (first 0.8 s)
    const auto& f = flights.front();
    double xmin = 1e9, xmax = -1e9;
    for (std::size_t i = 0; i < f.t.size() && f.t[i] <= f.t.front() + 0.8; ++i) xmin = std::min(xmin, f.x[i]), xmax = std::max(xmax, f.x[i]);
    sc.position.x = a.number("--camera-x", 0.5 * (xmin + xmax));
    sc.position.y = a.number("--camera-y", 1.2);
  }
  const Calibration cam = synthetic_calibration(sc);
  RenderOptions ro;
  ro.fps = a.number("--fps", 30);
  ro.noise_sigma = a.number("--noise", ro.noise_sigma);
  ro.exposure_s = a.number("--exposure", ro.exposure_s);
  ro.blur_samples = static_cast<int>(a.number("--blur-samples", ro.blur_samples));
  ro.seed = static_cast<std::uint64_t>(a.number("--seed", 1));
  ro.quality = static_cast<int>(a.number("--quality", ro.quality));
  if (ro.quality < 1 || ro.quality > 100) throw InputError("--quality must be 1 to 100");
  if (!(ro.noise_sigma >= 0) || ro.noise_sigma > 100) throw InputError("--noise must be between 0 and 100 grey levels");
  if (ro.blur_samples < 1 || ro.blur_samples > 64) throw InputError("--blur-samples must be 1 to 64");
  ro.marker = !a.flag("--no-marker");
  ro.marker_glider_m = a.has("--marker-at") ? pair_option(a, "--marker-at") : mp.cg;
  ro.marker_radius_m = a.number("--marker-radius", ro.marker_radius_m);
  if (!(ro.marker_radius_m > 0) || ro.marker_radius_m > 0.2) throw InputError("--marker-radius must be in (0, 0.2] m");
  if (a.has("--marker-colour")) ro.marker_bgr = colour_option(a.get("--marker-colour"));
  Progress prog{"render"};
  prog.quiet = a.flag("--quiet");
  ro.progress = [&](int d, int t) { prog(d, t); };
  const RenderResult rr = render_video(a.get("-o"), cam, g, flights, ro);
  if (a.has("--truth")) {
    std::ostringstream s;
    s << "flight,frame,t_s,x_m,y_m,pitch_deg,speed_m_s,u_px,v_px,marker_x_m,marker_y_m,visible\n";
    char buf[400];
    for (const auto& t : rr.truth) {
      std::snprintf(buf, sizeof buf, "%d,%d,%.6f,%.6f,%.6f,%.4f,%.4f,%.3f,%.3f,%.6f,%.6f,%d\n", t.flight, t.frame, t.t_video,
                    t.x, t.y, rad2deg(t.pitch), t.speed, t.cg_px.x, t.cg_px.y, t.marker_world.x, t.marker_world.y,
                    t.visible ? 1 : 0);
      s << buf;
    }
    write_file_atomic(a.get("--truth"), s.str());
  }
  if (a.has("--points")) {
    const std::string grid = a.get("--grid", "4x3");
    int nx, ny;
    char extra;
    if (std::sscanf(grid.c_str(), "%dx%d%c", &nx, &ny, &extra) != 2 || nx < 2 || ny < 2 || nx * ny > 400)
      throw InputError("--grid must be NXxNY (at least 2x2), for example 4x3");
    const double click = a.number("--click-sigma", 0.3);
    if (!(click >= 0) || click > 50) throw InputError("--click-sigma must be between 0 and 50 px");
    CalibrationInput pts = synthetic_reference_points(cam, nx, ny, click, ro.seed, 0.001, sc.position.z);
    pts.extra["video"] = a.get("-o");
    pts.extra["frame"] = 0;
    write_file_atomic(a.get("--points"), calibration_input_to_json(pts).dump(2) + "\n");
  }
  if (a.has("--camera")) save_calibration(cam, a.get("--camera"));
  if (!a.flag("--quiet")) {
    std::cout << "wrote " << a.get("-o") << ": " << rr.frames << " frames " << rr.width << "x" << rr.height << " at "
              << fmt(rr.fps) << " fps, " << flights.size() << " flight(s) in frames";
    for (const auto& [f0, f1] : rr.flight_frames) std::cout << " " << f0 << "-" << f1;
    std::cout << " (" << fmt(rr.seconds) << " s)\n";
    std::cout << "camera " << fmt(sc.position.z) << " m from the flight plane at x = " << fmt(sc.position.x) << " m, y = "
              << fmt(sc.position.y) << " m, focal " << fmt(cam.lens.fx, 5) << " px, k1 " << sc.k1 << ", k2 " << sc.k2 << "\n";
  }
  return 0;
}

const bool registered_calibrate = register_command(
    70, {"calibrate", 0, "camera calibration from reference points in the flight plane",
         "usage: pteromys calibrate POINTS.json -o CALIB.json [options]\n\n"
         "Fits the mapping between the video image and the flight plane (a homography, with\n"
         "radial lens distortion when enough points allow it) to reference points of known\n"
         "position (format pteromys-calib-points/1, docs/capture.md): at least 4, no three on\n"
         "a line; 6 or more for k1, 8 or more for k1 and k2. Prints the residual of every\n"
         "point in pixels and millimetres and the leave-one-out error (the accuracy to expect).\n\n"
         "options:\n"
         "  -o CALIB.json        calibration file (format pteromys-calibration/1)\n"
         "  --distortion MODEL   auto (default: chosen by leave-one-out error), none, k1, k1k2\n"
         "  --distance M         camera-to-flight-plane distance [m], measured: gives the camera pose\n"
         "                       (needed for the perspective silhouette model of 'track')\n"
         "  --focal PX           focal length [px] instead of the distance\n"
         "  --quiet              no summary\n",
         run_calibrate});

const bool registered_track = register_command(
    71, {"track", 0, "track a glider in a side-view video into a flight dataset",
         "usage: pteromys track VIDEO --calib CALIB.json --glider GLIDER.glider.json -o DATASET_DIR [options]\n\n"
         "Finds the glider in every frame (a moving silhouette against a median background, or\n"
         "a coloured marker), follows it with a Kalman filter in the flight plane, splits the\n"
         "video into launches (one flight each), moves the tracked point to the centre of\n"
         "gravity given by the glider file, and writes the flight dataset of spec/formats.md:\n"
         "DATASET_DIR/dataset.json, flights.csv, gliders/KEY.glider.json, plus tracks.csv (every\n"
         "point with its pixel, pitch and confidence) and capture.json (the run, uncertainty).\n"
         "Time t_s is frame / fps. Method, files and accuracy: docs/capture.md.\n\n"
         "options:\n"
         "  --calib FILE         calibration (pteromys calibrate) or a reference-points file\n"
         "  --glider FILE        the glider flown (its CG and silhouette)\n"
         "  -o DATASET_DIR       output directory\n"
         "  --glider-key KEY     key of the glider in the dataset (default: the file's name)\n"
         "  --frames A-B,C-D     one flight per frame range (default: launches found automatically)\n"
         "  --corrections FILE   manual corrections {\"frame\": [u, v] or null} (pteromys-corrections/1)\n"
         "  --detector NAME      background (default) or marker\n"
         "  --marker-colour C    marker colour #RRGGBB or R,G,B (default #dc1e1e)\n"
         "  --marker-at X,Y      glider-frame position of the tracked point [m] (default: the CG for\n"
         "                       a marker, the silhouette centroid otherwise)\n"
         "  --pitch SOURCE       auto (the silhouette's orientation; the path when no silhouette\n"
         "                       is seen), silhouette, path, none (the tracked point is the CG)\n"
         "  --aoa DEG            angle of attack added to the path direction for --pitch path (default 0)\n"
         "  --fps F              frame rate when the file does not state it or states it wrongly\n"
         "  --threshold K        foreground threshold in robust noise sigmas (default 6)\n"
         "  --gate K             Kalman gate in sigmas (default 5)\n"
         "  --max-missed N       frames without the glider before a flight ends (default 3)\n"
         "  --min-points N       shortest flight kept (default 6)\n"
         "  --name PREFIX        flight names PREFIX-01, ... (default KEY-VIDEONAME)\n"
         "  --append             add the flights to the dataset already in DATASET_DIR\n"
         "  --force              replace the dataset already in DATASET_DIR\n"
         "  --quiet              no progress or summary\n",
         run_track});

const bool registered_render = register_command(
    72, {"render-video", 0, "synthetic side-view video of simulated flights (test videos)",
         "usage: pteromys render-video GLIDER -o VIDEO.avi [--truth TRUTH.csv] [--points POINTS.json] [options]\n\n"
         "Simulates launches of the glider (baseline model) or reads trajectories, and renders\n"
         "them as a camera would film them from the side: the glider's plates in 3D (fuselage,\n"
         "wings seen in perspective), a marker disc on the fuselage, a textured background,\n"
         "lens distortion, motion blur, sensor noise, MJPG compression. Writes the true CG per\n"
         "frame (--truth), reference points as a person would click them (--points, for\n"
         "pteromys calibrate) and the true camera (--camera).\n\n"
         "options:\n"
         "  --launches S,C;S,C   launch speeds [m/s] and climb angles [deg] (default 9,5)\n"
         "  --trajectory CSV     flights to draw instead: columns t_s,x_m,y_m[,pitch_deg][,launch|flight]\n"
         "                       (pteromys simulate's output works)\n"
         "  --max-time S         seconds of each flight drawn (default 1.5)\n"
         "  --height M           launch height [m] (default 1.5)\n"
         "  --distance M         camera-to-flight-plane distance (default 4)\n"
         "  --camera-x M, --camera-y M   camera position (default: over the first 0.8 s, 1.2 m high)\n"
         "  --hfov DEG           horizontal field of view (default 66)\n"
         "  --k1 K, --k2 K       lens distortion (default -0.10, 0.02)\n"
         "  --tilt, --yaw, --roll DEG    camera turned away from looking straight at the plane\n"
         "  --size WxH           image size (default 1280x720)\n"
         "  --fps F              frame rate (default 30)\n"
         "  --exposure S         shutter time (default 0.004)\n"
         "  --blur-samples N     renders averaged over the exposure (default 5)\n"
         "  --noise SIGMA        sensor noise in grey levels (default 2)\n"
         "  --quality Q          JPEG quality (default 90)\n"
         "  --marker-at X,Y      marker centre, glider frame [m] (default: the CG); --no-marker\n"
         "  --marker-radius M    (default 0.012); --marker-colour C (default #dc1e1e)\n"
         "  --grid NXxNY         reference points (default 4x3); --click-sigma PX (default 0.3)\n"
         "  --seed N             background and noise (default 1)\n",
         run_render});

}  // namespace
}  // namespace pteromys::cli
