// Candidate effects of the diagnosis: parametric corrections of the fast
// wing-element model (effects.hpp; formulas in docs/diagnosis.md).
#include "pteromys/effects.hpp"

#include <algorithm>
#include <cmath>

#include "pteromys/elements.hpp"
#include "pteromys/geometry.hpp"
#include "pteromys/mass.hpp"

namespace pteromys {
namespace {

constexpr double kRadToDeg = 180.0 / kPi;

std::vector<EffectSpec> make_specs() {
  // Aerodynamic strengths: 1 is the correction's full theoretical size; the
  // fit may find up to 3 times that (the corrections are approximations of
  // the physics), fuselage drag and ground effect up to 10 (friction alone
  // underestimates a plate's drag; McCormick's factor is an empirical fit).
  auto k = [](double hi) { return EffectParameter{"strength", "-", 1.0, 0.0, hi, 1.0, {0.5, 1.0, 2.0}}; };
  return {
      {Effect::PitchDamping, "pitch_damping",
       "each wing sees the air velocity of the pitch rate at its 3/4-chord point", EffectLevel::Aerodynamic,
       {k(3)}},
      {Effect::Downwash, "downwash",
       "the other wings' strip-loaded wakes lower the angle of attack behind them (raise it ahead)",
       EffectLevel::Aerodynamic, {k(3)}},
      {Effect::FiniteSpan, "finite_span",
       "each wing's own induced angle C_L/(pi A e): lift-slope loss and induced drag of its aspect ratio",
       EffectLevel::Aerodynamic, {k(3)}},
      {Effect::FuselageDrag, "fuselage_drag", "laminar friction drag of the fuselage plate (both faces)",
       EffectLevel::Aerodynamic, {k(10)}},
      {Effect::GroundEffect, "ground_effect", "the induced angle falls near the ground (McCormick's factor)",
       EffectLevel::Aerodynamic, {k(3)}},
      {Effect::LaunchRotation, "launch_rotation", "a pitch rate at the first tracked point: each flight's own (a launch value) or one for all",
       EffectLevel::Launch, {{"pitch_rate_deg_s", "rad/s", 1.0, -20.0, 20.0, kRadToDeg, {-1.0, 1.0}}}},
      {Effect::AddedMass, "added_mass", "apparent mass and rotary inertia of the plates moving normal to themselves",
       EffectLevel::Aerodynamic, {k(3)}},
      {Effect::Wind, "wind", "a steady horizontal wind during the session",
       EffectLevel::Session, {{"wind_m_s", "m/s", 1.0, -15.0, 15.0, 1.0, {-1.0, 1.0}}}},
      {Effect::Camera, "camera", "the camera's scale (distance) and roll errors",
       EffectLevel::Observation,
       {{"scale_error", "-", 0.02, -0.5, 0.5, 1.0, {-0.03, 0.03}, 0.15},
        {"roll_deg", "rad", 0.02, -0.5, 0.5, kRadToDeg, {-0.035, 0.035}, 10.0 / kRadToDeg}},
       // A fitted camera error that a calibrated camera does not make is
       // another misfit absorbed (blind 1 m/s headwind: scale 17.5 %, roll
       // 8.7 deg; pitch damping + wind: scale -22 %).
       "a camera calibrated in the flight plane (docs/capture.md) errs in scale only by the glider's distance from "
       "that plane (2.5 % per 10 cm at 4 m: 15 % is 60 cm) and in roll by the calibration board's tilt (under "
       "10 degrees)"},
  };
}

const std::vector<EffectSpec>& specs() {
  static const std::vector<EffectSpec> s = make_specs();
  return s;
}

inline double wrap(double a) { return wrap_angle(a); }

using V3 = std::array<double, 3>;
inline V3 sub(const V3& a, const V3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline V3 cross3(const V3& a, const V3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double dot3(const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline double norm3(const V3& a) { return std::sqrt(dot3(a, a)); }

/// Segment a -> b of unit circulation (Biot-Savart, smoothed core).
V3 segment(const V3& p, const V3& a, const V3& b, double rc) {
  const V3 r1 = sub(p, a), r2 = sub(p, b), r0 = sub(b, a);
  const V3 c = cross3(r1, r2);
  const double l0 = norm3(r0);
  if (l0 <= 0) return {0, 0, 0};
  const double c2 = dot3(c, c) + rc * rc * l0 * l0;  // |r1 x r2|^2 = h^2 l0^2
  const double n1 = norm3(r1), n2 = norm3(r2);
  if (n1 <= 0 || n2 <= 0 || c2 <= 0) return {0, 0, 0};
  const double k = (dot3(r0, r1) / n1 - dot3(r0, r2) / n2) / (4 * kPi * c2);
  return {k * c[0], k * c[1], k * c[2]};
}

/// Semi-infinite leg from a to infinity along unit d, unit circulation.
V3 leg(const V3& p, const V3& a, const V3& d, double rc) {
  const V3 r1 = sub(p, a);
  const V3 c = cross3(d, r1);
  const double n1 = norm3(r1);
  const double c2 = dot3(c, c) + rc * rc;
  if (n1 <= 0 || c2 <= 0) return {0, 0, 0};
  const double k = (1 + dot3(d, r1) / n1) / (4 * kPi * c2);
  return {k * c[0], k * c[1], k * c[2]};
}

/// A point x along a wing's chord line (wing frame) in the glider frame, - cg.
Vec2 on_glider(double x, const Mount& m, Vec2 cg) {
  return Vec2{m.x_m, m.y_m} + rotate({x, 0.0}, deg2rad(m.angle_deg)) - cg;
}

Vec2 mean_point(const WingElements& el, double chord_fraction, const Mount& m, Vec2 cg) {
  double a = 0, x = 0;
  for (const auto& e : el.elements) {
    a += e.area;
    x += e.area * (e.x_le - chord_fraction * e.chord);
  }
  return on_glider(a > 0 ? x / a : 0.0, m, cg);
}

/// Wake angles of the downwash table (kWakeAngleMin..kWakeAngleMax, 1 degree).
constexpr int kWakeAngles = kWakeAngleMax - kWakeAngleMin + 1;

/// The planform in spanwise bands: the element slices (pieces of one slice
/// merged), consecutive slices grouped so that there are at most kWakeBands;
/// per band its extent, area, mean chord and area-weighted 1/4- and
/// 3/4-chord points (glider frame, - cg). Bands follow the slices so that a
/// constant chord gives equal band circulations (no spurious trailing legs).
std::vector<WingFeatures::Band> wake_bands(const WingElements& el, const Mount& m, Vec2 cg) {
  struct Slice {
    double z0, z1, a = 0, xq = 0, xt = 0;
  };
  std::vector<Slice> slices;
  for (const auto& e : el.elements) {  // ordered by z, then by streamline rank
    if (slices.empty() || std::abs(e.z0 - slices.back().z0) > 1e-12 || std::abs(e.z1 - slices.back().z1) > 1e-12)
      slices.push_back({e.z0, e.z1});
    Slice& sl = slices.back();
    sl.a += e.area;
    sl.xq += e.area * (e.x_le - 0.25 * e.chord);
    sl.xt += e.area * (e.x_le - 0.75 * e.chord);
  }
  const std::size_t n = slices.size();
  const std::size_t group = (n + kWakeBands - 1) / kWakeBands;
  std::vector<WingFeatures::Band> out;
  for (std::size_t i = 0; i < n; i += group) {
    Slice b{slices[i].z0, slices[i].z1};
    for (std::size_t k = i; k < std::min(n, i + group); ++k) {
      b.z1 = slices[k].z1;
      b.a += slices[k].a;
      b.xq += slices[k].xq;
      b.xt += slices[k].xt;
    }
    if (!(b.a > 0) || !(b.z1 > b.z0)) continue;
    WingFeatures::Band band;
    band.z0 = b.z0;
    band.z1 = b.z1;
    band.area = b.a;
    band.chord = b.a / (b.z1 - b.z0);
    band.quarter = on_glider(b.xq / b.a, m, cg);
    band.three_quarter = on_glider(b.xt / b.a, m, cg);
    out.push_back(band);
  }
  return out;
}

/// GliderFeatures::wake_influence: per ordered pair of wings and wake angle,
/// the area-weighted mean velocity that wing i's strip-loaded wake (a
/// horseshoe of circulation c/2 per band) induces at wing j's 3/4-chord
/// points. Vortex core: the larger of 5 % of the mean chord and half a band.
std::vector<Vec2> wake_table(const std::vector<WingFeatures>& wings) {
  const std::size_t n = wings.size();
  constexpr int na = kWakeAngles;
  std::vector<Vec2> out(n * n * na, Vec2{0, 0});
  if (n < 2) return out;
  for (int k = 0; k < na; ++k) {
    const double psi = deg2rad(static_cast<double>(kWakeAngleMin + k));
    const V3 d{-std::cos(psi), std::sin(psi), 0.0};
    for (std::size_t i = 0; i < n; ++i) {
      const auto& wi = wings[i];
      if (wi.bands.empty()) continue;
      double widest = 0;
      for (const auto& s : wi.bands) widest = std::max(widest, s.z1 - s.z0);
      const double rc = std::max(0.05 * wi.mean_chord, 0.5 * widest);
      for (std::size_t j = 0; j < n; ++j) {
        const auto& wj = wings[j];
        if (j == i || !(wj.area > 0)) continue;
        Vec2 sum{0, 0};
        for (const auto& t : wj.bands) {
          const V3 P{t.three_quarter.x, t.three_quarter.y, 0.5 * (t.z0 + t.z1)};
          Vec2 v{0, 0};
          for (const auto& s : wi.bands) {
            const V3 A{s.quarter.x, s.quarter.y, s.z0}, B{s.quarter.x, s.quarter.y, s.z1};
            const V3 u = horseshoe_velocity(P, A, B, d, 0.5 * s.chord, rc);
            v = v + Vec2{u[0], u[1]};
          }
          sum = sum + (t.area / wj.area) * v;
        }
        out[(i * n + j) * na + k] = sum;
      }
    }
  }
  return out;
}

}  // namespace

// ------------------------------------------------------------------ names

const std::vector<Effect>& all_effects() {
  static const std::vector<Effect> e = {Effect::PitchDamping, Effect::Downwash,       Effect::FiniteSpan,
                                        Effect::FuselageDrag, Effect::GroundEffect,   Effect::LaunchRotation,
                                        Effect::AddedMass,    Effect::Wind,           Effect::Camera};
  return e;
}

const EffectSpec& effect_spec(Effect e) { return specs()[static_cast<std::size_t>(e)]; }
const std::string& effect_name(Effect e) { return effect_spec(e).name; }

Effect effect_from_name(const std::string& name) {
  std::string known;
  for (const auto& s : specs()) {
    if (s.name == name) return s.effect;
    known += (known.empty() ? "" : ", ") + s.name;
  }
  throw InputError("unknown effect '" + name + "' (known: " + known + ")");
}

int implausible_parameter(Effect e, const std::vector<double>& values, const std::vector<double>* limits) {
  const auto& ps = effect_spec(e).parameters;
  for (std::size_t i = 0; i < ps.size() && i < values.size(); ++i) {
    const double lim = limits && i < limits->size() ? (*limits)[i] : ps[i].plausible;
    if (std::abs(values[i]) > lim) return static_cast<int>(i);
  }
  return -1;
}

double& EffectValues::at(Effect e, int i) {
  switch (e) {
    case Effect::PitchDamping: return pitch_damping;
    case Effect::Downwash: return downwash;
    case Effect::FiniteSpan: return finite_span;
    case Effect::FuselageDrag: return fuselage_drag;
    case Effect::GroundEffect: return ground_effect;
    case Effect::LaunchRotation: return launch_rotation;
    case Effect::AddedMass: return added_mass;
    case Effect::Wind: return wind;
    case Effect::Camera: return i == 0 ? camera_scale : camera_roll;
  }
  throw InputError("unknown effect");
}

double EffectValues::at(Effect e, int i) const { return const_cast<EffectValues*>(this)->at(e, i); }

bool EffectValues::aerodynamic_zero() const {
  return pitch_damping == 0 && downwash == 0 && finite_span == 0 && fuselage_drag == 0 && ground_effect == 0 &&
         added_mass == 0;
}

bool EffectValues::zero() const {
  return aerodynamic_zero() && launch_rotation == 0 && !launch_rotation_per_flight && wind == 0 && camera_scale == 0 && camera_roll == 0;
}

// --------------------------------------------------------------- geometry

GliderFeatures glider_features(const Glider& g, double dz, double gravity) {
  GliderFeatures f;
  const MassProperties mp = mass_properties(g);
  f.mass = mp.mass;
  f.inertia = mp.inertia;
  f.cg = mp.cg;
  double total_area = 0;
  for (const auto& w : g.wings) {
    const WingElements el = slice_wing(w.outline, dz);
    WingFeatures wf;
    wf.area = el.planform_area;
    wf.span = el.span;
    wf.aspect_ratio = wf.area > 0 ? wf.span * wf.span / wf.area : 0.0;
    wf.mean_chord = wf.span > 0 ? wf.area / wf.span : 0.0;
    wf.theta = deg2rad(w.mount.angle_deg);
    wf.mount = Vec2{w.mount.x_m, w.mount.y_m} - mp.cg;
    wf.quarter_chord = mean_point(el, 0.25, w.mount, mp.cg);
    wf.three_quarter_chord = mean_point(el, 0.75, w.mount, mp.cg);
    wf.mid_chord = mean_point(el, 0.5, w.mount, mp.cg);
    for (const auto& e : el.elements) {
      const double width = e.z1 - e.z0;
      wf.apparent_mass += kPi / 4 * e.chord * e.chord * width;
      wf.apparent_inertia += kPi / 128 * std::pow(e.chord, 4) * width;
    }
    wf.bands = wake_bands(el, w.mount, mp.cg);
    total_area += wf.area;
    f.span = std::max(f.span, wf.span);
    f.wings.push_back(wf);
  }
  for (std::size_t j = 0; j < f.wings.size(); ++j)
    if (f.wings[j].area > f.wings[f.main_wing].area) f.main_wing = static_cast<int>(j);
  if (f.wings.size() > 1) {
    int t = -1;
    for (std::size_t j = 0; j < f.wings.size(); ++j) {
      if (static_cast<int>(j) == f.main_wing) continue;
      if (t < 0 || f.wings[j].area < f.wings[t].area * (1 - 1e-9) ||
          (std::abs(f.wings[j].area - f.wings[t].area) <= 1e-9 * f.wings[t].area &&
           f.wings[j].quarter_chord.x < f.wings[t].quarter_chord.x))
        t = static_cast<int>(j);
    }
    // Equal areas (tandem): the aft wing carries the trim error.
    const auto& m = f.wings[f.main_wing];
    if (std::abs(f.wings[t].area - m.area) <= 1e-6 * m.area && m.quarter_chord.x < f.wings[t].quarter_chord.x)
      t = f.main_wing;
    f.trim_wing = t;
  }
  if (!g.fuselage.empty()) {
    const AreaMoments am = area_moments(g.fuselage);
    f.fuselage_area = am.A;
    if (am.A > 0) f.fuselage_centroid = Vec2{am.Sx / am.A, am.Sy / am.A} - mp.cg;
    const auto b = bounds(g.fuselage);
    f.fuselage_length = b.second.x - b.first.x;
  }
  const auto& mw = f.wings[f.main_wing];
  f.main_aspect_ratio = mw.aspect_ratio;
  if (f.trim_wing >= 0) {
    const int other = f.trim_wing == f.main_wing ? (f.main_wing == 0 ? 1 : 0) : f.trim_wing;
    const auto& tw = f.wings[other];
    f.tail_aspect_ratio = tw.aspect_ratio;
    f.tail_arm = std::abs(tw.quarter_chord.x - mw.quarter_chord.x);
    f.tail_volume = mw.area > 0 && mw.mean_chord > 0 ? tw.area * f.tail_arm / (mw.area * mw.mean_chord) : 0.0;
  }
  f.wing_loading = total_area > 0 ? f.mass * gravity / total_area : 0.0;
  f.fuselage_ratio = mw.area > 0 ? f.fuselage_area / mw.area : 0.0;
  f.wake_influence = wake_table(f.wings);
  return f;
}

Vec2 GliderFeatures::wake_unit(std::size_t i, std::size_t j, double psi) const {
  const std::size_t n = wings.size();
  constexpr int na = kWakeAngles;
  if (i >= n || j >= n || wake_influence.size() != n * n * na) return {0, 0};
  const double x = std::clamp(psi * kRadToDeg - kWakeAngleMin, 0.0, static_cast<double>(na - 1));
  const int k = std::min(static_cast<int>(x), na - 2);
  const double t = x - k;
  const Vec2* u = &wake_influence[(i * n + j) * na];
  return (1 - t) * u[k] + t * u[k + 1];
}

double helmbold_efficiency(double aspect_ratio, double section_slope) {
  if (!(aspect_ratio > 0) || !(section_slope > 0)) return 1.0;
  const double x = section_slope / (kPi * aspect_ratio);
  const double d = std::sqrt(1 + x * x) + x - 1;
  return d > 0 ? x / d : 1.0;
}

double ground_factor(double hb) {
  if (!(hb > 0)) return 0.0;
  const double u = 16 * hb;
  return u * u / (1 + u * u);
}

std::array<double, 3> horseshoe_velocity(const V3& p, const V3& a, const V3& b, const V3& d, double gamma,
                                         double rc) {
  // Leg from infinity into a (circulation along -d from a: a leg a -> inf with -gamma),
  // bound a -> b, leg b -> infinity.
  const V3 s = segment(p, a, b, rc), la = leg(p, a, d, rc), lb = leg(p, b, d, rc);
  return {gamma * (s[0] + lb[0] - la[0]), gamma * (s[1] + lb[1] - la[1]), gamma * (s[2] + lb[2] - la[2])};
}

// -------------------------------------------------------------- EffectAero

namespace {
// |v| < 1e-9 m/s (no air speed: no air force), without the square root.
inline bool at_rest(Vec2 v) { return v.x * v.x + v.y * v.y < 1e-18; }
}  // namespace

EffectAero::EffectAero(const MountedGlider& g, const GliderFeatures& f, const EffectValues& v, double height_origin)
    : g_(g), f_(f), values_(v), height_origin_(height_origin), base_(g) {
  if (f.wings.size() != g.aero().wing_count()) throw InputError("glider features do not match the mounted glider");
  if (f.wings.size() > 8) throw InputError("the effect corrections handle gliders of up to 8 wings");
  rho_ = g.aero().environment().air_density;
  mu_ = g.aero().environment().air_viscosity;
  iterate_ = v.downwash != 0 || v.finite_span != 0 || v.ground_effect != 0;
  for (std::size_t j = 0; j < f.wings.size(); ++j) {
    const double da = 0.02;
    const auto& t = g.aero().table(j);
    const double s = f.wings[j].area > 0 ? (t.lookup(8.0, da).lift - t.lookup(8.0, -da).lift) / (2 * da * f.wings[j].area)
                                         : 0.0;
    slope_.push_back(s);
    efficiency_.push_back(helmbold_efficiency(f.wings[j].aspect_ratio, s > 0.5 ? s : 2 * kPi));
  }
}

// The angle x with x + c C_L(x) = alpha_geo for wing j (its table at speed
// weights sw), from x.
double EffectAero::induced_solve(std::size_t j, const WingTable::SpeedWeights& sw, double c, double ageo,
                                 double x) const {
  // Newton with the table's local slope. Its convergence is quadratic, so
  // once a step is below kStep the next would be of order kStep^2 / (the
  // curvature's scale): two lift look-ups usually. Where the stall makes
  // 1 + c C_L' small or negative the step uses the small-angle slope instead,
  // relaxed, as a fixed-point iteration (linear convergence: stops below kTol).
  constexpr double kStep = 1e-5, kTol = 1e-10;
  constexpr int kMaxSteps = 8;
  const auto& t = g_.aero().table(j);
  const double area = f_.wings[j].area;
  for (int k = 0; k < kMaxSteps; ++k) {
    double dl = 0;
    const double cl = t.lift(sw, wrap(x), &dl) / area;
    double den = 1 + c * dl / area;
    const bool newton = den >= 0.2;
    if (!newton) den = std::max(0.2, 1 + c * slope_[j]);
    const double dx = -(x + c * cl - ageo) / den;
    x += dx;
    if (std::abs(dx) < (newton ? kStep : kTol)) break;
  }
  return x;
}

void EffectAero::flows(const FlightState& s, WingFlow* out, bool coefs, double cb, double sb) const {
  const std::size_t n = f_.wings.size();
  // Air velocity relative to the glider at the CG, glider frame.
  const Vec2 a{-(cb * s.v.x + sb * s.v.y), -(-sb * s.v.x + cb * s.v.y)};
  const auto& mounts = g_.mounts();
  Vec2 aj[8];
  Vec2 w[8];
  double eps[8], c[8];
  const std::size_t nn = n;
  const double h = s.p.y - height_origin_;
  for (std::size_t j = 0; j < nn; ++j) {
    const Vec2 r = f_.wings[j].three_quarter_chord;
    aj[j] = a + (values_.pitch_damping * s.omega) * Vec2{r.y, -r.x};
    w[j] = {0, 0};
    eps[j] = 0;
    c[j] = 0;
    if (values_.finite_span != 0 || values_.ground_effect != 0) {
      const auto& wf = f_.wings[j];
      const double ge = values_.ground_effect != 0 ? values_.ground_effect * (1 - ground_factor(h / wf.span)) : 0.0;
      c[j] = (values_.finite_span - ge) / (kPi * wf.aspect_ratio * efficiency_[j]);
    }
  }
  // Passes: the other wings' wakes (downwash) change each wing's local air
  // velocity, so they are iterated in 4 passes; a wing's own induced angle
  // (finite span, ground effect) is solved within each pass.
  const bool wakes = values_.downwash != 0;
  const int passes = wakes ? 4 : 1;
  // Interference: the wakes of the other wings, tabulated per wake angle
  // (GliderFeatures::wake_unit), scaled in each pass by V_i C_L,i.
  Vec2 unit[8][8];
  if (wakes) {
    const double V = norm(a);  // only the wakes' angle needs it: each wing's speed is its own
    const double psi = V > 0 ? std::atan2(a.y, -a.x) : 0.0;
    for (std::size_t i = 0; i < nn; ++i)
      for (std::size_t j = 0; j < nn; ++j) unit[i][j] = j == i ? Vec2{0, 0} : f_.wake_unit(i, j, psi);
  }
  for (int pass = 0; pass < passes; ++pass) {
    Vec2 u_prev{0, 0};
    double Vj = 0, g = 0;
    WingTable::SpeedWeights sw;
    for (std::size_t j = 0; j < nn; ++j) {
      // Without pitch damping or wakes every wing sees the CG's air velocity:
      // its speed, flow angle and speed weights (one grid for all wings'
      // tables) are computed once.
      const Vec2 u = aj[j] + w[j];
      const bool same = j > 0 && u.x == u_prev.x && u.y == u_prev.y;
      if (!same) {
        Vj = norm(u);
        g = std::atan2(u.y, -u.x);
      }
      u_prev = u;
      const double ageo = g + deg2rad(mounts[j].angle_deg);
      if (!coefs && !iterate_) {
        // The angles alone (max_alpha): no induced angle (c is zero, eps
        // stays 0), so nothing below feeds the tables back into them.
        out[j].speed = Vj;
        out[j].alpha = wrap(ageo);
        out[j].gamma = wrap(g);
        continue;
      }
      const auto& t = g_.aero().table(j);
      // All look-ups of this pass are at the same speed: its weights once.
      if (!same) t.speed_weights(Vj, sw);
      double x = ageo - eps[j];
      if (c[j] != 0) {
        x = induced_solve(j, sw, c[j], ageo, x);
        eps[j] = ageo - x;
      }
      if (!coefs && !wakes) {
        // max_alpha: no other wing needs this wing's lift.
        out[j].speed = Vj;
        out[j].alpha = wrap(x);
        out[j].gamma = wrap(g - eps[j]);
        continue;
      }
      out[j].coefs = t.lookup(sw, wrap(x));
      out[j].speed = Vj;
      out[j].alpha = wrap(x);
      out[j].gamma = wrap(g - eps[j]);
      out[j].cl = out[j].coefs.lift / f_.wings[j].area;
    }
    if (pass + 1 == passes) continue;
    // Interference: the other wings' wakes, circulation 1/2 V_i C_L,i c(z)
    // (strip loading) from this pass's table lift.
    for (std::size_t j = 0; j < nn; ++j) w[j] = {0, 0};
    for (std::size_t i = 0; i < nn; ++i) {
      const double scale = values_.downwash * out[i].speed * out[i].cl;
      for (std::size_t j = 0; j < nn; ++j)
        if (j != i) w[j] = w[j] + scale * unit[i][j];
    }
  }
}

std::vector<WingFlow> EffectAero::wing_flows(const FlightState& s) const {
  std::vector<WingFlow> out(f_.wings.size());
  flows(s, out.data(), true, std::cos(s.beta), std::sin(s.beta));
  return out;
}

Wrench EffectAero::evaluate(const FlightState& s) const {
  if (values_.aerodynamic_zero()) return base_.evaluate(s);
  if (at_rest(s.v)) return {};
  WingFlow fl[8];
  const double cb = std::cos(s.beta), sb = std::sin(s.beta);
  flows(s, fl, true, cb, sb);
  return wrench(s, fl, cb, sb);
}

Wrench EffectAero::evaluate_and_max_alpha(const FlightState& s, double& max_alpha_out) const {
  if (values_.aerodynamic_zero()) return base_.evaluate_and_max_alpha(s, max_alpha_out);
  if (at_rest(s.v)) {
    max_alpha_out = base_.max_alpha(s);
    return {};
  }
  // The angles flows() gives with its look-ups are the ones it gives without
  // them (max_alpha): the same induced solve and wake passes, and without an
  // induced angle x = ageo - 0 = ageo exactly.
  WingFlow fl[8];
  const double cb = std::cos(s.beta), sb = std::sin(s.beta);
  flows(s, fl, true, cb, sb);
  double m = 0;
  for (std::size_t j = 0; j < f_.wings.size(); ++j) m = std::max(m, std::abs(fl[j].alpha));
  max_alpha_out = m;
  return wrench(s, fl, cb, sb);
}

Wrench EffectAero::wrench(const FlightState& s, const WingFlow* fl, double cb, double sb) const {
  const auto& mounts = g_.mounts();
  const Vec2 cg = g_.mass().cg;
  Vec2 F{0, 0};
  double T = 0;
  // Wings that see the same flow angle (no induced angle or wakes, no pitch
  // damping) share its cosine and sine.
  double gamma_prev = 0, cg_ = 1, sg = 0;
  for (std::size_t j = 0; j < f_.wings.size(); ++j) {
    const WingCoefs& c = fl[j].coefs;  // the table at (speed, alpha), looked up by flows
    const double q = 0.5 * rho_ * fl[j].speed * fl[j].speed;
    if (j == 0 || fl[j].gamma != gamma_prev) {
      gamma_prev = fl[j].gamma;
      cg_ = std::cos(gamma_prev);
      sg = std::sin(gamma_prev);
    }
    // Drag along the local air velocity (-cos, sin), lift perpendicular (sin, cos).
    const Vec2 Fj{q * (-c.drag * cg_ + c.lift * sg), q * (c.drag * sg + c.lift * cg_)};
    const Vec2 arm = Vec2{mounts[j].x_m, mounts[j].y_m} - cg;
    T += q * c.moment + cross(arm, Fj);
    F = F + Fj;
  }
  if (values_.fuselage_drag != 0 && f_.fuselage_area > 0 && f_.fuselage_length > 0) {
    const double V = norm(s.v);
    const Vec2 a{-(cb * s.v.x + sb * s.v.y), -(-sb * s.v.x + cb * s.v.y)};
    const double re = rho_ * V * f_.fuselage_length / mu_;
    const double d = values_.fuselage_drag * 0.5 * rho_ * V * V * 2 * f_.fuselage_area * 1.328 / std::sqrt(re);
    const Vec2 Ff = (d / V) * a;
    T += cross(f_.fuselage_centroid, Ff);
    F = F + Ff;
  }
  return {rotate(F, cb, sb), T};
}

double EffectAero::max_alpha(const FlightState& s) const {
  if (values_.aerodynamic_zero()) return base_.max_alpha(s);
  if (at_rest(s.v)) return base_.max_alpha(s);
  WingFlow fl[8];
  flows(s, fl, false, std::cos(s.beta), std::sin(s.beta));
  double m = 0;
  for (std::size_t j = 0; j < f_.wings.size(); ++j) m = std::max(m, std::abs(fl[j].alpha));
  return m;
}

AddedMass EffectAero::added_mass(const FlightState& s) const {
  AddedMass am;
  if (values_.added_mass == 0) return am;
  const auto& mounts = g_.mounts();
  const double cb = std::cos(s.beta), sb = std::sin(s.beta);  // rotate(., s.beta), once for every wing
  for (std::size_t j = 0; j < f_.wings.size(); ++j) {
    const auto& wf = f_.wings[j];
    const double ma = values_.added_mass * rho_ * wf.apparent_mass;
    const double ia = values_.added_mass * rho_ * wf.apparent_inertia;
    const Vec2 n = rotate({0.0, 1.0}, s.beta + deg2rad(mounts[j].angle_deg));
    const Vec2 r = rotate(wf.mid_chord, cb, sb);
    const double J[3] = {n.x, n.y, cross(r, n)};
    const double zn_v = -n.y * s.v.x + n.x * s.v.y;  // (z x n) . v
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) am.m[a][b] += ma * J[a] * J[b];
      am.bias[a] -= ma * s.omega * zn_v * J[a];
    }
    am.m[2][2] += ia;
  }
  return am;
}

Vec2 camera_to_world(Vec2 q, const EffectValues& v) {
  return (1.0 / (1.0 + v.camera_scale)) * rotate(q, -v.camera_roll);
}

Vec2 world_to_camera(Vec2 p, const EffectValues& v) { return (1.0 + v.camera_scale) * rotate(p, v.camera_roll); }

}  // namespace pteromys
