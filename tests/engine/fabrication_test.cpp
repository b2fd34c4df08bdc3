// Slotted plates: joint choice, slot geometry, refusals (src/fabrication.cpp).
#include "pteromys/fabrication.hpp"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "pteromys/fabrication_geometry.hpp"
#include "pteromys/geometry.hpp"
#include "pteromys/io.hpp"
#include "test_support.hpp"

using namespace pteromys;
using pteromys::test::rect;

namespace {

std::string error_of(const Glider& g, const FabricationOptions& o = {}) {
  try {
    slotted_plates(g, o);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

const Joint& joint_of(const PlateSet& s, const std::string& wing) {
  for (const auto& j : s.joints)
    if (j.wing == wing) return j;
  throw std::runtime_error("no joint for " + wing);
}

/// Width across and length along `dir` of a polygon.
std::pair<double, double> extent_along(const Polygon& p, Vec2 dir) {
  const Vec2 n{-dir.y, dir.x};
  double a0 = 1e9, a1 = -1e9, b0 = 1e9, b1 = -1e9;
  for (const auto& v : p) {
    a0 = std::min(a0, dot(v, dir));
    a1 = std::max(a1, dot(v, dir));
    b0 = std::min(b0, dot(v, n));
    b1 = std::max(b1, dot(v, n));
  }
  return {a1 - a0, b1 - b0};
}

}  // namespace

// A rectangular wing (chord 60 mm) through a 20 mm tall rectangular fuselage:
// the hole is the root chord plus clearance long and thickness plus clearance
// wide (geometry of the slot, not the code's own output).
TEST(Fabrication, RectangularWingGetsAThroughSlotOfChordByThicknessPlusClearance) {
  const Glider g = test::simple_glider(0.06, 0.4, -0.05, 0.0, 0.0);
  FabricationOptions o;
  o.clearance_m = 0.0001;
  const PlateSet s = slotted_plates(g, o);
  ASSERT_EQ(s.plates.size(), 2u);
  const Plate& f = s.plates[0];
  EXPECT_EQ(f.name, "fuselage");
  ASSERT_EQ(f.holes.size(), 1u);
  EXPECT_EQ(joint_of(s, "main").type, JointType::ThroughSlot);
  const auto [len, wid] = extent_along(f.holes[0], {1, 0});
  EXPECT_NEAR(len, 0.06 + 0.0001, 1e-12);
  EXPECT_NEAR(wid, 0.001 + 0.0001, 1e-12);
  // area: 0.3 x 0.02 plate minus the hole (exact rectangles)
  EXPECT_NEAR(f.area_m2, 0.3 * 0.02 - 0.0601 * 0.0011, 1e-15);
  // the wing plate is whole
  EXPECT_NEAR(s.plates[1].area_m2, 0.06 * 0.4, 1e-15);
  EXPECT_TRUE(s.plates[1].holes.empty());
}

// The hole is tilted by the mounting angle and centred on the root chord.
TEST(Fabrication, FuselageSlotIsTiltedByTheMountingAngleOnTheRootChord) {
  for (double angle : {-4.0, 0.0, 3.0, 7.5}) {
    const Glider g = test::simple_glider(0.06, 0.4, -0.05, 0.002, angle);
    const PlateSet s = slotted_plates(g);
    const Plate& f = s.plates[0];
    ASSERT_EQ(f.holes.size(), 1u) << angle;
    const double th = deg2rad(angle);
    const Vec2 d{std::cos(th), std::sin(th)}, n{-d.y, d.x}, P{-0.05, 0.002};
    const double w = 0.001 + s.options.clearance_m;
    for (const auto& v : f.holes[0]) {
      // every corner is at +-w/2 across the chord line through the mount,
      // and between the trailing and leading edge (+- clearance/2) along it
      EXPECT_NEAR(std::fabs(dot(v - P, n)), w / 2, 1e-12) << angle;
      const double s_ = dot(v - P, d);
      EXPECT_TRUE(std::fabs(s_ - (-0.06 - s.options.clearance_m / 2)) < 1e-12 ||
                  std::fabs(s_ - s.options.clearance_m / 2) < 1e-12)
          << angle << " " << s_;
    }
  }
}

// Transform columns: u -> chord direction, v -> span, w -> normal; right-handed
// and orthonormal; the wing's origin maps to the mount.
TEST(Fabrication, WingTransformPlacesTheWingAtItsMount) {
  const Glider g = test::simple_glider(0.06, 0.4, -0.05, 0.003, 5.0);
  const PlateSet s = slotted_plates(g);
  const Plate& w = s.plates[1];
  const auto o = plate_to_glider(w, 0, 0, 0);
  EXPECT_NEAR(o[0], -0.05, 1e-15);
  EXPECT_NEAR(o[1], 0.003, 1e-15);
  const auto le = plate_to_glider(w, -0.06, 0.1, 0);  // trailing edge at z = 0.1
  const double th = deg2rad(5.0);
  EXPECT_NEAR(le[0], -0.05 - 0.06 * std::cos(th), 1e-15);
  EXPECT_NEAR(le[1], 0.003 - 0.06 * std::sin(th), 1e-15);
  EXPECT_NEAR(le[2], 0.1, 1e-15);
  const auto& M = w.transform;
  const double det = M[0] * (M[5] * M[10] - M[6] * M[9]) - M[1] * (M[4] * M[10] - M[6] * M[8]) +
                     M[2] * (M[4] * M[9] - M[5] * M[8]);
  EXPECT_NEAR(det, 1.0, 1e-14);
}

// Paper Fig. 2 style swept wing: its outer sections lie behind the root
// chord, so it cannot pass a closed slot; the refusal says so.
TEST(Fabrication, SweptWingCannotSlideThroughAClosedSlot) {
  const Glider g = load_glider(test::source_path("examples/gliders/swept-back.glider.json"));
  FabricationOptions o;
  o.joints["main"] = JointType::ThroughSlot;
  const std::string e = error_of(g, o);
  EXPECT_NE(e.find("no joint can hold wing 'main'"), std::string::npos) << e;
  EXPECT_NE(e.find("cannot slide sideways through a closed slot"), std::string::npos) << e;
  // The tip trailing edge (x = -160.47 mm) lies behind the hole's rear end:
  // root trailing edge at the fuselage face z = t/2 (-65 - 0.5 tan(25.5 deg) =
  // -65.24 mm, the trailing edge's sweep from the file) minus clearance/2
  // (0.025 mm): 160.47 - 65.26 = 95.2 mm.
  EXPECT_NE(e.find("95.2 mm behind"), std::string::npos) << e;
  // Left to choose, the engine splits the wing.
  const PlateSet s = slotted_plates(g);
  EXPECT_EQ(joint_of(s, "main").type, JointType::Halves);
  ASSERT_FALSE(joint_of(s, "main").refused.empty());
}

// A 4 mm tall fuselage crossed by a wing tilted 10 degrees whose root chord
// runs from 5 mm above it (mount) to 5.4 mm below it (60 sin 10 deg = 10.4 mm):
// any slot along that chord cuts the fuselage in two.
TEST(Fabrication, SlotThatCutsThePlateInTwoIsRefused) {
  Glider g = test::simple_glider(0.06, 0.4, -0.15, 0.005, 10.0);
  g.fuselage = rect(-0.3, -0.002, 0.0, 0.002);
  const std::string e = error_of(g);
  EXPECT_NE(e.find("no joint can hold wing 'main'"), std::string::npos) << e;
  EXPECT_NE(e.find("would cut the fuselage in two"), std::string::npos) << e;
}

// Wing 1.5 mm below the top edge of a 20 mm fuselage, no clearance: a closed
// slot would leave 1.5 - 0.5 = 1.0 mm of foam above it (< 2 mm), so that strip
// is cut away: the slot opens to the top edge (a saddle) and the wing rests on
// its lower face. Nothing of the fuselage within 2 mm above the slot remains.
TEST(Fabrication, ThinWebBesideASlotIsCutAwayIntoAnOpenSaddle) {
  const Glider g = test::simple_glider(0.06, 0.4, -0.1, 0.0085, 0.0);
  FabricationOptions o;
  o.clearance_m = 0;
  const PlateSet s = slotted_plates(g, o);
  EXPECT_EQ(joint_of(s, "main").type, JointType::Notch);
  const Plate& f = s.plates[0];
  EXPECT_TRUE(f.holes.empty());  // the slot is part of the outline now
  // the lower face of the slot is still there: a point 0.1 mm below it is material
  EXPECT_TRUE(fab::inside({f.outline, f.holes}, {-0.13, 0.0085 - 0.0005 - 0.0001}));
  // the 1 mm strip above it is gone
  EXPECT_FALSE(fab::inside({f.outline, f.holes}, {-0.13, 0.0085 + 0.0005 + 0.0005}));
  // area removed: the slot (60 x 1 mm) plus the strip above it (60 x 1 mm), no more than
  // that plus the small overcut toward the ends (two min-web margins)
  const double removed = 0.3 * 0.02 - f.area_m2;
  EXPECT_GE(removed, 0.06 * 0.002 - 1e-12);
  EXPECT_LE(removed, 0.064 * 0.0022);
}

// A 3.55 mm tall fuselage: a 1.05 mm slot in its middle leaves 1.25 mm on
// both sides, under the 2 mm minimum, whichever side is opened.
TEST(Fabrication, SlotLeavingThinWebsOnBothSidesIsRefusedWithTheirWidth) {
  Glider g = test::simple_glider(0.06, 0.4, -0.1, 0.0, 0.0);
  g.fuselage = rect(-0.3, -0.00355 / 2, 0.0, 0.00355 / 2);
  const std::string e = error_of(g);
  EXPECT_NE(e.find("no joint can hold wing 'main'"), std::string::npos) << e;
  EXPECT_NE(e.find("web of only 1.25 mm"), std::string::npos) << e;
  FabricationOptions o;
  o.min_web_m = 0.0012;
  EXPECT_EQ(error_of(g, o), "");
}

TEST(Fabrication, OptionsOutOfRangeAreRefusedInPlainWords) {
  const Glider g = test::simple_glider();
  auto with = [&](auto f) {
    FabricationOptions o;
    f(o);
    return error_of(g, o);
  };
  EXPECT_NE(with([](auto& o) { o.kerf_m = -0.1e-3; }).find("kerf"), std::string::npos);
  EXPECT_NE(with([](auto& o) { o.kerf_m = 2e-3; }).find("not narrower than the 1.05 mm slots"), std::string::npos);
  EXPECT_NE(with([](auto& o) { o.clearance_m = -0.95e-3; }).find("press fit"), std::string::npos);
  EXPECT_NE(with([](auto& o) { o.clearance_m = NAN; }).find("clearance"), std::string::npos);
  EXPECT_NE(with([](auto& o) { o.min_web_m = -1; }).find("minimum web"), std::string::npos);
  EXPECT_NE(with([](auto& o) { o.joints["nope"] = JointType::Halves; }).find("wing 'nope'"), std::string::npos);
  EXPECT_THROW(joint_type_from_name("wobble"), InputError);
}

// Halves: the two half plates are disjoint and together make the whole wing;
// each carries a root tab across the fuselage over half the root chord.
TEST(Fabrication, HalvesTogetherMakeTheWholeWing) {
  int tested = 0, impossible = 0;
  for (const auto& [path, g] : test::examples()) {
    if (!test::buildable(path)) continue;
    for (const auto& w : g.wings) {
      FabricationOptions o;
      o.joints[w.name] = JointType::Halves;
      PlateSet s;
      try {
        s = slotted_plates(g, o);
      } catch (const InputError& e) {
        // a wing whose root reaches the fuselage's edge (tails at the rear edge) has no closed hole
        EXPECT_NE(std::string(e.what()).find("break through the edge"), std::string::npos) << e.what();
        ++impossible;
        continue;
      }
      ++tested;
      const Plate *r = nullptr, *l = nullptr;
      for (const auto& p : s.plates) {
        if (p.wing == w.name && p.half == "right") r = &p;
        if (p.wing == w.name && p.half == "left") l = &p;
      }
      ASSERT_TRUE(r && l) << path;
      const double A = std::fabs(signed_area(w.outline));
      EXPECT_NEAR(r->area_m2 + l->area_m2, A, 1e-12 * A + 1e-14) << path << " " << w.name;
      // right half: z >= -t/2 everywhere, and z >= t/2 behind the split
      const double t = g.material.thickness_m, c = joint_of(s, w.name).split_x_m;
      for (const auto& v : r->outline) {
        EXPECT_GE(v.y, -t / 2 - 1e-12) << path;
        if (v.x < c - 1e-9) EXPECT_GE(v.y, t / 2 - 1e-12) << path;
      }
      for (const auto& v : l->outline) {
        EXPECT_LE(v.y, t / 2 + 1e-12) << path;
        if (v.x > c + 1e-9) EXPECT_LE(v.y, -t / 2 + 1e-12) << path;
      }
    }
  }
  EXPECT_GE(tested, 15);
  EXPECT_LE(impossible, 4);
}

// Cross-lap: the fuselage slot and the wing slot end at the same chord
// position (the split), so the two plates interlock without gap or overlap.
TEST(Fabrication, CrossLapSlotsMeetAtTheSplit) {
  int seen = 0;
  for (const auto& [path, g] : test::examples()) {
    if (!test::buildable(path)) continue;
    const PlateSet s = slotted_plates(g);
    for (std::size_t j = 0; j < g.wings.size(); ++j) {
      const Joint& jt = s.joints[j];
      if (jt.type != JointType::CrossLap) continue;
      ++seen;
      ASSERT_EQ(jt.slots.size(), 2u);
      const Wing& w = g.wings[j];
      const double th = deg2rad(w.mount.angle_deg);
      const Vec2 P{w.mount.x_m, w.mount.y_m}, d{std::cos(th), std::sin(th)};
      const Slot& fs = jt.slots[0];
      const Slot& ws = jt.slots[1];
      EXPECT_EQ(fs.plate, "fuselage");
      EXPECT_EQ(ws.plate, w.name);
      // fuselage slot's closed end on the chord line at the split
      EXPECT_NEAR(dot(fs.axis_origin - P, d), jt.split_x_m, 1e-12) << path;
      EXPECT_NEAR(cross(d, fs.axis_origin - P), 0.0, 1e-12) << path;
      EXPECT_NEAR(ws.axis_origin.x, jt.split_x_m, 1e-15) << path;
      EXPECT_NEAR(ws.axis_origin.y, 0.0, 1e-15) << path;
      // they open in opposite directions along the chord
      EXPECT_NEAR(dot(fs.axis_dir, d) * ws.axis_dir.x, -1.0, 1e-12) << path;
      // the split lies inside the part of the root chord that overlaps the fuselage
      EXPECT_GT(jt.split_x_m, jt.engaged_from_m);
      EXPECT_LT(jt.split_x_m, jt.engaged_to_m);
    }
  }
  EXPECT_GE(seen, 5);  // tails of the swept examples
}

// Every engraved mark lies on its part's material.
TEST(Fabrication, MarksLieOnTheMaterial) {
  for (const auto& [path, g] : test::examples()) {
    if (!test::buildable(path)) continue;
    const PlateSet s = slotted_plates(g);
    for (const auto& p : s.plates) {
      const fab::Region r{p.outline, p.holes};
      bool has_label = false;
      for (const auto& m : p.marks) {
        // inside, or on the boundary where a line was clipped
        for (const auto& q : m.points)
          EXPECT_TRUE(fab::inside(r, q) || fab::distance_to_boundary(r, q) < 1e-9) << path << " " << p.name << " "
                                                                                  << m.text;
        if (m.kind == Mark::Kind::Line) {
          const Vec2 mid = 0.5 * (m.points[0] + m.points[1]);
          EXPECT_TRUE(fab::inside(r, mid)) << path << " " << p.name << " " << m.text;
        }
        if (m.kind == Mark::Kind::Text && m.text == p.label) has_label = true;
      }
      EXPECT_TRUE(has_label) << path << " " << p.name;
    }
    // the fuselage carries the CG and the ballast
    bool cg = false, ballast = false;
    for (const auto& m : s.plates[0].marks) {
      cg = cg || m.text.find("centre of gravity") != std::string::npos;
      ballast = ballast || m.text.find("ballast") != std::string::npos;
    }
    EXPECT_TRUE(cg && ballast) << path;
  }
}

// Outlines counter-clockwise, holes clockwise, finished areas consistent.
TEST(Fabrication, OutlinesAreCounterClockwiseAndHolesClockwise) {
  for (const auto& [path, g] : test::examples()) {
    if (!test::buildable(path)) continue;
    const PlateSet s = slotted_plates(g);
    for (const auto& p : s.plates) {
      EXPECT_GT(signed_area(p.outline), 0) << path << " " << p.name;
      EXPECT_TRUE(is_simple(p.outline)) << path << " " << p.name;
      double a = signed_area(p.outline);
      for (const auto& h : p.holes) {
        EXPECT_LT(signed_area(h), 0) << path << " " << p.name;
        a += signed_area(h);
      }
      EXPECT_NEAR(a, p.area_m2, 1e-15);
      EXPECT_GT(signed_area(p.cut_outline), signed_area(p.outline));
    }
  }
}

// Kerf: a 40 x 20 mm rectangle with a 10 x 4 mm hole, offset by r = 0.1 mm:
// outline (40.2 x 20.2), hole (9.8 x 3.8) -- mitred corners keep rectangles.
TEST(Fabrication, KerfOffsetMovesOutlinesOutAndHolesIn) {
  const Polygon outer = rect(0, 0, 0.04, 0.02);
  Polygon hole = rect(0.01, 0.008, 0.02, 0.012);
  std::reverse(hole.begin(), hole.end());
  const auto [o, hs] = offset_for_kerf(outer, {hole}, 0.0001);
  EXPECT_NEAR(signed_area(o), 0.0402 * 0.0202, 1e-12);
  ASSERT_EQ(hs.size(), 1u);
  EXPECT_NEAR(signed_area(hs[0]), -0.0098 * 0.0038, 1e-12);
  const auto [lo, hi] = bounds(o);
  EXPECT_NEAR(lo.x, -0.0001, 1e-12);
  EXPECT_NEAR(hi.y, 0.0201, 1e-12);
}

// Any valid mounting either builds or is refused with a sentence; never a
// crash, never an invalid part. (Property test over random mounts.)
TEST(Fabrication, AnyValidMountingBuildsOrIsRefusedInWords) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ang(-6, 9), dy(-0.006, 0.008), dx(-0.03, 0.03);
  int built = 0, refused = 0;
  for (const char* name : {"tapered", "swept-back", "delta", "canard"}) {
    const Glider base = load_glider(test::source_path(std::string("examples/gliders/") + name + ".glider.json"));
    for (int k = 0; k < 12; ++k) {
      Glider g = base;
      for (auto& w : g.wings) {
        w.mount.angle_deg = ang(rng);
        w.mount.y_m += dy(rng);
        w.mount.x_m += dx(rng);
      }
      if (!validation_problems(g).empty()) continue;
      try {
        const PlateSet s = slotted_plates(g);
        ++built;
        for (const auto& p : s.plates) {
          EXPECT_TRUE(is_simple(p.outline)) << name;
          EXPECT_GT(p.area_m2, 0) << name;
        }
      } catch (const InputError& e) {
        ++refused;
        const std::string m = e.what();
        EXPECT_EQ(m.find('\n'), std::string::npos);
        EXPECT_TRUE(m.rfind("no joint can hold wing", 0) == 0 || m.rfind("the wings' joints", 0) == 0 ||
                    m.find("pass through each other") != std::string::npos)
            << m;
      }
    }
  }
  EXPECT_GT(built, 10);
  std::cout << "random mounts: " << built << " built, " << refused << " refused\n";
}

// Two wings whose root chords cross in the side view cannot both be built.
TEST(Fabrication, WingsCrossingAtTheirRootsAreRefused) {
  Glider g = test::simple_glider(0.06, 0.4, -0.05, 0.0, 0.0);
  Wing w2 = g.wings[0];
  w2.name = "second";
  w2.mount = {-0.06, 0.0, 8.0};
  g.wings.push_back(w2);
  const std::string e = error_of(g);
  EXPECT_NE(e.find("wings 'main' and 'second' pass through each other"), std::string::npos) << e;
}
