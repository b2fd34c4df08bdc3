#include "pteromys/flight.hpp"
#include "pteromys/text.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

namespace pteromys {

namespace {

inline double wrap(double a) { return wrap_angle(a); }

struct Deriv {
  Vec2 a;
  double alpha_dd = 0;
};

struct Integrand {
  const AeroForces& aero;
  RigidBody body;
  double g;
  Vec2 wind;
  /// `max_alpha` (optional): set to the model's max_alpha of the same
  /// air-relative state, computed with its forces.
  Deriv operator()(const FlightState& s, double* max_alpha = nullptr) const {
    FlightState air = s;
    air.v = s.v - wind;
    const Wrench w = max_alpha ? aero.evaluate_and_max_alpha(air, *max_alpha) : aero.evaluate(air);
    if (!aero.has_added_mass())
      return {{w.force.x / body.mass, w.force.y / body.mass - g}, w.moment / body.inertia};
    // Added mass: (diag(M, M, I) + m) q'' = F + bias + gravity (Gaussian
    // elimination with partial pivoting on the 3 x 3 system).
    const AddedMass am = aero.added_mass(air);
    double a[3][4] = {{body.mass + am.m[0][0], am.m[0][1], am.m[0][2], w.force.x + am.bias[0]},
                      {am.m[1][0], body.mass + am.m[1][1], am.m[1][2], w.force.y + am.bias[1] - body.mass * g},
                      {am.m[2][0], am.m[2][1], body.inertia + am.m[2][2], w.moment + am.bias[2]}};
    for (int c = 0; c < 3; ++c) {
      int piv = c;
      for (int r = c + 1; r < 3; ++r)
        if (std::abs(a[r][c]) > std::abs(a[piv][c])) piv = r;
      for (int k = 0; k < 4; ++k) std::swap(a[c][k], a[piv][k]);
      for (int r = c + 1; r < 3; ++r) {
        const double f = a[r][c] / a[c][c];
        for (int k = c; k < 4; ++k) a[r][k] -= f * a[c][k];
      }
    }
    double q[3];
    for (int r = 2; r >= 0; --r) {
      double v = a[r][3];
      for (int k = r + 1; k < 3; ++k) v -= a[r][k] * q[k];
      q[r] = v / a[r][r];
    }
    return {{q[0], q[1]}, q[2]};
  }
};

}  // namespace

double path_angle(const FlightState& s) { return -std::atan2(s.v.y, s.v.x); }
double angle_of_attack(const FlightState& s) { return wrap(path_angle(s) + s.beta); }

void fill_air(FlightSample& fs, Vec2 wind) {
  FlightState air;
  air.v = Vec2{fs.vx, fs.vy} - wind;
  air.beta = fs.pitch;
  fs.speed = norm(air.v);
  fs.alpha = angle_of_attack(air);
}

Wrench QuasiStaticAero::evaluate(const FlightState& s) const {
  const double V = norm(s.v);
  if (V < 1e-9) return {};
  const double theta = path_angle(s);
  const double gamma = wrap(theta + s.beta);
  const GliderForces F = g_.forces(V, gamma);
  const double c = s.v.x / V, sn = -s.v.y / V;  // cos and sin of theta
  // Drag opposes the velocity (cos theta, -sin theta); lift is perpendicular to it, upward.
  return {{-F.drag * c + F.lift * sn, F.drag * sn + F.lift * c}, F.moment};
}

double QuasiStaticAero::max_alpha(const FlightState& s) const {
  return g_.max_wing_alpha(angle_of_attack(s));
}

double QuasiStaticAero::alpha_limit() const { return g_.alpha_limit(); }

double check_time_step(double dt, const std::string& name) {
  if (!(dt >= kMinTimeStep) || dt > kMaxTimeStep)
    throw InputError(name + " must be in [" + fmt_number(kMinTimeStep) + ", " + fmt_number(kMaxTimeStep) +
                     "] s, got " + fmt_number(dt, 9));
  return dt;
}

std::vector<Launch> standard_launches(double height) {
  std::vector<Launch> out;
  for (double v : {7.0, 9.0, 11.0})
    for (double a : {0.0, 10.0}) {
      Launch l;
      l.speed = v;
      l.climb_deg = a;
      l.height = height;
      out.push_back(l);
    }
  return out;
}

FlightState launch_state(const Launch& l) {
  FlightState s;
  const double c = deg2rad(l.climb_deg);
  s.p = {0.0, l.height};
  s.v = {l.speed * std::cos(c), l.speed * std::sin(c)};
  s.beta = l.pitch_from_path ? c : deg2rad(l.pitch_deg);
  s.omega = deg2rad(l.pitch_rate_deg_s);
  return s;
}

Flight simulate(const AeroForces& aero, const RigidBody& body, const Launch& launch,
                const SimOptions& opt, double gravity) {
  return simulate_from(aero, body, launch_state(launch), opt, gravity);
}

Flight simulate_from(const AeroForces& aero, const RigidBody& body, const FlightState& start,
                     const SimOptions& opt, double gravity) {
  if (!(body.mass > 0) || !(body.inertia > 0)) throw InputError("mass and inertia must be positive");
  if (!(opt.dt > 0) || !(opt.t_max > 0)) throw InputError("time step and time limit must be positive");
  const Integrand f{aero, body, gravity, opt.wind};
  const double x0 = start.p.x;
  const double h = opt.dt;
  const int every = std::max(1, opt.record_every);
  Flight out;
  FlightState s = start;
  auto sample = [&](const FlightState& st) {
    FlightSample fs;
    fs.t = st.t;
    fs.x = st.p.x;
    fs.y = st.p.y;
    fs.pitch = st.beta;
    fs.omega = st.omega;
    fs.vx = st.v.x;
    fs.vy = st.v.y;
    if (opt.sample_air) fill_air(fs, opt.wind);
    return fs;
  };
  out.samples.push_back(sample(s));
  // The launch state is checked as every step's is: a launch whose wings
  // start outside the model's range (the nose pointed far off the path) is
  // not flown on a model that does not hold there.
  double am0 = 0;
  Deriv d = f(s, &am0);
  const double limit = aero.alpha_limit();
  const double max_pitch = deg2rad(opt.max_pitch_deg);
  out.max_alpha = am0;
  if (am0 > limit) {
    out.stable = false;
    out.end = FlightEnd::Unstable;
    out.reason = "angle of attack at launch is " + fmt_number(rad2deg(am0), 3) + " deg, outside the model's range of +-" +
                 fmt_number(rad2deg(limit), 3) + " deg (the nose points too far off the launch path)";
    out.flight_time = 0;
    out.distance = 0;
    return out;
  }
  const long nsteps = static_cast<long>(std::ceil(opt.t_max / h - 1e-9));
  // Room for every recorded step of a short flight (a tracked flight's
  // simulation records all its few hundred steps) without regrowing.
  out.samples.reserve(static_cast<std::size_t>(std::min(nsteps / every + 2, 4096L)));
  for (long step = 1; step <= nsteps; ++step) {
    FlightState n = s;
    double am = 0;  // the wings' largest |alpha| in this step (the stall check)
    if (opt.integrator == Integrator::Verlet) {
      // Velocity Verlet; the force at the new position uses the predicted
      // velocity (forces depend on velocity), one force evaluation per step.
      n.p = s.p + h * s.v + (0.5 * h * h) * d.a;
      n.beta = s.beta + h * s.omega + 0.5 * h * h * d.alpha_dd;
      FlightState pred = n;
      pred.v = s.v + h * d.a;
      pred.omega = s.omega + h * d.alpha_dd;
      pred.t = s.t + h;
      // The stall check's angles are those of this force evaluation: the
      // model's range is checked where the model is used (pred differs
      // from the step's end n by O(h^2) in velocity), and a model whose
      // angles need its flow solve (EffectAero: induced angles, wakes)
      // solves once a step instead of twice (one 20-point flight with
      // downwash 446 -> 246 us, finite span 232 -> 143 us).
      const Deriv d1 = f(pred, &am);
      n.v = s.v + (0.5 * h) * (d.a + d1.a);
      n.omega = s.omega + 0.5 * h * (d.alpha_dd + d1.alpha_dd);
      d = d1;
    } else {
      auto add = [](const FlightState& a, const FlightState& k, double c) {
        FlightState r = a;
        r.p = a.p + c * k.v;
        r.v = a.v + c * k.p;  // k.p carries the acceleration
        r.beta = a.beta + c * k.omega;
        r.omega = a.omega + c * k.beta;  // k.beta carries the angular acceleration
        return r;
      };
      // The rate of state a whose derivative is dd.
      auto rate_of = [](const FlightState& a, const Deriv& dd) {
        FlightState k;
        k.v = a.v;
        k.p = dd.a;
        k.omega = a.omega;
        k.beta = dd.alpha_dd;
        return k;
      };
      auto rate = [&](const FlightState& a) { return rate_of(a, f(a)); };
      // k1 from d: the force at s, computed before the loop or, with the
      // stall check, at the end of the step before (the same call on the
      // same state as rate(s)).
      const FlightState k1 = rate_of(s, d);
      const FlightState k2 = rate(add(s, k1, h / 2));
      const FlightState k3 = rate(add(s, k2, h / 2));
      const FlightState k4 = rate(add(s, k3, h));
      n.p = s.p + (h / 6) * (k1.v + 2.0 * k2.v + 2.0 * k3.v + k4.v);
      n.v = s.v + (h / 6) * (k1.p + 2.0 * k2.p + 2.0 * k3.p + k4.p);
      n.beta = s.beta + h / 6 * (k1.omega + 2 * k2.omega + 2 * k3.omega + k4.omega);
      n.omega = s.omega + h / 6 * (k1.beta + 2 * k2.beta + 2 * k3.beta + k4.beta);
    }
    n.t = start.t + step * h;

    const bool finite = std::isfinite(n.p.x) && std::isfinite(n.p.y) && std::isfinite(n.v.x) &&
                        std::isfinite(n.v.y) && std::isfinite(n.beta) && std::isfinite(n.omega);
    if (!finite) {
      out.stable = false;
      out.end = FlightEnd::Unstable;
      out.reason = "the simulation diverged (non-finite state) at t = " + fmt_number(n.t) + " s";
      break;
    }
    if (opt.integrator == Integrator::RK4) {
      // The stall check's angles with the force at n, which the next step
      // starts from (k1).
      d = f(n, &am);
    }
    out.max_alpha = std::max(out.max_alpha, am);
    if (n.p.y <= 0 && s.p.y > 0) {
      // Ground contact between the two steps: interpolate linearly in height.
      const double fr = s.p.y / (s.p.y - n.p.y);
      FlightState g = n;
      g.t = s.t + fr * h;
      g.p = s.p + fr * (n.p - s.p);
      g.v = s.v + fr * (n.v - s.v);
      g.beta = s.beta + fr * (n.beta - s.beta);
      g.omega = s.omega + fr * (n.omega - s.omega);
      g.p.y = 0;
      out.samples.push_back(sample(g));
      out.end = FlightEnd::Ground;
      s = g;
      break;
    }
    s = n;
    if (am > limit) {
      out.stable = false;
      out.end = FlightEnd::Unstable;
      out.reason = "angle of attack reached " + fmt_number(rad2deg(am), 3) + " deg at t = " + fmt_number(s.t) +
                   " s, outside the model's range of +-" + fmt_number(rad2deg(limit), 3) +
                   " deg (the glider stalls or tumbles)";
      out.samples.push_back(sample(s));
      break;
    }
    if (std::abs(s.beta) > max_pitch) {
      out.stable = false;
      out.end = FlightEnd::Unstable;
      out.reason = "the glider flipped: pitch passed " + fmt_number(opt.max_pitch_deg) + " deg at t = " +
                   fmt_number(s.t) + " s";
      out.samples.push_back(sample(s));
      break;
    }
    if (step == nsteps) {
      out.end = FlightEnd::TimeLimit;
      out.samples.push_back(sample(s));
      break;
    }
    if (step % every == 0) out.samples.push_back(sample(s));
  }
  out.flight_time = s.t - start.t;
  out.distance = s.p.x - x0;
  return out;
}

}  // namespace pteromys
