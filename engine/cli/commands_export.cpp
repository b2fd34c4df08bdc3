// pteromys export: slotted plates as a laser-cutting DXF and a STEP assembly.
#include <cmath>
#include <iostream>
#include <sstream>

#include "commands.hpp"
#include "common.hpp"
#include "pteromys/fabrication.hpp"

namespace pteromys::cli {
namespace {

double mm_option(const Args& a, const std::string& k, double def_m) {
  if (!a.has(k)) return def_m;
  const double v = a.number(k, def_m * 1000);
  if (!std::isfinite(v)) throw InputError(k + " must be a finite number of mm");
  return v / 1000.0;
}

/// "auto", "halves" (every wing) or "main=halves,tail=cross_lap".
std::map<std::string, JointType> joint_option(const std::string& spec) {
  std::map<std::string, JointType> out;
  std::stringstream ss(spec);
  std::string item;
  while (std::getline(ss, item, ',')) {
    if (item.empty()) continue;
    const auto eq = item.find('=');
    if (eq == std::string::npos) out["*"] = joint_type_from_name(item);
    else {
      const std::string wing = item.substr(0, eq);
      if (wing.empty()) throw InputError("--joint expects WING=TYPE, got '" + item + "'");
      out[wing] = joint_type_from_name(item.substr(eq + 1));
    }
  }
  if (out.empty()) throw InputError("--joint is empty (expected auto, through_slot, cross_lap, halves or WING=TYPE,...)");
  return out;
}

std::pair<double, double> sheet_option(const std::string& s) {
  const auto x = s.find_first_of("xX");
  try {
    if (x == std::string::npos) throw std::invalid_argument("");
    std::size_t n1 = 0, n2 = 0;
    const double w = std::stod(s.substr(0, x), &n1), h = std::stod(s.substr(x + 1), &n2);
    if (n1 != x || n2 != s.size() - x - 1 || !std::isfinite(w) || !std::isfinite(h)) throw std::invalid_argument("");
    return {w, h};
  } catch (const std::exception&) {
    throw InputError("--sheet expects WIDTHxHEIGHT in mm, e.g. 600x900 (got '" + s + "')");
  }
}

std::string fmt(double v) {
  std::ostringstream s;
  s.precision(4);
  s << v;
  return s.str();
}

int run_export(const std::vector<std::string>& argv) {
  const Args a = parse_args(argv,
                            {"--dxf", "--step", "--json", "--kerf", "--clearance", "--min-web", "--thickness", "--joint",
                             "--sheet", "--gap", "--margin", "--text-height"},
                            {"--fused", "--quiet"});
  if (a.positional.empty()) throw InputError("missing GLIDER file (see --help)");
  if (a.positional.size() > 1) throw InputError("unexpected argument '" + a.positional[1] + "'");
  if (!a.has("--dxf") && !a.has("--step") && !a.has("--json"))
    throw InputError("nothing to write: give --dxf OUT.dxf and/or --step OUT.step (or --json OUT.json)");
  if (a.flag("--fused") && !a.has("--step")) throw InputError("--fused applies to the STEP file; give --step OUT.step");
  if (a.has("--dxf")) check_writable(a.get("--dxf"), "DXF");
  if (a.has("--step")) check_writable(a.get("--step"), "STEP");
  if (a.has("--json")) check_writable(a.get("--json"), "summary");

  ExportRequest r;
  FabricationOptions& f = r.fabrication;
  f.kerf_m = mm_option(a, "--kerf", f.kerf_m);
  f.clearance_m = mm_option(a, "--clearance", f.clearance_m);
  f.min_web_m = mm_option(a, "--min-web", f.min_web_m);
  f.thickness_m = mm_option(a, "--thickness", 0.0);
  if (a.has("--thickness") && !(f.thickness_m > 0)) throw InputError("--thickness must be a positive number of mm");
  f.text_height_m = mm_option(a, "--text-height", f.text_height_m);
  if (a.has("--joint")) f.joints = joint_option(a.get("--joint"));
  if (a.has("--sheet")) {
    const auto [w, h] = sheet_option(a.get("--sheet"));
    r.sheet.width_m = w / 1000;
    r.sheet.height_m = h / 1000;
  }
  r.sheet.gap_m = mm_option(a, "--gap", r.sheet.gap_m);
  r.sheet.margin_m = mm_option(a, "--margin", r.sheet.margin_m);
  r.dxf_path = a.get("--dxf");
  r.step_path = a.get("--step");
  r.fused = a.flag("--fused");

  const Glider g = load_glider(a.positional[0]);
  const nlohmann::json j = export_glider(g, r);
  if (a.has("--json")) write_file_atomic(a.get("--json"), j.dump(2) + "\n");
  if (!a.flag("--quiet")) {
    std::cout << "glider '" << g.name << "': " << j["parts"].size() << " parts, " << fmt(j["thickness_mm"].get<double>())
              << " mm sheet, slots " << fmt(j["slot_width_mm"].get<double>()) << " mm wide, kerf "
              << fmt(j["kerf_mm"].get<double>()) << " mm\n";
    for (const auto& jt : j["joints"]) {
      std::cout << "  wing '" << jt["wing"].get<std::string>() << "': " << jt["type"].get<std::string>() << "\n";
      for (const auto& rf : jt["refused"])
        std::cout << "    (not " << rf["type"].get<std::string>() << ": " << rf["reason"].get<std::string>() << ")\n";
    }
    std::cout << "assembly:\n";
    int n = 1;
    for (const auto& s : j["assembly"]) std::cout << "  " << n++ << ". " << s.get<std::string>() << "\n";
    for (const auto& w : j["warnings"]) std::cout << "warning: " << w.get<std::string>() << "\n";
    for (const auto& file : j["files"]) std::cout << "wrote " << file.get<std::string>() << "\n";
    if (!r.dxf_path.empty()) std::cout << "  (" << j["sheets"] << " sheet(s) of " << a.get("--sheet", "600x900") << " mm)\n";
  }
  return 0;
}

const bool registered_export = register_command(40,
      {"export", 0, "fabrication files: slotted plates as laser-cut DXF and STEP",
       "usage: pteromys export GLIDER [--dxf OUT.dxf] [--step OUT.step] [options]\n\n"
       "Builds the fuselage and wing plates with interlocking slots that hold every wing\n"
       "at its mounting angle and position, chooses a joint per wing that can really be\n"
       "assembled (through slot, notch, cross-lap or wing halves) and writes:\n"
       "  - a DXF for laser cutting (millimetres; layers CUT: closed kerf-compensated\n"
       "    outlines, ENGRAVE: names, CG, ballast and wing positions, SHEET: sheet borders),\n"
       "    parts laid out without overlap on sheets;\n"
       "  - a STEP of the assembled glider (millimetres, glider frame), one named solid\n"
       "    per plate, or one fused solid with --fused.\n"
       "When a wing cannot be joined the command says why and writes nothing.\n"
       "See docs/fabrication.md.\n\n"
       "options:\n"
       "  --dxf OUT.dxf        laser-cutting layout\n"
       "  --step OUT.step      3D assembly (one solid per plate)\n"
       "  --fused              STEP: the unslotted plates fused into one solid (print in one piece)\n"
       "  --json OUT.json      summary: parts, joints, refused joints and why, assembly steps\n"
       "  --kerf MM            width of the laser's cut (default 0.2)\n"
       "  --clearance MM       slot width minus sheet thickness, negative for a press fit (default 0.05)\n"
       "  --min-web MM         narrowest material allowed beside a slot (default 2)\n"
       "  --thickness MM       measured sheet thickness for slots and solids\n"
       "                       (default: the glider file's material; mass is unchanged)\n"
       "  --joint SPEC         auto (default), through_slot, notch, cross_lap or halves for every wing,\n"
       "                       or per wing: main=halves,tail=cross_lap\n"
       "  --sheet WxH          sheet size in mm (default 600x900, a foam board)\n"
       "  --gap MM             space between parts on a sheet (default 4)\n"
       "  --margin MM          free border of a sheet (default 5)\n"
       "  --text-height MM     engraved name height (default 4)\n"
       "  --quiet              no summary on stdout\n",
       run_export});

}  // namespace
}  // namespace pteromys::cli
