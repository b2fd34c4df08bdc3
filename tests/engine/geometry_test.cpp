#include "pteromys/geometry.hpp"

#include <gtest/gtest.h>

#include "test_support.hpp"

using namespace pteromys;
using pteromys::test::rect;

// Closed forms: rectangle [0,a] x [0,b]: A = ab, Sx = a^2 b / 2, Sxx = a^3 b / 3,
// Sxy = a^2 b^2 / 4.
TEST(Geometry, RectangleMomentsMatchClosedForm) {
  const double a = 0.3, b = 0.02;
  const AreaMoments m = area_moments(rect(0, 0, a, b));
  EXPECT_NEAR(m.A, a * b, 1e-15);
  EXPECT_NEAR(m.Sx, a * a * b / 2, 1e-15);
  EXPECT_NEAR(m.Sy, a * b * b / 2, 1e-15);
  EXPECT_NEAR(m.Sxx, a * a * a * b / 3, 1e-15);
  EXPECT_NEAR(m.Syy, a * b * b * b / 3, 1e-15);
  EXPECT_NEAR(m.Sxy, a * a * b * b / 4, 1e-15);
}

// Right triangle (0,0) (a,0) (0,b): A = ab/2, centroid (a/3, b/3),
// Ixx about origin = int y^2 = a b^3 / 12, Sxy = a^2 b^2 / 24.
TEST(Geometry, TriangleMomentsMatchClosedFormInEitherOrientation) {
  const double a = 0.2, b = 0.1;
  for (bool cw : {false, true}) {
    Polygon p{{0, 0}, {a, 0}, {0, b}};
    if (cw) std::reverse(p.begin(), p.end());
    const AreaMoments m = area_moments(p);
    EXPECT_NEAR(m.A, a * b / 2, 1e-15);
    EXPECT_NEAR(m.Sx / m.A, a / 3, 1e-15);
    EXPECT_NEAR(m.Sy / m.A, b / 3, 1e-15);
    EXPECT_NEAR(m.Syy, a * b * b * b / 12, 1e-16);
    EXPECT_NEAR(m.Sxy, a * a * b * b / 24, 1e-16);
  }
}

TEST(Geometry, BowTieIsNotSimpleButSquareIs) {
  EXPECT_TRUE(is_simple(rect(0, 0, 1, 1)));
  EXPECT_FALSE(is_simple({{0, 0}, {1, 1}, {1, 0}, {0, 1}}));
  EXPECT_FALSE(is_simple({{0, 0}, {1, 0}}));
  // Touching at a vertex (figure eight through one point) is not simple.
  EXPECT_FALSE(is_simple({{0, 0}, {1, 0}, {1, 1}, {0.5, 0}, {0, 1}}));
}

TEST(Geometry, SegmentLengthInsideAnLShape) {
  // L shape: the horizontal line y = 0.5 runs inside for x in [0, 1] only.
  const Polygon L{{0, 0}, {2, 0}, {2, 0.2}, {1, 0.2}, {1, 1}, {0, 1}};
  EXPECT_NEAR(segment_length_inside(L, {-1, 0.5}, {3, 0.5}), 1.0, 1e-12);
  EXPECT_NEAR(segment_length_inside(L, {-1, 0.1}, {3, 0.1}), 2.0, 1e-12);
  EXPECT_NEAR(segment_length_inside(L, {-1, 2}, {3, 2}), 0.0, 1e-12);
}

TEST(Geometry, DistanceToBoundary) {
  EXPECT_NEAR(distance_to_boundary(rect(0, 0, 1, 1), {0.5, 0.25}), 0.25, 1e-15);
  EXPECT_NEAR(distance_to_boundary(rect(0, 0, 1, 1), {2, 2}), std::sqrt(2.0), 1e-15);
}
