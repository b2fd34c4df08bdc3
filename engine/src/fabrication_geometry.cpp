#include "pteromys/fabrication_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pteromys::fab {

bool point_in_polygon(const Polygon& p, Vec2 q) {
  bool in = false;
  const std::size_t n = p.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Vec2 a = p[i], b = p[j];
    if ((a.y > q.y) != (b.y > q.y)) {
      const double x = a.x + (q.y - a.y) * (b.x - a.x) / (b.y - a.y);
      if (q.x < x) in = !in;
    }
  }
  return in;
}

bool inside(const Region& r, Vec2 q) {
  if (!point_in_polygon(r.outline, q)) return false;
  for (const auto& h : r.holes)
    if (point_in_polygon(h, q)) return false;
  return true;
}

namespace {
int orient(Vec2 a, Vec2 b, Vec2 c) {
  const double v = cross(b - a, c - a);
  const double scale = std::max({norm(b - a) * norm(c - a), 1e-300});
  if (std::fabs(v) <= 1e-14 * scale) return 0;
  return v > 0 ? 1 : -1;
}
bool on_segment(Vec2 a, Vec2 b, Vec2 q) {
  return std::min(a.x, b.x) - 1e-15 <= q.x && q.x <= std::max(a.x, b.x) + 1e-15 &&
         std::min(a.y, b.y) - 1e-15 <= q.y && q.y <= std::max(a.y, b.y) + 1e-15;
}
}  // namespace

bool segments_intersect(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  const int o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
  if (o1 != o2 && o3 != o4) return true;
  if (o1 == 0 && on_segment(a, b, c)) return true;
  if (o2 == 0 && on_segment(a, b, d)) return true;
  if (o3 == 0 && on_segment(c, d, a)) return true;
  if (o4 == 0 && on_segment(c, d, b)) return true;
  return false;
}

double point_segment_distance(Vec2 q, Vec2 a, Vec2 b) {
  const Vec2 ab = b - a;
  const double L2 = dot(ab, ab);
  double t = L2 > 0 ? dot(q - a, ab) / L2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return norm(q - (a + t * ab));
}

double segment_distance(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  if (segments_intersect(a, b, c, d)) return 0.0;
  return std::min({point_segment_distance(a, c, d), point_segment_distance(b, c, d),
                   point_segment_distance(c, a, b), point_segment_distance(d, a, b)});
}

double polygon_distance(const Polygon& a, const Polygon& b, Vec2* where) {
  double best = std::numeric_limits<double>::infinity();
  Vec2 at = a.empty() ? Vec2{} : a[0];
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Vec2 p = a[i], q = a[(i + 1) % a.size()];
    for (std::size_t j = 0; j < b.size(); ++j) {
      const Vec2 r = b[j], s = b[(j + 1) % b.size()];
      const double d = segment_distance(p, q, r, s);
      if (d < best) {
        best = d;
        // closest point of [p, q] to [r, s], approximately: the nearer end or
        // the projection of the nearer end of [r, s]
        const double dr = point_segment_distance(r, p, q), ds = point_segment_distance(s, p, q);
        const Vec2 o = dr < ds ? r : s;
        const Vec2 pq = q - p;
        const double L2 = dot(pq, pq);
        const double t = L2 > 0 ? std::clamp(dot(o - p, pq) / L2, 0.0, 1.0) : 0.0;
        at = p + t * pq;
      }
    }
  }
  if (best > 0 && !a.empty() && !b.empty()) {
    if (point_in_polygon(b, a[0])) { best = 0; at = a[0]; }
    else if (point_in_polygon(a, b[0])) { best = 0; at = b[0]; }
  }
  if (where) *where = at;
  return best;
}

double distance_to_boundary(const Region& r, Vec2 q) {
  double best = std::numeric_limits<double>::infinity();
  auto scan = [&](const Polygon& p) {
    for (std::size_t i = 0; i < p.size(); ++i)
      best = std::min(best, point_segment_distance(q, p[i], p[(i + 1) % p.size()]));
  };
  scan(r.outline);
  for (const auto& h : r.holes) scan(h);
  return best;
}

