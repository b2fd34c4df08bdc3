#include "pteromys/elements.hpp"

#include <gtest/gtest.h>

#include "pteromys/geometry.hpp"
#include "test_support.hpp"

using namespace pteromys;
using pteromys::test::rect;

// Element areas sum to the planform area for every wing of every example,
// for several spacings (exact slicing; only rounding remains).
TEST(Elements, AreasSumToPlanformAreaForEveryExample) {
  for (const auto& [path, g] : test::examples())
    for (const auto& w : g.wings)
      for (double dz : {0.002, 0.005, 0.013}) {
        const WingElements we = slice_wing(w.outline, dz);
        double sum = 0;
        for (const auto& e : we.elements) sum += e.area;
        const double exact = std::abs(signed_area(w.outline));
        EXPECT_NEAR(sum, exact, 1e-12 * exact) << path << " " << w.name << " dz=" << dz;
        EXPECT_NEAR(we.planform_area, exact, 1e-15) << path;
      }
}

TEST(Elements, RectangleGivesStraightEdgesAndItsChord) {
  const WingElements we = slice_wing(rect(-0.06, -0.2, 0.0, 0.2), 0.01);
  ASSERT_EQ(we.elements.size(), 40u);
  for (const auto& e : we.elements) {
    EXPECT_NEAR(e.chord, 0.06, 1e-14);
    EXPECT_NEAR(e.xi_l, 0, 1e-14);
    EXPECT_NEAR(e.xi_t, 0, 1e-14);
    EXPECT_NEAR(e.x_qc, -0.015, 1e-14);
    EXPECT_NEAR(e.z1 - e.z0, 0.01, 1e-14);
  }
  EXPECT_FALSE(we.multiple_in_streamline);
}

// A wing swept back by Lambda with a straight taper: every element has
// xi_l = Lambda, and xi_t = atan(tan Lambda + (c_root - c_tip) / s) on both
// sides (sweep measured outboard).
TEST(Elements, SweptTaperedWingHasItsEdgeAngles) {
  const double lam = deg2rad(30), s = 0.2, cr = 0.07, ct = 0.04;
  const double dx = s * std::tan(lam);
  const Polygon p{{0, 0}, {-dx, s}, {-dx - ct, s}, {-cr, 0}, {-dx - ct, -s}, {-dx, -s}};
  const WingElements we = slice_wing(p, 0.01);
  const double xi_t = std::atan2(dx + ct - cr, s);
  for (const auto& e : we.elements) {
    EXPECT_NEAR(e.xi_l, lam, 1e-12);
    EXPECT_NEAR(e.xi_t, xi_t, 1e-12);
  }
}

// Cut lines sit at multiples of dz: the slicing of a symmetric wing is symmetric.
TEST(Elements, SlicingIsSymmetricForSymmetricWings) {
  for (const auto& [path, g] : test::examples())
    for (const auto& w : g.wings) {
      const WingElements we = slice_wing(w.outline, 0.005);
      const auto& el = we.elements;
      const std::size_t n = el.size();
      for (std::size_t i = 0; i < n; ++i) {
        const auto& a = el[i];
        const auto& b = el[n - 1 - i];
        EXPECT_NEAR(a.z0, -b.z1, 1e-12) << path;
        EXPECT_NEAR(a.area, b.area, 1e-6 * a.area + 1e-12) << path;  // files hold 6 decimals
        EXPECT_NEAR(a.xi_l, b.xi_l, 1e-3) << path << " " << w.name << " element " << i;
      }
    }
}

// Non-convex planform: a hook-shaped channel cut into a square. Streamlines
// (lines of constant z) with z in [-0.1, 0.05] cross the planform twice.
TEST(Elements, DetectsSeveralElementsInOneStreamline) {
  const Polygon q{{0, -0.1}, {0, 0.1}, {-0.1, 0.1}, {-0.1, -0.1}, {-0.08, -0.1},
                  {-0.08, 0.05}, {-0.03, 0.05}, {-0.03, -0.05}, {-0.07, -0.05}, {-0.07, -0.1}};
  ASSERT_TRUE(is_simple(q));
  const WingElements we = slice_wing(q, 0.01);
  EXPECT_TRUE(we.multiple_in_streamline);
  ASSERT_FALSE(we.multiple_ranges.empty());
  double sum = 0;
  int rank1 = 0;
  for (const auto& e : we.elements) {
    sum += e.area;
    if (e.streamline_rank > 0) ++rank1;
  }
  EXPECT_NEAR(sum, std::abs(signed_area(q)), 1e-15);
  EXPECT_GT(rank1, 0);
  ASSERT_EQ(we.multiple_ranges.size(), 1u);
  EXPECT_NEAR(we.multiple_ranges.front().first, -0.1, 1e-12);
  EXPECT_NEAR(we.multiple_ranges.front().second, 0.05, 1e-12);
}

TEST(Elements, RejectsBadSpacing) {
  EXPECT_THROW(slice_wing(rect(-1, -1, 0, 1), 0.0), InputError);
  EXPECT_THROW(slice_wing(rect(-1, -1, 0, 1), -1.0), InputError);
}
