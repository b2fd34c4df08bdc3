// Sheet layout and DXF writing (src/dxf_export.cpp). The DXF's content is
// read back with an independent reader (ezdxf) in tests/python/test_export.py;
// here: the packing itself.
#include "pteromys/dxf_export.hpp"

#include <cstdio>
#include <fstream>
#include <unistd.h>

#include <gtest/gtest.h>

#include "pteromys/geometry.hpp"
#include "pteromys/io.hpp"
#include "test_support.hpp"

using namespace pteromys;

namespace {

struct Box {
  int sheet;
  Vec2 lo, hi;
};

std::vector<Box> placed_boxes(const PlateSet& s, const Layout& l) {
  std::vector<Box> out;
  for (const auto& pl : l.placements) {
    Box b{pl.sheet, {1e9, 1e9}, {-1e9, -1e9}};
    for (const auto& v : s.plates[pl.plate].cut_outline) {
      const Vec2 r = pl.rotation_deg == 0 ? v : Vec2{-v.y, v.x};
      const Vec2 q = r + pl.offset;
      b.lo = {std::min(b.lo.x, q.x), std::min(b.lo.y, q.y)};
      b.hi = {std::max(b.hi.x, q.x), std::max(b.hi.y, q.y)};
    }
    out.push_back(b);
  }
  return out;
}

void expect_valid_layout(const PlateSet& s, const Layout& l, const SheetOptions& o, const std::string& what) {
  const auto boxes = placed_boxes(s, l);
  ASSERT_EQ(boxes.size(), s.plates.size());
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const Box& a = boxes[i];
    EXPECT_GE(a.sheet, 0);
    EXPECT_LT(a.sheet, l.sheets);
    EXPECT_GE(a.lo.x, o.margin_m - 1e-12) << what;
    EXPECT_GE(a.lo.y, o.margin_m - 1e-12) << what;
    EXPECT_LE(a.hi.x, o.width_m - o.margin_m + 1e-12) << what;
    EXPECT_LE(a.hi.y, o.height_m - o.margin_m + 1e-12) << what;
    for (std::size_t j = i + 1; j < boxes.size(); ++j) {
      const Box& b = boxes[j];
      if (a.sheet != b.sheet) continue;
      // bounding boxes at least `gap` apart in x or in y
      const bool apart = a.hi.x + o.gap_m <= b.lo.x + 1e-12 || b.hi.x + o.gap_m <= a.lo.x + 1e-12 ||
                         a.hi.y + o.gap_m <= b.lo.y + 1e-12 || b.hi.y + o.gap_m <= a.lo.y + 1e-12;
      EXPECT_TRUE(apart) << what << ": parts " << s.plates[i].name << " and " << s.plates[j].name;
    }
  }
}

}  // namespace

TEST(DxfExport, PartsArePackedOnTheSheetWithoutOverlap) {
  for (const auto& [path, g] : test::examples()) {
    PlateSet s;
    try {
      s = slotted_plates(g);
    } catch (const InputError&) {
      continue;  // refused examples: tests/python/test_export.py checks their messages
    }
    const SheetOptions o;
    const Layout l = layout_plates(s, o);
    EXPECT_EQ(l.sheets, 1) << path;  // every example fits one 600 x 900 mm foam board
    expect_valid_layout(s, l, o, path);
  }
}

// A sheet just larger than the biggest part forces several sheets.
TEST(DxfExport, SmallSheetsAreFilledOneAfterAnother) {
  const Glider g = load_glider(test::source_path("examples/gliders/swept-back.glider.json"));
  const PlateSet s = slotted_plates(g);  // fuselage, two wing halves, tail
  SheetOptions o;
  o.width_m = 0.32;
  o.height_m = 0.24;
  const Layout l = layout_plates(s, o);
  EXPECT_GE(l.sheets, 2);
  expect_valid_layout(s, l, o, "small sheets");
}

TEST(DxfExport, PartLargerThanTheSheetIsRefused) {
  const Glider g = load_glider(test::source_path("examples/gliders/big-rectangular.glider.json"));
  const PlateSet s = slotted_plates(g);  // main wing spans 580 mm
  SheetOptions o;
  o.width_m = 0.3;
  o.height_m = 0.5;
  try {
    layout_plates(s, o);
    FAIL() << "expected a refusal";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("part 'main'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("does not fit on a 300 x 500 mm sheet"), std::string::npos) << e.what();
  }
  o.width_m = -1;
  EXPECT_THROW(layout_plates(s, o), InputError);
}

// The writer leaves no temporary file and no partial file when it cannot write.
TEST(DxfExport, WriterLeavesNoPartialFile) {
  const Glider g = load_glider(test::source_path("examples/gliders/tapered.glider.json"));
  const PlateSet s = slotted_plates(g);
  const Layout l = layout_plates(s, {});
  EXPECT_THROW(write_dxf(s, l, "/nonexistent-dir/parts.dxf"), InputError);
  const std::string p = std::string(PTEROMYS_BINARY_DIR) + "/dxf_test_" + std::to_string(::getpid()) + ".dxf";
  write_dxf(s, l, p);
  std::ifstream f(p);
  EXPECT_TRUE(f.good());
  std::string all((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  EXPECT_NE(all.find("$INSUNITS"), std::string::npos);
  EXPECT_NE(all.find("EOF"), std::string::npos);
  std::remove(p.c_str());
  std::ifstream t(p + ".tmp-" + std::to_string(::getpid()));
  EXPECT_FALSE(t.good());
}
