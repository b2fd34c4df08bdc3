// Plane polygon geometry: areas, moments, validity (CGAL exact predicates).
#pragma once

#include <string>

#include "pteromys/types.hpp"

namespace pteromys {

/// Area integrals of a polygon region R: A = int 1, Sx = int x, Sy = int y,
/// Sxx = int x^2, Syy = int y^2, Sxy = int x y (dA over R). Exact for
/// polygons (Green's theorem); sign-independent of vertex order.
struct AreaMoments {
  double A = 0, Sx = 0, Sy = 0, Sxx = 0, Syy = 0, Sxy = 0;
};
AreaMoments area_moments(const Polygon& p);

/// Signed area (positive for counter-clockwise vertex order) [m^2].
double signed_area(const Polygon& p);

/// True when the polygon is simple (no self-intersection, no repeated
/// vertex), decided with CGAL's exact predicates.
bool is_simple(const Polygon& p);

/// Returns the polygon in counter-clockwise order.
Polygon counter_clockwise(const Polygon& p);

/// Point-in-polygon (boundary counts as inside), exact predicates.
bool contains(const Polygon& p, Vec2 q);

/// Length of the part of segment [a, b] inside polygon p [m].
double segment_length_inside(const Polygon& p, Vec2 a, Vec2 b);

/// Distance from point q to the boundary of p [m].
double distance_to_boundary(const Polygon& p, Vec2 q);

/// Axis-aligned bounds (min corner, max corner).
std::pair<Vec2, Vec2> bounds(const Polygon& p);

}  // namespace pteromys
