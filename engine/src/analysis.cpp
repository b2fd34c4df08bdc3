#include "pteromys/analysis.hpp"
#include "pteromys/text.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace pteromys {

namespace {

// Range of glider angles of attack for which every wing stays inside the
// model's valid range.
std::pair<double, double> valid_gamma_range(const MountedGlider& g) {
  const double lim = g.alpha_limit();
  double lo = -lim, hi = lim;
  for (const auto& m : g.mounts()) {
    const double th = deg2rad(m.angle_deg);
    lo = std::max(lo, -lim - th);
    hi = std::min(hi, lim - th);
  }
  return {lo, hi};
}

std::string launch_name(const Launch& l) {
  return "the launch at " + fmt_number(l.speed) + " m/s, " + fmt_number(l.climb_deg) + " deg up";
}

}  // namespace

namespace {

// The trim and glide searches work on any characteristic function
// F(V, gamma) -> GliderForces: the mounted glider's tables or a general
// aerodynamic model (level_forces).
template <class Forces>
bool trim_of(const Forces& forces, double v, double lo, double hi, TrimPoint* out) {
  if (!(hi > lo)) return false;
  const int n = std::max(8, static_cast<int>(std::ceil((hi - lo) / deg2rad(0.5))));
  double best_gamma = 0;
  bool found = false;
  double prev_g = lo, prev_m = forces(v, lo).moment;
  for (int i = 1; i <= n; ++i) {
    const double gm = lo + (hi - lo) * i / n;
    const double m = forces(v, gm).moment;
    if (prev_m >= 0 && m < 0) {
      // Stable equilibrium (moment falls through zero): refine by bisection.
      double a = prev_g, b = gm, ma = prev_m;
      for (int it = 0; it < 60 && b - a > 1e-12; ++it) {
        const double c = 0.5 * (a + b);
        const double mc = forces(v, c).moment;
        if ((mc >= 0) == (ma >= 0)) { a = c; ma = mc; } else { b = c; }
      }
      const double root = 0.5 * (a + b);
      if (!found || std::abs(root) < std::abs(best_gamma)) best_gamma = root;
      found = true;
    }
    prev_g = gm;
    prev_m = m;
  }
  if (!found) return false;
  if (out) {
    const GliderForces f = forces(v, best_gamma);
    const double h = deg2rad(0.25);
    out->v = v;
    out->gamma = best_gamma;
    out->lift = f.lift;
    out->drag = f.drag;
    out->dmoment_dgamma = (forces(v, best_gamma + h).moment - forces(v, best_gamma - h).moment) / (2 * h);
  }
  return true;
}

template <class Forces>
Glide glide_of(const Forces& forces, double W, double lo, double hi) {
  Glide gl;
  double v = 7.0;
  TrimPoint t;
  for (int it = 0; it < 30; ++it) {
    if (!trim_of(forces, v, lo, hi, &t)) return gl;
    const double F = std::hypot(t.lift, t.drag);
    if (!(F > 0)) return gl;
    const double vn = std::clamp(v * std::sqrt(W / F), 0.5, 100.0);
    const bool done = std::abs(vn - v) < 1e-6 * v;
    v = vn;
    if (done) break;
  }
  if (!trim_of(forces, v, lo, hi, &t) || !(t.lift > 0)) return gl;
  gl.exists = true;
  gl.gamma = t.gamma;
  gl.speed = v;
  gl.ratio = t.lift / std::max(t.drag, 1e-12);
  gl.path_angle = std::atan2(t.drag, t.lift);
  gl.sink_rate = v * std::sin(gl.path_angle);
  return gl;
}

}  // namespace

bool find_trim(const MountedGlider& g, double v, double lo, double hi, TrimPoint* out) {
  return trim_of([&g](double vv, double gm) { return g.forces(vv, gm); }, v, lo, hi, out);
}

GliderForces level_forces(const AeroForces& a, double v, double gamma, double height) {
  FlightState s;
  s.p = {0.0, height};
  s.v = {v, 0.0};  // level path: theta = 0, so the pitch angle is gamma
  s.beta = gamma;
  const Wrench w = a.evaluate(s);
  return {-w.force.x, w.force.y, w.moment};
}

double neutral_point(const MountedGlider& g, double v, double gm) {
  const double h = deg2rad(0.25);
  const GliderForces fp = g.forces(v, gm + h), fm = g.forces(v, gm - h);
  const double dT = (fp.moment - fm.moment) / (2 * h);
  auto fy = [](const GliderForces& f, double gg) { return f.lift * std::cos(gg) + f.drag * std::sin(gg); };
  const double dFy = (fy(fp, gm + h) - fy(fm, gm - h)) / (2 * h);
  if (dFy == 0) return std::nan("");
  return g.mass().cg.x + dT / dFy;
}

Glide steady_glide(const MountedGlider& g, double lo, double hi) {
  return glide_of([&g](double v, double gm) { return g.forces(v, gm); },
                  g.mass().mass * g.aero().environment().gravity, lo, hi);
}

Glide steady_glide(const AeroForces& a, const RigidBody& body, double gravity, double lo, double hi) {
  return glide_of([&a](double v, double gm) { return level_forces(a, v, gm); }, body.mass * gravity, lo, hi);
}

