#include "pteromys/glider.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "pteromys/geometry.hpp"
#include "pteromys/text.hpp"

namespace pteromys {

namespace {

bool all_finite(const Polygon& p) {
  return std::all_of(p.begin(), p.end(),
                     [](const Vec2& v) { return std::isfinite(v.x) && std::isfinite(v.y); });
}

// Problems of one plate outline; `what` names it ("fuselage", "wing 'main'").
void outline_problems(const Polygon& p, const std::string& what, const ValidationTolerances& tol,
                      std::vector<std::string>& out) {
  if (p.size() < 3) {
    out.push_back(what + " outline has " + std::to_string(p.size()) +
                  " points; a plate needs at least 3");
    return;
  }
  if (!all_finite(p)) {
    out.push_back(what + " outline has a NaN or infinite coordinate");
    return;
  }
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec2 a = p[i], b = p[(i + 1) % p.size()];
    if (norm(b - a) < tol.min_edge_m) {
      out.push_back(what + " outline repeats the point (" + fmt_number(a.x, 4) + ", " + fmt_number(a.y, 4) +
                    ") (points " + std::to_string(i) + " and " +
                    std::to_string((i + 1) % p.size()) + "); remove the duplicate");
      return;
    }
  }
  // All points on one line: degenerate (CGAL would also call it non-simple).
  std::size_t far = 0;
  for (std::size_t i = 1; i < p.size(); ++i)
    if (norm(p[i] - p[0]) > norm(p[far] - p[0])) far = i;
  const Vec2 axis = p[far] - p[0];
  bool collinear = true;
  for (const auto& v : p)
    if (std::abs(cross(axis, v - p[0])) > 1e-12 * dot(axis, axis)) collinear = false;
  const double area = std::abs(signed_area(p));
  if (collinear) {
    out.push_back(what + " outline is degenerate: all its points lie on one line");
    return;
  }
  if (!is_simple(p)) {
    out.push_back(what + " outline crosses itself; draw it as a simple closed polygon");
    return;
  }
  if (area < tol.min_area_m2) {
    out.push_back(what + " outline is degenerate: its area is " + fmt_number(area, 4) + " m^2");
    return;
  }
  const auto [lo, hi] = bounds(p);
  const double extent = std::max(hi.x - lo.x, hi.y - lo.y);
  if (extent > tol.max_extent_m) {
    out.push_back(what + " is " + fmt_number(extent, 4) +
                  " m long; coordinates must be in metres (were they written in millimetres?)");
  }
}

}  // namespace

std::vector<std::pair<double, double>> root_chord_intervals(const Polygon& outline) {
  std::vector<double> xs;
  const std::size_t n = outline.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 a = outline[i], b = outline[(i + 1) % n];
    // Half-open rule: a vertex on z = 0 is counted once per crossing.
    if ((a.y <= 0 && b.y > 0) || (b.y <= 0 && a.y > 0)) {
      const double t = (0 - a.y) / (b.y - a.y);
      xs.push_back(a.x + t * (b.x - a.x));
    }
  }
  std::sort(xs.begin(), xs.end());
  std::vector<std::pair<double, double>> out;
  for (std::size_t i = 0; i + 1 < xs.size(); i += 2) out.emplace_back(xs[i], xs[i + 1]);
  return out;
}

double root_overlap_with_fuselage(const Glider& g, std::size_t j) {
  const Wing& w = g.wings.at(j);
  const double th = deg2rad(w.mount.angle_deg);
  const Vec2 P{w.mount.x_m, w.mount.y_m};
  double total = 0;
  for (const auto& [xt, xl] : root_chord_intervals(w.outline)) {
    const Vec2 a = P + rotate({xt, 0.0}, th), b = P + rotate({xl, 0.0}, th);
    total += segment_length_inside(g.fuselage, a, b);
  }
  return total;
}

