// Calibration files: reference points (pteromys-calib-points/1) and the
// calibration (pteromys-calibration/1), docs/capture.md.
#include <cmath>

#include "pteromys/capture.hpp"
#include "pteromys/io.hpp"
#include "json_reader.hpp"

namespace pteromys::capture {
using nlohmann::json;

namespace {

using R = detail::JsonReader;

json mat3_json(const Mat3& m) {
  return json::array({json::array({m[0], m[1], m[2]}), json::array({m[3], m[4], m[5]}), json::array({m[6], m[7], m[8]})});
}

Lens lens_from_json(const json& cam, const R& r, const std::string& path) {
  Lens l;
  const Mat3 k = r.mat3(r.key(cam, "camera_matrix", path), path + ".camera_matrix");
  l.fx = k[0];
  l.fy = k[4];
  l.cx = k[2];
  l.cy = k[5];
  if (!(l.fx > 0 && l.fy > 0)) r.fail(path + ".camera_matrix must have positive focal lengths");
  if (cam.contains("dist_coeffs")) {
    const json& d = cam["dist_coeffs"];
    if (!d.is_array() || d.size() > 5) r.fail(path + ".dist_coeffs must be a list of up to 5 numbers (k1, k2, p1, p2, k3)");
    for (std::size_t i = 0; i < d.size(); ++i) l.dist[i] = r.number(d[i], path + ".dist_coeffs[" + std::to_string(i) + "]");
  }
  return l;
}

}  // namespace

CalibrationInput calibration_input_from_json(const json& j, const std::string& what) {
  const R r{what + ": "};
  if (!j.is_object()) r.fail("must be a JSON object");
  if (!j.contains("format") || j["format"] != "pteromys-calib-points/1")
    r.fail("unknown format (expected \"format\": \"pteromys-calib-points/1\")");
  CalibrationInput in;
  const Vec2 size = r.pair(r.key(j, "image_size_px", ""), "image_size_px");
  if (size.x < 1 || size.y < 1 || size.x != std::floor(size.x) || size.y != std::floor(size.y) || size.x > 1e5 || size.y > 1e5)
    r.fail("image_size_px must be two positive whole numbers [width, height]");
  in.width = static_cast<int>(size.x);
  in.height = static_cast<int>(size.y);
  const json& pts = r.key(j, "points", "");
  if (!pts.is_array()) r.fail("points must be a list");
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const std::string p = "points[" + std::to_string(i) + "]";
    CalibrationPoint cp;
    cp.name = pts[i].is_object() && pts[i].contains("name") && pts[i]["name"].is_string()
                  ? pts[i]["name"].get<std::string>()
                  : "#" + std::to_string(i + 1);
    cp.world = r.pair(r.key(pts[i], "world_m", p), p + ".world_m");
    cp.image = r.pair(r.key(pts[i], "image_px", p), p + ".image_px");
    in.points.push_back(cp);
  }
  if (j.contains("distortion")) {
    if (!j["distortion"].is_string()) r.fail("distortion must be one of \"auto\", \"none\", \"k1\", \"k1k2\"");
    in.distortion = j["distortion"].get<std::string>();
    if (in.distortion != "auto" && in.distortion != "none" && in.distortion != "k1" && in.distortion != "k1k2")
      r.fail("distortion must be one of \"auto\", \"none\", \"k1\", \"k1k2\" (got \"" + in.distortion + "\")");
  }
  if (j.contains("click_sigma_px")) {
    in.click_sigma_px = r.number(j["click_sigma_px"], "click_sigma_px");
    if (!(in.click_sigma_px > 0)) r.fail("click_sigma_px must be positive");
  }
  if (j.contains("camera") && !j["camera"].is_null()) {
    const json& cam = j["camera"];
    if (!cam.is_object()) r.fail("camera must be an object");
    if (cam.contains("camera_matrix")) {
      in.lens = lens_from_json(cam, r, "camera");
      in.lens.intrinsics_known = true;
    }
    if (cam.contains("focal_px")) {
      in.focal_px = r.number(cam["focal_px"], "camera.focal_px");
      if (!(in.focal_px > 0)) r.fail("camera.focal_px must be positive");
    }
    if (cam.contains("distance_m")) {
      in.distance_m = r.number(cam["distance_m"], "camera.distance_m");
      if (!(in.distance_m > 0)) r.fail("camera.distance_m must be positive");
    }
  }
  for (const char* k : {"video", "frame", "note"})
    if (j.contains(k)) in.extra[k] = j[k];
  return in;
}

