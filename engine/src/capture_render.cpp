// Synthetic side-view videos of known flights (docs/capture.md, "Test videos").
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <unistd.h>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "pteromys/io.hpp"
#include "pteromys/capture_render.hpp"
#include "pteromys/mass.hpp"

namespace pteromys::capture {
namespace {

using M3 = std::array<double, 9>;

M3 mul(const M3& a, const M3& b) {
  M3 c{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) c[3 * i + j] += a[3 * i + k] * b[3 * k + j];
  return c;
}
M3 transpose(const M3& a) { return {a[0], a[3], a[6], a[1], a[4], a[7], a[2], a[5], a[8]}; }
M3 rot_x(double a) { return {1, 0, 0, 0, std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a)}; }
M3 rot_y(double a) { return {std::cos(a), 0, std::sin(a), 0, 1, 0, -std::sin(a), 0, std::cos(a)}; }
M3 rot_z(double a) { return {std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a), 0, 0, 0, 1}; }

// Clip a polygon (x, z) to the half plane side * z >= 0 (Sutherland-Hodgman).
Polygon clip_half(const Polygon& p, int side) {
  Polygon out;
  const std::size_t n = p.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 a = p[i], b = p[(i + 1) % n];
    const double da = side * a.y, db = side * b.y;
    if (da >= 0) out.push_back(a);
    if ((da >= 0) != (db >= 0)) {
      const double s = da / (da - db);
      out.push_back({a.x + s * (b.x - a.x), 0.0});
    }
  }
  // drop repeated points
  Polygon clean;
  for (const auto& v : out)
    if (clean.empty() || std::hypot(v.x - clean.back().x, v.y - clean.back().y) > 1e-12) clean.push_back(v);
  if (clean.size() > 1 && std::hypot(clean.front().x - clean.back().x, clean.front().y - clean.back().y) < 1e-12)
    clean.pop_back();
  return clean;
}

// Procedural background: a textured wall with panels and a floor below the
// image row `floor_v` (where the world line y = 0 is seen).
cv::Mat make_background(int w, int h, std::uint64_t seed, double floor_v) {
  cv::RNG rng(seed * 7919 + 17);
  cv::Mat wall(h, w, CV_32FC3, cv::Scalar(150, 165, 175));
  for (int scale : {6, 24, 96, 320}) {
    const int sw = w / scale + 3, sh = h / scale + 3;
    cv::Mat small(sh, sw, CV_32FC3);
    rng.fill(small, cv::RNG::UNIFORM, -1.0, 1.0);
    cv::Mat big;
    cv::resize(small, big, cv::Size(sw * scale, sh * scale), 0, 0, cv::INTER_CUBIC);
    const double amp = scale == 6 ? 10 : scale == 24 ? 16 : scale == 96 ? 22 : 26;
    wall += big(cv::Rect(scale, scale, w, h)) * amp;
  }
  cv::Mat speck(h, w, CV_32FC3);
  rng.fill(speck, cv::RNG::NORMAL, 0.0, 5.0);
  cv::GaussianBlur(speck, speck, cv::Size(3, 3), 0.7);
  wall += speck;
  // vertical boards
  for (int x = rng.uniform(40, 160); x < w; x += rng.uniform(140, 260))
    cv::line(wall, {x, 0}, {x, h - 1}, cv::Scalar(95, 105, 115), 2, cv::LINE_AA);
  // posters and panels
  for (int i = 0; i < 7; ++i) {
    const int rw = rng.uniform(w / 16, w / 5), rh = rng.uniform(h / 10, h / 3);
    const int x0 = rng.uniform(0, w - rw), y0 = rng.uniform(0, h - rh);
    const cv::Scalar col(rng.uniform(30, 230), rng.uniform(30, 230), rng.uniform(30, 230));
    cv::Mat roi = wall(cv::Rect(x0, y0, rw, rh));
    cv::Mat patch(rh, rw, CV_32FC3, col);
    cv::Mat n(rh, rw, CV_32FC3);
    rng.fill(n, cv::RNG::NORMAL, 0.0, 6.0);
    patch += n;
    // a few stripes or letters-like marks on the panel
    for (int k = 0; k < 5; ++k) {
      const int yy = rng.uniform(0, rh);
      cv::line(patch, {rng.uniform(0, rw / 2), yy}, {rng.uniform(rw / 2, rw), yy},
               cv::Scalar(rng.uniform(0, 255), rng.uniform(0, 255), rng.uniform(0, 255)), rng.uniform(1, 4), cv::LINE_AA);
    }
    patch.copyTo(roi);
    cv::rectangle(wall, cv::Rect(x0, y0, rw, rh), cv::Scalar(50, 50, 50), 2, cv::LINE_AA);
  }
  // floor
  const int fv = static_cast<int>(std::floor(floor_v));
  if (fv < h) {
    const int y0 = std::max(0, fv);
    cv::Mat floor(h - y0, w, CV_32FC3, cv::Scalar(70, 105, 135));
    cv::Mat n(h - y0, w, CV_32FC3);
    rng.fill(n, cv::RNG::NORMAL, 0.0, 9.0);
    cv::GaussianBlur(n, n, cv::Size(9, 3), 3.0, 0.8);
    floor += n * 2.0;
    for (int y = rng.uniform(3, 20); y < h - y0; y += rng.uniform(14, 40))
      cv::line(floor, {0, y}, {w - 1, y}, cv::Scalar(45, 70, 95), 1, cv::LINE_AA);
    floor.copyTo(wall(cv::Rect(0, y0, w, h - y0)));
  }
  cv::Mat out;
  wall.convertTo(out, CV_8UC3);
  return out;
}