std::vector<std::string> validation_problems(const Glider& g, const ValidationTolerances& tol) {
  std::vector<std::string> out;
  const auto& m = g.material;
  if (!std::isfinite(m.thickness_m) || m.thickness_m <= 0)
    out.push_back("material thickness must be a positive number of metres (got " +
                  fmt_number(m.thickness_m, 4) + ")");
  else if (m.thickness_m > 0.05)
    out.push_back("material thickness " + fmt_number(m.thickness_m, 4) +
                  " m is not a plate; thickness is in metres (1 mm = 0.001)");
  if (!std::isfinite(m.density_kg_m3) || m.density_kg_m3 <= 0)
    out.push_back("material density must be a positive number of kg/m^3 (got " +
                  fmt_number(m.density_kg_m3, 4) + ")");

  outline_problems(g.fuselage, "fuselage", tol, out);
  const bool fuselage_ok = out.empty() || std::none_of(out.begin(), out.end(), [](const auto& s) {
                             return s.rfind("fuselage", 0) == 0;
                           });

  if (g.wings.empty()) out.push_back("the glider has no wing");
  std::set<std::string> names;
  for (std::size_t j = 0; j < g.wings.size(); ++j) {
    const Wing& w = g.wings[j];
    const std::string what = "wing '" + (w.name.empty() ? std::to_string(j) : w.name) + "'";
    if (w.name.empty()) out.push_back("wing " + std::to_string(j) + " has no name");
    else if (!names.insert(w.name).second) out.push_back("two wings are named '" + w.name + "'");
    if (!std::isfinite(w.mount.x_m) || !std::isfinite(w.mount.y_m) ||
        !std::isfinite(w.mount.angle_deg)) {
      out.push_back(what + " mount has a NaN or infinite number");
      continue;
    }
    const std::size_t before = out.size();
    outline_problems(w.outline, what, tol, out);
    if (out.size() != before) continue;
    // Mirror symmetry about z = 0 (spec: within 0.1 mm): every mirrored vertex
    // lies on the outline.
    double worst = 0;
    Vec2 worst_pt;
    for (const auto& v : w.outline) {
      const double d = distance_to_boundary(w.outline, {v.x, -v.y});
      if (d > worst) { worst = d; worst_pt = v; }
    }
    if (worst > tol.symmetry_m) {
      out.push_back(what + " is not mirror-symmetric about z = 0: the mirror image of point (" +
                    fmt_number(worst_pt.x, 4) + ", " + fmt_number(worst_pt.y, 4) + ") is " + fmt_number(worst * 1000, 4) +
                    " mm from the outline (allowed 0.1 mm)");
      continue;
    }
    if (std::abs(w.mount.angle_deg) > 60)
      out.push_back(what + " mounting angle " + fmt_number(w.mount.angle_deg, 4) +
                    " deg is not a wing angle (expected within +-60 deg)");
    if (fuselage_ok && root_overlap_with_fuselage(g, j) <= 0)
      out.push_back(what + " does not touch the fuselage: its root chord at (" +
                    fmt_number(w.mount.x_m, 4) + ", " + fmt_number(w.mount.y_m, 4) +
                    ") m lies outside the fuselage plate");
  }
  for (std::size_t k = 0; k < g.ballast.size(); ++k) {
    const Ballast& b = g.ballast[k];
    const std::string what = "ballast '" + (b.name.empty() ? std::to_string(k) : b.name) + "'";
    if (!std::isfinite(b.mass_kg) || !std::isfinite(b.x_m) || !std::isfinite(b.y_m))
      out.push_back(what + " has a NaN or infinite number");
    else if (b.mass_kg < 0)
      out.push_back(what + " has negative mass " + fmt_number(b.mass_kg, 4) + " kg");
  }
  return out;
}

void validate(const Glider& g, const ValidationTolerances& tol) {
  const auto problems = validation_problems(g, tol);
  if (problems.empty()) return;
  std::string msg = problems.front();
  for (std::size_t i = 1; i < problems.size(); ++i) msg += "; " + problems[i];
  throw InputError(msg);
}

}  // namespace pteromys
