// Camera calibration from reference points in the flight plane (docs/capture.md).
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <sstream>

#include <Eigen/Dense>

#include "pteromys/capture.hpp"

namespace pteromys::capture {
namespace {

using Eigen::Matrix3d;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;

Matrix3d to_eigen(const Mat3& m) {
  Matrix3d e;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) e(i, j) = m[3 * i + j];
  return e;
}
Mat3 from_eigen(const Matrix3d& e) {
  Mat3 m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m[3 * i + j] = e(i, j);
  return m;
}

Vec2 apply_h(const Matrix3d& h, Vec2 p) {
  const Vector3d q = h * Vector3d(p.x, p.y, 1.0);
  return {q(0) / q(2), q(1) / q(2)};
}

std::string fmt(double v, int prec = 3) {
  std::ostringstream s;
  s.precision(prec);
  s << v;
  return s.str();
}

// Hartley normalisation: centroid to the origin, mean distance sqrt(2).
Matrix3d normaliser(const std::vector<Vec2>& p) {
  double mx = 0, my = 0;
  for (const auto& q : p) mx += q.x, my += q.y;
  mx /= p.size();
  my /= p.size();
  double d = 0;
  for (const auto& q : p) d += std::hypot(q.x - mx, q.y - my);
  d /= p.size();
  const double s = d > 0 ? std::sqrt(2.0) / d : 1.0;
  Matrix3d t;
  t << s, 0, -s * mx, 0, s, -s * my, 0, 0, 1;
  return t;
}

// Smallest-to-largest singular value ratio of the centred 2 x n point cloud:
// 0 when the points lie on one line.
double line_ratio(const std::vector<Vec2>& p) {
  double mx = 0, my = 0;
  for (const auto& q : p) mx += q.x, my += q.y;
  mx /= p.size();
  my /= p.size();
  Eigen::Matrix2d c = Eigen::Matrix2d::Zero();
  for (const auto& q : p) {
    const Eigen::Vector2d d(q.x - mx, q.y - my);
    c += d * d.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(c);
  const double l0 = std::max(0.0, es.eigenvalues()(0)), l1 = es.eigenvalues()(1);
  return l1 > 0 ? std::sqrt(l0 / l1) : 0.0;
}

// DLT estimate of the homography world -> image (both given as points);
// returns the homography and the conditioning s8/s1 of the normalised system.
Matrix3d dlt(const std::vector<Vec2>& w, const std::vector<Vec2>& im, double* conditioning) {
  const Matrix3d tw = normaliser(w), ti = normaliser(im);
  const int n = static_cast<int>(w.size());
  MatrixXd a(2 * n, 9);
  for (int i = 0; i < n; ++i) {
    const Vector3d p = tw * Vector3d(w[i].x, w[i].y, 1);
    const Vector3d q = ti * Vector3d(im[i].x, im[i].y, 1);
    const double x = p(0), y = p(1), u = q(0), v = q(1);
    a.row(2 * i) << -x, -y, -1, 0, 0, 0, u * x, u * y, u;
    a.row(2 * i + 1) << 0, 0, 0, -x, -y, -1, v * x, v * y, v;
  }
  Eigen::JacobiSVD<MatrixXd> svd(a, Eigen::ComputeFullV);
  const VectorXd s = svd.singularValues();
  if (conditioning) *conditioning = s.size() >= 8 && s(0) > 0 ? s(7) / s(0) : 0.0;
  const VectorXd h = svd.matrixV().col(8);
  Matrix3d hn;
  hn << h(0), h(1), h(2), h(3), h(4), h(5), h(6), h(7), h(8);
  Matrix3d hm = ti.inverse() * hn * tw;
  return hm / hm.norm();
}

int n_distortion_params(const std::string& model) {
  if (model == "k1") return 1;
  if (model == "k1k2") return 2;
  return 0;
}
int min_points(const std::string& model) {
  if (model == "k1") return 6;
  if (model == "k1k2") return 8;
  return 4;
}

struct Fit {
  Matrix3d H;   // world -> undistorted pixel
  Lens lens;
  double rms_px = 0;
  double distortion_sigma_px = 0;  // 1-sigma uncertainty of the distortion at the image corner [px]
  bool converged = true;
};

Lens default_lens(int width, int height) {
  Lens l;
  l.cx = (width - 1) / 2.0;
  l.cy = (height - 1) / 2.0;
  l.fx = l.fy = 0.5 * std::hypot(width, height);
  return l;
}

// Least squares (Levenberg-Marquardt) of the homography and the distortion
// coefficients of `model` on the reprojection residual in distorted pixels.
Fit fit_points(const std::vector<Vec2>& w, const std::vector<Vec2>& im, const std::string& model,
               const Lens& base, double click_sigma_px) {
  const bool known = base.intrinsics_known;
  const int nd = known ? 0 : n_distortion_params(model);
  std::vector<Vec2> und(im.size());
  for (std::size_t i = 0; i < im.size(); ++i) und[i] = known ? undistort(base, im[i]) : im[i];
  const Matrix3d h0 = dlt(w, und, nullptr);
  // Parameters: the homography in normalised coordinates (Hn(2,2) = 1), then k1, k2.
  const Matrix3d tw = normaliser(w), ti = normaliser(und);
  Matrix3d hn = ti * h0 * tw.inverse();
  hn /= hn(2, 2);
  const int np = 8 + nd;
  VectorXd p(np);
  for (int k = 0; k < 8; ++k) p(k) = hn(k / 3, k % 3);
  for (int k = 0; k < nd; ++k) p(8 + k) = 0.0;
  const Matrix3d ti_inv = ti.inverse();
  std::vector<Vector3d> wn(w.size());
  for (std::size_t i = 0; i < w.size(); ++i) wn[i] = Vector3d(w[i].x, w[i].y, 1);
  auto unpack = [&](const VectorXd& q, Matrix3d& h, Lens& lens) {
    Matrix3d m;
    m << q(0), q(1), q(2), q(3), q(4), q(5), q(6), q(7), 1.0;
    h = ti_inv * m * tw;
    lens = base;
    if (!known) {
      lens.dist = {0, 0, 0, 0, 0};
      if (nd >= 1) lens.dist[0] = q(8);
      if (nd >= 2) lens.dist[1] = q(9);
    }
  };
  const int n = static_cast<int>(w.size());
  auto residual = [&](const VectorXd& q, VectorXd& r) {
    Matrix3d h;
    Lens lens;
    unpack(q, h, lens);
    r.resize(2 * n);
    for (int i = 0; i < n; ++i) {
      const Vector3d u = h * wn[i];
      const Vec2 d = distort(lens, {u(0) / u(2), u(1) / u(2)});
      r(2 * i) = d.x - im[i].x;
      r(2 * i + 1) = d.y - im[i].y;
    }
  };
  VectorXd r, rt;
  // Central differences, column by column.
  auto jacobian = [&](const VectorXd& at, MatrixXd& Jout) {
    VectorXd up, down;
    for (int k = 0; k < np; ++k) {
      const double step = 1e-7 * std::max(1.0, std::abs(at(k)));
      VectorXd q = at;
      q(k) += step;
      residual(q, up);
      q(k) = at(k) - step;
      residual(q, down);
      Jout.col(k) = (up - down) / (2 * step);
    }
  };
  residual(p, r);
  double cost = r.squaredNorm();
  double mu = 1e-3;
  MatrixXd J(2 * n, np);
  bool converged = false;
  for (int it = 0; it < 200; ++it) {
    jacobian(p, J);
    const MatrixXd jtj = J.transpose() * J;
    const VectorXd g = J.transpose() * r;
    bool improved = false;
    for (int inner = 0; inner < 20; ++inner) {
      MatrixXd a = jtj;
      for (int k = 0; k < np; ++k) a(k, k) += mu * std::max(jtj(k, k), 1e-12);
      const VectorXd dp = a.ldlt().solve(-g);
      const VectorXd q = p + dp;
      residual(q, rt);
      const double c2 = rt.squaredNorm();
      if (std::isfinite(c2) && c2 < cost) {
        const double rel = (cost - c2) / std::max(cost, 1e-30);
        p = q;
        r = rt;
        cost = c2;
        mu = std::max(mu / 3, 1e-12);
        improved = true;
        if (rel < 1e-14 || dp.norm() < 1e-14 * (1 + p.norm())) converged = true;
        break;
      }
      mu *= 4;
    }
    if (!improved || converged) {
      converged = true;
      break;
    }
  }
  Fit f;
  unpack(p, f.H, f.lens);
  f.H /= f.H.norm();
  f.rms_px = std::sqrt(cost / n);
  f.converged = converged;
  // Uncertainty of the distortion at the image corner (r = 1), from the
  // Gauss-Newton covariance with the clicking accuracy as noise.
  if (nd > 0) {
    jacobian(p, J);
    const MatrixXd cov = (J.transpose() * J).completeOrthogonalDecomposition().pseudoInverse() *
                         (click_sigma_px * click_sigma_px);
    // displacement at the corner: s * (k1 + k2)
    VectorXd e = VectorXd::Zero(np);
    for (int k = 0; k < nd; ++k) e(8 + k) = base.fx;
    f.distortion_sigma_px = std::sqrt(std::max(0.0, e.dot(cov * e)));
  }
  return f;
}

Vec2 world_of(const Matrix3d& h_inv, const Lens& lens, Vec2 px) {
  return apply_h(h_inv, undistort(lens, px));
}

double loo_rms(const std::vector<Vec2>& w, const std::vector<Vec2>& im, const std::string& model,
               const Lens& base, double click_sigma, std::vector<double>* per_point) {
  const std::size_t n = w.size();
  double s = 0;
  if (per_point) per_point->assign(n, -1.0);
  for (std::size_t i = 0; i < n; ++i) {
    std::vector<Vec2> w2, i2;
    for (std::size_t k = 0; k < n; ++k)
      if (k != i) w2.push_back(w[k]), i2.push_back(im[k]);
    const Fit f = fit_points(w2, i2, model, base, click_sigma);
    double e;
    try {
      const Vec2 q = world_of(f.H.inverse(), f.lens, im[i]);
      e = std::hypot(q.x - w[i].x, q.y - w[i].y);
    } catch (const InputError&) {
      e = std::numeric_limits<double>::infinity();
    }
    if (!std::isfinite(e)) e = 1e9;
    if (per_point) (*per_point)[i] = e;
    s += e * e;
  }
  return std::sqrt(s / n);
}

// Camera pose from the homography for an ideal pinhole of focal f.
Pose pose_from_h(const Matrix3d& h, double f, double cx, double cy, double fy = 0) {
  if (fy <= 0) fy = f;
  Matrix3d k;
  k << f, 0, cx, 0, fy, cy, 0, 0, 1;
  const Matrix3d m = k.inverse() * h;
  Vector3d m1 = m.col(0), m2 = m.col(1), m3 = m.col(2);
  double lambda = 2.0 / (m1.norm() + m2.norm());
  if (m3(2) * lambda < 0) lambda = -lambda;
  const Vector3d r1 = lambda * m1, r2 = lambda * m2, t = lambda * m3;
  Matrix3d r;
  r.col(0) = r1;
  r.col(1) = r2;
  r.col(2) = r1.cross(r2);
  Eigen::JacobiSVD<Matrix3d> svd(r, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Matrix3d ro = svd.matrixU() * svd.matrixV().transpose();
  if (ro.determinant() < 0) ro = -ro;
  Pose p;
  p.known = true;
  p.focal_px = f;
  p.focal_y_px = fy;
  p.R = from_eigen(ro);
  p.t = {t(0), t(1), t(2)};
  const Vector3d c = -ro.transpose() * t;
  p.centre = {c(0), c(1), c(2)};
  p.distance_m = std::abs(c(2));
  return p;
}

// Angle between the two plane axes of the camera before orthonormalisation
// (90 deg for a consistent focal length) [deg].
double axis_angle_deg(const Matrix3d& h, double f, double cx, double cy, double fy) {
  Matrix3d k;
  k << f, 0, cx, 0, fy, cy, 0, 0, 1;
  const Matrix3d m = k.inverse() * h;
  const Vector3d a = m.col(0).normalized(), b = m.col(1).normalized();
  return rad2deg(std::acos(std::clamp(a.dot(b), -1.0, 1.0)));
}

void check_points(const CalibrationInput& in) {
  const auto& pts = in.points;
  if (in.width <= 0 || in.height <= 0) throw InputError("the image size (image_size_px) must be given as two positive whole numbers");
  if (pts.size() < 4)
    throw InputError("at least 4 reference points are needed to calibrate the camera, got " + std::to_string(pts.size()));
  for (const auto& p : pts) {
    if (!std::isfinite(p.world.x) || !std::isfinite(p.world.y) || !std::isfinite(p.image.x) || !std::isfinite(p.image.y))
      throw InputError("reference point '" + p.name + "' has a coordinate that is not a finite number");
    if (p.image.x < -0.5 || p.image.y < -0.5 || p.image.x > in.width - 0.5 || p.image.y > in.height - 0.5)
      throw InputError("reference point '" + p.name + "' is outside the " + std::to_string(in.width) + "x" +
                       std::to_string(in.height) + " image (" + fmt(p.image.x, 6) + ", " + fmt(p.image.y, 6) + " px)");
  }
  double extent = 0;
  for (const auto& a : pts)
    for (const auto& b : pts) extent = std::max(extent, std::hypot(a.world.x - b.world.x, a.world.y - b.world.y));
  for (std::size_t i = 0; i < pts.size(); ++i)
    for (std::size_t j = i + 1; j < pts.size(); ++j) {
      if (std::hypot(pts[i].world.x - pts[j].world.x, pts[i].world.y - pts[j].world.y) <= 1e-6 * std::max(extent, 1e-9))
        throw InputError("reference points '" + pts[i].name + "' and '" + pts[j].name + "' have the same world position");
      if (std::hypot(pts[i].image.x - pts[j].image.x, pts[i].image.y - pts[j].image.y) < 0.5)
        throw InputError("reference points '" + pts[i].name + "' and '" + pts[j].name + "' are at the same place in the image");
    }
  std::vector<Vec2> w, im;
  for (const auto& p : pts) w.push_back(p.world), im.push_back(p.image);
  if (line_ratio(w) < 0.02)
    throw InputError("the reference points lie (nearly) on one line in the flight plane: use points spread both "
                     "along the flight and in height");
  if (line_ratio(im) < 0.02)
    throw InputError("the reference points lie (nearly) on one line in the image: use points spread over the image");
  if (pts.size() == 4) {
    for (int skip = 0; skip < 4; ++skip) {
      std::vector<Vec2> tri;
      std::vector<std::string> names;
      for (int k = 0; k < 4; ++k)
        if (k != skip) tri.push_back(w[k]), names.push_back(pts[k].name);
      const double area = 0.5 * std::abs(cross(tri[1] - tri[0], tri[2] - tri[0]));
      if (area < 0.01 * extent * extent)
        throw InputError("reference points '" + names[0] + "', '" + names[1] + "' and '" + names[2] +
                         "' lie (nearly) on one line: four points determine the camera only when no three are aligned");
    }
  }
  double cond = 0;
  dlt(w, im, &cond);
  if (cond < 1e-4)
    throw InputError("the reference points do not determine the image-to-plane mapping (too many of them on one "
                     "line): add points off that line");
}

}  // namespace

// ------------------------------------------------------------------ lens

Vec2 distort(const Lens& l, Vec2 u) {
  const double x = (u.x - l.cx) / l.fx, y = (u.y - l.cy) / l.fy;
  const double k1 = l.dist[0], k2 = l.dist[1], p1 = l.dist[2], p2 = l.dist[3], k3 = l.dist[4];
  const double r2 = x * x + y * y;
  const double radial = 1 + r2 * (k1 + r2 * (k2 + r2 * k3));
  const double xd = x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x);
  const double yd = y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y;
  return {l.fx * xd + l.cx, l.fy * yd + l.cy};
}

Vec2 undistort(const Lens& l, Vec2 d) {
  if (l.dist == std::array<double, 5>{0, 0, 0, 0, 0}) return d;
  // Newton on the normalised coordinates with the analytic Jacobian of distort().
  const double xd = (d.x - l.cx) / l.fx, yd = (d.y - l.cy) / l.fy;
  const double k1 = l.dist[0], k2 = l.dist[1], p1 = l.dist[2], p2 = l.dist[3], k3 = l.dist[4];
  double x = xd, y = yd;
  for (int it = 0; it < 60; ++it) {
    const double r2 = x * x + y * y;
    const double radial = 1 + r2 * (k1 + r2 * (k2 + r2 * k3));
    const double dradial = k1 + r2 * (2 * k2 + 3 * k3 * r2);  // d radial / d r2
    const double fx = x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x) - xd;
    const double fy = y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y - yd;
    const double a = radial + x * dradial * 2 * x + 2 * p1 * y + p2 * 6 * x;
    const double b = x * dradial * 2 * y + 2 * p1 * x + p2 * 2 * y;
    const double c = y * dradial * 2 * x + p1 * 2 * x + 2 * p2 * y;
    const double e = radial + y * dradial * 2 * y + p1 * 6 * y + 2 * p2 * x;
    const double det = a * e - b * c;
    if (!(det > 1e-9)) break;
    const double dx = (e * fx - b * fy) / det, dy = (-c * fx + a * fy) / det;
    x -= dx;
    y -= dy;
    if (std::abs(dx) + std::abs(dy) < 1e-14) {
      const Vec2 out{l.fx * x + l.cx, l.fy * y + l.cy};
      const Vec2 back = distort(l, out);
      if (std::hypot(back.x - d.x, back.y - d.y) < 1e-8) return out;
      break;
    }
  }
  throw InputError("the lens model cannot be inverted at pixel (" + fmt(d.x, 6) + ", " + fmt(d.y, 6) +
                   "): the distortion estimate is not valid that far from the image centre");
}