struct Interp {
  const KnownFlight& f;
  // CG, pitch at time t (linear interpolation, clamped to the flight)
  void at(double t, double& x, double& y, double& pitch) const {
    const auto& ts = f.t;
    if (t <= ts.front()) {
      x = f.x.front(), y = f.y.front(), pitch = f.pitch.front();
      return;
    }
    if (t >= ts.back()) {
      x = f.x.back(), y = f.y.back(), pitch = f.pitch.back();
      return;
    }
    const std::size_t i = std::upper_bound(ts.begin(), ts.end(), t) - ts.begin();
    const double s = (t - ts[i - 1]) / (ts[i] - ts[i - 1]);
    x = f.x[i - 1] + s * (f.x[i] - f.x[i - 1]);
    y = f.y[i - 1] + s * (f.y[i] - f.y[i - 1]);
    pitch = f.pitch[i - 1] + s * (f.pitch[i] - f.pitch[i - 1]);
  }
};

// Image polygon of a world polygon, edges subdivided so that distortion bends them.
std::vector<cv::Point2d> project_polygon(const Calibration& cam, const std::vector<Point3>& poly) {
  std::vector<cv::Point2d> out;
  const std::size_t n = poly.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Point3 a = poly[i], b = poly[(i + 1) % n];
    const Vec2 pa = project_point(cam, a), pb = project_point(cam, b);
    if (!std::isfinite(pa.x) || !std::isfinite(pb.x)) return {};
    const int m = std::max(1, static_cast<int>(std::ceil(std::hypot(pb.x - pa.x, pb.y - pa.y) / 4.0)));
    out.emplace_back(pa.x, pa.y);
    for (int k = 1; k < m; ++k) {
      const double s = static_cast<double>(k) / m;
      const Vec2 q = project_point(cam, {a.x + s * (b.x - a.x), a.y + s * (b.y - a.y), a.z + s * (b.z - a.z)});
      out.emplace_back(q.x, q.y);
    }
  }
  return out;
}

}  // namespace

