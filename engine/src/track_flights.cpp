// Stage 2 of tracking: candidates -> flights of the centre of gravity
// (docs/capture.md, "Association", "Centre of gravity", "Uncertainty").
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include <Eigen/Dense>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "pteromys/capture_render.hpp"
#include "pteromys/geometry.hpp"
#include "pteromys/io.hpp"
#include "pteromys/mass.hpp"
#include "pteromys/track.hpp"

namespace pteromys::capture {
namespace {

using Vec4 = Eigen::Matrix<double, 4, 1>;
using Mat4 = Eigen::Matrix<double, 4, 4>;
using Mat2 = Eigen::Matrix2d;

double wrap_half_pi(double a) {  // into (-pi/2, pi/2]
  while (a > kPi / 2) a -= kPi;
  while (a <= -kPi / 2) a += kPi;
  return a;
}

struct Obs {
  int frame = 0;
  double t = 0;
  Vec2 px, w;
  Mat2 R;  // measurement covariance in the plane [m^2]
  int cand = -1;  // index into the frame's candidates; -1 manual
  double area = 0, angle_deg = 0, elongation = 1;
  double confidence = 1;
  bool manual = false;
};

struct Kalman {
  Vec4 x;
  Mat4 P;
  void predict(double dt, double q) {
    Mat4 F = Mat4::Identity();
    F(0, 2) = F(1, 3) = dt;
    Mat4 Q = Mat4::Zero();
    const double a = dt * dt * dt * dt / 4, b = dt * dt * dt / 2, c = dt * dt;
    Q(0, 0) = Q(1, 1) = a;
    Q(0, 2) = Q(2, 0) = Q(1, 3) = Q(3, 1) = b;
    Q(2, 2) = Q(3, 3) = c;
    x = F * x;
    P = F * P * F.transpose() + q * Q;
  }
  // squared Mahalanobis distance of a measurement
  double d2(const Eigen::Vector2d& z, const Mat2& R) const {
    const Eigen::Vector2d nu = z - x.head<2>();
    const Mat2 S = P.topLeftCorner<2, 2>() + R;
    return nu.dot(S.ldlt().solve(nu));
  }
  void update(const Eigen::Vector2d& z, const Mat2& R) {
    Eigen::Matrix<double, 2, 4> H = Eigen::Matrix<double, 2, 4>::Zero();
    H(0, 0) = H(1, 1) = 1;
    const Mat2 S = H * P * H.transpose() + R;
    const Eigen::Matrix<double, 4, 2> K = P * H.transpose() * S.inverse();
    x += K * (z - H * x);
    P = (Mat4::Identity() - K * H) * P;
    P = 0.5 * (P + P.transpose());
  }
};

// Local quadratic fit of y(t) over a window of +-k points: smoothed value,
// slope, and the smoother's row (for the exact residual variance).
struct LocalFit {
  std::vector<double> value, slope;
  double tr = 0;  // trace of (I - S)(I - S)^T
};
LocalFit local_quadratic(const std::vector<double>& t, const std::vector<double>& y, int k) {
  const int n = static_cast<int>(t.size());
  LocalFit f;
  f.value.resize(n);
  f.slope.resize(n);
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    int a = std::max(0, i - k), b = std::min(n - 1, i + k);
    while (b - a + 1 < std::min(n, 2 * k + 1)) {  // full windows at the ends
      if (a > 0) --a;
      else if (b < n - 1) ++b;
      else break;
    }
    const int m = b - a + 1;
    const int deg = std::min(2, m - 1);
    Eigen::MatrixXd A(m, deg + 1);
    for (int j = 0; j < m; ++j) {
      const double dt = t[a + j] - t[i];
      double p = 1;
      for (int d = 0; d <= deg; ++d) A(j, d) = p, p *= dt;
    }
    const Eigen::MatrixXd pinv = (A.transpose() * A).ldlt().solve(A.transpose());  // (deg+1) x m
    double v = 0, s = 0;
    for (int j = 0; j < m; ++j) {
      v += pinv(0, j) * y[a + j];
      if (deg >= 1) s += pinv(1, j) * y[a + j];
      S(i, a + j) = pinv(0, j);
    }
    f.value[i] = v;
    f.slope[i] = s;
  }
  const Eigen::MatrixXd IS = Eigen::MatrixXd::Identity(n, n) - S;
  f.tr = (IS * IS.transpose()).trace();
  return f;
}

// The glider's silhouette seen through a calibrated camera with a known pose.
struct SilhouetteModel {
  const Calibration* cal = nullptr;
  std::vector<Plate3> plates;
  Vec2 cg_g;
  int s = 1;  // +1: the glider flies toward +x (world), -1 toward -x
  // Centroid and principal-axis angle (image, counter-clockwise from +u) of
  // the silhouette, and where the CG is seen, for a CG at `cg` and pitch `beta`.
  bool view(Vec2 cg, double beta, Vec2& centroid, double& angle_deg, Vec2& cg_px) const {
    std::vector<std::vector<cv::Point2d>> polys;
    double x0 = 1e18, y0 = 1e18, x1 = -1e18, y1 = -1e18;
    for (const auto& p : plates) {
      std::vector<cv::Point2d> q;
      for (const auto& v : p.outline) {
        const Vec2 r = rotate({v.x - cg_g.x, v.y - cg_g.y}, beta);
        const Vec2 px = project_point(*cal, {cg.x + s * r.x, cg.y + r.y, s * v.z});
        if (!std::isfinite(px.x)) return false;
        q.emplace_back(px.x, px.y);
        x0 = std::min(x0, px.x), y0 = std::min(y0, px.y), x1 = std::max(x1, px.x), y1 = std::max(y1, px.y);
      }
      polys.push_back(std::move(q));
    }
    const double sc = 4.0;  // supersampling
    const int W = static_cast<int>(std::ceil((x1 - x0) * sc)) + 4, H = static_cast<int>(std::ceil((y1 - y0) * sc)) + 4;
    if (W > 4000 || H > 4000 || W < 1 || H < 1) return false;
    cv::Mat m = cv::Mat::zeros(H, W, CV_8U);
    std::vector<std::vector<cv::Point>> ip;
    for (const auto& q : polys) {
      std::vector<cv::Point> r;
      for (const auto& p : q)
        r.emplace_back(static_cast<int>(std::lround(((p.x - x0) * sc + 2) * 16)), static_cast<int>(std::lround(((p.y - y0) * sc + 2) * 16)));
      ip.push_back(std::move(r));
    }
    // plain fill of pixel centres at 4x: coverage to 1/4 px without the bias of anti-aliased filling
    for (const auto& r : ip) cv::fillPoly(m, std::vector<std::vector<cv::Point>>{r}, cv::Scalar(255), cv::LINE_8, 4);
    const cv::Moments mo = cv::moments(m, true);
    if (mo.m00 <= 0) return false;
    const double cu = mo.m10 / mo.m00, cv_ = mo.m01 / mo.m00;
    centroid = {(cu - 2) / sc + x0, (cv_ - 2) / sc + y0};
    const double a = 0.5 * std::atan2(2 * mo.mu11, mo.mu20 - mo.mu02);
    angle_deg = -rad2deg(a);
    cg_px = project_point(*cal, {cg.x, cg.y, 0.0});
    return true;
  }
};

Mat2 meas_cov(const Calibration& c, Vec2 px, double sigma_px) {
  const auto J = world_per_pixel(c, px);
  Mat2 j;
  j << J[0], J[1], J[2], J[3];
  return j * j.transpose() * (sigma_px * sigma_px);
}

// World direction angle (mod pi) of an image direction at `px` given as an
// angle counter-clockwise on screen from +u [deg].
double world_axis_angle(const Calibration& c, Vec2 px, double angle_deg) {
  const auto J = world_per_pixel(c, px);
  const double a = deg2rad(angle_deg);
  const double du = std::cos(a), dv = -std::sin(a);
  return std::atan2(J[2] * du + J[3] * dv, J[0] * du + J[1] * dv);
}

}  // namespace

