// Tracking files: corrections (pteromys-corrections/1), frame ranges,
// tracks.csv and capture.json (docs/capture.md).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <sys/stat.h>

#include "pteromys/io.hpp"
#include "pteromys/track.hpp"

namespace pteromys::capture {
using nlohmann::json;

std::map<int, Correction> corrections_from_json(const json& j, const std::string& what) {
  if (!j.is_object()) throw InputError(what + ": must be a JSON object {\"frame\": [u, v] or null}");
  const json* m = &j;
  if (j.contains("format")) {
    if (j["format"] != "pteromys-corrections/1")
      throw InputError(what + ": unknown format (expected \"pteromys-corrections/1\")");
    if (!j.contains("corrections") || !j["corrections"].is_object())
      throw InputError(what + ": missing object 'corrections' {\"frame\": [u, v] or null}");
    m = &j["corrections"];
  }
  std::map<int, Correction> out;
  for (auto it = m->begin(); it != m->end(); ++it) {
    const std::string& k = it.key();
    char* end = nullptr;
    const long f = std::strtol(k.c_str(), &end, 10);
    if (k.empty() || *end != '\0' || f < 0 || f > 100000000)
      throw InputError(what + ": '" + k + "' is not a frame number (keys are frame indices from 0)");
    Correction c;
    const json& v = it.value();
    if (v.is_null()) {
      c.absent = true;
    } else {
      if (!v.is_array() || v.size() != 2 || !v[0].is_number() || !v[1].is_number())
        throw InputError(what + ": frame " + k + " must be [u, v] in pixels, or null when the glider is not visible");
      c.px = {v[0].get<double>(), v[1].get<double>()};
      if (!std::isfinite(c.px.x) || !std::isfinite(c.px.y))
        throw InputError(what + ": frame " + k + " has a coordinate that is not a finite number");
    }
    out[static_cast<int>(f)] = c;
  }
  return out;
}

json corrections_to_json(const std::map<int, Correction>& c, const std::string& video) {
  json m = json::object();
  for (const auto& [f, x] : c) m[std::to_string(f)] = x.absent ? json(nullptr) : json::array({x.px.x, x.px.y});
  return {{"format", "pteromys-corrections/1"}, {"video", video}, {"corrections", m}};
}

std::map<int, Correction> load_corrections(const std::string& path) {
  const std::string what = "corrections file '" + path + "'";
  return corrections_from_json(parse_json(read_file(path), what), what);
}

std::vector<FrameRange> parse_frame_ranges(const std::string& text) {
  std::vector<FrameRange> out;
  std::stringstream ss(text);
  std::string part;
  while (std::getline(ss, part, ',')) {
    while (!part.empty() && part.front() == ' ') part.erase(part.begin());
    while (!part.empty() && part.back() == ' ') part.pop_back();
    if (part.empty()) continue;
    const auto dash = part.find('-');
    auto num = [&](const std::string& s) {
      char* end = nullptr;
      const long v = std::strtol(s.c_str(), &end, 10);
      if (s.empty() || *end != '\0' || v < 0 || v > 100000000)
        throw InputError("frame range '" + part + "' must be FIRST-LAST with frame numbers from 0 (for example 30-75)");
      return static_cast<int>(v);
    };
    if (dash == std::string::npos) throw InputError("frame range '" + part + "' must be FIRST-LAST (for example 30-75)");
    const int a = num(part.substr(0, dash)), b = num(part.substr(dash + 1));
    if (b < a) throw InputError("frame range '" + part + "' ends before it starts");
    out.push_back({a, b});
  }
  if (out.empty()) throw InputError("no frame range given (for example --frames 30-75,120-160)");
  std::sort(out.begin(), out.end());
  for (std::size_t i = 1; i < out.size(); ++i)
    if (out[i].first <= out[i - 1].second)
      throw InputError("frame ranges " + std::to_string(out[i - 1].first) + "-" + std::to_string(out[i - 1].second) + " and " +
                       std::to_string(out[i].first) + "-" + std::to_string(out[i].second) + " overlap");
  return out;
}

std::string tracks_csv(const TrackResult& r, const std::string& video) {
  std::string v = video;
  for (char& c : v)
    if (c == ',' || c == '\n' || c == '"') c = '_';
  std::ostringstream s;
  s << "flight,video,frame,t_s,u_px,v_px,x_tracked_m,y_tracked_m,x_m,y_m,pitch_deg,confidence,source\n";
  char buf[512];
  for (const auto& f : r.flights)
    for (const auto& p : f.points) {
      std::snprintf(buf, sizeof buf, "%s,%s,%d,%.6f,%.3f,%.3f,%.5f,%.5f,%.5f,%.5f,%.3f,%.3f,%s\n", f.name.c_str(), v.c_str(),
                    p.frame, p.t, p.px.x, p.px.y, p.tracked.x, p.tracked.y, p.cg.x, p.cg.y, p.pitch_deg, p.confidence,
                    p.manual ? "manual" : "auto");
      s << buf;
    }
  return s.str();
}

json track_summary_json(const TrackResult& r, const Detections& d, const Calibration& c, const TrackOptions& o,
                        const std::string& key) {
  json j;
  j["format"] = "pteromys-capture/1";
  j["video"] = d.video;
  j["image_size_px"] = {d.width, d.height};
  j["frame_rate_hz"] = d.fps;
  j["frames"] = d.frame_count;
  j["frames_processed"] = d.frames.size();
  j["detector"] = d.detector == Detector::Background ? "background" : "marker";
  j["detection_seconds"] = d.seconds;
  j["detection_fps"] = d.seconds > 0 ? d.frames.size() / d.seconds : 0.0;
  j["glider"] = key;
  j["pitch_source"] = r.pitch_source;
  j["tracked_point_glider_m"] = {r.tracked_point_m.x, r.tracked_point_m.y};
  j["cg_glider_m"] = {r.cg_glider_m.x, r.cg_glider_m.y};
  j["silhouette_model"] = d.detector == Detector::Background && !o.tracked_point_given
                              ? (r.perspective_model ? "perspective" : "side view")
                              : "none";
  j["aoa_deg"] = o.aoa_deg;
  j["corrections"] = o.corrections.size();
  j["sigma_m"] = {{"noise", r.sigma_noise_m},
                  {"calibration", r.sigma_calibration_m},
                  {"cg_offset", r.sigma_cg_m},
                  {"silhouette_model", r.sigma_model_m},
                  {"total", r.tracking_sigma_m}};
  j["calibration"] = {{"rms_px", c.rms_px},
                      {"rms_m", c.rms_m},
                      {"leave_one_out_rms_m", c.loo_rms_m >= 0 ? json(c.loo_rms_m) : json(nullptr)},
                      {"distortion", c.distortion_model},
                      {"camera_distance_m", c.pose.known ? json(c.pose.distance_m) : json(nullptr)}};
  j["flights"] = json::array();
  for (const auto& f : r.flights) {
    int manual = 0;
    double conf = 1;
    for (const auto& p : f.points) manual += p.manual, conf = std::min(conf, p.confidence);
    j["flights"].push_back({{"name", f.name},
                            {"video", d.video},
                            {"first_frame", f.first_frame},
                            {"last_frame", f.last_frame},
                            {"points", f.points.size()},
                            {"manual_points", manual},
                            {"missed_frames", f.missed},
                            {"min_confidence", conf},
                            {"mean_speed_m_s", f.mean_speed_m_s},
                            {"noise_sigma_m", f.noise_sigma_m},
                            {"sigma_m", f.sigma_m},
                            {"end", f.end}});
  }
  j["notes"] = r.notes;
  return j;
}

namespace {
bool is_file(const std::string& p) {
  struct stat st {};
  return stat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}
std::string base_stem(const std::string& path) {
  const std::string b = file_stem(path);
  return b.empty() ? "video" : b;
}
}  // namespace

Dataset write_capture_dataset(const std::string& dir, const TrackResult& r, const Detections& d, const Calibration& c,
                              const TrackOptions& o, const Glider& g, const std::string& key, bool append, bool replace) {
  if (r.flights.empty()) throw InputError("there is no flight to write");
  if (key.empty()) throw InputError("the glider key is empty");
  for (char ch : key)
    if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '-' || ch == '_'))
      throw InputError("the glider key may hold only letters, digits, '-' and '_'");
  const bool exists = is_file(dir + "/dataset.json");
  if (exists && !append && !replace)
    throw InputError("'" + dir + "' already holds a dataset: append these flights to it, or replace it");
  Dataset ds = tracks_to_dataset(r, g, key, d.fps);
  json runs = json::array();
  std::string old_tracks;
  if (exists && append) {
    const Dataset prev = load_dataset(dir + "/dataset.json");
    if (std::abs(prev.frame_rate_hz - d.fps) > 1e-6 * d.fps)
      throw InputError("the dataset in '" + dir + "' has a frame rate of " + std::to_string(prev.frame_rate_hz) +
                       " Hz but the video has " + std::to_string(d.fps) + " Hz: one dataset holds one frame rate");
    if (prev.gliders.count(key) && glider_to_json(prev.gliders.at(key)).dump() != glider_to_json(g).dump())
      throw InputError("glider key '" + key + "' already names a different glider in '" + dir + "': choose another key");
    for (const auto& f : prev.flights)
      for (const auto& n : ds.flights)
        if (f.name == n.name)
          throw InputError("flight '" + n.name + "' is already in '" + dir + "' (was this video added before?): choose other names");
    if (is_file(dir + "/capture.json")) {
      const json old = parse_json(read_file(dir + "/capture.json"), "'" + dir + "/capture.json'");
      if (old.contains("runs") && old["runs"].is_array()) runs = old["runs"];
    }
    if (is_file(dir + "/tracks.csv")) old_tracks = read_file(dir + "/tracks.csv");
    double n_old = 0, n_new = 0;
    for (const auto& f : prev.flights) n_old += f.points.size();
    for (const auto& f : r.flights) n_new += f.points.size();
    Dataset merged = prev;
    merged.gliders[key] = g;
    if (!merged.glider_files.count(key)) merged.glider_files[key] = "gliders/" + key + ".glider.json";
    for (const auto& col : ds.extra_columns)
      if (std::find(merged.extra_columns.begin(), merged.extra_columns.end(), col) == merged.extra_columns.end())
        merged.extra_columns.push_back(col);
    for (const auto& f : ds.flights) merged.flights.push_back(f);
    merged.tracking_sigma_m = std::sqrt((n_old * prev.tracking_sigma_m * prev.tracking_sigma_m +
                                         n_new * ds.tracking_sigma_m * ds.tracking_sigma_m) / (n_old + n_new));
    ds = merged;
  }
  const auto problems = dataset_problems(ds);
  if (!problems.empty()) throw InputError("cannot write the dataset: " + problems.front());
  runs.push_back(track_summary_json(r, d, c, o, key));
  std::string tracks = tracks_csv(r, base_stem(d.video));
  if (!old_tracks.empty() && old_tracks.find('\n') != std::string::npos)
    tracks = old_tracks + tracks.substr(tracks.find('\n') + 1);
  // tracks.csv and capture.json first, dataset.json (written by save_dataset) last
  {
    struct stat st {};
    if (stat(dir.c_str(), &st) != 0 && mkdir(dir.c_str(), 0755) != 0)
      throw InputError("cannot create directory '" + dir + "'");
  }
  write_file_atomic(dir + "/tracks.csv", tracks);
  write_file_atomic(dir + "/capture.json", json({{"format", "pteromys-capture/1"}, {"runs", runs}}).dump(2) + "\n");
  save_dataset(ds, dir);
  return ds;
}

}  // namespace pteromys::capture
