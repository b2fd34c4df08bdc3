// pteromys diagnose: where and why the simulation and tracked flights
// disagree (issue 7; spec/formats.md "Diagnosis result"; docs/diagnosis.md).
#include <fcntl.h>
#include <stdio.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>
#include <set>
#include <sstream>

#include "commands.hpp"
#include "common.hpp"
#include "pteromys/dataset.hpp"
#include "pteromys/diagnose.hpp"
#include "pteromys/io.hpp"
#include "pteromys/version.hpp"

namespace pteromys::cli {
namespace {

/// The value a dataset took for a key it did not give (Dataset::defaulted).
std::string defaulted_value(const Dataset& d, const std::string& key) {
  std::ostringstream s;
  if (key == "frame_rate_hz") s << d.frame_rate_hz << " Hz";
  else if (key == "tracking_sigma_m") s << d.tracking_sigma_m << " m";
  else if (key == "air.density_kg_m3") s << d.air_density << " kg/m3";
  else if (key == "air.viscosity_pa_s") s << d.air_viscosity << " Pa s";
  else if (key == "gravity_m_s2") s << d.gravity << " m/s2";
  else s << "its default";
  return s.str();
}

std::vector<Effect> parse_effect_list(const std::string& s) {
  std::vector<Effect> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) {
    if (item.empty()) continue;
    out.push_back(effect_from_name(item));
  }
  if (out.empty()) throw InputError("--effects needs at least one effect name");
  check_candidate_effects(out, "--effects: ");  // before the dataset is read, as diagnose() would after
  return out;
}

// An on/off pair of flags (--NAME, --no-NAME): both given contradict each
// other; neither keeps the default.
bool on_off(const Args& a, const std::string& name, bool def) {
  const std::string on = "--" + name, off = "--no-" + name;
  if (a.flag(on) && a.flag(off)) throw InputError(on + " and " + off + " contradict each other");
  return a.flag(on) || (def && !a.flag(off));
}

/// Directory of the Python package next to this executable (build tree:
/// <build>/bin/pteromys -> <build>/python), or "" when there is none.
std::string python_dir() {
  char buf[4096];
  const ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
  if (n <= 0) return "";
  buf[n] = 0;
  const std::filesystem::path exe(buf);
  const auto cand = exe.parent_path().parent_path() / "python";
  if (exists((cand / "pteromys" / "diagnose_report.py").string())) return cand.string();
  return "";
}

/// The environment of the report's renderer: this process's, with the
/// pteromys package next to this executable first on PYTHONPATH and
/// matplotlib's Agg backend.
std::vector<std::string> report_environment() {
  std::vector<std::string> env;
  std::string pythonpath;
  for (char** e = environ; e && *e; ++e) {
    const std::string v = *e;
    if (v.rfind("PYTHONPATH=", 0) == 0) pythonpath = v.substr(11);
    else if (v.rfind("MPLBACKEND=", 0) != 0) env.push_back(v);
  }
  const std::string py = python_dir();
  if (!py.empty()) pythonpath = py + (pythonpath.empty() ? std::string() : ":" + pythonpath);
  if (!pythonpath.empty()) env.push_back("PYTHONPATH=" + pythonpath);
  env.push_back("MPLBACKEND=Agg");
  return env;
}

/// Before a diagnosis that may take hours: whether the report can be
/// rendered at all (python3 with matplotlib and pteromys.diagnose_report).
void check_report_renderer(const std::string& dir) {
  const int rc = run_program({"/usr/bin/python3", "-c", "import matplotlib.pyplot, pteromys.diagnose_report"},
                             report_environment(), -2);
  if (rc != 0)
    throw InputError("cannot write report '" + dir + "': /usr/bin/python3 cannot import matplotlib and "
                     "pteromys.diagnose_report, which render it (scripts/setup.sh installs them); run without "
                     "--report, or fix that first");
}

/// Renders the report (HTML and PNG plots, pteromys.diagnose_report under
/// Debian's Python) into a temporary directory beside `dir` and puts it in
/// place; nothing is left behind on failure or on a signal, and an earlier
/// report is replaced in one step where the file system can exchange two
/// directories.
void write_report(const std::string& json_path, const std::string& dir, bool quiet) {
  const std::string tmp = dir + ".tmp-" + std::to_string(getpid());
  std::error_code ec;
  std::filesystem::remove_all(tmp, ec);
  register_temp_dir(tmp);
  if (mkdir(tmp.c_str(), 0777) != 0) {
    forget_temp_dir(tmp);
    throw InputError("cannot create directory '" + tmp + "'");
  }
  std::vector<std::string> args = {"/usr/bin/python3", "-m", "pteromys.diagnose_report", json_path, tmp};
  if (quiet) args.push_back("--quiet");
  const int rc = run_program(args, report_environment(), 2);
  if (rc != 0 || !exists(tmp + "/index.html")) {
    discard_temp_dir(tmp);
    const std::string how = rc < 0    ? "could not be started"
                            : rc > 128 ? "was ended by signal " + std::to_string(rc - 128)
                            : rc != 0  ? "ended with status " + std::to_string(rc) + "; its message is above"
                                       : "wrote no index.html";
    throw InputError("the report could not be rendered (python3 -m pteromys.diagnose_report " + how + ")");
  }
  if (const std::string why = report_dir_problem(dir); !why.empty()) {
    discard_temp_dir(tmp);
    throw InputError("cannot write report '" + dir + "': " + why);
  }
  if (exists(dir)) {
    // Replace an earlier report: exchange the two directories in one step,
    // then remove the old one (now at tmp)
    if (renameat2(AT_FDCWD, tmp.c_str(), AT_FDCWD, dir.c_str(), RENAME_EXCHANGE) == 0) {
      discard_temp_dir(tmp);
      return;
    }
    // a file system that cannot exchange: move the old one aside, the new
    // one in, with signals held between the two renames (a handler there
    // would leave no report at DIR), then remove the old one
    const std::string old = dir + ".old-" + std::to_string(getpid());
    sigset_t all, held;
    sigfillset(&all);
    pthread_sigmask(SIG_BLOCK, &all, &held);
    const bool aside = std::rename(dir.c_str(), old.c_str()) == 0;
    const bool in = aside && std::rename(tmp.c_str(), dir.c_str()) == 0;
    if (aside && !in) std::rename(old.c_str(), dir.c_str());  // put the earlier report back
    if (in) {
      forget_temp_dir(tmp);
      register_temp_dir(old);
    }
    pthread_sigmask(SIG_SETMASK, &held, nullptr);
    if (!in) {
      discard_temp_dir(tmp);
      throw InputError(aside ? "cannot rename '" + tmp + "' to '" + dir + "'"
                             : "cannot replace the existing report directory '" + dir + "'");
    }
    discard_temp_dir(old);
    return;
  }
  if (std::rename(tmp.c_str(), dir.c_str()) != 0) {
    discard_temp_dir(tmp);
    throw InputError("cannot rename '" + tmp + "' to '" + dir + "'");
  }
  forget_temp_dir(tmp);
}

int run_diagnose(const std::vector<std::string>& argv) {
  const std::set<std::string> valued = {"--json", "--report", "--model", "--folds", "--effects", "--alpha",
                                        "--min-shrink", "--none-tolerance", "--collinearity-limit",
                                        "--max-centres", "--insertion-tries", "--threads",
                                        "--ground-y", "--dt", "--dz", "--launch-window", "--near-ground",
                                        "--iterations", "--worst-flights", "--polish", "--launch-rotation",
                                        "--oracle", "--plausible", "--profile-min-gliders",
                                        "--profiled-candidates", "--step-alpha", "--leader-reached",
                                        "--stability", "--launch-withhold-dominance"};
  const Args a = parse_args(argv, valued,
                            {"--quiet", "--no-trim", "--no-full-fit", "--no-holdout-test", "--no-second-round",
                             "--profile", "--no-profile", "--no-glider-guard", "--no-bound-guard",
                             "--no-launch-withhold", "--no-launch-rates-confirm",
                             "--prefer-identifiable", "--carry-steps", "--no-carry-steps",
                             "--leader-start", "--no-leader-start",
                             "--heldout-steps", "--no-heldout-steps", "--heldout-fold-start", "--no-heldout-fold-start", "--zeroed-reference", "--no-zeroed-reference", "--theory-starts", "--no-theory-starts",
                             "--hold-theory", "--no-hold-theory",
                             "--escalate", "--no-escalate", "--step-per-flight", "--no-step-per-flight",
                             "--no-unstepped-refit"});
  if (a.positional.empty()) throw InputError("missing DATASET.json (see --help)");
  if (a.positional.size() > 1) throw InputError("unexpected argument '" + a.positional[1] + "'");
  if (!a.has("--json") && !a.has("--report")) throw InputError("missing --json OUT.json (see --help)");
  if (a.has("--json")) check_writable(a.get("--json"), "diagnosis");
  // "rep/" (as completion gives it) names the directory rep: the report is
  // made beside it, in rep.tmp-PID, not inside it
  const std::string report_dir = strip_slash(a.get("--report"));
  if (a.has("--report")) {
    const std::string r = report_dir;
    if (r.empty()) throw InputError("--report needs a directory");
    if (r == "/" || r == "." || r == "..")
      throw InputError("cannot write report '" + r + "': a report replaces its directory; name a new one");
    if (exists(r) && !is_dir(r))
      throw InputError("cannot write report '" + r + "': it exists and is not a directory");
    const auto p = std::filesystem::path(r).parent_path();
    const std::string parent = p.empty() ? std::string(".") : p.string();
    if (!std::filesystem::is_directory(parent))
      throw InputError("cannot write report '" + r + "': directory '" + parent + "' does not exist");
    if (const std::string why = report_dir_problem(r); !why.empty())
      throw InputError("cannot write report '" + r + "': " + why);
    // the report is made beside it and renamed into place
    if (access(parent.c_str(), W_OK | X_OK) != 0)
      throw InputError("cannot write report '" + r + "': directory '" + parent + "' is not writable");
    check_report_renderer(r);
    // The report replaces its directory as a whole: a --json inside it would
    // be deleted with the earlier report (or refused after the whole run as
    // a file that is not the report's).
    if (a.has("--json") && own_descriptor(a.get("--json")) < 0) {
      const std::string rep = resolved_path(r);
      const std::string jdir = directory_of(resolved_path(a.get("--json")));
      if (jdir == rep || jdir.rfind(rep + "/", 0) == 0)
        throw InputError("cannot write the diagnosis '" + a.get("--json") + "' inside the report's directory '" + r +
                         "': the report replaces that directory as a whole, and the result would go with it; "
                         "write it beside the report");
    }
  }

  DiagnoseOptions o;
  o.folds = a.whole("--folds", o.folds, 2, 1000);
  if (a.has("--effects")) o.effects = parse_effect_list(a.get("--effects"));
  o.trim = !a.flag("--no-trim");
  o.full_fit = !a.flag("--no-full-fit");
  o.holdout_chi2_test = !a.flag("--no-holdout-test");
  o.second_effect = !a.flag("--no-second-round");
  o.glider_guard = !a.flag("--no-glider-guard");
  o.bound_guard = !a.flag("--no-bound-guard");
  o.launch_withhold = !a.flag("--no-launch-withhold");
  o.launch_withhold_dominance = a.number("--launch-withhold-dominance", o.launch_withhold_dominance);
  if (!(o.launch_withhold_dominance >= 0) || !std::isfinite(o.launch_withhold_dominance))
    throw InputError("--launch-withhold-dominance must be a finite number >= 0 (0: always withhold)");
  o.launch_rates_confirm = !a.flag("--no-launch-rates-confirm");
  o.prefer_identifiable = a.flag("--prefer-identifiable");
  o.profile = on_off(a, "profile", o.profile);
  o.carry_steps = on_off(a, "carry-steps", o.carry_steps);
  o.leader_start = on_off(a, "leader-start", o.leader_start);
  if (a.has("--leader-reached")) {
    o.leader_reached = a.number("--leader-reached", o.leader_reached);
    if (!(o.leader_reached >= 0)) throw InputError("--leader-reached must not be negative");
  }
  o.heldout_steps = on_off(a, "heldout-steps", o.heldout_steps);
  o.heldout_fold_start = on_off(a, "heldout-fold-start", o.heldout_fold_start);
  o.zeroed_reference = on_off(a, "zeroed-reference", o.zeroed_reference);
  o.theory_starts = on_off(a, "theory-starts", o.theory_starts);
  o.hold_theory = on_off(a, "hold-theory", o.hold_theory);
  o.escalate = on_off(a, "escalate", o.escalate);
  o.step_per_flight = on_off(a, "step-per-flight", o.step_per_flight);
  o.refit_unstepped = !a.flag("--no-unstepped-refit");
  o.alpha = a.number("--alpha", o.alpha);
  if (!(o.alpha > 0 && o.alpha < 1)) throw InputError("--alpha must be in (0, 1)");
  o.min_shrink = a.number("--min-shrink", o.min_shrink);
  if (!(o.min_shrink >= 0 && o.min_shrink < 1)) throw InputError("--min-shrink must be in [0, 1)");
  o.none_tolerance = a.number("--none-tolerance", o.none_tolerance);
  if (!(o.none_tolerance >= 0) || !std::isfinite(o.none_tolerance)) throw InputError("--none-tolerance must not be negative");
  o.collinearity_limit = a.number("--collinearity-limit", o.collinearity_limit);
  if (!(o.collinearity_limit > 0 && o.collinearity_limit <= 1))
    throw InputError("--collinearity-limit must be in (0, 1] (an R-squared)");
  o.fit.max_centres = a.whole("--max-centres", o.fit.max_centres, 1, 200);
  o.fit.insertion_tries = a.whole("--insertion-tries", o.fit.insertion_tries, 1, 1000);
  o.threads = a.whole("--threads", 0, 0, 256);
  o.sim.ground_y = a.number("--ground-y", 0.0);
  if (!std::isfinite(o.sim.ground_y)) throw InputError("--ground-y must be a number");
  o.sim.dt = a.number("--dt", o.sim.dt);
  check_time_step(o.sim.dt, "--dt");
  o.sim.aero.dz = a.number("--dz", o.sim.aero.dz);
  if (!(o.sim.aero.dz > 0) || o.sim.aero.dz > 0.1) throw InputError("--dz must be in (0, 0.1] m");
  o.sim.max_iterations = a.whole("--iterations", o.sim.max_iterations, 1, 1000);
  o.launch_window_s = a.number("--launch-window", o.launch_window_s);
  o.near_ground_m = a.number("--near-ground", o.near_ground_m);
  if (!(o.launch_window_s >= 0) || !(o.near_ground_m >= 0)) throw InputError("--launch-window and --near-ground must not be negative");
  o.worst_flights = a.whole("--worst-flights", o.worst_flights, 0, 1000);
  o.polish = a.whole("--polish", o.polish, 0, 100);
  o.profile_min_gliders = a.whole("--profile-min-gliders", o.profile_min_gliders, 1, 100000);
  o.profiled_candidates = a.whole("--profiled-candidates", o.profiled_candidates, 0, 100);
  if (a.has("--step-alpha")) {
    o.step_alpha = a.number("--step-alpha", o.step_alpha);
    if (!(o.step_alpha > 0 && o.step_alpha <= 1)) throw InputError("--step-alpha must be in (0, 1]");
  }
  if (a.has("--launch-rotation"))
    o.launch_rotation_per_flight = launch_rotation_per_flight_from(a.get("--launch-rotation"), "--launch-rotation");
  if (a.has("--oracle")) o.oracle = oracle_from(a.get("--oracle"), "--oracle");
  if (a.has("--plausible")) o.plausible = plausible_from(a.get("--plausible"), "--plausible");
  if (a.has("--model")) {
    const auto m = load_model(a.get("--model"));
    if (auto rbf = std::dynamic_pointer_cast<const RbfModel>(m)) o.start = rbf;
    else if (auto fp = std::dynamic_pointer_cast<const FlatPlateModel>(m)) o.fit.prior = fp->params();
    else throw InputError("--model must be an RBF or flat-plate model file");
  } else if (auto fp = std::dynamic_pointer_cast<const FlatPlateModel>(default_model())) {
    o.fit.prior = fp->params();
  }

  // --stability N: N runs in all (the diagnosis and N - 1 re-runs at
  // slightly changed steps); checked before the dataset is read.
  const int stability = a.has("--stability") ? a.whole("--stability", 3, 2, 7) : 0;

  const std::string path = a.positional[0];
  const Dataset d = load_dataset(path);
  {
    std::vector<NamedPath> in;
    for (const auto& f : dataset_files(path, d)) in.push_back({"an input of the dataset", f});
    if (a.has("--model")) in.push_back({"the model", a.get("--model")});
    std::vector<NamedPath> out;
    if (a.has("--json")) out.push_back({"the diagnosis", a.get("--json")});
    if (a.has("--report")) out.push_back({"the report", report_dir});
    check_distinct_outputs(out, in);
  }
  const bool quiet = a.flag("--quiet");
  std::set<std::string> flown;
  for (const auto& f : d.flights) flown.insert(f.glider);
  // (fewer gliders: diagnose() refuses the dataset, and a header saying
  // "1 folds" would only stand before its message)
  const bool enough = flown.size() >= static_cast<std::size_t>(kMinDiagnosisGliders);
  if (!quiet && enough) {
    // leave-gliders-out: at most one fold per glider with flights
    const int folds = std::min<int>(o.folds, static_cast<int>(flown.size()));
    std::cerr << "pteromys diagnose: " << d.flights.size() << " flights of " << flown.size() << " gliders, "
              << o.effects.size() << " candidate effects, " << folds << " folds"
              << (folds < o.folds ? " (at most one per glider; " + std::to_string(o.folds) + " asked)" : std::string())
              << "\n";
  }
  // a value the verdict rests on, assumed: said even with --quiet, which
  // stops progress, not warnings (not before a refusal of the dataset)
  if (enough)
    for (const auto& k : d.defaulted)
      std::cerr << "pteromys diagnose: warning: " << path << " gives no " << k << "; " << defaulted_value(d, k)
                << " is assumed"
                << (k == "tracking_sigma_m" ? " (the verdicts none and unexplained are judged against it)" : "") << "\n";
  const DiagnoseCallback progress = [quiet](const DiagnoseProgress& p) {
    if (quiet) return;
    char head[64];
    std::snprintf(head, sizeof head, "[%7.1f s] (%d/%d) ", p.elapsed_s, p.step, p.steps);
    std::cerr << head << p.message << "\n";
  };
  const DiagnoseResult r = diagnose(d, o, progress);
  nlohmann::json j = diagnosis_json(r, o);
  std::optional<StabilityCheck> st;
  if (stability > 0) {
    st = check_stability(d, o, r, stability, progress);
    add_stability_json(j, *st);
  }
  j["dataset"]["path"] = path;
  j["pteromys_version"] = kVersion;
  const std::string text = j.dump(1) + "\n";
  // The result first: a report that fails (its renderer was checked before
  // the run) then leaves the complete result of a run that may have taken
  // hours, and says so.
  if (a.has("--json")) write_file_atomic(a.get("--json"), text);
  if (a.has("--report")) {
    std::string src = a.get("--json");
    std::string scratch;
    // rendered from the result file, or from a scratch copy of it (deleted
    // by the signal handlers too)
    struct stat st {};
    if (src.empty() || own_descriptor(src) >= 0 || stat(src.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) {
      scratch = temp_path_for(report_dir + ".json");
      write_file_atomic(scratch, text);
      src = scratch;
    }
    try {
      write_report(src, report_dir, quiet);
    } catch (const std::exception& e) {
      if (!scratch.empty()) discard_temp_file(scratch);
      if (!a.has("--json")) throw;
      throw InputError(std::string(e.what()) + "; the diagnosis result is in '" + a.get("--json") + "'");
    }
    if (!scratch.empty()) discard_temp_file(scratch);
  }
  if (!quiet) {
    std::cout << "verdict: " << r.verdict << "\n" << r.summary << (st ? " " + st->sentence : std::string()) << "\n";
    std::cout << "baseline: fit RMSE " << r.fit_rmse_m << " m, held-out RMSE " << r.holdout_rmse_m << " m (noise alone "
              << r.noise_rmse_m << " m); " << r.seconds << " s\n";
    for (const auto& e : r.effects)
      std::printf("  %-16s held-out %.4f m  shrink %6.1f %%  %s\n", e.name.c_str(), e.holdout_rmse_m, 100 * e.shrink,
                  e.significant ? "significant" : "");
    if (a.has("--report")) std::cout << "report: " << report_dir << "/index.html\n";
  }
  return 0;
}

const bool registered_diagnose = register_command(
    70, {"diagnose", 0, "sim-to-real gap: where the model misses, which effect explains it",
         "usage: pteromys diagnose DATASET.json --json OUT.json [--report DIR] [options]\n\n"
         "Fits the wing-element model (coefficients, launches, a build-trim error per glider)\n"
         "to tracked flights and measures it on held-out gliders (leave-gliders-out\n"
         "cross-validation); shows where the misfit lies (flight phase, glider and geometry,\n"
         "flight state, whiteness of the residuals); refits every candidate effect of the\n"
         "library -- pitch_damping, downwash, finite_span, fuselage_drag, ground_effect,\n"
         "launch_rotation, added_mass, wind, camera -- as a small parametric correction of\n"
         "the model, and tests which one explains the gap (likelihood ratio against the\n"
         "known tracking noise with Holm's correction, confirmed on held-out gliders).\n"
         "Writes the result (format pteromys-diagnosis/1: baseline, effects sorted best\n"
         "first with holdout_rmse_m, shrink, significant; verdict = an effect, none or\n"
         "unexplained) and, with --report, DIR/index.html with plots. Needs flights of at\n"
         "least 3 gliders. Progress goes to stderr. See docs/diagnosis.md.\n\n"
         "options:\n"
         "  --json OUT.json         diagnosis result\n"
         "  --report DIR            readable report (index.html and PNG plots; needs python3\n"
         "                          with matplotlib and the pteromys module)\n"
         "  --model MODEL.json      RBF model the coefficient fits start from, or a flat-plate\n"
         "                          model to use as their prior (default: the shipped flat-plate\n"
         "                          element, engine/models/default.model.json)\n"
         "  --folds K               leave-gliders-out folds (default 4)\n"
         "  --effects A,B,...       candidates to test (default: the whole library)\n"
         "  --no-trim               no build-trim error per glider\n"
         "  --alpha A               family-wise level of the likelihood-ratio tests (default 0.01)\n"
         "  --min-shrink F          held-out RMSE must fall by this fraction (default 0.05)\n"
         "  --no-holdout-test       do not require the held-out chi-square confirmation\n"
         "  --none-tolerance T      'none' when the held-out chi-square ratio is <= 1 + T\n"
         "                          (default 0.3)\n"
         "  --collinearity-limit R  an effect whose signature re-tuned coefficients reproduce to\n"
         "                          an R-squared above R cannot be told apart from them (default 0.95)\n"
         "  --max-centres N         RBF centres of the baseline fits (default 10)\n"
         "  --insertion-tries N     experimental: centres tried per insertion of the coefficient fits\n"
         "                          while they stay over twice the tracking noise (default 1)\n"
         "  --ground-y Y            dataset y of the ground [m] (default 0)\n"
         "  --launch-window S       launch phase: first S seconds tracked (default 0.25)\n"
         "  --near-ground M         near-ground phase: below M metres (default 0.3)\n"
         "  --iterations N          solver iterations per effect fit (default 8)\n"
         "  --polish N              refit the N most promising candidates jointly with the RBF\n"
         "                          centre values (default 0 = coefficients fixed); N >= the\n"
         "                          number of candidates (e.g. 9) refits all of them, each\n"
         "                          aerodynamic one from its theoretical size: slower (about\n"
         "                          4x), and what finds effects the coefficients absorb (docs)\n"
         "  --no-profile            without polish, do not also refit the (at most 3) candidates\n"
         "                          whose linearised gain with the centre values re-tuned passes\n"
         "                          the test, from that step and jointly with the centre values\n"
         "                          (the default does: it finds effects the coefficients absorb;\n"
         "                          without it faster, docs); --profile: the default, explicitly\n"
         "  --profile-min-gliders N profiled starts only in fits to at least N gliders (all\n"
         "                          gliders, a fold's training gliders; default 6): on fewer the\n"
         "                          re-tuned centre values overfit, and those fits keep them fixed\n"
         "  --profiled-candidates N at most N candidates per fit refitted from their step, the\n"
         "                          largest linearised gains first (default 3; each costs about a\n"
         "                          fixed-coefficient fit; a verdict's effect not among them on\n"
         "                          all gliders is refitted from its step there for its strength)\n"
         "  --step-alpha A          level of that screen in the folds (default 1: every\n"
         "                          candidate with a linearised gain, up to N; A = --alpha,\n"
         "                          0.01 by default: the test's level; all gliders keep --alpha):\n"
         "                          only a start, significance is decided after the fits (docs)\n"
         "  --no-carry-steps        the folds refit from their step only the candidates whose\n"
         "                          gain passes there (by default those refitted from their step\n"
         "                          on all gliders are refitted so in every fold too, whatever\n"
         "                          their gain there, and the aerodynamic correction that led\n"
         "                          there is also started at its strength there: docs);\n"
         "                          --carry-steps: the default, explicitly\n"
         "  --no-leader-start       keep the carried steps but not the leader's start (to\n"
         "                          measure the two apart: docs); --leader-start: the default\n"
         "  --leader-reached F      no leader's start in a fold whose own linearised step fitted\n"
         "                          the leader at F of its strength on all gliders or more\n"
         "                          (default 0.5; 100: always started, as before: docs)\n"
         "  --no-heldout-steps      by default a candidate the held-out gliders confirm but whose\n"
         "                          gain on all gliders was under the screen is refitted from its\n"
         "                          step there before its likelihood-ratio test (docs); with this\n"
         "                          option it is not; --heldout-steps: the default, explicitly\n"
         "  --stability N           run the diagnosis N times in all (2-7), the re-runs with the\n"
         "                          simulation step changed by 5 %, 10 %, ... either way, and say\n"
         "                          whether the verdict stayed the same (key 'stability'; the\n"
         "                          verdict is the first run's; N times as long; docs)\n"
         "  --no-heldout-fold-start by default such a refit also starts at the mean of the\n"
         "                          folds' fitted strengths, switched on in steps (docs); with\n"
         "                          this option it does not; --heldout-fold-start: the default\n"
         "  --no-zeroed-reference   by default the likelihood ratios' reference also considers\n"
         "                          each candidate's fit with its values at 0, launches refitted\n"
         "                          (docs); with this option only candidates fitted exactly at 0\n"
         "                          are; --zeroed-reference: the default, explicitly\n"
         "  --theory-starts         every aerodynamic correction also starts at its theoretical\n"
         "                          size (strength 1, reached in quarter steps) with the centre\n"
         "                          values refitted with it (experimental: docs);\n"
         "                          --no-theory-starts: without (the default)\n"
         "  --hold-theory           with theoretical-size starts, keep the strength at 1 unless\n"
         "                          the training flights reject it (experimental: docs);\n"
         "                          --no-hold-theory: free it (the default)\n"
         "  --escalate              when the search leaves a real gap unexplained, search again\n"
         "                          with theoretical-size starts (slower: docs);\n"
         "                          --no-escalate: answer after the first search\n"
         "  --step-per-flight       profiled starts for launch_rotation per flight too: from its\n"
         "                          fit the centre values take their linearised step (docs);\n"
         "                          --no-step-per-flight: without (the default)\n"
         "  --no-unstepped-refit    do not refit a candidate fitted before the baseline's step\n"
         "                          at the baseline's final centre values (the search before\n"
         "                          2026-11-30; docs)\n"
         "  --launch-rotation M     per-flight (default): every flight's own pitch rate at its\n"
         "                          first point is fitted (one value per flight); common: one\n"
         "                          rate for every flight of the session\n"
         "  --no-second-round       do not test the other candidates added to the verdict's effect\n"
         "  --no-glider-guard       let an effect be significant whose held-out shrink falls\n"
         "                          below the margin once one glider is left out and that\n"
         "                          improves fewer than 3/4 of the held-out gliders (by default\n"
         "                          such a gain, resting on one glider, is not significant; in\n"
         "                          both rounds)\n"
         "  --no-bound-guard        let an effect be significant more than half of whose held-out\n"
         "                          gain comes from folds whose fit ran to the outer tenth of its\n"
         "                          range (by default such a gain is not taken as the effect;\n"
         "                          in both rounds)\n"
         "  --no-launch-withhold    name wind or the camera even when launch rotation fits the\n"
         "                          training flights too with the rates turning one way (by\n"
         "                          default such a verdict is withheld, `unexplained`, with the\n"
         "                          effect under \"withheld\": a launch habit can imitate it;\n"
         "                          launch rotation is named instead when significant)\n"
         "  --launch-withhold-dominance K  do not withhold such a verdict when its fit to all\n"
         "                          gliders closes more than K times the share of the baseline's\n"
         "                          misfit that launch rotation's closes (default 5; 0: always\n"
         "                          withhold)\n"
         "  --no-launch-rates-confirm  hold per-flight launch rotation to the shrink margin (by\n"
         "                          default its held-out rates sharing a direction confirm it,\n"
         "                          with any held-out shrink above zero)\n"
         "  --prefer-identifiable   name a significant effect that re-tuned coefficients cannot\n"
         "                          imitate before a better one they can, unless the latter\n"
         "                          predicts the held-out gliders significantly better (paired\n"
         "                          t over gliders; experimental, off by default: docs)\n"
         "  --oracle E=V[:V2],...   validation on data whose effects are known: also predict the\n"
         "                          held-out gliders with the baseline plus these effects at these\n"
         "                          values (units of \"parameters\", e.g. wind=-1,camera=0.03:2),\n"
         "                          centre values refitted with them (\"oracle\" in the JSON)\n"
         "  --plausible E=V[:V2],.. the largest size an effect's parameters may take and still be\n"
         "                          that effect (units of \"parameters\"; inf: no limit); a fit\n"
         "                          beyond it is not significant. Default camera=0.15:10 (scale\n"
         "                          error, roll in degrees), e.g. camera=0.05:3 for a camera known\n"
         "                          to within 5 % and 3 degrees\n"
         "  --no-full-fit           skip the fit to all gliders (faster; LR tests from the folds)\n"
         "  --worst-flights N       flights shown before/after in the report (default 6)\n"
         "  --threads N             worker threads (default: all cores)\n"
         "  --dt S                  simulation step [s] (default 0.002)\n"
         "  --dz M                  wing-element spacing [m] (default 0.005)\n"
         "  --quiet                 no progress and no summary on stdout (warnings and errors\n"
         "                          are still said)\n",
         run_diagnose});

}  // namespace
}  // namespace pteromys::cli