Vec2 silhouette_centroid_glider(const Glider& g) {
  const AreaMoments f = area_moments(g.fuselage);
  double A = f.A, Sx = f.Sx, Sy = f.Sy;
  // wings seen edge-on: a band of the plate thickness along the chord
  for (const auto& w : g.wings) {
    double xmin = 1e9, xmax = -1e9;
    for (const auto& v : w.outline) xmin = std::min(xmin, v.x), xmax = std::max(xmax, v.x);
    const double a = (xmax - xmin) * g.material.thickness_m;
    const Vec2 mid = rotate({0.5 * (xmin + xmax), 0.0}, deg2rad(w.mount.angle_deg));
    A += a;
    Sx += a * (w.mount.x_m + mid.x);
    Sy += a * (w.mount.y_m + mid.y);
  }
  return {Sx / A, Sy / A};
}

bool valid_flight_prefix(const std::string& prefix) {
  return !prefix.empty() && prefix.size() <= 100 && safe_name(prefix, "-_.") == prefix;
}

TrackResult track_flights(const Detections& d, const Calibration& cal, const Glider& g, const TrackOptions& o) {
  if (d.width != cal.width || d.height != cal.height)
    throw InputError("the video is " + std::to_string(d.width) + "x" + std::to_string(d.height) +
                     " pixels but the calibration was made for " + std::to_string(cal.width) + "x" +
                     std::to_string(cal.height) + " images");
  if (!(d.fps > 0)) throw InputError("the video's frame rate is unknown");
  if (o.min_points < 2) throw InputError("min_points must be at least 2");
  if (!valid_flight_prefix(o.name_prefix))
    throw InputError("the flight name prefix '" + o.name_prefix + "' must be 1-100 letters, digits, '-', '_' or '.' "
                     "(it names the flights in flights.csv)");
  if (o.max_missed < 0 || o.smooth_half_window < 1) throw InputError("max_missed must be >= 0 and the smoothing window >= 1");
  if (!(o.gate_sigma > 0 && o.accel_sigma_m_s2 > 0 && o.pixel_sigma > 0)) throw InputError("gating parameters must be positive");
  if (!std::isfinite(o.aoa_deg) || std::abs(o.aoa_deg) > 45) throw InputError("the angle of attack must be between -45 and 45 degrees");
  for (const auto& [f, c] : o.corrections) {
    if (f < 0 || f >= d.frame_count)
      throw InputError("a correction is given for frame " + std::to_string(f) + " but the video has frames 0 to " +
                       std::to_string(d.frame_count - 1));
    if (!c.absent && (!std::isfinite(c.px.x) || !std::isfinite(c.px.y) || c.px.x < -0.5 || c.px.y < -0.5 ||
                      c.px.x > d.width - 0.5 || c.px.y > d.height - 0.5))
      throw InputError("the correction of frame " + std::to_string(f) + " is outside the image");
  }
  for (const auto& [a, b] : o.ranges)
    if (a < 0 || b < a || b >= d.frame_count)
      throw InputError("frame range " + std::to_string(a) + "-" + std::to_string(b) + " is not inside the video (frames 0 to " +
                       std::to_string(d.frame_count - 1) + ")");

  TrackResult res;
  const MassProperties mp = mass_properties(g);
  res.cg_glider_m = mp.cg;
  const bool background = d.detector == Detector::Background;
  bool have_silhouettes = background;
  for (const auto& f : d.frames) have_silhouettes |= !f.silhouettes.empty();
  PitchSource ps = o.pitch;
  if (ps == PitchSource::Auto) ps = have_silhouettes ? PitchSource::Silhouette : PitchSource::Path;
  if (ps == PitchSource::Silhouette && !have_silhouettes)
    throw InputError("the pitch can come from the silhouette only when silhouettes were detected (use pitch from the path)");
  res.pitch_source = ps == PitchSource::Silhouette ? "silhouette" : ps == PitchSource::Path ? "path" : "none";
  const bool model_centroid = background && !o.tracked_point_given && ps != PitchSource::None;
  res.perspective_model = model_centroid && cal.pose.known;
  Vec2 ref = o.tracked_point_given ? o.tracked_point_m : background ? silhouette_centroid_glider(g) : mp.cg;
  if (ps == PitchSource::None) ref = mp.cg;
  res.tracked_point_m = ref;
  const double dt_frame = 1.0 / d.fps;
  const double q = o.accel_sigma_m_s2 * o.accel_sigma_m_s2;
  const double fus_area = std::abs(signed_area(g.fuselage));

  // frames and corrections on one timeline
  std::map<int, const FrameCandidates*> by_frame;
  for (const auto& f : d.frames) by_frame[f.frame] = &f;
  std::set<int> timeline;
  for (const auto& f : d.frames) timeline.insert(f.frame);
  for (const auto& [f, c] : o.corrections) timeline.insert(f);
  std::vector<int> frames(timeline.begin(), timeline.end());

  // candidates in the plane
  struct WCand {
    Vec2 w;
    Mat2 R;
    bool ok = false;
    double area_ratio = 1;  // area / expected
  };
  std::map<int, std::vector<WCand>> wc;
  for (const auto& f : d.frames) {
    auto& v = wc[f.frame];
    for (const auto& c : f.candidates) {
      WCand x;
      try {
        x.w = image_to_world(cal, c.px);
        x.R = meas_cov(cal, c.px, o.pixel_sigma);
        // a blob cut by the image border has a biased centroid: not used
        x.ok = std::isfinite(x.w.x) && std::isfinite(x.w.y) && !c.clipped;
        if (background) {
          const auto J = world_per_pixel(cal, c.px);
          const double px_area = std::abs(J[0] * J[3] - J[1] * J[2]);  // m^2 per px
          x.area_ratio = c.area_px * px_area / fus_area;
        }
      } catch (const InputError&) {
        x.ok = false;
      }
      v.push_back(x);
    }
  }
  auto area_ok = [&](const WCand& c) {
    return !background || (c.area_ratio >= 1.0 / o.area_ratio_max && c.area_ratio <= o.area_ratio_max);
  };
  auto has_corr = [&](int f) { return o.corrections.count(f) > 0; };
  auto manual_obs = [&](int f) {
    Obs ob;
    ob.frame = f;
    ob.t = f * dt_frame;
    ob.px = o.corrections.at(f).px;
    ob.w = image_to_world(cal, ob.px);
    ob.R = meas_cov(cal, ob.px, 1.0);
    ob.manual = true;
    ob.confidence = 1;
    return ob;
  };
  auto cand_obs = [&](int f, int i, double conf) {
    const FrameCandidates& fc = *by_frame.at(f);
    const auto& c = fc.candidates[i];
    const auto& w = wc.at(f)[i];
    Obs ob;
    ob.frame = f;
    ob.t = f * dt_frame;
    ob.px = c.px;
    ob.w = w.w;
    ob.R = w.R;
    ob.cand = i;
    ob.area = c.area_px;
    ob.angle_deg = c.angle_deg;
    ob.elongation = c.elongation;
    ob.confidence = conf;
    if (!background) {
      // the orientation is the silhouette's around the marker (largest one holding it)
      ob.elongation = 1.0;
      double best = 0;
      for (const auto& sc : fc.silhouettes)
        if (!sc.clipped && c.px.x >= sc.x0 - 2 && c.px.x <= sc.x1 + 2 && c.px.y >= sc.y0 - 2 && c.px.y <= sc.y1 + 2 &&
            sc.area_px > best) {
          best = sc.area_px;
          ob.angle_deg = sc.angle_deg;
          ob.elongation = sc.elongation;
        }
    }
    return ob;
  };
  auto n_cands = [&](int f) { return by_frame.count(f) ? static_cast<int>(by_frame.at(f)->candidates.size()) : 0; };

  // Starts a flight at frames[i]: three consecutive frames with a candidate
  // moving at a plausible, nearly constant velocity. Returns the points.
  // Options for a frame while starting a flight: the manual point when the
  // frame is corrected (none when marked absent), else the usable candidates.
  auto options = [&](int f) {
    std::vector<Obs> v;
    if (has_corr(f)) {
      if (!o.corrections.at(f).absent) v.push_back(manual_obs(f));
      return v;
    }
    for (int c = 0; c < n_cands(f); ++c)
      if (wc[f][c].ok && area_ok(wc[f][c])) v.push_back(cand_obs(f, c, 0.8));
    return v;
  };
  auto area_ratio = [](const Obs& a, const Obs& b) {
    if (a.manual || b.manual || a.area <= 0 || b.area <= 0) return 1.0;
    return b.area / a.area;
  };
  // Starts a flight at frames[i]: four consecutive frames with a point
  // moving at a plausible speed with a nearly constant acceleration.
  auto acquire = [&](std::size_t i, std::size_t end_i) -> std::vector<Obs> {
    if (i + 3 >= end_i) return {};
    const int f0 = frames[i], f1 = frames[i + 1], f2 = frames[i + 2], f3 = frames[i + 3];
    if (f1 != f0 + 1 || f2 != f0 + 2 || f3 != f0 + 3) return {};
    const auto O0 = options(f0), O1 = options(f1), O2 = options(f2), O3 = options(f3);
    double best = std::numeric_limits<double>::infinity();
    std::vector<Obs> out;
    for (const auto& A : O0)
      for (const auto& B : O1) {
        const double sp = std::hypot(B.w.x - A.w.x, B.w.y - A.w.y) / dt_frame;
        if (sp < o.min_speed_m_s || sp > o.max_speed_m_s) continue;
        const double ar = area_ratio(A, B);
        if (ar < 0.5 || ar > 2.0) continue;
        const Vec2 pred{2 * B.w.x - A.w.x, 2 * B.w.y - A.w.y};
        for (const auto& C : O2) {
          const double e = std::hypot(C.w.x - pred.x, C.w.y - pred.y);
          const double meas = std::sqrt(std::max(C.R.trace(), 1e-12));
          const double tol = 1.5 * o.accel_sigma_m_s2 * dt_frame * dt_frame + 6 * meas;
          if (e >= tol) continue;
          // a fourth frame must confirm: constant acceleration from the three
          const Vec2 acc{C.w.x - 2 * B.w.x + A.w.x, C.w.y - 2 * B.w.y + A.w.y};
          const Vec2 pred3{C.w.x + (C.w.x - B.w.x) + acc.x, C.w.y + (C.w.y - B.w.y) + acc.y};
          for (const auto& D : O3) {
            const double e3 = std::hypot(D.w.x - pred3.x, D.w.y - pred3.y);
            // and move on over the four frames: a static object whose centroid
            // flickers between two spots (a poster's edge) goes back and forth
            const double net = std::hypot(D.w.x - A.w.x, D.w.y - A.w.y) / (3 * dt_frame);
            const double same_way = (B.w.x - A.w.x) * (D.w.x - C.w.x) + (B.w.y - A.w.y) * (D.w.y - C.w.y);
            if (net < o.min_speed_m_s || same_way <= 0) continue;
            if (e3 < 2 * tol && e + e3 < best) best = e + e3, out = {A, B, C, D};
          }
        }
      }
    return out;
  };

  struct Raw {
    std::vector<Obs> pts;
    std::string end;
    int first = 0, last = 0;
  };
  std::vector<Raw> raws;

  // Tracks frames[i0 .. i1) as one episode list. In range mode everything
  // between i0 and i1 is one flight; otherwise each confirmed track is one.
  auto run = [&](std::size_t i0, std::size_t i1, bool one_flight) {
    Raw cur;
    bool tracking = false;
    Kalman kf;
    int missed = 0, slow = 0, last_frame = -1;
    auto finish = [&](const std::string& why) {
      if (!one_flight) {
        if (!cur.pts.empty()) {
          cur.end = why;
          raws.push_back(cur);
        }
        cur = Raw();
      }
      tracking = false;
      missed = slow = 0;
    };
    auto start_from = [&](const std::vector<Obs>& pts) {
      for (const auto& p : pts) cur.pts.push_back(p);
      const Obs& a = pts.front();
      const Obs& b = pts.back();
      kf.x << b.w.x, b.w.y, 0, 0;
      kf.P = Mat4::Zero();
      kf.P.topLeftCorner<2, 2>() = b.R;
      if (pts.size() >= 2) {
        const Obs& c = pts[pts.size() - 2];
        const double dt = b.t - c.t;
        kf.x(2) = (b.w.x - c.w.x) / dt;
        kf.x(3) = (b.w.y - c.w.y) / dt;
        kf.P.bottomRightCorner<2, 2>() = (b.R + c.R) / (dt * dt) + Mat2::Identity() * q * dt * dt;
      } else {
        kf.P.bottomRightCorner<2, 2>() = Mat2::Identity() * 100.0;  // unknown velocity (10 m/s)
      }
      (void)a;
      tracking = true;
      missed = slow = 0;
      last_frame = b.frame;
    };
    for (std::size_t i = i0; i < i1; ++i) {
      const int f = frames[i];
      if (!tracking) {
        const auto pts = acquire(i, i1);
        if (!pts.empty()) {
          start_from(pts);
          i += pts.size() - 1;
        } else if (has_corr(f) && !o.corrections.at(f).absent) {
          start_from({manual_obs(f)});  // a click alone starts a flight
        }
        continue;
      }
      kf.predict((f - last_frame) * dt_frame, q);
      last_frame = f;
      bool got = false;
      if (has_corr(f)) {
        if (!o.corrections.at(f).absent) {
          const Obs ob = manual_obs(f);
          kf.update({ob.w.x, ob.w.y}, ob.R);
          // a click fixes the position, not the velocity: keep the gate open
          // for the automatic points after it (1 m/s more velocity doubt)
          kf.P.bottomRightCorner<2, 2>() += Mat2::Identity();
          cur.pts.push_back(ob);
          got = true;
        }
      } else {
        int best = -1, inside = 0;
        double bd = std::numeric_limits<double>::infinity();
        for (int c = 0; c < n_cands(f); ++c) {
          const auto& C = wc[f][c];
          if (!C.ok || !area_ok(C)) continue;
          const double d2 = kf.d2({C.w.x, C.w.y}, C.R);
          if (d2 < o.gate_sigma * o.gate_sigma) {
            ++inside;
            if (d2 < bd) bd = d2, best = c;
          }
        }
        if (best >= 0) {
          const double conf = std::exp(-bd / 18.0) * (inside > 1 ? 0.6 : 1.0);
          const Obs ob = cand_obs(f, best, conf);
          kf.update({ob.w.x, ob.w.y}, ob.R);
          cur.pts.push_back(ob);
          got = true;
        }
      }
      if (got) {
        missed = 0;
        const double sp = std::hypot(kf.x(2), kf.x(3));
        slow = sp < o.stop_speed_m_s ? slow + 1 : 0;
        if (slow >= 3 && !one_flight) {
          // landed: keep the points up to the first slow one
          cur.pts.resize(cur.pts.size() - 2);
          finish("landed");
        }
        continue;
      }
      ++missed;
      // left the image?
      bool outside = false;
      try {
        const Vec2 p = world_to_image(cal, {kf.x(0), kf.x(1)});
        outside = !(p.x > -0.02 * d.width && p.y > -0.02 * d.height && p.x < 1.02 * d.width && p.y < 1.02 * d.height);
      } catch (const InputError&) {
        outside = true;
      }
      if (outside) finish("left the image");
      else if (missed > o.max_missed) finish("lost");
    }
    if (one_flight) {
      cur.end = "range end";
      raws.push_back(cur);
    } else if (tracking) {
      finish(i1 == frames.size() ? "video end" : "range end");
    }
  };

  // Scatter of a track about a smooth path, and the limit beyond which it is
  // not a glider (5 px and 1.5 cm): a glider moves smoothly.
  auto scatter = [&](const std::vector<Obs>& pts, double& limit) {
    const int n = static_cast<int>(pts.size());
    std::vector<double> t(n), x(n), y(n);
    double mpp = 0;
    for (int i = 0; i < n; ++i) {
      t[i] = pts[i].t, x[i] = pts[i].w.x, y[i] = pts[i].w.y;
      const auto J = world_per_pixel(cal, pts[i].px);
      mpp += std::sqrt(std::abs(J[0] * J[3] - J[1] * J[2])) / n;
    }
    limit = std::max(0.015, 5 * mpp);
    const int k = std::max(1, o.smooth_half_window);
    const LocalFit fx = local_quadratic(t, x, k), fy = local_quadratic(t, y, k);
    double ss = 0;
    for (int i = 0; i < n; ++i) ss += std::pow(x[i] - fx.value[i], 2) + std::pow(y[i] - fy.value[i], 2);
    return fx.tr + fy.tr > 1e-9 ? std::sqrt(ss / (fx.tr + fy.tr)) : 0.0;
  };
  // Associate; tracks that scatter like noise are dropped, their candidates
  // banned, and the association run again (the glider may have been missed
  // while a noise track held the filter).
  for (int attempt = 0; attempt < 5; ++attempt) {
    raws.clear();
    if (o.ranges.empty()) {
      run(0, frames.size(), false);
    } else {
      for (const auto& [a, b] : o.ranges) {
        std::size_t i0 = std::lower_bound(frames.begin(), frames.end(), a) - frames.begin();
        std::size_t i1 = std::upper_bound(frames.begin(), frames.end(), b) - frames.begin();
        const std::size_t before = raws.size();
        run(i0, i1, true);
        for (std::size_t k = before; k < raws.size(); ++k) raws[k].first = a, raws[k].last = b;
      }
    }
    bool banned = false;
    for (auto& raw : raws) {
      if (static_cast<int>(raw.pts.size()) < std::max(o.min_points, 3)) continue;
      bool manual = false;
      for (const auto& p : raw.pts) manual |= p.manual;
      if (manual) continue;
      // a flight goes somewhere: over its whole duration at least the
      // slowest launch speed accepted (a landed or static object does not)
      if (o.ranges.empty()) {
        const Obs& a = raw.pts.front();
        const Obs& b = raw.pts.back();
        const double net = std::hypot(b.w.x - a.w.x, b.w.y - a.w.y) / std::max(b.t - a.t, 1e-9);
        if (net < o.min_speed_m_s) {
          for (const auto& p : raw.pts)
            if (p.cand >= 0) wc[p.frame][p.cand].ok = false;
          res.notes.push_back("frames " + std::to_string(a.frame) + "-" + std::to_string(b.frame) +
                              ": a track was left out, it moves " + std::to_string(int(std::lround(net * 100)) / 100.0).substr(0, 4) +
                              " m/s on average (a static object, not a glider?)");
          raw.pts.clear();
          banned = true;
          continue;
        }
      }
      double limit = 0;
      const double sc = scatter(raw.pts, limit);
      if (sc <= limit) continue;
      for (const auto& p : raw.pts)
        if (p.cand >= 0) wc[p.frame][p.cand].ok = false;
      res.notes.push_back("frames " + std::to_string(raw.pts.front().frame) + "-" + std::to_string(raw.pts.back().frame) +
                          ": a track was left out, its points scatter by " + std::to_string(int(std::lround(sc * 1000))) +
                          " mm about a smooth path (not a glider?)");
      raw.pts.clear();
      banned = true;
    }
    if (!banned) break;
  }

  // ------------------------------------------------ flights, pitch and CG
  SilhouetteModel model;
  model.cal = &cal;
  model.plates = glider_plates(g);
  model.cg_g = mp.cg;
  const Vec2 offset_g{mp.cg.x - ref.x, mp.cg.y - ref.y};
  // axis of the side silhouette in the glider frame (orthographic)
  double phi0 = 0;
  {
    const AreaMoments m = area_moments(g.fuselage);
    const double cx = m.Sx / m.A, cy = m.Sy / m.A;
    const double mxx = m.Sxx / m.A - cx * cx, myy = m.Syy / m.A - cy * cy, mxy = m.Sxy / m.A - cx * cy;
    phi0 = 0.5 * std::atan2(2 * mxy, mxx - myy);
  }
  const double pitch_sigma = deg2rad(o.pitch_sigma_deg >= 0 ? o.pitch_sigma_deg : ps == PitchSource::Silhouette ? 3.0 : 5.0);
  int flight_no = 0;
  double mpp_sum = 0;
  int mpp_n = 0;
  for (auto& raw : raws) {
    auto& pts = raw.pts;
    if (static_cast<int>(pts.size()) < o.min_points) {
      if (!pts.empty())
        res.notes.push_back("frames " + std::to_string(pts.front().frame) + "-" + std::to_string(pts.back().frame) +
                            ": a track of " + std::to_string(pts.size()) + " points was left out (fewer than " +
                            std::to_string(o.min_points) + ")");
      else if (!o.ranges.empty())
        res.notes.push_back("frames " + std::to_string(raw.first) + "-" + std::to_string(raw.last) + ": no glider found");
      continue;
    }
    const int n = static_cast<int>(pts.size());
    std::vector<double> t(n), x(n), y(n);
    for (int i = 0; i < n; ++i) t[i] = pts[i].t, x[i] = pts[i].w.x, y[i] = pts[i].w.y;
    const int k = std::max(1, o.smooth_half_window);
    LocalFit fx = local_quadratic(t, x, k), fy = local_quadratic(t, y, k);
    double vx_mean = 0;
    for (int i = 0; i < n; ++i) vx_mean += fx.slope[i];
    const int s = vx_mean >= 0 ? 1 : -1;
    model.s = s;
    // pitch per point
    std::vector<double> beta(n, 0.0), path(n);
    for (int i = 0; i < n; ++i) path[i] = std::atan2(fy.slope[i], s * fx.slope[i]);
    if (ps == PitchSource::Path) {
      for (int i = 0; i < n; ++i) beta[i] = path[i] + deg2rad(o.aoa_deg);
    } else if (ps == PitchSource::Silhouette) {
      std::vector<double> raw_b(n);
      for (int i = 0; i < n; ++i) {
        const Obs& p = pts[i];
        if (p.manual || p.elongation < 1.6) {
          raw_b[i] = std::numeric_limits<double>::quiet_NaN();
          continue;
        }
        const double phi_w = world_axis_angle(cal, p.px, p.angle_deg);
        // the axis in the glider's own (mirrored when s = -1) frame, mod pi
        const double phi_g = std::atan2(std::sin(phi_w), s * std::cos(phi_w));
        double b = wrap_half_pi(phi_g - phi0 - path[i]) + path[i];
        if (res.perspective_model) {
          // the pitch at which the projected model shows the measured axis
          // (fixed-point iteration: the model's axis turns with the pitch)
          for (int it = 0; it < 4; ++it) {
            Vec2 cen, cgp;
            double ang;
            const Vec2 cg_guess{p.w.x + s * rotate(offset_g, b).x, p.w.y + rotate(offset_g, b).y};
            if (!model.view(cg_guess, b, cen, ang, cgp)) break;
            const double dphi = wrap_half_pi(phi_w - world_axis_angle(cal, cen, ang));
            b += s * dphi;
            if (std::abs(dphi) < 1e-4) break;
          }
        }
        raw_b[i] = b;
      }
      // smooth the pitch over time (points without a usable silhouette take the fit)
      std::vector<double> tt, bb;
      for (int i = 0; i < n; ++i)
        if (std::isfinite(raw_b[i])) tt.push_back(t[i]), bb.push_back(raw_b[i]);
      if (tt.size() >= 3) {
        const LocalFit fb = local_quadratic(tt, bb, k);
        for (int i = 0; i < n; ++i) {
          // nearest smoothed value in time (linear interpolation)
          const auto it = std::lower_bound(tt.begin(), tt.end(), t[i]);
          if (it == tt.begin()) beta[i] = fb.value.front() + fb.slope.front() * (t[i] - tt.front());
          else if (it == tt.end()) beta[i] = fb.value.back() + fb.slope.back() * (t[i] - tt.back());
          else {
            const std::size_t j = it - tt.begin();
            const double a = (t[i] - tt[j - 1]) / (tt[j] - tt[j - 1]);
            beta[i] = fb.value[j - 1] + a * (fb.value[j] - fb.value[j - 1]);
          }
        }
      } else {
        for (int i = 0; i < n; ++i) beta[i] = path[i];
        res.notes.push_back("flight at frames " + std::to_string(pts.front().frame) + "-" + std::to_string(pts.back().frame) +
                            ": silhouette too small or round for its orientation; pitch from the path");
      }
    }
    // tracked point -> CG
    FlightTrack ft;
    ft.name = o.name_prefix + "-" + (flight_no + 1 < 10 ? "0" : "") + std::to_string(flight_no + 1);
    ++flight_no;
    ft.first_frame = o.ranges.empty() ? pts.front().frame : raw.first;
    ft.last_frame = o.ranges.empty() ? pts.back().frame : raw.last;
    ft.end = raw.end;
    for (int i = 0; i < n; ++i) {
      const Obs& p = pts[i];
      TrackPoint tp;
      tp.frame = p.frame;
      tp.t = p.t;
      tp.px = p.px;
      tp.tracked = p.w;
      tp.confidence = p.confidence;
      tp.manual = p.manual;
      tp.area_px = p.area;
      tp.pitch_deg = rad2deg(beta[i]);
      if (ps == PitchSource::None) {
        tp.cg = p.w;
      } else if (res.perspective_model && !p.manual) {
        // silhouette centroid -> CG through the projected model (two passes)
        Vec2 cg{p.w.x + s * rotate(offset_g, beta[i]).x, p.w.y + rotate(offset_g, beta[i]).y};
        for (int it = 0; it < 3; ++it) {
          Vec2 cen, cgp;
          double ang;
          if (!model.view(cg, beta[i], cen, ang, cgp)) break;
          cg = image_to_world(cal, {p.px.x + cgp.x - cen.x, p.px.y + cgp.y - cen.y});
        }
        tp.cg = cg;
      } else {
        const Vec2 r = rotate(offset_g, beta[i]);
        tp.cg = {p.w.x + s * r.x, p.w.y + r.y};
      }
      if (s < 0) tp.cg.x = -tp.cg.x, tp.tracked.x = -tp.tracked.x;
      ft.points.push_back(tp);
    }
    // noise from the residual of the smooth fit of the CG track
    std::vector<double> cx(n), cy(n);
    for (int i = 0; i < n; ++i) cx[i] = ft.points[i].cg.x, cy[i] = ft.points[i].cg.y;
    const LocalFit gx = local_quadratic(t, cx, k), gy = local_quadratic(t, cy, k);
    double ss = 0;
    for (int i = 0; i < n; ++i) ss += std::pow(cx[i] - gx.value[i], 2) + std::pow(cy[i] - gy.value[i], 2);
    const double tr = gx.tr + gy.tr;
    ft.noise_sigma_m = tr > 1e-9 ? std::sqrt(ss / tr) : 0.0;
    for (const auto& p : pts) {
      const auto J = world_per_pixel(cal, p.px);
      mpp_sum += std::sqrt(std::abs(J[0] * J[3] - J[1] * J[2]));
      ++mpp_n;
    }
    if (s < 0)
      res.notes.push_back(ft.name + ": the glider flies toward -x of the calibration; its x is mirrored (x -> -x) so that "
                          "x points along the flight");
    double sp = 0;
    for (int i = 0; i < n; ++i) sp += std::hypot(gx.slope[i], gy.slope[i]);
    ft.mean_speed_m_s = sp / n;
    ft.missed = (ft.last_frame - ft.first_frame + 1) - n;
    res.flights.push_back(ft);
  }
  // uncertainty components (per coordinate)
  {
    double num = 0, den = 0;
    for (const auto& f : res.flights) {
      const double w = static_cast<double>(f.points.size());
      num += w * f.noise_sigma_m * f.noise_sigma_m;
      den += w;
    }
    res.sigma_noise_m = den > 0 ? std::sqrt(num / den) : 0.0;
    const double mpp = mpp_n > 0 ? mpp_sum / mpp_n : 0.0;
    const double click = cal.click_sigma_px * mpp / std::sqrt(2.0);
    res.sigma_calibration_m = std::max(cal.loo_rms_m >= 0 ? cal.loo_rms_m / std::sqrt(2.0) : cal.rms_m / std::sqrt(2.0), click);
    const double arm = std::hypot(offset_g.x, offset_g.y);
    res.sigma_cg_m = ps == PitchSource::None ? 0.0 : arm * pitch_sigma / std::sqrt(2.0);
    if (model_centroid && !cal.pose.known) {
      // wings seen 15 degrees from edge-on shift the silhouette centroid by
      // this much; a typical error when the camera distance is unknown
      double A = std::abs(signed_area(g.fuselage));
      const Vec2 c0 = silhouette_centroid_glider(g);
      double Sx = A * c0.x, Sy = A * c0.y;
      for (const auto& w : g.wings) {
        const AreaMoments m = area_moments(w.outline);
        const double a = std::abs(m.A) * std::sin(deg2rad(15.0));
        const Vec2 mid = rotate({m.Sx / m.A, 0.0}, deg2rad(w.mount.angle_deg));
        A += a;
        Sx += a * (w.mount.x_m + mid.x);
        Sy += a * (w.mount.y_m + mid.y);
      }
      res.sigma_model_m = std::hypot(Sx / A - c0.x, Sy / A - c0.y) / std::sqrt(2.0);
      res.notes.push_back("the camera distance is unknown: the silhouette centroid is modelled as seen straight from the "
                          "side; give camera.distance_m (or focal_px) in the calibration points for the perspective model");
    }
    const double sys2 = res.sigma_calibration_m * res.sigma_calibration_m + res.sigma_cg_m * res.sigma_cg_m +
                        res.sigma_model_m * res.sigma_model_m;
    res.tracking_sigma_m = std::sqrt(res.sigma_noise_m * res.sigma_noise_m + sys2);
    for (auto& f : res.flights) f.sigma_m = std::sqrt(f.noise_sigma_m * f.noise_sigma_m + sys2);
  }
  // doubtful points
  for (const auto& f : res.flights) {
    int low = 0;
    for (const auto& p : f.points) low += p.confidence < 0.3;
    if (low > 0) res.notes.push_back(f.name + ": " + std::to_string(low) + " point(s) with low confidence (< 0.3): check them");
  }
  return res;
}

Dataset tracks_to_dataset(const TrackResult& r, const Glider& g, const std::string& key, double fps) {
  Dataset d;
  d.glider_files[key] = "gliders/" + key + ".glider.json";
  d.gliders[key] = g;
  d.frame_rate_hz = fps;
  d.tracking_sigma_m = std::max(r.tracking_sigma_m, 1e-4);
  d.extra_columns = {"first_frame", "last_frame", "flight_sigma_m"};
  for (const auto& f : r.flights) {
    TrackedFlight tf;
    tf.name = f.name;
    tf.glider = key;
    for (const auto& p : f.points) tf.points.push_back({p.t, p.cg.x, p.cg.y});
    tf.extra["first_frame"] = std::to_string(f.first_frame);
    tf.extra["last_frame"] = std::to_string(f.last_frame);
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.5f", f.sigma_m);
    tf.extra["flight_sigma_m"] = buf;
    d.flights.push_back(tf);
  }
  return d;
}

}  // namespace pteromys::capture
