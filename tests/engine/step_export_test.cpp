// STEP read back with OpenCASCADE's reader (src/step_export.cpp): one named
// valid solid per plate, volumes, no interpenetration, wing angles and
// positions measured on the solids, assembly paths free of material.
#include "pteromys/step_export.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <unistd.h>

#include <BRepAdaptor_Surface.hxx>
#include <BRepAlgoAPI_Common.hxx>
#include <BRepBndLib.hxx>
#include <BRepBuilderAPI_Transform.hxx>
#include <BRepCheck_Analyzer.hxx>
#include <BRepGProp.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <GProp_GProps.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <STEPCAFControl_Reader.hxx>
#include <TDF_LabelSequence.hxx>
#include <TDataStd_Name.hxx>
#include <TDocStd_Document.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <XCAFApp_Application.hxx>
#include <XCAFDoc_DocumentTool.hxx>
#include <XCAFDoc_ShapeTool.hxx>
#include <gtest/gtest.h>

#include "pteromys/geometry.hpp"
#include "pteromys/io.hpp"
#include "test_support.hpp"

using namespace pteromys;

namespace {

struct ReadBack {
  std::vector<std::string> names;
  std::vector<TopoDS_Shape> shapes;
};

ReadBack read_step(const std::string& path) {
  ReadBack rb;
  Handle(XCAFApp_Application) app = XCAFApp_Application::GetApplication();
  Handle(TDocStd_Document) doc;
  app->NewDocument("MDTV-XCAF", doc);
  STEPCAFControl_Reader r;
  r.SetNameMode(Standard_True);
  if (r.ReadFile(path.c_str()) != IFSelect_RetDone || !r.Transfer(doc)) {
    app->Close(doc);
    return rb;
  }
  Handle(XCAFDoc_ShapeTool) tool = XCAFDoc_DocumentTool::ShapeTool(doc->Main());
  TDF_LabelSequence labels;
  tool->GetFreeShapes(labels);
  for (Standard_Integer i = 1; i <= labels.Length(); ++i) {
    Handle(TDataStd_Name) n;
    std::string name;
    if (labels.Value(i).FindAttribute(TDataStd_Name::GetID(), n)) {
      const TCollection_ExtendedString& e = n->Get();
      for (Standard_Integer k = 1; k <= e.Length(); ++k) name += static_cast<char>(e.Value(k));
    }
    rb.names.push_back(name);
    rb.shapes.push_back(tool->GetShape(labels.Value(i)));
  }
  app->Close(doc);
  return rb;
}

double volume(const TopoDS_Shape& s) {
  GProp_GProps g;
  BRepGProp::VolumeProperties(s, g);
  return g.Mass();
}

int count_solids(const TopoDS_Shape& s) {
  int n = 0;
  for (TopExp_Explorer e(s, TopAbs_SOLID); e.More(); e.Next()) ++n;
  return n;
}

double common_volume(const TopoDS_Shape& a, const TopoDS_Shape& b) {
  Bnd_Box ba, bb;
  BRepBndLib::Add(a, ba);
  BRepBndLib::Add(b, bb);
  if (ba.IsOut(bb)) return 0.0;
  BRepAlgoAPI_Common c(a, b);
  if (!c.IsDone()) return -1;
  return volume(c.Shape());
}

TopoDS_Shape moved(const TopoDS_Shape& s, double dx, double dy, double dz) {
  gp_Trsf t;
  t.SetTranslation(gp_Vec(dx, dy, dz));
  return BRepBuilderAPI_Transform(s, t, Standard_True).Shape();
}

/// Unit normal of the largest planar face.
gp_Dir largest_face_normal(const TopoDS_Shape& s) {
  double best = -1;
  gp_Dir n(0, 0, 1);
  for (TopExp_Explorer e(s, TopAbs_FACE); e.More(); e.Next()) {
    const TopoDS_Face f = TopoDS::Face(e.Current());
    BRepAdaptor_Surface surf(f);
    if (surf.GetType() != GeomAbs_Plane) continue;
    GProp_GProps g;
    BRepGProp::SurfaceProperties(f, g);
    if (g.Mass() > best) {
      best = g.Mass();
      n = surf.Plane().Axis().Direction();
    }
  }
  return n;
}

std::vector<gp_Pnt> vertices(const TopoDS_Shape& s) {
  std::vector<gp_Pnt> out;
  for (TopExp_Explorer e(s, TopAbs_VERTEX); e.More(); e.Next()) out.push_back(BRep_Tool::Pnt(TopoDS::Vertex(e.Current())));
  return out;
}

std::string tmp_path(const std::string& name) {
  return std::string(PTEROMYS_BINARY_DIR) + "/step_test_" + name + "_" + std::to_string(::getpid()) + ".step";
}

std::string stem(const std::string& path) {
  const auto s = path.find_last_of('/');
  return path.substr(s + 1, path.find('.', s) - s - 1);
}

struct Written {
  PlateSet plates;
  ReadBack rb;
};

Written write_and_read(const Glider& g, const FabricationOptions& o, const std::string& name) {
  Written w;
  w.plates = slotted_plates(g, o);
  const std::string p = tmp_path(name);
  write_step_parts(w.plates, p);
  w.rb = read_step(p);
  std::remove(p.c_str());
  return w;
}

}  // namespace

