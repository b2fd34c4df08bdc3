// Kerf compensation: cut paths offset from the finished part by half the
// laser's cut width (CGAL straight-skeleton offsets, mitred corners).
#include <cmath>
#include <limits>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/create_offset_polygons_2.h>

#include "pteromys/fabrication.hpp"
#include "pteromys/fabrication_geometry.hpp"
#include "pteromys/geometry.hpp"

namespace pteromys {
namespace {
using IK = CGAL::Exact_predicates_inexact_constructions_kernel;
using IPoly = CGAL::Polygon_2<IK>;

IPoly to_ik(const Polygon& p) {
  IPoly q;
  for (const auto& v : p) q.push_back(IK::Point_2(v.x, v.y));
  return q;
}
Polygon from_ik(const IPoly& q) {
  Polygon p;
  for (auto it = q.vertices_begin(); it != q.vertices_end(); ++it) p.push_back({it->x(), it->y()});
  return p;
}
Polygon oriented(Polygon p, bool ccw) {
  if ((signed_area(p) > 0) != ccw) std::reverse(p.begin(), p.end());
  return p;
}
}  // namespace

std::pair<Polygon, std::vector<Polygon>> offset_for_kerf(const Polygon& outline, const std::vector<Polygon>& holes,
                                                         double r) {
  if (!std::isfinite(r) || r < 0) throw InputError("kerf must be a number >= 0");
  // Tiny features (below a micrometre) only upset the skeleton.
  Polygon out = oriented(fab::clean_polygon(outline, 1e-9), true);
  std::vector<Polygon> hs;
  for (const auto& h : holes) hs.push_back(oriented(fab::clean_polygon(h, 1e-9), true));
  if (r == 0) {
    for (auto& h : hs) h = oriented(h, false);
    return {out, hs};
  }
  // Outline: exterior offset. CGAL returns the offset of its bounding frame as
  // well; the wanted contour is the one whose area is nearest A + r P.
  const double want = std::fabs(signed_area(out)) + r * fab::perimeter(out);
  const auto res = CGAL::create_exterior_skeleton_and_offset_polygons_2(r, to_ik(out));
  Polygon best;
  double err = std::numeric_limits<double>::infinity();
  for (const auto& q : res) {
    const Polygon p = from_ik(*q);
    const double e = std::fabs(std::fabs(signed_area(p)) - want);
    if (e < err) {
      err = e;
      best = p;
    }
  }
  if (best.size() < 3 || err > 0.05 * want)
    throw std::runtime_error("kerf offset of an outline failed (CGAL straight skeleton)");
  std::vector<Polygon> cut_holes;
  for (const auto& h : hs) {
    const auto hr = CGAL::create_interior_skeleton_and_offset_polygons_2(r, to_ik(h));
    if (hr.empty()) throw InputError("kerf is wider than a hole of a part; a laser this wide cannot cut it");
    for (const auto& q : hr) cut_holes.push_back(oriented(from_ik(*q), false));
  }
  return {oriented(best, true), cut_holes};
}

}  // namespace pteromys
