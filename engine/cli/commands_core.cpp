// pteromys evaluate, pteromys simulate.
#include <cmath>
#include <iostream>

#include "commands.hpp"
#include "common.hpp"

namespace pteromys::cli {
namespace {

int run_evaluate(const std::vector<std::string>& argv) {
  auto valued = aero_valued_options();
  valued.insert({"--json", "--csv"});
  const Args a = parse_args(argv, valued, {"--quiet"});
  if (a.has("--json")) check_writable(a.get("--json"), "report");
  if (a.has("--csv")) check_writable(a.get("--csv"), "trajectories");
  check_setup_outputs(a, {{"the report", "--json"}, {"the trajectories", "--csv"}});
  Setup s = load_setup(a);
  const MountedGlider mg = mount(s.glider, s.model, s.env, s.aero);
  std::vector<std::string> names;
  for (const auto& w : s.glider.wings) names.push_back(w.name);
  s.analysis.sim.record_every = 5;
  const Flyability f = analyse(mg, names, s.analysis);
  nlohmann::json j = report_to_json(f);
  j["glider"] = s.glider.name;
  j["model"] = s.model->kind();
  std::vector<std::pair<std::string, std::string>> outputs;
  if (a.has("--json")) outputs.emplace_back(a.get("--json"), j.dump(2) + "\n");
  if (a.has("--csv")) outputs.emplace_back(a.get("--csv"), trajectories_csv(f));
  if (!outputs.empty()) write_files_together(outputs);
  if (!a.has("--json")) std::cout << j.dump(2) << "\n";
  if (a.has("--json") && !a.flag("--quiet")) std::cout << summary_text(f);
  return 0;
}

int run_simulate(const std::vector<std::string>& argv) {
  auto valued = aero_valued_options();
  valued.insert({"--csv", "--every"});
  const Args a = parse_args(argv, valued, {});
  if (!a.has("--csv")) throw InputError("missing --csv OUT (see --help)");
  check_writable(a.get("--csv"), "trajectories");
  check_setup_outputs(a, {{"the trajectories", "--csv"}});
  Setup s = load_setup(a);
  const double every = a.number("--every", 5);
  if (!(every >= 1) || every > 1e6 || every != std::floor(every))  // 2.5 used to be cut to 2
    throw InputError("--every must be a positive whole number");
  s.analysis.sim.record_every = static_cast<int>(every);
  const MountedGlider mg = mount(s.glider, s.model, s.env, s.aero);
  std::vector<std::string> names;
  for (const auto& w : s.glider.wings) names.push_back(w.name);
  const Flyability f = analyse(mg, names, s.analysis);
  write_file_atomic(a.get("--csv"), trajectories_csv(f));
  return 0;
}

const bool registered_evaluate = register_command(10,
      {"evaluate", 0, "flyability report of a glider (mass, trim, stability, standard launches)",
       "usage: pteromys evaluate GLIDER [--json OUT.json] [--csv TRAJ.csv] [options]\n\n"
       "Evaluates a glider file as it is (mounts unchanged): mass properties, trim and\n"
       "pitch stability, steady glide, and the six standard hand launches (7, 9, 11 m/s;\n"
       "0 and 10 deg upward). Writes the report (format pteromys-report/1) to --json,\n"
       "or prints it when --json is not given; prints a summary otherwise.\n\n"
       "options:\n"
       "  --json OUT.json      report file\n"
       "  --csv TRAJ.csv       trajectories of the launches (as pteromys simulate)\n"
       "  --quiet              no summary on stdout\n" +
           std::string(kAeroOptionsHelp),
       run_evaluate});
const bool registered_simulate = register_command(20,
      {"simulate", 0, "trajectories of the six standard launches as CSV",
       "usage: pteromys simulate GLIDER --csv OUT.csv [options]\n\n"
       "Simulates the six standard hand launches and writes their trajectories with the\n"
       "header launch,t_s,x_m,y_m,pitch_deg,speed_m_s; launch numbers the launches from 0\n"
       "in the order of the report, x and y are the centre of gravity (launch point at\n"
       "x = 0, y = launch height).\n\n"
       "options:\n"
       "  --csv OUT.csv        output file (required)\n"
       "  --every N            keep every N-th time step (default 5 = every 10 ms)\n" +
           std::string(kAeroOptionsHelp),
       run_simulate});

}  // namespace
}  // namespace pteromys::cli