json calibration_input_to_json(const CalibrationInput& in) {
  json j;
  j["format"] = "pteromys-calib-points/1";
  j["image_size_px"] = {in.width, in.height};
  j["distortion"] = in.distortion;
  j["click_sigma_px"] = in.click_sigma_px;
  json cam = json::object();
  if (in.lens.intrinsics_known) {
    cam["camera_matrix"] = mat3_json({in.lens.fx, 0, in.lens.cx, 0, in.lens.fy, in.lens.cy, 0, 0, 1});
    cam["dist_coeffs"] = in.lens.dist;
  }
  if (in.focal_px > 0) cam["focal_px"] = in.focal_px;
  if (in.distance_m > 0) cam["distance_m"] = in.distance_m;
  if (!cam.empty()) j["camera"] = cam;
  j["points"] = json::array();
  for (const auto& p : in.points)
    j["points"].push_back({{"name", p.name}, {"world_m", {p.world.x, p.world.y}}, {"image_px", {p.image.x, p.image.y}}});
  if (in.extra.is_object())
    for (auto it = in.extra.begin(); it != in.extra.end(); ++it) j[it.key()] = it.value();
  return j;
}

CalibrationInput load_calibration_points(const std::string& path) {
  const std::string what = "calibration points file '" + path + "'";
  return calibration_input_from_json(parse_json(read_file(path), what), what);
}

json calibration_to_json(const Calibration& c) {
  json j;
  j["format"] = "pteromys-calibration/1";
  j["image_size_px"] = {c.width, c.height};
  j["homography"] = mat3_json(c.H);
  j["homography_note"] = "world (x_m, y_m, 1) -> undistorted pixel (u, v, 1), up to scale";
  j["lens"] = {{"model", c.distortion_model},
               {"camera_matrix", mat3_json({c.lens.fx, 0, c.lens.cx, 0, c.lens.fy, c.lens.cy, 0, 0, 1})},
               {"dist_coeffs", c.lens.dist},
               {"intrinsics_known", c.lens.intrinsics_known}};
  if (c.pose.known)
    j["camera"] = {{"focal_px", c.pose.focal_px},
                   {"focal_y_px", c.pose.focal_y_px},
                   {"rotation", mat3_json(c.pose.R)},
                   {"translation_m", c.pose.t},
                   {"position_m", {c.pose.centre.x, c.pose.centre.y, c.pose.centre.z}},
                   {"distance_m", c.pose.distance_m},
                   {"from", c.pose.source}};
  else
    j["camera"] = nullptr;
  json res;
  res["rms_px"] = c.rms_px;
  res["max_px"] = c.max_px;
  res["rms_m"] = num_or_null(c.rms_m);
  res["max_m"] = num_or_null(c.max_m);
  res["leave_one_out_rms_m"] = c.loo_rms_m >= 0 ? json(c.loo_rms_m) : json(nullptr);
  res["click_sigma_px"] = c.click_sigma_px;
  res["points"] = json::array();
  for (const auto& p : c.residuals) {
    json q = {{"name", p.name}, {"du_px", p.du_px}, {"dv_px", p.dv_px}, {"dx_m", num_or_null(p.dx_m)}, {"dy_m", num_or_null(p.dy_m)}};
    q["leave_one_out_m"] = p.loo_m >= 0 ? json(p.loo_m) : json(nullptr);
    res["points"].push_back(q);
  }
  if (!c.model_loo_m.empty()) {
    json m = json::object();
    for (const auto& [k, v] : c.model_loo_m) m[k] = num_or_null(v);
    res["models_leave_one_out_rms_m"] = m;
  }
  j["residual"] = res;
  j["warnings"] = c.warnings;
  j["points_input"] = calibration_input_to_json(c.input);
  return j;
}

