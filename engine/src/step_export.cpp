// STEP for 3D printing and CAD exchange, written with OpenCASCADE's XCAF
// (docs/fabrication.md, "STEP").
#include "pteromys/io.hpp"
#include "pteromys/step_export.hpp"

#include <cmath>
#include <cstdio>
#include <mutex>
#include <unistd.h>

#include <BRepAlgoAPI_Fuse.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakePolygon.hxx>
#include <BRepBuilderAPI_Transform.hxx>
#include <BRepCheck_Analyzer.hxx>
#include <BRepGProp.hxx>
#include <BRepPrimAPI_MakePrism.hxx>
#include <GProp_GProps.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_Printer.hxx>
#include <STEPCAFControl_Writer.hxx>
#include <ShapeUpgrade_UnifySameDomain.hxx>
#include <Standard_Failure.hxx>
#include <TCollection_ExtendedString.hxx>
#include <TDataStd_Name.hxx>
#include <TDocStd_Document.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_ListOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Solid.hxx>
#include <XCAFApp_Application.hxx>
#include <XCAFDoc_DocumentTool.hxx>
#include <XCAFDoc_ShapeTool.hxx>
#include <gp_Pln.hxx>
#include <gp_Trsf.hxx>

#include "pteromys/fabrication_geometry.hpp"
#include "pteromys/geometry.hpp"

namespace pteromys {
namespace {

constexpr double kMM = 1000.0;

TopoDS_Wire make_wire(const Polygon& p, double w_mm) {
  BRepBuilderAPI_MakePolygon mp;
  for (const auto& v : p) mp.Add(gp_Pnt(v.x * kMM, v.y * kMM, w_mm));
  mp.Close();
  if (!mp.IsDone()) throw std::runtime_error("OpenCASCADE could not build a polygon wire");
  return mp.Wire();
}

/// Prism of a plate's outline minus holes across w in [-t/2, t/2], placed by
/// the 4 x 4 transform (metres) in millimetres.
TopoDS_Shape plate_solid(const Polygon& outline, const std::vector<Polygon>& holes, double t,
                         const std::array<double, 16>& M) {
  const double w0 = -t / 2 * kMM;
  Polygon out = fab::clean_polygon(outline, 1e-9);
  if (signed_area(out) < 0) std::reverse(out.begin(), out.end());
  BRepBuilderAPI_MakeFace mf(gp_Pln(gp_Pnt(0, 0, w0), gp_Dir(0, 0, 1)), make_wire(out, w0), Standard_True);
  for (const auto& h : holes) {
    Polygon q = fab::clean_polygon(h, 1e-9);
    if (signed_area(q) > 0) std::reverse(q.begin(), q.end());  // inner wires run clockwise
    mf.Add(make_wire(q, w0));
  }
  if (!mf.IsDone()) throw std::runtime_error("OpenCASCADE could not build a plate face");
  BRepPrimAPI_MakePrism prism(mf.Face(), gp_Vec(0, 0, t * kMM));
  if (!prism.IsDone()) throw std::runtime_error("OpenCASCADE could not extrude a plate");
  gp_Trsf tr;
  tr.SetValues(M[0], M[1], M[2], M[3] * kMM, M[4], M[5], M[6], M[7] * kMM, M[8], M[9], M[10], M[11] * kMM);
  BRepBuilderAPI_Transform move(prism.Shape(), tr, Standard_True);
  TopoDS_Shape s = move.Shape();
  if (!BRepCheck_Analyzer(s).IsValid()) throw std::runtime_error("OpenCASCADE built an invalid plate solid");
  return s;
}

double volume(const TopoDS_Shape& s) {
  GProp_GProps g;
  BRepGProp::VolumeProperties(s, g);
  return g.Mass();
}

/// Quiets OpenCASCADE's informational messages (transfer statistics on
/// stdout) for the lifetime of the object and restores the printers' levels,
/// so that a host application (FreeCAD) keeps its own settings.
class QuietOcct {
 public:
  QuietOcct() {
    const auto& printers = Message::DefaultMessenger()->Printers();
    for (auto it = printers.cbegin(); it != printers.cend(); ++it) {
      saved_.emplace_back(*it, (*it)->GetTraceLevel());
      (*it)->SetTraceLevel(Message_Fail);
    }
  }
  ~QuietOcct() {
    for (auto& [p, level] : saved_) p->SetTraceLevel(level);
  }