// ----------------------------------------------------------- calibration

Calibration calibrate(const CalibrationInput& in) {
  check_points(in);
  Calibration c;
  c.input = in;
  c.width = in.width;
  c.height = in.height;
  c.click_sigma_px = in.click_sigma_px > 0 ? in.click_sigma_px : 0.5;
  std::vector<Vec2> w, im;
  for (const auto& p : in.points) w.push_back(p.world), im.push_back(p.image);
  const int n = static_cast<int>(w.size());
  Lens base = in.lens.intrinsics_known ? in.lens : default_lens(in.width, in.height);
  std::string model;
  if (in.lens.intrinsics_known) {
    model = "known";
  } else if (in.distortion == "none" || in.distortion == "k1" || in.distortion == "k1k2") {
    model = in.distortion;
    if (n < min_points(model))
      throw InputError("distortion model '" + model + "' needs at least " + std::to_string(min_points(model)) +
                       " reference points, got " + std::to_string(n));
  } else if (in.distortion == "auto" || in.distortion.empty()) {
    model = "auto";
  } else {
    throw InputError("unknown distortion model '" + in.distortion + "' (use auto, none, k1 or k1k2)");
  }
  const double max_sigma_px = 3.0;  // distortion at the corner must be known to this [px]
  if (model == "auto") {
    std::vector<std::string> cands = {"none"};
    if (n >= 6) cands.push_back("k1");
    if (n >= 8) cands.push_back("k1k2");
    if (n < 5 || cands.size() == 1) {
      model = "none";
    } else {
      double best = std::numeric_limits<double>::infinity();
      std::vector<std::pair<std::string, double>> scores;
      for (const auto& m : cands) {
        if (m != "none") {
          const Fit f = fit_points(w, im, m, base, c.click_sigma_px);
          if (!f.converged || f.distortion_sigma_px > max_sigma_px || std::abs(f.lens.dist[0]) > 1.0) {
            c.warnings.push_back("distortion model '" + m + "' not considered: the points do not constrain it");
            continue;
          }
        }
        const double e = loo_rms(w, im, m, base, c.click_sigma_px, nullptr);
        scores.push_back({m, e});
        best = std::min(best, e);
      }
      c.model_loo_m = scores;
      model = "none";
      for (const auto& [m, e] : scores)  // the simplest model within 5 % of the best
        if (e <= 1.05 * best) {
          model = m;
          break;
        }
    }
  }
  const Fit f = fit_points(w, im, model, base, c.click_sigma_px);
  if (model == "k1" || model == "k1k2") {
    if (f.distortion_sigma_px > max_sigma_px)
      throw InputError("the reference points do not constrain lens distortion '" + model +
                       "' (uncertainty " + fmt(f.distortion_sigma_px, 2) +
                       " px at the corners): spread them over the whole image, or use distortion none");
  }
  c.distortion_model = model;
  c.lens = f.lens;
  c.H = from_eigen(f.H);
  const Matrix3d hinv = f.H.inverse();
  c.H_inv = from_eigen(hinv / hinv.norm());
  // every point must be in front of the camera: the same sign of w
  int positive = 0;
  for (const auto& p : w) positive += (f.H * Vector3d(p.x, p.y, 1))(2) > 0;
  if (positive != 0 && positive != n)
    throw InputError("the reference points are not consistent with one camera looking at a plane: check for "
                     "swapped or mistyped coordinates");
  // residuals
  double s_px = 0, s_m = 0;
  int worst = -1;
  double worst_px = -1;
  for (int i = 0; i < n; ++i) {
    PointResidual r;
    r.name = in.points[i].name;
    const Vec2 pred = distort(c.lens, apply_h(f.H, w[i]));
    r.du_px = im[i].x - pred.x;
    r.dv_px = im[i].y - pred.y;
    Vec2 back{NAN, NAN};
    try {
      back = world_of(hinv, c.lens, im[i]);
    } catch (const InputError&) {
    }
    r.dx_m = back.x - w[i].x;
    r.dy_m = back.y - w[i].y;
    const double epx = std::hypot(r.du_px, r.dv_px), em = std::hypot(r.dx_m, r.dy_m);
    s_px += epx * epx;
    s_m += em * em;
    c.max_px = std::max(c.max_px, epx);
    c.max_m = std::max(c.max_m, em);
    if (epx > worst_px) worst_px = epx, worst = i;
    c.residuals.push_back(r);
  }
  c.rms_px = std::sqrt(s_px / n);
  c.rms_m = std::sqrt(s_m / n);
  if (!std::isfinite(c.rms_m) || c.max_px > 0.02 * std::hypot(in.width, in.height))
    throw InputError("the reference points are not consistent with a camera looking at the flight plane (residual " +
                     fmt(worst_px, 3) + " px at point '" + in.points[worst].name +
                     "'): check that point's world and image coordinates");
  // leave-one-out error
  const int needed = model == "known" ? 4 : min_points(model) - (model == "none" ? 0 : 1);
  if (n - 1 >= std::max(needed, model == "none" || model == "known" ? 4 : 5) && n >= 5) {
    std::vector<double> per;
    const std::string m = model == "known" ? "none" : model;
    c.loo_rms_m = loo_rms(w, im, m, base, c.click_sigma_px, &per);
    for (int i = 0; i < n; ++i) c.residuals[i].loo_m = per[i];
  } else {
    c.warnings.push_back("with " + std::to_string(n) +
                         " points the fit is exact: the residual says nothing about the accuracy; add points");
  }
  if (c.rms_px > 5 * c.click_sigma_px)
    c.warnings.push_back("the reprojection residual (" + fmt(c.rms_px, 3) + " px) is much larger than the clicking accuracy (" +
                         fmt(c.click_sigma_px, 3) + " px): check the points' coordinates or the lens model");
  // pose
  const Matrix3d h = f.H;
  const double cx = c.lens.cx, cy = c.lens.cy;
  if (in.lens.intrinsics_known) {
    c.pose = pose_from_h(h, in.lens.fx, cx, cy, in.lens.fy);
    c.pose.source = "intrinsics";
  } else if (in.focal_px > 0) {
    c.pose = pose_from_h(h, in.focal_px, cx, cy);
    c.pose.source = "focal_px";
  } else if (in.distance_m > 0) {
    double fl = base.fx;
    bool ok = false;
    for (int it = 0; it < 100; ++it) {
      const Pose p = pose_from_h(h, fl, cx, cy);
      if (!(p.distance_m > 0)) break;
      const double next = fl * in.distance_m / p.distance_m;
      if (!std::isfinite(next) || next <= 0) break;
      if (std::abs(next - fl) < 1e-9 * fl) {
        ok = true;
        fl = next;
        break;
      }
      fl = next;
    }
    if (!ok || fl < 0.05 * base.fx || fl > 100 * base.fx)
      throw InputError("the camera distance " + fmt(in.distance_m) +
                       " m does not fit the reference points (no focal length reproduces it)");
    c.pose = pose_from_h(h, fl, cx, cy);
    c.pose.source = "distance_m";
  }
  if (c.pose.known) {
    const double ang = axis_angle_deg(h, c.pose.focal_px, cx, cy, c.pose.focal_y_px);
    if (std::abs(ang - 90.0) > 3.0)
      c.warnings.push_back("the focal length does not fit the reference points well (plane axes at " + fmt(ang, 3) +
                           " deg instead of 90): the camera pose is approximate");
  }
  return c;
}