Calibration synthetic_calibration(const SyntheticCamera& cam) {
  if (cam.width < 16 || cam.height < 16) throw InputError("the synthetic camera needs an image of at least 16 x 16 pixels");
  if (!(cam.hfov_deg > 1 && cam.hfov_deg < 170)) throw InputError("the field of view must be between 1 and 170 degrees");
  if (!(cam.position.z > 0)) throw InputError("the synthetic camera must be in front of the flight plane (position z > 0)");
  Calibration c;
  c.width = cam.width;
  c.height = cam.height;
  const double f = 0.5 * cam.width / std::tan(deg2rad(cam.hfov_deg) / 2);
  c.lens.fx = c.lens.fy = f;
  c.lens.cx = (cam.width - 1) / 2.0 + cam.cx_offset_px;
  c.lens.cy = (cam.height - 1) / 2.0 + cam.cy_offset_px;
  c.lens.dist = {cam.k1, cam.k2, 0, 0, 0};
  c.lens.intrinsics_known = true;
  c.distortion_model = "known";
  // Camera axes in the world (columns): x right = +x, y down = -y, z forward = -z,
  // then turned: yaw about the vertical, tilt about x, roll about the optical axis.
  const M3 base = {1, 0, 0, 0, -1, 0, 0, 0, -1};
  const M3 c2w = mul(mul(mul(rot_y(-deg2rad(cam.yaw_deg)), rot_x(deg2rad(cam.tilt_deg))), base), rot_z(deg2rad(cam.roll_deg)));
  const M3 R = transpose(c2w);
  const std::array<double, 3> t = {-(R[0] * cam.position.x + R[1] * cam.position.y + R[2] * cam.position.z),
                                   -(R[3] * cam.position.x + R[4] * cam.position.y + R[5] * cam.position.z),
                                   -(R[6] * cam.position.x + R[7] * cam.position.y + R[8] * cam.position.z)};
  c.pose.known = true;
  c.pose.focal_px = c.pose.focal_y_px = f;
  c.pose.R = R;
  c.pose.t = t;
  c.pose.centre = cam.position;
  c.pose.distance_m = std::abs(cam.position.z);
  c.pose.source = "synthetic";
  c.H = plane_homography(R, t, f, c.lens.cx, c.lens.cy);
  // inverse
  const Mat3& m = c.H;
  Mat3 inv = {m[4] * m[8] - m[5] * m[7], m[2] * m[7] - m[1] * m[8], m[1] * m[5] - m[2] * m[4],
              m[5] * m[6] - m[3] * m[8], m[0] * m[8] - m[2] * m[6], m[2] * m[3] - m[0] * m[5],
              m[3] * m[7] - m[4] * m[6], m[1] * m[6] - m[0] * m[7], m[0] * m[4] - m[1] * m[3]};
  double n = 0;
  for (double v : inv) n += v * v;
  for (double& v : inv) v /= std::sqrt(n);
  c.H_inv = inv;
  return c;
}

CalibrationInput synthetic_reference_points(const Calibration& truth, int nx, int ny, double click_sigma_px,
                                            std::uint64_t seed, double round_m, double distance_m) {
  if (nx < 2 || ny < 2) throw InputError("the reference grid needs at least 2 x 2 points");
  CalibrationInput in;
  in.width = truth.width;
  in.height = truth.height;
  in.click_sigma_px = std::max(click_sigma_px, 0.05);
  in.distance_m = distance_m;
  std::mt19937_64 gen(seed * 104729 + 3);
  std::normal_distribution<double> noise(0.0, click_sigma_px);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const Vec2 px{truth.width * (0.08 + 0.84 * i / (nx - 1.0)), truth.height * (0.08 + 0.84 * j / (ny - 1.0))};
      Vec2 w = image_to_world(truth, px);
      if (round_m > 0) w = {std::round(w.x / round_m) * round_m, std::round(w.y / round_m) * round_m};
      Vec2 im = world_to_image(truth, w);
      im.x += noise(gen);
      im.y += noise(gen);
      char name[32];
      std::snprintf(name, sizeof name, "r%dc%d", j + 1, i + 1);
      in.points.push_back({name, w, im});
    }
  return in;
}

std::vector<Plate3> glider_plates(const Glider& g) {
  std::vector<Plate3> out;
  Plate3 fus;
  for (const auto& v : g.fuselage) fus.outline.push_back({v.x, v.y, 0.0});
  out.push_back(fus);
  for (std::size_t j = 0; j < g.wings.size(); ++j) {
    const auto& w = g.wings[j];
    const double c = std::cos(deg2rad(w.mount.angle_deg)), s = std::sin(deg2rad(w.mount.angle_deg));
    for (int side : {-1, 1}) {
      const Polygon half = clip_half(w.outline, side);
      if (half.size() < 3) continue;
      Plate3 p;
      p.wing = static_cast<int>(j);
      p.side = side;
      for (const auto& v : half) p.outline.push_back({w.mount.x_m + c * v.x, w.mount.y_m + s * v.x, v.y});
      out.push_back(p);
    }
  }
  return out;
}

