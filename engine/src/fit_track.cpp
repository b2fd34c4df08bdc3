// Tracked-flight simulation and the launch fit (paper eq. 5).
#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Dense>
#include <unsupported/Eigen/LevenbergMarquardt>

#include "pteromys/fit.hpp"

namespace pteromys {
namespace {

/// Delegates to a model but never declares the flight unstable: beyond the
/// model's range the force table holds its edge values.
class UnboundedAero final : public AeroForces {
 public:
  explicit UnboundedAero(const AeroForces& a) : a_(a) {}
  Wrench evaluate(const FlightState& s) const override { return a_.evaluate(s); }
  double max_alpha(const FlightState& s) const override { return a_.max_alpha(s); }
  Wrench evaluate_and_max_alpha(const FlightState& s, double& m) const override {
    return a_.evaluate_and_max_alpha(s, m);
  }
  double alpha_limit() const override { return std::numeric_limits<double>::infinity(); }
  bool has_added_mass() const override { return a_.has_added_mass(); }
  AddedMass added_mass(const FlightState& s) const override { return a_.added_mass(s); }

 private:
  const AeroForces& a_;
};

FlightSample lerp(const FlightSample& a, const FlightSample& b, double s) {
  FlightSample r;
  auto L = [s](double u, double v) { return u + s * (v - u); };
  r.t = L(a.t, b.t);
  r.x = L(a.x, b.x);
  r.y = L(a.y, b.y);
  r.pitch = L(a.pitch, b.pitch);
  r.speed = L(a.speed, b.speed);
  r.alpha = L(a.alpha, b.alpha);
  r.omega = L(a.omega, b.omega);
  r.vx = L(a.vx, b.vx);
  r.vy = L(a.vy, b.vy);
  return r;
}

}  // namespace

double huber_weight(double e, double c) {
  if (c <= 0 || e <= c) return 1.0;
  return std::sqrt(c * (2 * e - c)) / e;  // |w d|^2 = Huber rho(e) = 2 c e - c^2
}

Track simulate_track(const AeroForces& aero, const RigidBody& body, const LaunchParams& p,
                     const std::vector<double>& times, const TrackOptions& opt) {
  Track tr;
  if (times.empty()) return tr;
  const double h = opt.sim.dt;
  if (!(h > 0)) throw InputError("time step must be positive");
  SimOptions so = opt.sim;
  so.record_every = 1;
  so.sample_air = false;  // filled below at the samples the tracked points fall between
  so.t_max = std::max(times.back() - p.t, 0.0) + 2 * h;
  if (opt.continue_outside_range) so.max_pitch_deg = 1e12;
  FlightState s0;
  s0.t = 0;
  s0.p = {p.x, p.y + opt.height_offset};
  s0.v = {p.speed * std::cos(p.climb), p.speed * std::sin(p.climb)};
  s0.beta = p.pitch;
  s0.omega = p.pitch_rate;
  const UnboundedAero unbounded(aero);
  const AeroForces& use = opt.continue_outside_range ? static_cast<const AeroForces&>(unbounded) : aero;
  const Flight f = simulate_from(use, body, s0, so, opt.gravity);
  const auto& S = f.samples;
  tr.max_alpha = f.max_alpha;
  tr.left_model_range = f.max_alpha > aero.alpha_limit();
  tr.end = f.end;
  tr.reason = f.reason;
  tr.end_time = p.t + S.back().t;
  tr.ended_early = S.back().t < times.back() - p.t - 1e-12;
  if (tr.ended_early && tr.reason.empty())
    tr.reason = f.end == FlightEnd::Ground ? "the glider reached the ground" : "the simulation stopped";
  tr.positions.resize(times.size());
  tr.states.resize(times.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < times.size(); ++i) {
    const double tau = std::max(times[i] - p.t, 0.0);
    while (k + 1 < S.size() && S[k + 1].t < tau) ++k;
    FlightSample st;
    if (k + 1 < S.size()) {
      // Cubic Hermite interpolation of position with the velocities at both ends.
      FlightSample a = S[k], b = S[k + 1];
      fill_air(a, so.wind);
      fill_air(b, so.wind);
      const double dt = b.t - a.t;
      const double s = dt > 0 ? std::clamp((tau - a.t) / dt, 0.0, 1.0) : 0.0;
      const double s2 = s * s, s3 = s2 * s;
      const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
      st = lerp(a, b, s);
      st.x = h00 * a.x + h10 * dt * a.vx + h01 * b.x + h11 * dt * b.vx;
      st.y = h00 * a.y + h10 * dt * a.vy + h01 * b.y + h11 * dt * b.vy;
    } else {
      // Past the end of the simulation: ballistic extrapolation from the last state.
      st = S.back();
      fill_air(st, so.wind);
      const double d = tau - st.t;
      st.t = tau;
      st.x += st.vx * d;
      st.y += st.vy * d - 0.5 * opt.gravity * d * d;
      st.vy -= opt.gravity * d;
    }
    st.t += p.t;
    st.y -= opt.height_offset;
    tr.positions[i] = {st.x, st.y};
    tr.states[i] = st;
  }
  return tr;
}

LaunchParams initial_launch_guess(const std::vector<TrackedPoint>& pts, int n) {
  if (pts.size() < 3) throw InputError("a flight needs at least 3 points to estimate its launch");
  n = std::clamp<int>(n, 3, static_cast<int>(pts.size()));
  // Least-squares parabola q(tau) = a + b tau + c tau^2 through the first n points.
  Eigen::MatrixXd A(n, 3);
  Eigen::MatrixXd B(n, 2);
  for (int i = 0; i < n; ++i) {
    const double tau = pts[i].t - pts[0].t;
    A(i, 0) = 1;
    A(i, 1) = tau;
    A(i, 2) = tau * tau;
    B(i, 0) = pts[i].x;
    B(i, 1) = pts[i].y;
  }
  const Eigen::MatrixXd C = A.colPivHouseholderQr().solve(B);
  LaunchParams p;
  p.t = pts[0].t;
  p.x = C(0, 0);
  p.y = C(0, 1);
  const double vx = C(1, 0), vy = C(1, 1);
  if (!(vx > 0))
    throw InputError("the first points do not move along +x (the dataset's x axis must point along the flight)");
  p.speed = std::hypot(vx, vy);
  p.climb = std::atan2(vy, vx);
  p.pitch = p.climb;
  p.pitch_rate = 0;
  return p;
}

namespace {

/// Eq. 5 as a least-squares problem: parameters (x, y, V, climb[, pitch][, omega]).
struct LaunchProblem : Eigen::DenseFunctor<double> {
  const AeroForces& aero;
  RigidBody body;
  std::vector<double> times;
  std::vector<Vec2> q;
  LaunchParams base;
  bool fit_pitch, fit_rate;
  TrackOptions topt;
  double robust;
  int evaluations = 0;

