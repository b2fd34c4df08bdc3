#include "pteromys/geometry.hpp"

#include <algorithm>
#include <limits>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/Polygon_2_algorithms.h>

namespace pteromys {
namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_2;

std::vector<Point> to_cgal(const Polygon& p) {
  std::vector<Point> out;
  out.reserve(p.size());
  for (const auto& v : p) out.emplace_back(v.x, v.y);
  return out;
}
}  // namespace

AreaMoments area_moments(const Polygon& p) {
  // Green's theorem over each edge (a -> b), exact for polygons.
  AreaMoments m;
  const std::size_t n = p.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 a = p[i], b = p[(i + 1) % n];
    const double c = a.x * b.y - b.x * a.y;
    m.A += c;
    m.Sx += (a.x + b.x) * c;
    m.Sy += (a.y + b.y) * c;
    m.Sxx += (a.x * a.x + a.x * b.x + b.x * b.x) * c;
    m.Syy += (a.y * a.y + a.y * b.y + b.y * b.y) * c;
    m.Sxy += (a.x * b.y + 2 * a.x * a.y + 2 * b.x * b.y + b.x * a.y) * c;
  }
  m.A /= 2;
  m.Sx /= 6;
  m.Sy /= 6;
  m.Sxx /= 12;
  m.Syy /= 12;
  m.Sxy /= 24;
  if (m.A < 0) {
    m.A = -m.A; m.Sx = -m.Sx; m.Sy = -m.Sy;
    m.Sxx = -m.Sxx; m.Syy = -m.Syy; m.Sxy = -m.Sxy;
  }
  return m;
}

double signed_area(const Polygon& p) {
  double a = 0;
  for (std::size_t i = 0, n = p.size(); i < n; ++i) a += cross(p[i], p[(i + 1) % n]);
  return a / 2;
}

bool is_simple(const Polygon& p) {
  if (p.size() < 3) return false;
  const auto pts = to_cgal(p);
  // CGAL's test treats repeated vertices as non-simple; exact predicates.
  return CGAL::is_simple_2(pts.begin(), pts.end(), K());
}

Polygon counter_clockwise(const Polygon& p) {
  Polygon q = p;
  if (signed_area(q) < 0) std::reverse(q.begin(), q.end());
  return q;
}

bool contains(const Polygon& p, Vec2 q) {
  const auto pts = to_cgal(p);
  const auto side = CGAL::bounded_side_2(pts.begin(), pts.end(), Point(q.x, q.y), K());
  return side != CGAL::ON_UNBOUNDED_SIDE;
}

double segment_length_inside(const Polygon& p, Vec2 a, Vec2 b) {
  // Split [a, b] at its crossings with the polygon edges and add up the
  // pieces whose midpoint is inside.
  std::vector<double> ts{0.0, 1.0};
  const Vec2 d = b - a;
  const std::size_t n = p.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 c = p[i], e = p[(i + 1) % n] - p[i];
    const double den = cross(d, e);
    if (std::abs(den) < 1e-300) continue;  // parallel: endpoints handled by other edges
    const Vec2 ac = c - a;
    const double t = cross(ac, e) / den;
    const double u = cross(ac, d) / den;
    if (t > 0 && t < 1 && u >= 0 && u <= 1) ts.push_back(t);
  }
  std::sort(ts.begin(), ts.end());
  const double len = norm(d);
  double inside = 0;
  for (std::size_t i = 0; i + 1 < ts.size(); ++i) {
    const double t0 = ts[i], t1 = ts[i + 1];
    if (t1 - t0 <= 0) continue;
    const Vec2 mid = a + ((t0 + t1) / 2) * d;
    if (contains(p, mid)) inside += (t1 - t0) * len;
  }
  return inside;
}

double distance_to_boundary(const Polygon& p, Vec2 q) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0, n = p.size(); i < n; ++i) {
    const Vec2 a = p[i], b = p[(i + 1) % n];
    const Vec2 ab = b - a;
    const double l2 = dot(ab, ab);
    double t = l2 > 0 ? dot(q - a, ab) / l2 : 0.0;
    t = std::clamp(t, 0.0, 1.0);
    best = std::min(best, norm(q - (a + t * ab)));
  }
  return best;
}

std::pair<Vec2, Vec2> bounds(const Polygon& p) {
  Vec2 lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  Vec2 hi{-lo.x, -lo.y};
  for (const auto& v : p) {
    lo.x = std::min(lo.x, v.x); lo.y = std::min(lo.y, v.y);
    hi.x = std::max(hi.x, v.x); hi.y = std::max(hi.y, v.y);
  }
  return {lo, hi};
}

}  // namespace pteromys