// One valid, named solid per plate; volume = finished area x thickness
// (area from the plates' own polygons; tests/python/test_export.py checks the
// areas against the glider file independently).
TEST(StepExport, ReadBackGivesOneNamedSolidPerPlateWithAreaTimesThickness) {
  for (const auto& [path, g] : test::examples()) {
    if (!test::buildable(path)) continue;
    const Written w = write_and_read(g, {}, stem(path));
    ASSERT_EQ(w.rb.shapes.size(), w.plates.plates.size()) << path;
    for (std::size_t i = 0; i < w.rb.shapes.size(); ++i) {
      const Plate& p = w.plates.plates[i];
      EXPECT_EQ(w.rb.names[i], p.name) << path;
      EXPECT_EQ(count_solids(w.rb.shapes[i]), 1) << path << " " << p.name;
      EXPECT_TRUE(BRepCheck_Analyzer(w.rb.shapes[i]).IsValid()) << path << " " << p.name;
      const double expect = p.area_m2 * p.thickness_m * 1e9;  // mm^3
      EXPECT_NEAR(volume(w.rb.shapes[i]), expect, 1e-6 * expect) << path << " " << p.name;
    }
  }
}

// Pairwise common volume of the assembled solids is zero with a positive
// clearance; with a press fit (clearance -0.1 mm) it is positive (the test
// can see an overlap) and at most the interference band: |c| x t x engaged
// length per joint (the slot's two long sides each overlap |c|/2 x t).
TEST(StepExport, AssembledSolidsDoNotInterpenetrateBeyondTheClearance) {
  for (const char* name : {"examples/gliders/tapered", "examples/gliders/swept-back", "examples/gliders/canard",
                           "examples/gliders/delta", "examples/gliders/rectangular",
                           "tests/data/fabrication/edge_mounted_tail"}) {
    const Glider g = load_glider(test::source_path(std::string(name) + ".glider.json"));
    for (double clearance : {0.00005, -0.0001}) {
      FabricationOptions o;
      o.clearance_m = clearance;
      const Written w = write_and_read(g, o, stem(name));
      ASSERT_EQ(w.rb.shapes.size(), w.plates.plates.size());
      double total = 0, bound = 0;
      for (const auto& j : w.plates.joints) {
        // interference of the long sides plus, for closed holes shorter than the
        // root section by |c|, the two ends: |c| x t x (engaged length + t)
        bound += std::fabs(clearance) * 1000 * g.material.thickness_m * 1000 *
                 ((j.engaged_to_m - j.engaged_from_m) * 1000 + 2 * g.material.thickness_m * 1000);
      }
      for (std::size_t a = 0; a < w.rb.shapes.size(); ++a)
        for (std::size_t b = a + 1; b < w.rb.shapes.size(); ++b) {
          const double v = common_volume(w.rb.shapes[a], w.rb.shapes[b]);
          ASSERT_GE(v, 0) << name;
          total += v;
          if (clearance > 0)
            EXPECT_LT(v, 1e-6) << name << ": " << w.plates.plates[a].name << " x " << w.plates.plates[b].name;
        }
      if (clearance < 0) {
        EXPECT_GT(total, 0.05 * bound) << name;
        EXPECT_LE(total, bound) << name;
      }
    }
  }
}