std::vector<std::pair<Vec2, Vec2>> clip_segment(const Region& r, Vec2 a, Vec2 b, double min_len) {
  std::vector<double> ts{0.0, 1.0};
  const Vec2 ab = b - a;
  auto scan = [&](const Polygon& p) {
    for (std::size_t i = 0; i < p.size(); ++i) {
      const Vec2 c = p[i], d = p[(i + 1) % p.size()];
      const Vec2 cd = d - c;
      const double den = cross(ab, cd);
      if (std::fabs(den) < 1e-300) continue;
      const double t = cross(c - a, cd) / den, u = cross(c - a, ab) / den;
      if (t > 0 && t < 1 && u >= 0 && u <= 1) ts.push_back(t);
    }
  };
  scan(r.outline);
  for (const auto& h : r.holes) scan(h);
  std::sort(ts.begin(), ts.end());
  std::vector<std::pair<Vec2, Vec2>> out;
  for (std::size_t i = 0; i + 1 < ts.size(); ++i) {
    const double t0 = ts[i], t1 = ts[i + 1];
    if ((t1 - t0) * norm(ab) <= std::max(min_len, 0.0)) continue;
    if (!inside(r, a + (0.5 * (t0 + t1)) * ab)) continue;
    const Vec2 p = a + t0 * ab, q = a + t1 * ab;
    if (!out.empty() && norm(out.back().second - p) < 1e-12) out.back().second = q;
    else out.emplace_back(p, q);
  }
  return out;
}

Polygon clean_polygon(const Polygon& p, double tol) {
  Polygon q;
  for (const auto& v : p)
    if (q.empty() || norm(v - q.back()) > tol) q.push_back(v);
  while (q.size() > 1 && norm(q.front() - q.back()) <= tol) q.pop_back();
  bool changed = true;
  while (changed && q.size() > 3) {
    changed = false;
    for (std::size_t i = 0; i < q.size() && q.size() > 3; ++i) {
      const Vec2 a = q[(i + q.size() - 1) % q.size()], b = q[i], c = q[(i + 1) % q.size()];
      const double L = norm(c - a);
      // deviation of b from the line a-c, and b must lie between a and c
      if (L > 0 && std::fabs(cross(c - a, b - a)) / L <= tol && dot(b - a, c - a) >= 0 && dot(b - c, a - c) >= 0) {
        q.erase(q.begin() + static_cast<std::ptrdiff_t>(i));
        changed = true;
        --i;
      }
    }
  }
  return q;
}

double perimeter(const Polygon& p) {
  double s = 0;
  for (std::size_t i = 0; i < p.size(); ++i) s += norm(p[(i + 1) % p.size()] - p[i]);
  return s;
}

Polygon oriented_box(Vec2 c, double hx, double hy, double angle) {
  const Vec2 u{std::cos(angle), std::sin(angle)}, v{-u.y, u.x};
  return {c + (-hx) * u + (-hy) * v, c + hx * u + (-hy) * v, c + hx * u + hy * v, c + (-hx) * u + hy * v};
}

bool box_fits(const Region& r, const Polygon& box, double margin) {
  for (const auto& c : box)
    if (!inside(r, c)) return false;
  if (!inside(r, 0.25 * (box[0] + box[1] + box[2] + box[3]))) return false;
  auto clear = [&](const Polygon& p) {
    for (std::size_t i = 0; i < p.size(); ++i) {
      const Vec2 a = p[i], b = p[(i + 1) % p.size()];
      for (std::size_t k = 0; k < box.size(); ++k)
        if (segment_distance(a, b, box[k], box[(k + 1) % box.size()]) < margin) return false;
      // a boundary piece entirely inside the box
      if (point_in_polygon(box, a)) return false;
    }
    return true;
  };
  if (!clear(r.outline)) return false;
  for (const auto& h : r.holes)
    if (!clear(h)) return false;
  return true;
}

}  // namespace pteromys::fab
