// Bindings: slotted plates and fabrication files (docs/fabrication.md).
#include <cmath>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "pteromys/fabrication.hpp"

namespace pteromys::python {
namespace {

py::array_t<double> points_array(const Polygon& p) {
  py::array_t<double> a({static_cast<py::ssize_t>(p.size()), static_cast<py::ssize_t>(2)});
  auto r = a.mutable_unchecked<2>();
  for (std::size_t i = 0; i < p.size(); ++i) {
    r(i, 0) = p[i].x;
    r(i, 1) = p[i].y;
  }
  return a;
}

py::list polygons(const std::vector<Polygon>& ps) {
  py::list l;
  for (const auto& p : ps) l.append(points_array(p));
  return l;
}

double finite_mm(const py::object& v, const char* what) {
  double x;
  try {
    x = v.cast<double>();
  } catch (const py::cast_error&) {
    throw InputError(std::string(what) + " must be a number of mm");
  }
  if (!std::isfinite(x)) throw InputError(std::string(what) + " must be a finite number of mm");
  return x;
}

FabricationOptions fab_options(const py::object& kerf, const py::object& clearance, const py::object& min_web,
                               const py::object& joint, const py::object& thickness) {
  FabricationOptions o;
  o.kerf_m = finite_mm(kerf, "kerf_mm") / 1000;
  o.clearance_m = finite_mm(clearance, "clearance_mm") / 1000;
  o.min_web_m = finite_mm(min_web, "min_web_mm") / 1000;
  if (!thickness.is_none()) {
    o.thickness_m = finite_mm(thickness, "thickness_mm") / 1000;
    if (!(o.thickness_m > 0)) throw InputError("thickness_mm must be positive");
  }
  if (joint.is_none()) return o;
  if (py::isinstance<py::str>(joint)) {
    o.joints["*"] = joint_type_from_name(joint.cast<std::string>());
  } else if (py::isinstance<py::dict>(joint)) {
    for (const auto& [k, v] : joint.cast<py::dict>()) {
      if (!py::isinstance<py::str>(k) || !py::isinstance<py::str>(v))
        throw InputError("joint must map wing names to joint types, e.g. {'main': 'halves'}");
      o.joints[k.cast<std::string>()] = joint_type_from_name(v.cast<std::string>());
    }
  } else {
    throw InputError("joint must be None, a joint type or a dict {wing name: joint type}");
  }
  return o;
}

py::dict joint_dict(const Joint& j) {
  py::dict d;
  d["wing"] = j.wing;
  d["type"] = joint_type_name(j.type);
  d["direction"] = j.direction;
  d["split_x_m"] = j.split_x_m;
  d["engaged_m"] = py::make_tuple(j.engaged_from_m, j.engaged_to_m);
  d["how"] = j.how;
  d["step"] = j.step;
  py::list refused;
  for (const auto& [t, why] : j.refused) {
    py::dict r;
    r["type"] = joint_type_name(t);
    r["reason"] = why;
    refused.append(r);
  }
  d["refused"] = refused;
  py::list slots;
  for (const auto& s : j.slots) {
    py::dict q;
    q["plate"] = s.plate;
    q["rect"] = points_array(s.rect);
    q["open"] = s.open;
    q["width_m"] = s.width_m;
    q["axis_origin"] = py::make_tuple(s.axis_origin.x, s.axis_origin.y);
    q["axis_dir"] = py::make_tuple(s.axis_dir.x, s.axis_dir.y);
    q["length_m"] = s.length_m;
    slots.append(q);
  }
  d["slots"] = slots;
  return d;
}

py::list plates_list(const PlateSet& s) {
  py::list out;
  for (const auto& p : s.plates) {
    py::dict d;
    d["name"] = p.name;
    d["kind"] = p.kind;
    d["wing"] = p.wing.empty() ? py::object(py::none()) : py::object(py::str(p.wing));
    d["half"] = p.half.empty() ? py::object(py::none()) : py::object(py::str(p.half));
    d["label"] = p.label;
    d["outline"] = points_array(p.outline);
    d["holes"] = polygons(p.holes);
    d["cut_outline"] = points_array(p.cut_outline);
    d["cut_holes"] = polygons(p.cut_holes);
    py::array_t<double> M({4, 4});
    auto r = M.mutable_unchecked<2>();
    for (int i = 0; i < 16; ++i) r(i / 4, i % 4) = p.transform[i];
    d["transform"] = M;
    d["thickness_m"] = p.thickness_m;
    d["area_m2"] = p.area_m2;
    d["design_area_m2"] = p.design_area_m2;
    py::list joints;
    for (auto j : p.joints) joints.append(joint_dict(s.joints[j]));
    d["joints"] = joints;
    py::list marks;
    for (const auto& m : p.marks) {
      py::dict q;
      q["kind"] = mark_kind_name(m.kind);
      q["points"] = points_array(m.points);
      q["text"] = m.text;
      q["size_m"] = m.size_m;
      q["angle_deg"] = m.angle_deg;
      marks.append(q);
    }
    d["marks"] = marks;
    out.append(d);
  }
  return out;
}

py::object json_to_py(const nlohmann::json& j) { return py::module_::import("json").attr("loads")(j.dump()); }

void bind_fabrication(py::module_& m) {
  const double k0 = FabricationOptions{}.kerf_m * 1000, c0 = FabricationOptions{}.clearance_m * 1000,
               w0 = FabricationOptions{}.min_web_m * 1000;
  m.def("slotted_plates",
        [](const py::object& go, const py::object& kerf, const py::object& clearance, const py::object& min_web,
           const py::object& joint, const py::object& thickness) {
          const Glider g = to_glider(go);
          const FabricationOptions o = fab_options(kerf, clearance, min_web, joint, thickness);
          PlateSet s;
          {
            py::gil_scoped_release nogil;
            s = slotted_plates(g, o);
          }
          return plates_list(s);
        },
        py::arg("glider"), py::arg("kerf_mm") = k0, py::arg("clearance_mm") = c0, py::arg("min_web_mm") = w0,
        py::arg("joint") = py::none(), py::arg("thickness_mm") = py::none(),
        "The glider's plates with interlocking slots (docs/fabrication.md).\n\n"
        "Returns a list of dicts, fuselage first: name, kind ('fuselage' | 'wing'), wing, half,\n"
        "label (engraved name), outline ((n, 2) array [m], plate frame, counter-clockwise,\n"
        "open slots as notches), holes (list of (k, 2) arrays, clockwise), cut_outline/cut_holes\n"
        "(laser paths offset by kerf/2), transform ((4, 4): plate (u, v, w, 1) -> glider (x, y, z, 1),\n"
        "w across the thickness, plate in w in [-t/2, t/2]), thickness_m, area_m2, design_area_m2,\n"
        "joints (wing, type 'through_slot' | 'notch' | 'cross_lap' | 'halves', direction, split_x_m,\n"
        "engaged_m, how, step, refused [{type, reason}], slots [{plate, rect (4, 2), open, width_m, ...}])\n"
        "and marks ({kind 'line' | 'cross' | 'text', points (m, 2) [m], text, size_m, angle_deg}).\n"
        "joint: None (choose), a type for every wing, or {wing name: type}.\n"
        "Raises pteromys.InputError with a plain-words reason when a wing cannot be joined.");
  m.def("fabrication_plan",
        [](const py::object& go, const py::object& kerf, const py::object& clearance, const py::object& min_web,
           const py::object& joint, const py::object& thickness) {
          const Glider g = to_glider(go);
          const FabricationOptions o = fab_options(kerf, clearance, min_web, joint, thickness);
          nlohmann::json j;
          {
            py::gil_scoped_release nogil;
            j = plates_summary(slotted_plates(g, o));
          }
          return json_to_py(j);
        },
        py::arg("glider"), py::arg("kerf_mm") = k0, py::arg("clearance_mm") = c0, py::arg("min_web_mm") = w0,
        py::arg("joint") = py::none(), py::arg("thickness_mm") = py::none(),
        "Summary of the joints (chosen type, refused types and why), parts and assembly steps.");
  m.def("export",
        [](const py::object& go, const py::object& dxf, const py::object& step, const py::object& kerf,
           const py::object& clearance, const py::object& min_web, const py::object& sheet, bool fused,
           const py::object& joint, const py::object& thickness, const py::object& gap) {
          const Glider g = to_glider(go);
          ExportRequest r;
          r.fabrication = fab_options(kerf, clearance, min_web, joint, thickness);
          auto path = [](const py::object& p) {
            if (p.is_none()) return std::string();
            return py::str(py::module_::import("os").attr("fspath")(p)).cast<std::string>();
          };
          r.dxf_path = path(dxf);
          r.step_path = path(step);
          if (r.dxf_path.empty() && r.step_path.empty())
            throw InputError("nothing to write: give dxf=PATH and/or step=PATH");
          if (fused && r.step_path.empty()) throw InputError("fused applies to the STEP file; give step=PATH");
          py::sequence sq;
          try {
            sq = sheet.cast<py::sequence>();
          } catch (const py::cast_error&) {
            throw InputError("sheet_mm must be (width, height) in mm");
          }
          if (py::len(sq) != 2) throw InputError("sheet_mm must be (width, height) in mm");
          r.sheet.width_m = finite_mm(sq[0], "sheet width") / 1000;
          r.sheet.height_m = finite_mm(sq[1], "sheet height") / 1000;
          r.sheet.gap_m = finite_mm(gap, "gap_mm") / 1000;
          r.fused = fused;
          nlohmann::json j;
          {
            py::gil_scoped_release nogil;
            j = export_glider(g, r);
          }
          return json_to_py(j);
        },
        py::arg("glider"), py::arg("dxf") = py::none(), py::arg("step") = py::none(), py::arg("kerf_mm") = k0,
        py::arg("clearance_mm") = c0, py::arg("min_web_mm") = w0, py::arg("sheet_mm") = py::make_tuple(600.0, 900.0),
        py::arg("fused") = false, py::arg("joint") = py::none(), py::arg("thickness_mm") = py::none(),
        py::arg("gap_mm") = SheetOptions{}.gap_m * 1000,
        "Writes the laser-cutting DXF and/or the STEP assembly (as `pteromys export`).\n"
        "Returns the summary dict: parts, joints, assembly, warnings, sheets, files, step_solids.");
}

const bool registered = register_binder(40, bind_fabrication);
}  // namespace
}  // namespace pteromys::python
