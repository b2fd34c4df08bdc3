// pteromys generate: synthetic tracked flights from the reference simulator.
#include <dirent.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <cstdio>
#include <iostream>
#include <sstream>

#include "commands.hpp"
#include "common.hpp"
#include "pteromys/io.hpp"
#include "pteromys/reference.hpp"
#include "pteromys/version.hpp"

namespace pteromys::cli {
namespace {

// Glider files: the arguments, with each directory's *.glider.json (keys by glider_key_of).
std::vector<std::string> glider_paths(const std::vector<std::string>& args) {
  std::vector<std::string> out;
  for (const auto& a : args) {
    if (is_dir(a)) {
      std::vector<std::string> found;
      if (DIR* d = opendir(a.c_str())) {
        while (dirent* e = readdir(d)) {
          const std::string n = e->d_name;
          if (n.size() > 12 && n.substr(n.size() - 12) == ".glider.json") found.push_back(strip_slash(a) + "/" + n);
        }
        closedir(d);
      }
      if (found.empty()) throw InputError("directory '" + a + "' holds no .glider.json files");
      std::sort(found.begin(), found.end());
      out.insert(out.end(), found.begin(), found.end());
    } else {
      out.push_back(a);
    }
  }
  return out;
}

std::pair<double, double> range(const std::string& s, const std::string& opt) {
  const auto c = s.find(':');
  auto num = [&](const std::string& v) {
    char* end = nullptr;
    const double x = std::strtod(v.c_str(), &end);
    if (v.empty() || *end != '\0' || !std::isfinite(x))
      throw InputError("option " + opt + " needs MIN:MAX or a number, got '" + s + "'");
    return x;
  };
  if (c == std::string::npos) {
    const double x = num(s);
    return {x, x};
  }
  const double a = num(s.substr(0, c)), b = num(s.substr(c + 1));
  if (b < a) throw InputError("option " + opt + ": MAX is below MIN in '" + s + "'");
  return {a, b};
}

int run_generate(const std::vector<std::string>& argv) {
  const Args a = parse_args(argv,
                            {"-o", "--output", "--flights-per-glider", "--seed", "--noise-m", "--frame-rate",
                             "--effects", "--strength", "--points", "--window", "--speed", "--speed-relative", "--retrim", "--climb",
                             "--height", "--wind", "--threads", "--dt", "--span-panels", "--chord-panels",
                             "--launch-rotation", "--camera-scale-error", "--camera-roll-deg"},
                            {"--quiet", "--strict"});
  if (a.positional.empty()) throw InputError("missing GLIDER files (see --help)");
  if (a.has("-o") && a.has("--output")) throw InputError("give the output directory once (-o or --output)");
  const std::string out = strip_slash(a.has("-o") ? a.get("-o") : a.get("--output"));
  if (out.empty()) throw InputError("missing -o DATASET_DIR (see --help)");
  if (exists(out) && !is_dir(out)) throw InputError("output '" + out + "' exists and is not a directory");
  if (!is_dir(directory_of(out)))
    throw InputError("cannot write dataset '" + out + "': directory '" + directory_of(out) + "' does not exist");

  GenerateOptions o;
  o.effects = parse_effects(a.get("--effects", "physics"));
  apply_strengths(o.effects, a.get("--strength", ""));
  o.flights_per_glider = a.whole("--flights-per-glider", 6, 1, 10000);
  const double seed = a.number("--seed", 1);
  if (seed < 0 || seed != std::floor(seed) || seed > 9.007e15) throw InputError("--seed needs a whole number >= 0");
  o.seed = static_cast<std::uint64_t>(seed);
  o.camera.noise_sigma_m = a.number("--noise-m", 0.05);
  o.camera.frame_rate_hz = a.number("--frame-rate", 30.0);
  if (!(o.camera.noise_sigma_m > 0))
    throw InputError("--noise-m must be positive (the dataset states the tracking sigma; use 1e-9 for almost exact points)");
  std::string pspec = a.get("--points", "15-20");
  if (pspec.find(':') == std::string::npos) std::replace(pspec.begin(), pspec.end(), '-', ':');
  const auto pts = range(pspec, "--points");
  if (pts.first != std::floor(pts.first) || pts.second != std::floor(pts.second) || pts.first < 6 || pts.second > 100000)
    throw InputError("--points needs whole numbers MIN-MAX with MIN >= 6 (for example 15-20)");
  o.points_min = static_cast<int>(pts.first);
  o.points_max = static_cast<int>(pts.second);
  const std::string win = a.get("--window", "launch");
  if (win == "launch") o.window = TrackWindow::Launch;
  else if (win == "landing") o.window = TrackWindow::Landing;
  else if (win == "whole") o.window = TrackWindow::Whole;
  else throw InputError("--window must be launch, landing or whole, got '" + win + "'");
  if (a.has("--speed") && a.has("--speed-relative"))
    throw InputError("give launch speeds once: --speed (m/s) or --speed-relative (glide speeds)");
  if (a.has("--speed-relative")) {
    const auto sr = range(a.get("--speed-relative"), "--speed-relative");
    if (!(sr.first >= 0.3 && sr.second <= 5.0))
      throw InputError("--speed-relative needs factors of the glide speed between 0.3 and 5 (for example 1:1.5)");
    o.launcher.speed_relative = true;
    o.launcher.speed_min = sr.first;
    o.launcher.speed_max = sr.second;
    o.launcher.speed_sigma = 0.04;  // 4 % of the glide speed (0.25 m/s at 6 m/s)
  } else {
    const auto sp = range(a.get("--speed", "7:11"), "--speed");
    o.launcher.speed_min = sp.first;
    o.launcher.speed_max = sp.second;
  }
  if (a.has("--retrim")) {
    o.retrim = true;
    o.retrim_alpha_deg = a.number("--retrim", 4.0);
  }
  const auto cl = range(a.get("--climb", "0:10"), "--climb");
  o.launcher.climb_min_deg = cl.first;
  o.launcher.climb_max_deg = cl.second;
  o.launcher.height = a.number("--height", 1.5);
  o.launcher.rotation_deg_s = a.number("--launch-rotation", o.launcher.rotation_deg_s);
  o.camera.scale_error = a.number("--camera-scale-error", o.camera.scale_error);
  o.camera.roll_error_deg = a.number("--camera-roll-deg", o.camera.roll_error_deg);
  o.wind_m_s = a.number("--wind", -1.0);
  o.threads = a.whole("--threads", 2, 1, 64);
  o.dt = check_time_step(a.number("--dt", 0.002), "--dt");
  o.aero.span_panels = a.whole("--span-panels", o.aero.span_panels, 1, 200);
  o.aero.chord_panels = a.whole("--chord-panels", o.aero.chord_panels, 1, 50);

  // Gliders (validated on loading; messages name the file).
  std::vector<std::pair<std::string, Glider>> gliders;
  for (const auto& p : glider_paths(a.positional)) gliders.emplace_back(glider_key_of(p), load_glider(p));

  const bool quiet = a.flag("--quiet");
  const auto t0 = std::chrono::steady_clock::now();
  int last_pct = -1;
  o.progress = [&](int done, int total, const std::string& key) {
    if (quiet) return;
    const int pct = 100 * done / total;
    if (pct / 10 != last_pct / 10 || done == total) {
      last_pct = pct;
      const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::fprintf(stderr, "generate: %d/%d flights (%d%%, glider %s), %.1f s\n", done, total, pct, key.c_str(), el);
    }
  };
  o.strict = a.flag("--strict");
  GenerateStats st;
  const Dataset d = generate_dataset(gliders, o, &st);
  if (st.dropped > 0)
    std::fprintf(stderr, "generate: warning: %d launches left out: no draw gave 6 tracked points (the glider hits the ground or tumbles at once)%s\n",
                 st.dropped, st.dropped_gliders.empty() ? "" : "; gliders left out of the dataset:");
  for (const auto& k : st.dropped_gliders) std::fprintf(stderr, "generate: warning:   %s\n", k.c_str());

  // Provenance beside the dataset (readers ignore unknown files).
  nlohmann::json gen;
  gen["format"] = "pteromys-generation/1";
  gen["generator"] = std::string("pteromys ") + kVersion + " reference simulator";
  gen["effects"] = o.effects.describe();
  nlohmann::json eff;
  for (const auto& n : Effects::names()) eff[n] = {{"on", o.effects[n].on}, {"strength", o.effects[n].strength}};
  gen["effect_switches"] = eff;
  gen["seed"] = o.seed;
  if (o.retrim) gen["retrim_alpha_deg"] = o.retrim_alpha_deg;
  gen["flights_per_glider"] = o.flights_per_glider;
  gen["points"] = {o.points_min, o.points_max};
  gen["window"] = win;
  gen["launcher"] = {{o.launcher.speed_relative ? "speed_glide_speeds" : "speed_m_s",
                      {o.launcher.speed_min, o.launcher.speed_max}},
                     {o.launcher.speed_relative ? "speed_sigma_glide_speeds" : "speed_sigma_m_s",
                      o.launcher.speed_sigma},
                     {"climb_deg", {o.launcher.climb_min_deg, o.launcher.climb_max_deg}},
                     {"climb_sigma_deg", o.launcher.climb_sigma_deg},
                     {"pitch_sigma_deg", o.launcher.pitch_sigma_deg},
                     {"height_m", o.launcher.height},
                     {"launch_rotation_deg_s", o.launcher.rotation_deg_s},
                     {"launch_rotation_sigma_deg_s", o.launcher.rotation_sigma_deg_s},
                     {"release_delay_s", o.launcher.release_delay_s}};
  gen["wind_m_s"] = o.effects.wind.factor() * o.wind_m_s;
  gen["camera"] = {{"frame_rate_hz", o.camera.frame_rate_hz},
                   {"noise_sigma_m", o.camera.noise_sigma_m},
                   {"centre_m", {o.camera.centre.x, o.camera.centre.y}},
                   {"scale", o.camera.scale * (1 + o.effects.camera.factor() * o.camera.scale_error)},
                   {"roll_deg", o.camera.roll_deg + o.effects.camera.factor() * o.camera.roll_error_deg}};
  gen["panels"] = {{"span_per_half_wing", o.aero.span_panels}, {"chord", o.aero.chord_panels}};
  gen["dt_s"] = o.dt;
  gen["stats"] = {{"flights", st.flights}, {"redrawn", st.redrawn}, {"unstable", st.unstable},
                  {"dropped_launches", st.dropped}, {"dropped_gliders", st.dropped_gliders},
                  {"setup_s", st.setup_seconds}, {"simulate_s", st.simulate_seconds}};

  // A new directory is written beside and renamed into place, so a failure
  // leaves nothing; into an existing directory every file is replaced
  // atomically and dataset.json comes last.
  if (!exists(out)) {
    const std::string tmp = out + ".tmp-" + std::to_string(getpid());
    register_temp_dir(tmp);  // removed by the signal handlers too
    try {
      if (mkdir(tmp.c_str(), 0777) != 0) throw InputError("cannot create directory '" + tmp + "'");
      save_dataset(d, tmp);
      write_file_atomic(tmp + "/generation.json", gen.dump(2) + "\n");
      if (std::rename(tmp.c_str(), out.c_str()) != 0) throw InputError("cannot rename '" + tmp + "' to '" + out + "'");
      forget_temp_dir(tmp);
    } catch (...) {
      discard_temp_dir(tmp);
      throw;
    }
  } else {
    write_file_atomic(out + "/generation.json", gen.dump(2) + "\n");
    save_dataset(d, out);
  }
  const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::cout << "wrote " << d.flights.size() << " flights of " << d.gliders.size() << " gliders to " << out
            << "/dataset.json (effects: " << o.effects.describe() << "; " << st.redrawn << " launches redrawn, "
            << st.dropped << " left out, " << st.unstable << " flights end unstable; " << std::fixed;
  std::cout.precision(1);
  std::cout << el << " s)\n";
  return 0;
}

const bool registered_generate = register_command(
    50, {"generate", 0, "synthetic tracked flights from the reference simulator (dataset)",
         "usage: pteromys generate GLIDER... -o DATASET_DIR [options]\n\n"
         "Simulates hand launches of each glider (files, or directories of .glider.json)\n"
         "with the reference simulator (vortex lattice of all wings, post-stall flat-plate\n"
         "sections, switchable effects; docs/reference_simulator.md) and records them as a\n"
         "side camera would: DATASET_DIR/dataset.json, flights.csv and gliders/ in the\n"
         "spec's flight-dataset format, plus generation.json (the settings). Flights are\n"
         "named KEY-NN after the glider file; optional per-flight columns hold the true\n"
         "launch (true_speed_m_s, true_climb_deg, true_pitch_deg, true_pitch_rate_deg_s,\n"
         "true_height_m, true_release_t_s, true_end). Deterministic given --seed.\n\n"
         "options:\n"
         "  -o, --output DIR          dataset directory (created; parent must exist)\n"
         "  --flights-per-glider N    launches per glider (default 6)\n"
         "  --seed S                  random seed (default 1)\n"
         "  --noise-m SIGMA           tracking noise per coordinate [m] (default 0.05)\n"
         "  --frame-rate HZ           camera frame rate (default 30)\n"
         "  --points MIN-MAX          tracked points per flight (default 15-20)\n"
         "  --window W                launch (default: from release), landing, or whole\n"
         "  --effects SPEC            physics (default: the six aerodynamic effects), baseline\n"
         "                            (none: what the wing-element model assumes), all, or a\n"
         "                            comma list of: pitch_damping, downwash, finite_span,\n"
         "                            fuselage_drag, ground_effect, launch_rotation, added_mass,\n"
         "                            wind, camera\n"
         "  --strength E=V,...        strength of effects (switches them on; 0 = off)\n"
         "  --speed MIN:MAX           nominal launch speeds [m/s] (default 7:11)\n"
         "  --speed-relative MIN:MAX  nominal launch speeds as multiples of each glider's\n"
         "                            steady glide speed in the simulated reality (a person\n"
         "                            throws a glider at about its flying speed; column\n"
         "                            glide_speed_m_s); the glider must have a stable glide\n"
         "  --retrim DEG              trim each glider for the simulated reality, as a person\n"
         "                            bends the tail until it glides: its smallest wing's\n"
         "                            mounting angle is turned (within 15 degrees), with nose\n"
         "                            weight where needed for a 5 % static margin, until the\n"
         "                            stable pitch equilibrium is at DEG angle of attack; the\n"
         "                            dataset's glider files hold the trimmed mounts (column\n"
         "                            trim_turn_deg, trim_weight_kg)\n"
         "  --climb MIN:MAX           nominal climb angles [deg] (default 0:10)\n"
         "  --height M                launch height [m] (default 1.5)\n"
         "  --wind M_S                wind along x at wind strength 1 (default -1: headwind)\n"
         "  --launch-rotation DEG_S   mean pitch rate at release at strength 1 (default 60)\n"
         "  --camera-scale-error K    scale error at camera strength 1 (default 0.03)\n"
         "  --camera-roll-deg DEG     camera roll at camera strength 1 (default 2)\n"
         "  --dt S                    simulation step [s] (default 0.002)\n"
         "  --span-panels N           lattice strips per half wing (default 10)\n"
         "  --chord-panels N          lattice panels per strip (default 4)\n"
         "  --threads N               gliders simulated in parallel (default 2)\n"
         "  --strict                  fail when a launch gives fewer than 6 tracked points in 20\n"
         "                            draws (default: leave it out with a warning; a glider\n"
         "                            without flights is left out of the dataset)\n"
         "  --quiet                   no progress on stderr\n",
         run_generate});

}  // namespace
}  // namespace pteromys::cli
