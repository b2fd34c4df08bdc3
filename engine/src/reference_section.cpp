// Reference simulator: effect switches and the 2D sharp-flat-plate section law.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "pteromys/reference.hpp"

namespace pteromys {

// ---------------------------------------------------------------- effects

const std::vector<std::string>& Effects::names() {
  static const std::vector<std::string> n = {"pitch_damping", "downwash",      "finite_span",
                                             "fuselage_drag", "ground_effect", "launch_rotation",
                                             "added_mass",    "wind",          "camera"};
  return n;
}

EffectSwitch& Effects::operator[](const std::string& name) {
  if (name == "pitch_damping") return pitch_damping;
  if (name == "downwash") return downwash;
  if (name == "finite_span") return finite_span;
  if (name == "fuselage_drag") return fuselage_drag;
  if (name == "ground_effect") return ground_effect;
  if (name == "launch_rotation") return launch_rotation;
  if (name == "added_mass") return added_mass;
  if (name == "wind") return wind;
  if (name == "camera") return camera;
  std::string all;
  for (const auto& n : names()) all += (all.empty() ? "" : ", ") + n;
  throw InputError("unknown effect '" + name + "' (known: " + all + ")");
}

const EffectSwitch& Effects::operator[](const std::string& name) const {
  return const_cast<Effects&>(*this)[name];
}

Effects Effects::baseline() { return Effects{}; }

Effects Effects::physics() {
  Effects e;
  for (auto* s : {&e.pitch_damping, &e.downwash, &e.finite_span, &e.fuselage_drag, &e.ground_effect,
                  &e.added_mass})
    s->on = true;
  return e;
}

Effects Effects::all() {
  Effects e;
  for (const auto& n : names()) e[n].on = true;
  return e;
}

std::string Effects::describe() const {
  std::ostringstream s;
  s.precision(6);
  bool any = false;
  for (const auto& n : names()) {
    const EffectSwitch& e = (*this)[n];
    if (!e.on) continue;
    s << (any ? "," : "") << n << "=" << e.strength;
    any = true;
  }
  return any ? s.str() : "none";
}

namespace {
std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : s) {
    if (c == sep) {
      out.push_back(cur);
      cur.clear();
    } else if (!std::isspace(static_cast<unsigned char>(c))) {
      cur += c;
    }
  }
  out.push_back(cur);
  return out;
}
}  // namespace

Effects parse_effects(const std::string& spec) {
  if (spec == "physics" || spec.empty()) return Effects::physics();
  if (spec == "baseline" || spec == "none") return Effects::baseline();
  if (spec == "all") return Effects::all();
  Effects e = Effects::baseline();
  for (const auto& n : split(spec, ',')) {
    if (n.empty()) throw InputError("empty effect name in '" + spec + "'");
    e[n].on = true;
  }
  return e;
}

void apply_strengths(Effects& e, const std::string& spec) {
  if (spec.empty()) return;
  for (const auto& item : split(spec, ',')) {
    const auto eq = item.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == item.size())
      throw InputError("strength '" + item + "' is not of the form effect=value");
    EffectSwitch& sw = e[item.substr(0, eq)];
    const std::string v = item.substr(eq + 1);
    char* end = nullptr;
    const double x = std::strtod(v.c_str(), &end);
    if (end == v.c_str() || *end != '\0' || !std::isfinite(x))
      throw InputError("strength of '" + item.substr(0, eq) + "' must be a finite number, got '" + v + "'");
    sw.strength = x;
    sw.on = x != 0;
  }
}

// ------------------------------------------------------------ section law

double SectionLaw::attached_fraction(double alpha, double* df) const {
  const double a = std::abs(alpha);
  const double af = std::min(a, kPi - a);
  const double w = deg2rad(stall_width_deg);
  const double f = 1.0 / (1.0 + std::exp((af - deg2rad(stall_deg)) / w));
  if (df) {
    const double sa = alpha < 0 ? -1.0 : 1.0;
    const double daf = a < kPi / 2 ? sa : -sa;
    *df = -f * (1 - f) / w * daf;
  }
  return f;
}

double SectionLaw::attached_normal_force(double alpha, double* d) const {
  const double s = std::sin(alpha), c = std::cos(alpha);
  if (d) *d = lift_slope * (c < 0 ? -1.0 : 1.0) * (c * c - s * s);
  return lift_slope * s * std::abs(c);
}

double SectionLaw::separated_normal_force(double alpha, double cn90) const {
  const double s = std::sin(alpha);
  return cn90 * s / (0.56 + 0.44 * std::abs(s));
}

double SectionLaw::normal_force(double alpha, double cn90, double* dcn) const {
  const double s = std::sin(alpha), c = std::cos(alpha);
  const double den = 0.56 + 0.44 * std::abs(s);
  double df = 0, datt = 0;
  const double f = attached_fraction(alpha, dcn ? &df : nullptr);
  const double cn_att = attached_normal_force(alpha, dcn ? &datt : nullptr);
  const double cn_sep = cn90 * s / den;
  if (dcn) {
    const double dsep = cn90 * c * 0.56 / (den * den);
    *dcn = df * (cn_att - cn_sep) + f * datt + (1 - f) * dsep;
  }
  return f * cn_att + (1 - f) * cn_sep;
}

double SectionLaw::centre_of_pressure(double alpha, double cn90) const {
  const double s = std::sin(alpha), c = std::cos(alpha);
  const double f = attached_fraction(alpha);
  const double cn_att = lift_slope * std::abs(s * c);
  const double cn_sep = cn90 * std::abs(s) / (0.56 + 0.44 * std::abs(s));
  const double x_att = c >= 0 ? 0.25 : 0.75;
  const double x_sep = 0.5 - 0.25 * c;
  const double wa = f * cn_att, ws = (1 - f) * cn_sep;
  if (wa + ws < 1e-12) return x_att;
  return (wa * x_att + ws * x_sep) / (wa + ws);
}

double SectionLaw::friction(double re) const {
  const double r = std::max(re, 100.0);
  if (r < transition_re) return 2.0 * 1.328 / std::sqrt(r);
  // Prandtl-Schlichting mixed laminar/turbulent flow, 0.074 Re^-0.2 - A / Re
  // per face, A chosen for continuity at the transition (1739 at 5e5; the
  // textbook rounds it to 1742).
  const double tr = transition_re;
  const double a = tr * (0.074 / std::pow(tr, 0.2) - 1.328 / std::sqrt(tr));
  return 2.0 * std::max(0.074 / std::pow(r, 0.2) - a / r, 1.328 / std::sqrt(r));
}

double normal_force_90(double aspect_ratio) {
  if (!(aspect_ratio > 0)) return 1.98;
  return 1.98 - 0.81 * (1.0 - std::exp(-20.0 / aspect_ratio));
}

}  // namespace pteromys