Vec2 image_to_world(const Calibration& c, Vec2 px) { return apply_h(to_eigen(c.H_inv), undistort(c.lens, px)); }

Vec2 world_to_image(const Calibration& c, Vec2 w) { return distort(c.lens, apply_h(to_eigen(c.H), w)); }

Vec2 project_point(const Calibration& c, Point3 p) {
  if (!c.pose.known)
    throw InputError("the camera pose is unknown: give the focal length or the camera distance in the calibration points file");
  const auto& R = c.pose.R;
  const double xc = R[0] * p.x + R[1] * p.y + R[2] * p.z + c.pose.t[0];
  const double yc = R[3] * p.x + R[4] * p.y + R[5] * p.z + c.pose.t[1];
  const double zc = R[6] * p.x + R[7] * p.y + R[8] * p.z + c.pose.t[2];
  if (!(zc > 1e-9)) return {NAN, NAN};
  const Vec2 u{c.pose.focal_px * xc / zc + c.lens.cx, c.pose.focal_y_px * yc / zc + c.lens.cy};
  return distort(c.lens, u);
}

std::array<double, 4> world_per_pixel(const Calibration& c, Vec2 px) {
  const double h = 0.5;
  const Vec2 a = image_to_world(c, {px.x + h, px.y}), b = image_to_world(c, {px.x - h, px.y});
  const Vec2 d = image_to_world(c, {px.x, px.y + h}), e = image_to_world(c, {px.x, px.y - h});
  return {(a.x - b.x) / (2 * h), (d.x - e.x) / (2 * h), (a.y - b.y) / (2 * h), (d.y - e.y) / (2 * h)};
}

Mat3 plane_homography(const Mat3& R, const std::array<double, 3>& t, double f, double cx, double cy) {
  Matrix3d k;
  k << f, 0, cx, 0, f, cy, 0, 0, 1;
  Matrix3d rt;
  rt << R[0], R[1], t[0], R[3], R[4], t[1], R[6], R[7], t[2];
  Matrix3d h = k * rt;
  return from_eigen(h / h.norm());
}

}  // namespace pteromys::capture
