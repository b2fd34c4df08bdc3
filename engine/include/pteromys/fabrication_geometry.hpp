// Small double-precision 2D helpers of the fabrication code: regions with
// holes, distances, clipping. Exact Boolean operations live in
// fabrication.cpp (CGAL); these helpers measure and place things on results.
// Units: whatever the inputs use (the engine passes metres).
#pragma once

#include <utility>
#include <vector>

#include "pteromys/types.hpp"

namespace pteromys::fab {

/// A plate's finished shape: outline (any orientation) minus holes.
struct Region {
  Polygon outline;
  std::vector<Polygon> holes;
};

/// Crossing-number point-in-polygon test (points on the boundary may go
/// either way).
bool point_in_polygon(const Polygon& p, Vec2 q);
/// Inside the outline and outside every hole.
bool inside(const Region& r, Vec2 q);

/// True when the closed segments [a, b] and [c, d] share a point.
bool segments_intersect(Vec2 a, Vec2 b, Vec2 c, Vec2 d);
/// Distance from q to segment [a, b].
double point_segment_distance(Vec2 q, Vec2 a, Vec2 b);
/// Distance between segments (0 when they intersect).
double segment_distance(Vec2 a, Vec2 b, Vec2 c, Vec2 d);
/// Distance between the boundaries of two polygons, 0 when the boundaries
/// cross or one polygon lies inside the other. `where` gets a point of `a`
/// closest to `b`.
double polygon_distance(const Polygon& a, const Polygon& b, Vec2* where = nullptr);
/// Distance from q to the boundary of a region (outline and holes).
double distance_to_boundary(const Region& r, Vec2 q);

/// Pieces of segment [a, b] inside the region, each longer than min_len.
std::vector<std::pair<Vec2, Vec2>> clip_segment(const Region& r, Vec2 a, Vec2 b, double min_len = 0.0);

/// Drops repeated vertices (closer than tol) and vertices on a straight line
/// through their neighbours (deviation below tol).
Polygon clean_polygon(const Polygon& p, double tol);

double perimeter(const Polygon& p);

/// Rectangle centred at c with half sizes (hx along the direction at angle
/// `angle` [rad], hy across), counter-clockwise.
Polygon oriented_box(Vec2 c, double hx, double hy, double angle);

/// True when the box lies inside the region with at least `margin` to its
/// boundary (corners inside, no boundary edge within margin of the box).
bool box_fits(const Region& r, const Polygon& box, double margin);

}  // namespace pteromys::fab