Calibration calibration_from_json(const json& j, const std::string& what) {
  const R r{what + ": "};
  if (!j.is_object()) r.fail("must be a JSON object");
  if (!j.contains("format") || j["format"] != "pteromys-calibration/1") {
    if (j.contains("format") && j["format"] == "pteromys-calib-points/1")
      r.fail("this is a reference-points file, not a calibration: run 'pteromys calibrate' on it first");
    r.fail("unknown format (expected \"format\": \"pteromys-calibration/1\")");
  }
  Calibration c;
  const Vec2 size = r.pair(r.key(j, "image_size_px", ""), "image_size_px");
  c.width = static_cast<int>(size.x);
  c.height = static_cast<int>(size.y);
  if (c.width < 1 || c.height < 1) r.fail("image_size_px must be two positive whole numbers");
  c.H = r.mat3(r.key(j, "homography", ""), "homography");
  const json& lens = r.key(j, "lens", "");
  c.lens = lens_from_json(lens, r, "lens");
  c.distortion_model = lens.contains("model") && lens["model"].is_string() ? lens["model"].get<std::string>() : "known";
  c.lens.intrinsics_known = lens.contains("intrinsics_known") && lens["intrinsics_known"].is_boolean() &&
                            lens["intrinsics_known"].get<bool>();
  // inverse homography
  {
    const Mat3& m = c.H;
    const double det = m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) +
                       m[2] * (m[3] * m[7] - m[4] * m[6]);
    if (!std::isfinite(det) || std::abs(det) < 1e-300) r.fail("homography is singular");
    Mat3 inv = {m[4] * m[8] - m[5] * m[7], m[2] * m[7] - m[1] * m[8], m[1] * m[5] - m[2] * m[4],
                m[5] * m[6] - m[3] * m[8], m[0] * m[8] - m[2] * m[6], m[2] * m[3] - m[0] * m[5],
                m[3] * m[7] - m[4] * m[6], m[1] * m[6] - m[0] * m[7], m[0] * m[4] - m[1] * m[3]};
    double n = 0;
    for (double v : inv) n += v * v;
    n = std::sqrt(n);
    for (double& v : inv) v /= n;
    c.H_inv = inv;
  }
  if (j.contains("camera") && j["camera"].is_object()) {
    const json& cam = j["camera"];
    c.pose.known = true;
    c.pose.focal_px = r.number(r.key(cam, "focal_px", "camera"), "camera.focal_px");
    c.pose.focal_y_px = cam.contains("focal_y_px") ? r.number(cam["focal_y_px"], "camera.focal_y_px") : c.pose.focal_px;
    c.pose.R = r.mat3(r.key(cam, "rotation", "camera"), "camera.rotation");
    const json& t = r.key(cam, "translation_m", "camera");
    if (!t.is_array() || t.size() != 3) r.fail("camera.translation_m must be three numbers");
    for (int i = 0; i < 3; ++i) c.pose.t[i] = r.number(t[i], "camera.translation_m");
    const json& p = r.key(cam, "position_m", "camera");
    if (!p.is_array() || p.size() != 3) r.fail("camera.position_m must be three numbers");
    c.pose.centre = {r.number(p[0], "camera.position_m"), r.number(p[1], "camera.position_m"), r.number(p[2], "camera.position_m")};
    c.pose.distance_m = std::abs(c.pose.centre.z);
    c.pose.source = cam.contains("from") && cam["from"].is_string() ? cam["from"].get<std::string>() : "";
  }
  if (j.contains("residual") && j["residual"].is_object()) {
    const json& res = j["residual"];
    auto opt = [&](const char* k, double& dst) {
      if (res.contains(k) && res[k].is_number()) dst = res[k].get<double>();
    };
    opt("rms_px", c.rms_px);
    opt("max_px", c.max_px);
    opt("rms_m", c.rms_m);
    opt("max_m", c.max_m);
    opt("leave_one_out_rms_m", c.loo_rms_m);
    opt("click_sigma_px", c.click_sigma_px);
    if (res.contains("points") && res["points"].is_array())
      for (const auto& q : res["points"]) {
        PointResidual pr;
        if (q.contains("name") && q["name"].is_string()) pr.name = q["name"].get<std::string>();
        auto g = [&](const char* k, double& dst) {
          if (q.contains(k) && q[k].is_number()) dst = q[k].get<double>();
        };
        g("du_px", pr.du_px);
        g("dv_px", pr.dv_px);
        g("dx_m", pr.dx_m);
        g("dy_m", pr.dy_m);
        g("leave_one_out_m", pr.loo_m);
        c.residuals.push_back(pr);
      }
  }
  if (j.contains("warnings") && j["warnings"].is_array())
    for (const auto& w : j["warnings"])
      if (w.is_string()) c.warnings.push_back(w.get<std::string>());
  if (j.contains("points_input") && j["points_input"].is_object()) {
    try {
      c.input = calibration_input_from_json(j["points_input"], what + " (points_input)");
    } catch (const InputError&) {
    }
  }
  // a sanity check: the centre of the image maps to a finite world point
  try {
    const Vec2 w = image_to_world(c, {c.width / 2.0, c.height / 2.0});
    if (!std::isfinite(w.x) || !std::isfinite(w.y)) r.fail("the homography does not map the image centre into the flight plane");
  } catch (const InputError& e) {
    r.fail(std::string("the calibration cannot be used: ") + e.what());
  }
  return c;
}

Calibration load_calibration(const std::string& path) {
  const std::string what = "calibration file '" + path + "'";
  return calibration_from_json(parse_json(read_file(path), what), what);
}

void save_calibration(const Calibration& c, const std::string& path) {
  write_file_atomic(path, calibration_to_json(c).dump(2) + "\n");
}

}  // namespace pteromys::capture