 private:
  std::vector<std::pair<Handle(Message_Printer), Message_Gravity>> saved_;
};

void write_doc(const std::vector<std::pair<std::string, TopoDS_Shape>>& shapes, const std::string& path) {
  // The XCAF application, the STEP settings and the message printers are
  // process-wide: one writer at a time (Python threads may call export).
  static std::mutex m;
  const std::lock_guard<std::mutex> lock(m);
  Handle(XCAFApp_Application) app = XCAFApp_Application::GetApplication();
  Handle(TDocStd_Document) doc;
  app->NewDocument("MDTV-XCAF", doc);
  Handle(XCAFDoc_ShapeTool) tool = XCAFDoc_DocumentTool::ShapeTool(doc->Main());
  for (const auto& [name, shape] : shapes) {
    const TDF_Label l = tool->AddShape(shape, Standard_False);
    TDataStd_Name::Set(l, TCollection_ExtendedString(name.c_str(), Standard_True));
  }
  Interface_Static::SetCVal("write.step.unit", "MM");
  Interface_Static::SetCVal("write.step.schema", "AP214IS");
  QuietOcct quiet;
  STEPCAFControl_Writer w;
  w.SetNameMode(Standard_True);
  const std::string tmp = temp_path_for(path, ".step");
  const bool ok = w.Transfer(doc, STEPControl_AsIs) && w.Write(tmp.c_str()) == IFSelect_RetDone;
  app->Close(doc);
  if (!ok) {
    std::remove(tmp.c_str());
    throw InputError("cannot write '" + path +
                     "': OpenCASCADE could not write it (directory missing or not writable, the disk full or a "
                     "file size limit); the old file, if any, is unchanged");
  }
  // Checked again: the file must be complete before it replaces anything.
  commit_temp_file(tmp, path, "END-ISO-10303-21;");
}

}  // namespace

StepResult write_step_parts(const PlateSet& s, const std::string& path) {
  std::vector<std::pair<std::string, TopoDS_Shape>> shapes;
  StepResult r;
  try {
    for (const auto& p : s.plates) {
      shapes.emplace_back(p.name, plate_solid(p.outline, p.holes, p.thickness_m, p.transform));
      r.names.push_back(p.name);
      r.volumes_mm3.push_back(volume(shapes.back().second));
    }
  } catch (const Standard_Failure& e) {
    throw std::runtime_error(std::string("OpenCASCADE failed building the plates: ") + e.GetMessageString());
  }
  write_doc(shapes, path);
  return r;
}

StepResult write_step_fused(const Glider& g, double t, const std::string& path) {
  StepResult r;
  TopoDS_Shape fused;
  try {
    const TopoDS_Shape fus = plate_solid(g.fuselage, {}, t, {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1});
    TopTools_ListOfShape args, tools;
    args.Append(fus);
    for (const auto& w : g.wings) {
      const double th = deg2rad(w.mount.angle_deg), c = std::cos(th), s = std::sin(th);
      tools.Append(plate_solid(w.outline, {}, t, {c, 0, s, w.mount.x_m, s, 0, -c, w.mount.y_m, 0, 1, 0, 0, 0, 0, 0, 1}));
    }
    BRepAlgoAPI_Fuse fuse;
    fuse.SetArguments(args);
    fuse.SetTools(tools);
    fuse.Build();
    if (!fuse.IsDone()) throw std::runtime_error("OpenCASCADE could not fuse the plates");
    ShapeUpgrade_UnifySameDomain unify(fuse.Shape(), Standard_True, Standard_True, Standard_False);
    unify.Build();
    fused = unify.Shape();
  } catch (const Standard_Failure& e) {
    throw std::runtime_error(std::string("OpenCASCADE failed fusing the plates: ") + e.GetMessageString());
  }
  int solids = 0;
  TopoDS_Shape solid;
  for (TopExp_Explorer ex(fused, TopAbs_SOLID); ex.More(); ex.Next()) {
    ++solids;
    solid = ex.Current();
  }
  if (solids != 1)
    throw InputError("the fused glider is " + std::to_string(solids) +
                     " separate solids, not one: a part does not touch the rest");
  const std::string name = g.name.empty() ? "glider" : g.name;
  r.names.push_back(name);
  r.volumes_mm3.push_back(volume(solid));
  write_doc({{name, solid}}, path);
  return r;
}

}  // namespace pteromys