Flyability analyse(const MountedGlider& g, const std::vector<std::string>& names,
                   const AnalysisOptions& opt) {
  Flyability r;
  r.mass = g.mass();
  r.mounts = g.mounts();
  r.wing_names = names;
  const auto [glo, ghi] = valid_gamma_range(g);

  // Model limits met by this design.
  for (std::size_t j = 0; j < g.aero().wing_count(); ++j) {
    const auto& el = g.aero().elements(j);
    for (const auto& [z0, z1] : el.multiple_ranges)
      r.warnings.push_back("wing '" + (j < names.size() ? names[j] : std::to_string(j)) +
                           "': between z = " + fmt_number(z0) + " and " + fmt_number(z1) +
                           " m one streamline crosses the planform more than once; the "
                           "wing-element model ignores the interference of such elements "
                           "(paper section 8), so results there are less reliable");
  }
  // Reference chord: mean chord of the wing with the largest area.
  double best_area = -1;
  for (std::size_t j = 0; j < g.aero().wing_count(); ++j) {
    const auto& el = g.aero().elements(j);
    if (el.planform_area > best_area) {
      best_area = el.planform_area;
      r.reference_chord = el.span > 0 ? el.planform_area / el.span : 0;
    }
  }

  // Trim points on Omega.
  const int nspeeds = 4;
  for (int i = 0; i < nspeeds; ++i) {
    const double v = opt.region.v_min + (opt.region.v_max - opt.region.v_min) * i / (nspeeds - 1);
    TrimPoint t;
    if (find_trim(g, v, std::max(glo, opt.region.gamma_min), std::min(ghi, opt.region.gamma_max), &t))
      r.trim.push_back(t);
  }

  // Pitch stability over the whole valid range.
  r.glide = steady_glide(g, glo, ghi);
  const double vref = r.glide.exists ? r.glide.speed : 0.5 * (opt.region.v_min + opt.region.v_max);
  if (!r.glide.exists) {
    // Why no stable equilibrium: look at the moment over the valid range.
    double mmin = 1e300, mmax = -1e300;
    bool unstable_root = false;
    const int n = 80;
    double prev = 0;
    for (int i = 0; i <= n; ++i) {
      const double gm = glo + (ghi - glo) * i / n;
      const double m = g.forces(vref, gm).moment;
      mmin = std::min(mmin, m);
      mmax = std::max(mmax, m);
      if (i > 0 && prev < 0 && m >= 0) unstable_root = true;
      prev = m;
    }
    if (unstable_root)
      r.reasons.push_back(
          "the glider is pitch-unstable: where the pitching moment is zero it grows with the angle "
          "of attack, so any disturbance pitches it further; the centre of gravity is behind the "
          "neutral point: move it forward (nose ballast) or enlarge the tail");
    else if (mmin > 0)
      r.reasons.push_back(
          "the glider pitches nose-up at every angle of attack, so it would climb and stall: "
          "move the centre of gravity back (less nose ballast), lower the main wing's angle or "
          "raise the tail's angle");
    else if (mmax < 0)
      r.reasons.push_back(
          "the glider pitches nose-down at every angle of attack, so it would dive: move the "
          "centre of gravity back (less nose ballast), raise the main wing's angle or lower the "
          "tail's angle");
    else
      r.reasons.push_back("no steady glide exists within the model's angle-of-attack range");
  } else {
    r.pitch_stable = true;
    r.neutral_point_x = neutral_point(g, vref, r.glide.gamma);
    if (std::isfinite(r.neutral_point_x) && r.reference_chord > 0)
      r.static_margin = (r.mass.cg.x - r.neutral_point_x) / r.reference_chord;
    if (std::isfinite(r.static_margin) && r.static_margin < 0.03)
      r.warnings.push_back("the static margin is only " + fmt_number(100 * r.static_margin, 2) +
                           " % of the main chord: the glider is nearly neutral in pitch and small building "
                           "errors may make it unstable; move the centre of gravity forward or enlarge the tail");
    if (r.glide.speed > opt.max_trim_speed)
      r.reasons.push_back("the wings are too small for the weight: a steady glide needs " +
                          fmt_number(r.glide.speed) + " m/s, more than a hand launch gives (" +
                          fmt_number(opt.max_trim_speed) + " m/s); enlarge the wings or lighten the glider");
    if (r.glide.ratio < opt.min_glide_ratio)
      r.reasons.push_back("the glider does not glide: lift/drag in the steady glide is only " +
                          fmt_number(r.glide.ratio) + " (needs at least " + fmt_number(opt.min_glide_ratio) +
                          "); raise the wings' angles or reduce drag");
  }

  // The six standard launches.
  const RigidBody body{r.mass.mass, r.mass.inertia};
  const QuasiStaticAero qa(g);
  for (const Launch& l : standard_launches(opt.launch_height)) {
    LaunchResult lr;
    lr.launch = l;
    lr.flight = simulate(qa, body, l, opt.sim, g.aero().environment().gravity);
    const bool in_region = l.speed >= opt.region.v_min - 1e-9 && l.speed <= opt.region.v_max + 1e-9;
    if (in_region && !lr.flight.stable && r.reasons.size() < 8)
      r.reasons.push_back(launch_name(l) + " is unstable: " + lr.flight.reason);
    if (!opt.keep_samples) {
      auto& s = lr.flight.samples;
      if (s.size() > 2) s.erase(s.begin() + 1, s.end() - 1);
    }
    r.launches.push_back(std::move(lr));
  }
  r.flyable = r.reasons.empty();
  return r;
}

}  // namespace pteromys