  LaunchProblem(const AeroForces& a, const RigidBody& b, const std::vector<TrackedPoint>& pts, int m,
                const LaunchParams& base_, const LaunchFitOptions& o)
      : DenseFunctor<double>(4 + (o.fit_pitch ? 1 : 0) + (o.fit_pitch_rate ? 1 : 0), 2 * m),
        aero(a), body(b), base(base_), fit_pitch(o.fit_pitch), fit_rate(o.fit_pitch_rate), topt(o.track),
        robust(o.robust_m) {
    for (int i = 0; i < m; ++i) {
      times.push_back(pts[i].t);
      q.push_back({pts[i].x, pts[i].y});
    }
  }
  Eigen::VectorXd pack(const LaunchParams& p) const {
    Eigen::VectorXd x(inputs());
    x << p.x, p.y, p.speed, p.climb, Eigen::VectorXd::Zero(inputs() - 4);
    int k = 4;
    if (fit_pitch) x(k++) = p.pitch;
    if (fit_rate) x(k++) = p.pitch_rate;
    return x;
  }
  LaunchParams unpack(const Eigen::VectorXd& x) const {
    LaunchParams p = base;
    p.x = x(0);
    p.y = x(1);
    p.speed = std::max(std::abs(x(2)), 0.05);
    p.climb = x(3);
    int k = 4;
    if (fit_pitch) p.pitch = x(k++);
    if (fit_rate) p.pitch_rate = x(k++);
    return p;
  }
  void residuals(const Eigen::VectorXd& x, Eigen::VectorXd& r) {
    ++evaluations;
    const Track tr = simulate_track(aero, body, unpack(x), times, topt);
    for (std::size_t i = 0; i < q.size(); ++i) {
      const double dx = tr.positions[i].x - q[i].x, dy = tr.positions[i].y - q[i].y;
      const double w = huber_weight(std::hypot(dx, dy), robust);
      r(2 * i) = w * dx;
      r(2 * i + 1) = w * dy;
    }
  }
  // The solver asks for the Jacobian at the point it evaluated last (the
  // accepted one): keep the residuals of the last evaluations to save a simulation.
  Eigen::VectorXd last_x[2], last_r[2];
  int last_i = 0;
  int operator()(const Eigen::VectorXd& x, Eigen::VectorXd& r) {
    residuals(x, r);
    last_x[last_i] = x;
    last_r[last_i] = r;
    last_i ^= 1;
    return r.allFinite() ? 0 : -1;
  }
  int df(const Eigen::VectorXd& x, Eigen::MatrixXd& J) {
    // Forward differences; steps in natural units (m, m/s, rad, rad/s): the
    // trajectory's sensitivities are of order one and smooth (the tables are C1).
    Eigen::VectorXd r0(values()), r1(values());
    if (last_x[0].size() == x.size() && last_x[0] == x) r0 = last_r[0];
    else if (last_x[1].size() == x.size() && last_x[1] == x) r0 = last_r[1];
    else residuals(x, r0);
    for (int j = 0; j < inputs(); ++j) {
      Eigen::VectorXd xp = x;
      const double h = 1e-6 * std::max(1.0, std::abs(x(j)));
      xp(j) += h;
      residuals(xp, r1);
      J.col(j) = (r1 - r0) / h;
    }
    return 0;
  }
};

LaunchFit run_launch_lm(const AeroForces& aero, const RigidBody& body, const std::vector<TrackedPoint>& pts, int m,
                        const LaunchParams& start, const LaunchFitOptions& o) {
  LaunchProblem prob(aero, body, pts, m, start, o);
  Eigen::VectorXd x = prob.pack(start);
  Eigen::LevenbergMarquardt<LaunchProblem> lm(prob);
  lm.setMaxfev(std::max(20, o.max_evaluations / (prob.inputs() + 2)));
  lm.setFactor(1.0);
  lm.setXtol(1e-7);
  lm.setFtol(1e-7);
  lm.minimize(x);
  LaunchFit out;
  out.launch = prob.unpack(x);
  const Track tr = simulate_track(aero, body, out.launch, prob.times, o.track);
  double s = 0;
  for (int i = 0; i < m; ++i) s += std::pow(norm(tr.positions[i] - prob.q[i]), 2);
  out.rmse_m = std::sqrt(s / m);
  if (!std::isfinite(out.rmse_m)) out.rmse_m = std::numeric_limits<double>::infinity();
  out.evaluations = prob.evaluations;
  return out;
}

}  // namespace

LaunchFit fit_launch(const AeroForces& aero, const RigidBody& body, const std::vector<TrackedPoint>& pts,
                     const LaunchFitOptions& o, const LaunchParams* start) {
  const int n = static_cast<int>(pts.size());
  if (o.points < 0 || o.points == 1 || o.points == 2)
    throw InputError("the launch fit's number of points must be 0 (all) or at least 3; got " +
                     std::to_string(o.points));
  const int m = o.points == 0 ? n : std::min(o.points, n);
  if (m < 3) throw InputError("a flight needs at least 3 points to fit its launch");
  if (2 * m < 4 + (o.fit_pitch ? 1 : 0) + (o.fit_pitch_rate ? 1 : 0))
    throw InputError("too few points to fit the launch parameters");
  if (start) return run_launch_lm(aero, body, pts, m, *start, o);
  const LaunchParams guess = initial_launch_guess(pts, std::min(m, 6));
  LaunchFit best;
  best.rmse_m = std::numeric_limits<double>::infinity();
  int total = 0;
  std::vector<double> starts = o.fit_pitch ? o.start_alpha_deg : std::vector<double>{0.0};
  if (starts.empty()) starts.push_back(0.0);
  for (double a : starts) {
    LaunchParams s = guess;
    s.pitch = guess.climb + deg2rad(a);
    const LaunchFit f = run_launch_lm(aero, body, pts, m, s, o);
    total += f.evaluations;
    if (f.rmse_m < best.rmse_m) best = f;
  }
  best.evaluations = total;
  return best;
}

}  // namespace pteromys