// The wing's mounting angle measured on its solid (normal of its largest
// face) equals the design's within 0.05 deg, and the outline's outer vertices
// (away from the slots) sit where the mount puts them within 0.1 mm.
TEST(StepExport, WingAngleAndPositionMeasuredOnTheSolidsMatchTheDesign) {
  for (const auto& [path, g] : test::examples()) {
    if (!test::buildable(path)) continue;
    const Written w = write_and_read(g, {}, stem(path));
    const double t = g.material.thickness_m * 1000;
    for (std::size_t i = 0; i < w.plates.plates.size(); ++i) {
      const Plate& p = w.plates.plates[i];
      if (p.kind != "wing") continue;
      const Wing* wing = nullptr;
      for (const auto& x : g.wings)
        if (x.name == p.wing) wing = &x;
      ASSERT_TRUE(wing);
      gp_Dir n = largest_face_normal(w.rb.shapes[i]);
      if (n.Y() < 0) n.Reverse();
      EXPECT_NEAR(n.Z(), 0.0, 1e-9) << path;
      const double angle = rad2deg(std::atan2(-n.X(), n.Y()));
      EXPECT_NEAR(angle, wing->mount.angle_deg, 0.05) << path << " " << p.name;
      const auto vs = vertices(w.rb.shapes[i]);
      const double th = deg2rad(wing->mount.angle_deg);
      int checked = 0;
      for (const auto& v : wing->outline) {
        if (std::fabs(v.y) < 0.005) continue;  // slots and half steps are near the root
        if ((p.half == "right" && v.y < 0) || (p.half == "left" && v.y > 0)) continue;
        for (double side : {-0.5, 0.5}) {
          const double x = (wing->mount.x_m + v.x * std::cos(th)) * 1000 + side * t * std::sin(th);
          const double y = (wing->mount.y_m + v.x * std::sin(th)) * 1000 - side * t * std::cos(th);
          const gp_Pnt want(x, y, v.y * 1000);
          double best = 1e9;
          for (const auto& q : vs) best = std::min(best, q.Distance(want));
          EXPECT_LT(best, 0.1) << path << " " << p.name << " vertex (" << v.x << ", " << v.y << ")";
          ++checked;
        }
      }
      EXPECT_GE(checked, 4) << path << " " << p.name;
    }
  }
}

// Fused: one solid; its volume is the plates' sum minus each wing's overlap
// with the fuselage (a t x t bar along the part of the root chord inside the
// fuselage, root_overlap_with_fuselage), within 1 % of those bars.
TEST(StepExport, FusedOptionWritesOneSolidOfTheUnion) {
  for (const char* name : {"tapered", "swept-back"}) {
    const Glider g = load_glider(test::source_path(std::string("examples/gliders/") + name + ".glider.json"));
    const std::string p = tmp_path(std::string(name) + "_fused");
    const double t = g.material.thickness_m;
    write_step_fused(g, t, p);
    const ReadBack rb = read_step(p);
    std::remove(p.c_str());
    ASSERT_EQ(rb.shapes.size(), 1u);
    EXPECT_EQ(count_solids(rb.shapes[0]), 1);
    EXPECT_EQ(rb.names[0], g.name);
    double sum = std::fabs(signed_area(g.fuselage)) * t, bars = 0;
    for (std::size_t j = 0; j < g.wings.size(); ++j) {
      sum += std::fabs(signed_area(g.wings[j].outline)) * t;
      bars += t * t * root_overlap_with_fuselage(g, j);
    }
    EXPECT_NEAR(volume(rb.shapes[0]), (sum - bars) * 1e9, 0.01 * bars * 1e9) << name;
  }
}

