// pteromys optimize.
#include <iostream>
#include <cmath>
#include <sstream>

#include "commands.hpp"
#include "common.hpp"
#include "pteromys/optimize.hpp"

namespace pteromys::cli {
namespace {

std::vector<std::string> split_list(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}

int run_optimize(const std::vector<std::string>& argv) {
  auto valued = aero_valued_options();
  valued.insert({"-o", "--json", "--csv", "--lock", "--algorithm", "--max-evaluations", "--w1", "--w2",
                 "--speed-range", "--alpha-range", "--angle-range", "--min-overlap", "--w4", "--min-static-margin", "--min-wing-gap-mm"});
  const Args a = parse_args(argv, valued, {"--ballast", "--quiet"});
  if (!a.has("-o")) throw InputError("missing -o OUT.glider.json (see --help)");
  check_writable(a.get("-o"), "glider");
  if (a.has("--json")) check_writable(a.get("--json"), "report");
  if (a.has("--csv")) check_writable(a.get("--csv"), "trajectories");
  check_setup_outputs(a, {{"the optimised glider", "-o"}, {"the report", "--json"}, {"the trajectories", "--csv"}});
  Setup s = load_setup(a);
  OptimizeOptions opt;
  opt.analysis = s.analysis;
  opt.analysis.sim.record_every = 5;
  opt.locks = split_list(a.get("--lock"));
  opt.optimise_ballast = a.flag("--ballast");
  opt.algorithm = a.get("--algorithm", opt.algorithm);
  opt.max_evaluations = a.whole("--max-evaluations", opt.max_evaluations, 1, 10000000);
  opt.w1 = a.number("--w1", opt.w1);
  opt.w2 = a.number("--w2", opt.w2);
  opt.w4 = a.number("--w4", opt.w4);
  opt.min_static_margin = a.number("--min-static-margin", opt.min_static_margin);
  opt.min_overlap_fraction = a.number("--min-overlap", opt.min_overlap_fraction);
  opt.min_wing_gap_m = a.number("--min-wing-gap-mm", 1000 * opt.min_wing_gap_m) / 1000;
  if (!(opt.min_overlap_fraction >= 0 && opt.min_overlap_fraction <= 1))
    throw InputError("--min-overlap must be a fraction between 0 and 1");
  auto range = [&](const char* key, double& lo, double& hi, double scale) {
    if (!a.has(key)) return;
    const auto parts = split_list(a.get(key));
    char* e1 = nullptr;
    char* e2 = nullptr;
    if (parts.size() != 2) throw InputError(std::string(key) + " needs LO,HI");
    const double l = std::strtod(parts[0].c_str(), &e1), h = std::strtod(parts[1].c_str(), &e2);
    if (*e1 || *e2 || !std::isfinite(l) || !std::isfinite(h) || !(h > l))
      throw InputError(std::string(key) + " needs two numbers LO,HI with LO < HI");
    lo = l * scale;
    hi = h * scale;
  };
  range("--speed-range", opt.region.v_min, opt.region.v_max, 1.0);
  range("--alpha-range", opt.region.gamma_min, opt.region.gamma_max, kPi / 180);
  range("--angle-range", opt.angle_min_deg, opt.angle_max_deg, 1.0);
  if (!(opt.region.v_min > 0)) throw InputError("--speed-range must be positive speeds");
  const OptimizeResult r = optimize(s.glider, s.model, opt, s.env, s.aero);
  nlohmann::json j = report_to_json(r.report);
  j["glider"] = s.glider.name;
  j["model"] = s.model->kind();
  j["optimisation"] = {{"algorithm", r.algorithm},
                       {"evaluations", r.evaluations},
                       {"seconds", r.seconds},
                       {"stop_reason", r.stop_reason},
                       {"cost_start", {{"c1", r.cost_start.c1}, {"c2", r.cost_start.c2}, {"c3", r.cost_start.c3}, {"c4", r.cost_start.c4}, {"total", r.cost_start.total}}},
                       {"cost", {{"c1", r.cost.c1}, {"c2", r.cost.c2}, {"c3", r.cost.c3}, {"c4", r.cost.c4}, {"total", r.cost.total}}},
                       {"variables", nlohmann::json::array()}};
  for (const auto& v : r.variables)
    j["optimisation"]["variables"].push_back(
        {{"name", v.name}, {"value", v.value}, {"lower", v.lower}, {"upper", v.upper}, {"locked", v.locked}});
  // the glider and its report together: one that cannot be written leaves
  // none changed
  std::vector<std::pair<std::string, std::string>> outputs{{a.get("-o"), glider_to_json(r.glider).dump(2) + "\n"}};
  if (a.has("--json")) outputs.emplace_back(a.get("--json"), j.dump(2) + "\n");
  if (a.has("--csv")) outputs.emplace_back(a.get("--csv"), trajectories_csv(r.report));
  write_files_together(outputs);
  if (!a.flag("--quiet")) {
    std::cout << "optimised " << r.variables.size() << " variables in " << r.evaluations << " cost evaluations ("
              << r.seconds * 1000 << " ms); cost " << r.cost_start.total << " -> " << r.cost.total << "\n";
    for (std::size_t i = 0; i < s.glider.wings.size(); ++i) {
      const Mount& m0 = s.glider.wings[i].mount;
      const Mount& m1 = r.glider.wings[i].mount;
      std::cout << "  " << s.glider.wings[i].name << ": angle " << m0.angle_deg << " -> " << m1.angle_deg
                << " deg, x " << m0.x_m << " -> " << m1.x_m << " m, y " << m0.y_m << " -> " << m1.y_m << " m\n";
    }
    std::cout << summary_text(r.report);
  }
  return 0;
}

const bool registered = register_command(30, {"optimize", 0,
    "adjust mounting angles and positions so that the glider flies",
    "usage: pteromys optimize GLIDER -o OUT.glider.json [--json REPORT.json] [--csv TRAJ.csv] [options]\n\n"
    "Moves and tilts the wings (paper section 6) to minimise C = w1 C1 + w2 C2 + C3 over\n"
    "Omega = speeds x angles of attack: C1 pitch stability, C2 lift balance on the T_z = 0\n"
    "line, C3 drag. Writes the glider with the new mounts to -o and the flyability report\n"
    "of the result (format pteromys-report/1, plus an 'optimisation' section) to --json.\n\n"
    "options:\n"
    "  -o OUT.glider.json     optimised glider (required)\n"
    "  --json REPORT.json     report of the optimised design\n"
    "  --csv TRAJ.csv         trajectories of the standard launches of the result\n"
    "  --lock LIST            variables to keep, comma-separated: WING.angle, WING.x, WING.y, ballast.x\n"
    "  --ballast              also move the ballast along x (all items together)\n"
    "  --algorithm NAME       bobyqa (default), cobyla, sbplx, neldermead (NLopt) or steepest (the paper's)\n"
    "  --max-evaluations N    cost evaluations allowed (default 3000)\n"
    "  --w1 W, --w2 W         cost weights (default 100 and 1, as the paper)\n"
    "  --w4 W                 weight of the static-margin term C4 (default 1; 0 = the paper's cost)\n"
    "  --min-static-margin H  static margin C4 asks for, fraction of the main chord (default 0.10)\n"
    "  --speed-range LO,HI    Omega's speeds [m/s] (default 6,9)\n"
    "  --alpha-range LO,HI    Omega's angles of attack [deg] (default -10,10)\n"
    "  --angle-range LO,HI    bounds of the mounting angles [deg] (default -10,15)\n"
    "  --min-overlap F        fraction of each root chord kept inside the fuselage (default 0.6)\n"
    "  --min-wing-gap-mm G    gap kept between consecutive wings' root chords, front to back\n"
    "                         in the drawn order (default 10 mm)\n"
    "  --quiet                no summary on stdout\n" +
        std::string(kAeroOptionsHelp),
    run_optimize});

}  // namespace
}  // namespace pteromys::cli