Point3 glider_to_world(Point3 p, Vec2 cg_glider, Vec2 cg_world, double beta) {
  const Vec2 r = rotate({p.x - cg_glider.x, p.y - cg_glider.y}, beta);
  return {cg_world.x + r.x, cg_world.y + r.y, p.z};
}

RenderResult render_video(const std::string& path, const Calibration& cam, const Glider& g,
                          const std::vector<KnownFlight>& flights, const RenderOptions& opt) {
  const auto clock0 = std::chrono::steady_clock::now();
  if (!cam.pose.known) throw InputError("rendering needs a camera with a known pose");
  if (!(opt.fps > 0 && opt.fps <= 1000)) throw InputError("the frame rate must be in (0, 1000] frames per second");
  if (!(opt.exposure_s >= 0 && opt.exposure_s <= 1.0 / opt.fps)) throw InputError("the exposure must be between 0 and one frame");
  if (opt.fourcc.size() != 4) throw InputError("the codec must be a four-character code such as MJPG");
  if (!(opt.wing_shade >= 0 && opt.wing_shade <= 1.5)) throw InputError("the wing shade must be between 0 and 1.5");
  if (flights.empty()) throw InputError("no flight to render");
  for (const auto& f : flights) {
    if (f.t.size() < 2 || f.x.size() != f.t.size() || f.y.size() != f.t.size() || f.pitch.size() != f.t.size())
      throw InputError("a flight to render needs at least two samples with t, x, y and pitch each");
    for (std::size_t i = 0; i < f.t.size(); ++i) {
      if (!std::isfinite(f.t[i]) || !std::isfinite(f.x[i]) || !std::isfinite(f.y[i]) || !std::isfinite(f.pitch[i]))
        throw InputError("a flight to render has a value that is not a finite number");
      if (i > 0 && !(f.t[i] > f.t[i - 1])) throw InputError("the times of a flight to render must increase");
    }
  }
  const MassProperties mp = mass_properties(g);
  const std::vector<Plate3> plates = glider_plates(g);
  const int near_side = cam.pose.centre.z >= 0 ? 1 : -1;
  // painter's order: far half wings, fuselage, marker, near half wings
  std::vector<int> order;
  for (std::size_t i = 0; i < plates.size(); ++i)
    if (plates[i].side == -near_side) order.push_back(static_cast<int>(i));
  order.push_back(0);
  order.push_back(-1);  // marker
  for (std::size_t i = 0; i < plates.size(); ++i)
    if (plates[i].side == near_side) order.push_back(static_cast<int>(i));
  std::vector<Point3> marker;
  if (opt.marker) {
    const double zf = near_side * g.material.thickness_m / 2;
    for (int k = 0; k < 40; ++k) {
      const double a = 2 * kPi * k / 40;
      marker.push_back({opt.marker_glider_m.x + opt.marker_radius_m * std::cos(a),
                        opt.marker_glider_m.y + opt.marker_radius_m * std::sin(a), zf});
    }
  }
  // frame schedule
  RenderResult res;
  res.width = cam.width;
  res.height = cam.height;
  res.fps = opt.fps;
  int frame = opt.lead_frames;
  std::vector<int> first(flights.size());
  for (std::size_t i = 0; i < flights.size(); ++i) {
    const auto& f = flights[i];
    first[i] = frame;
    const int n = static_cast<int>(std::floor((f.t.back() - f.t.front() - opt.phase_s) * opt.fps)) + 1;
    res.flight_frames.push_back({frame, frame + std::max(n, 1) - 1});
    frame += std::max(n, 1) + opt.gap_frames;
  }
  res.frames = res.flight_frames.back().second + 1 + opt.tail_frames;
  // background: the floor where the world line y = 0 is seen at the image centre column
  double floor_v = cam.height + 10.0;
  {
    const Vec2 w0 = image_to_world(cam, {cam.width / 2.0, cam.height / 2.0});
    const Vec2 p = world_to_image(cam, {w0.x, 0.0});
    if (std::isfinite(p.y)) floor_v = p.y;
  }
  const cv::Mat background = make_background(cam.width, cam.height, opt.seed, floor_v);
  // writer (to a temporary file, renamed at the end)
  const auto dot = path.find_last_of('.');
  const auto slash = path.find_last_of('/');
  const std::string ext = dot != std::string::npos && (slash == std::string::npos || dot > slash) ? path.substr(dot) : "";
  const std::string tmp = temp_path_for(path, ext);
  const int fourcc = cv::VideoWriter::fourcc(opt.fourcc[0], opt.fourcc[1], opt.fourcc[2], opt.fourcc[3]);
  cv::VideoWriter writer;
  const cv::Size size(cam.width, cam.height);
  if (opt.fourcc == "MJPG") writer.open(tmp, cv::CAP_OPENCV_MJPEG, fourcc, opt.fps, size, true);
  if (!writer.isOpened()) writer.open(tmp, cv::CAP_FFMPEG, fourcc, opt.fps, size, true);
  if (!writer.isOpened()) {
    std::remove(tmp.c_str());
    throw InputError("cannot write the video '" + path + "' with codec " + opt.fourcc +
                     " (directory missing or not writable, or codec not supported for this file type)");
  }
  writer.set(cv::VIDEOWRITER_PROP_QUALITY, opt.quality);
  cv::RNG rng(opt.seed * 31 + 5);
  cv::Mat frame_img, noise(cam.height, cam.width, CV_16SC3), acc;
  const cv::Scalar glider_col(opt.glider_bgr[0], opt.glider_bgr[1], opt.glider_bgr[2]);
  const cv::Scalar wing_col = glider_col * opt.wing_shade;
  const cv::Scalar marker_col(opt.marker_bgr[0], opt.marker_bgr[1], opt.marker_bgr[2]);
  const int S = std::max(1, opt.blur_samples);
  try {
    std::size_t fi = 0;
    for (int k = 0; k < res.frames; ++k) {
      background.copyTo(frame_img);
      while (fi < flights.size() && k > res.flight_frames[fi].second) ++fi;
      if (fi < flights.size() && k >= res.flight_frames[fi].first) {
        const KnownFlight& f = flights[fi];
        const Interp ip{f};
        const double tc = f.t.front() + opt.phase_s + (k - first[fi]) / opt.fps;
        // polygons of every sub-sample
        std::vector<std::vector<std::pair<std::vector<cv::Point2d>, cv::Scalar>>> layers(S);
        double x0 = 1e18, y0 = 1e18, x1 = -1e18, y1 = -1e18;
        for (int s = 0; s < S; ++s) {
          const double ts = S == 1 ? tc : tc + opt.exposure_s * ((s + 0.5) / S - 0.5);
          double x, y, pitch;
          ip.at(ts, x, y, pitch);
          for (int idx : order) {
            std::vector<Point3> wp;
            cv::Scalar col;
            if (idx == -1) {
              if (marker.empty()) continue;
              for (const auto& q : marker) wp.push_back(glider_to_world(q, mp.cg, {x, y}, pitch));
              col = marker_col;
            } else {
              for (const auto& q : plates[idx].outline) wp.push_back(glider_to_world(q, mp.cg, {x, y}, pitch));
              col = plates[idx].wing < 0 ? glider_col : wing_col;
            }
            auto poly = project_polygon(cam, wp);
            if (poly.size() < 3) continue;
            for (const auto& p : poly) {
              x0 = std::min(x0, p.x), y0 = std::min(y0, p.y);
              x1 = std::max(x1, p.x), y1 = std::max(y1, p.y);
            }
            layers[s].push_back({std::move(poly), col});
          }
        }
        const cv::Rect roi = cv::Rect(static_cast<int>(std::floor(x0)) - 2, static_cast<int>(std::floor(y0)) - 2,
                                      static_cast<int>(std::ceil(x1 - x0)) + 5, static_cast<int>(std::ceil(y1 - y0)) + 5) &
                             cv::Rect(0, 0, cam.width, cam.height);
        if (roi.area() > 0 && x1 > x0) {
          cv::Mat bg;
          background(roi).convertTo(bg, CV_32FC3);
          acc = cv::Mat::zeros(roi.size(), CV_32FC3);
          // Coverage by 4 x 4 supersampling: a plain fill of sub-pixel centres,
          // averaged over each pixel (OpenCV's anti-aliased fill is off by up
          // to 0.2 px and inflates small polygons).
          const int ss = 4;
          cv::Mat hi(roi.height * ss, roi.width * ss, CV_8U), a, a3;
          for (int s = 0; s < S; ++s) {
            cv::Mat layer = bg.clone();
            for (const auto& [poly, col] : layers[s]) {
              std::vector<cv::Point> pts;
              for (const auto& p : poly)  // pixel centre i of the image = sub-pixel centre ss i + (ss - 1) / 2
                pts.emplace_back(static_cast<int>(std::lround(((p.x - roi.x) * ss + 0.5 * (ss - 1)) * 256)),
                                 static_cast<int>(std::lround(((p.y - roi.y) * ss + 0.5 * (ss - 1)) * 256)));
              hi.setTo(0);
              cv::fillPoly(hi, std::vector<std::vector<cv::Point>>{pts}, cv::Scalar(255), cv::LINE_8, 8);
              cv::resize(hi, a, roi.size(), 0, 0, cv::INTER_AREA);
              a.convertTo(a, CV_32F, 1.0 / 255);
              cv::merge(std::vector<cv::Mat>{a, a, a}, a3);
              cv::Mat colour(roi.size(), CV_32FC3, col);
              const cv::Mat keep = cv::Scalar::all(1.0) - a3;
              layer = layer.mul(keep) + colour.mul(a3);
            }
            acc += layer * (1.0 / S);
          }
          acc.convertTo(frame_img(roi), CV_8UC3);
        }
        TruthFrame tf;
        tf.flight = static_cast<int>(fi);
        tf.frame = k;
        tf.t_video = k / opt.fps;
        tf.t_flight = tc;
        ip.at(tc, tf.x, tf.y, tf.pitch);
        double xa, ya, pa, xb, yb, pb;
        const double h = 1e-3;
        ip.at(tc - h, xa, ya, pa);
        ip.at(tc + h, xb, yb, pb);
        tf.speed = std::hypot(xb - xa, yb - ya) / (2 * h);
        const Point3 cgw{tf.x, tf.y, 0.0};
        tf.cg_px = project_point(cam, cgw);
        const Point3 mw = glider_to_world({opt.marker_glider_m.x, opt.marker_glider_m.y, 0.0}, mp.cg, {tf.x, tf.y}, tf.pitch);
        tf.marker_world = {mw.x, mw.y};
        tf.visible = std::isfinite(tf.cg_px.x) && tf.cg_px.x >= 0 && tf.cg_px.y >= 0 && tf.cg_px.x <= cam.width - 1 &&
                     tf.cg_px.y <= cam.height - 1;
        res.truth.push_back(tf);
      }
      if (opt.flicker != 0) {
        const double gain = 1.0 + opt.flicker * std::sin(2 * kPi * 0.173 * k);
        frame_img.convertTo(frame_img, -1, gain);
      }
      if (opt.noise_sigma > 0) {
        rng.fill(noise, cv::RNG::NORMAL, 0.0, opt.noise_sigma);
        cv::add(frame_img, noise, frame_img, cv::noArray(), CV_8UC3);
      }
      writer.write(frame_img);
      if (opt.progress) opt.progress(k + 1, res.frames);
    }
    writer.release();
  } catch (...) {
    writer.release();
    std::remove(tmp.c_str());
    throw;
  }
  // OpenCV's writer does not report write errors (a full disk, a size
  // limit): read the video back and count its frames before it replaces
  // anything.
  {
    cv::VideoCapture check(tmp);
    int n = 0;
    cv::Mat f;
    while (check.isOpened() && check.read(f)) ++n;
    if (n != res.frames) {
      std::remove(tmp.c_str());
      throw InputError("cannot write the video '" + path + "': it holds " + std::to_string(n) + " of " +
                       std::to_string(res.frames) +
                       " frames when read back (a full disk or a file size limit?); the old file, if any, is unchanged");
    }
  }
  commit_temp_file(tmp, path);
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - clock0).count();
  return res;
}

}  // namespace pteromys::capture