// Each wing is brought into place along its straight path (spanwise for a
// through slot and for halves, along the chord for a cross-lap), in the
// assembly order, without passing through the parts already in place:
// sampled every 2 mm, the common volume with every placed solid stays below
// 1e-6 mm^3. Control: the swept wing forced whole through the same hole does
// collide.
TEST(StepExport, AssemblyPathsAreFreeOfMaterial) {
  const auto t0 = std::chrono::steady_clock::now();
  for (const char* name : {"examples/gliders/tapered", "examples/gliders/swept-back", "examples/gliders/delta",
                           "examples/gliders/small-dart", "examples/gliders/canard", "examples/gliders/three-wing",
                           "tests/data/fabrication/edge_mounted_tail", "tests/data/fabrication/edge_mounted_canard"}) {
    const Glider g = load_glider(test::source_path(std::string(name) + ".glider.json"));
    const Written w = write_and_read(g, {}, stem(name));
    const auto& plates = w.plates.plates;
    std::vector<std::size_t> placed{0};  // the fuselage
    std::vector<std::size_t> order(w.plates.joints.size());
    for (std::size_t j = 0; j < order.size(); ++j) order[w.plates.joints[j].step - 1] = j;
    for (std::size_t j : order) {
      const Joint& jt = w.plates.joints[j];
      const Wing& wing = g.wings[j];
      std::vector<std::size_t> parts;
      for (std::size_t i = 0; i < plates.size(); ++i)
        if (plates[i].wing == wing.name) parts.push_back(i);
      for (std::size_t i : parts) {
        const Plate& p = plates[i];
        // path direction and length [mm]
        gp_Vec dir;
        double L;
        const auto [lo, hi] = bounds(wing.outline);
        if (jt.type == JointType::CrossLap) {
          const double th = deg2rad(wing.mount.angle_deg);
          dir = gp_Vec(std::cos(th), std::sin(th), 0) * (jt.direction > 0 ? -1.0 : 1.0);  // away from the final place
          L = (hi.x - lo.x) * 1000 + 320;
        } else {
          const bool whole = jt.type == JointType::ThroughSlot || jt.type == JointType::Notch;
          const bool from_plus = whole ? jt.direction > 0 : p.half == "right";
          dir = gp_Vec(0, 0, from_plus ? 1.0 : -1.0);
          L = (whole ? (hi.y - lo.y) * 1000 : 0) + 2 * g.material.thickness_m * 1000 + 1;
        }
        for (double s = 0; s <= L; s += 2.0) {
          const TopoDS_Shape m = moved(w.rb.shapes[i], dir.X() * s, dir.Y() * s, dir.Z() * s);
          for (std::size_t q : placed) {
            const double v = common_volume(m, w.rb.shapes[q]);
            ASSERT_GE(v, 0);
            EXPECT_LT(v, 1e-6) << name << ": " << p.name << " hits " << plates[q].name << " at " << s << " mm";
            if (v >= 1e-6) goto next_part;
          }
        }
      next_part:
        placed.push_back(i);
      }
    }
  }
  // Control: swept-back, whole main wing slid spanwise through the halves' hole.
  {
    const Glider g = load_glider(test::source_path("examples/gliders/swept-back.glider.json"));
    FabricationOptions o;
    o.joints["main"] = JointType::Halves;
    PlateSet s = slotted_plates(g, o);
    Plate whole = s.plates[1];  // right half -> whole wing
    whole.outline = counter_clockwise(g.wings[0].outline);
    whole.holes.clear();
    whole.name = "main whole";
    s.plates = {s.plates[0], whole};
    const std::string p = tmp_path("control");
    write_step_parts(s, p);
    const ReadBack rb = read_step(p);
    std::remove(p.c_str());
    ASSERT_EQ(rb.shapes.size(), 2u);
    double worst = 0;
    for (double z = 0; z <= 410; z += 2.0) worst = std::max(worst, common_volume(moved(rb.shapes[1], 0, 0, z), rb.shapes[0]));
    EXPECT_GT(worst, 1.0) << "a swept wing slid through a closed slot must hit the fuselage";
  }
  std::printf("assembly path sweeps took %.1f s\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
}
