// pteromys fit: aerodynamic coefficients from tracked flights (paper section 5.2).
#include <chrono>
#include <cstdio>
#include <ctime>
#include <iostream>
#include <sstream>

#include "commands.hpp"
#include "common.hpp"
#include "pteromys/dataset.hpp"
#include "pteromys/fit.hpp"
#include "pteromys/version.hpp"

namespace pteromys::cli {
namespace {

double nonneg(const Args& a, const std::string& key, double def) {
  const double v = a.number(key, def);
  if (!(v >= 0)) throw InputError(key + " must not be negative");
  return v;
}

std::string utc_now() {
  const std::time_t t = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return buf;
}

nlohmann::json prediction_summary(const std::vector<FlightPrediction>& p) {
  return {{"rmse_m", predictions_rmse(p)}, {"rmse_after_m", predictions_rmse(p, true)}};
}

int run_fit(const std::vector<std::string>& argv) {
  const std::set<std::string> valued = {"-o", "--json", "--max-centres", "--model", "--launch-points",
                                        "--min-improvement", "--rounds", "--iterations", "--robust",
                                        "--regularisation", "--candidates", "--insertion-tries", "--holdout", "--threads", "--stop",
                                        "--dz", "--dt", "--integrator", "--note"};
  const Args a = parse_args(argv, valued, {"--quiet", "--no-prior", "--fit-pitch-rate"});
  if (a.positional.empty()) throw InputError("missing DATASET.json (see --help)");
  if (a.positional.size() > 1) throw InputError("unexpected argument '" + a.positional[1] + "'");
  if (!a.has("-o")) throw InputError("missing -o MODEL.json (see --help)");
  check_writable(a.get("-o"), "model");
  if (a.has("--json")) check_writable(a.get("--json"), "report");

  FitOptions opt;
  opt.max_centres = a.whole("--max-centres", opt.max_centres, 1, 200);
  opt.launch.points = a.whole("--launch-points", opt.launch.points, 0, 100000);
  if (opt.launch.points > 0 && opt.launch.points < 3)
    throw InputError("--launch-points must be 0 (all points) or at least 3");
  opt.launch.fit_pitch_rate = a.flag("--fit-pitch-rate");
  opt.min_improvement = nonneg(a, "--min-improvement", opt.min_improvement);
  if (opt.min_improvement >= 1) throw InputError("--min-improvement is a fraction below 1");
  const std::string stop = a.get("--stop", "bic");
  if (stop == "none") {
    if (a.has("--min-improvement")) throw InputError("--stop none keeps every centre; drop --min-improvement");
    opt.information_criterion = false;
    opt.min_improvement = 0;
  } else if (stop != "bic") {
    throw InputError("--stop must be bic or none, got '" + stop + "'");
  }
  opt.max_rounds = a.whole("--rounds", opt.max_rounds, 1, 100);
  opt.max_iterations = a.whole("--iterations", opt.max_iterations, 1, 10000);
  opt.robust_m = nonneg(a, "--robust", opt.robust_m);
  opt.regularisation_m = nonneg(a, "--regularisation", opt.regularisation_m);
  opt.candidates = a.whole("--candidates", opt.candidates, 1, 1000);
  opt.insertion_tries = a.whole("--insertion-tries", opt.insertion_tries, 1, 1000);
  opt.threads = a.whole("--threads", 0, 0, 256);
  opt.aero.dz = a.number("--dz", opt.aero.dz);
  if (!(opt.aero.dz > 0) || opt.aero.dz > 0.1) throw InputError("--dz must be in (0, 0.1] m");
  opt.launch.track.sim.dt = a.number("--dt", opt.launch.track.sim.dt);
  check_time_step(opt.launch.track.sim.dt, "--dt");
  const std::string integ = a.get("--integrator", "verlet");
  if (integ == "verlet") opt.launch.track.sim.integrator = Integrator::Verlet;
  else if (integ == "rk4") opt.launch.track.sim.integrator = Integrator::RK4;
  else throw InputError("--integrator must be verlet or rk4, got '" + integ + "'");
  opt.use_prior = !a.flag("--no-prior");
  if (a.has("--model")) {
    const auto m = load_model(a.get("--model"));
    if (auto rbf = std::dynamic_pointer_cast<const RbfModel>(m)) {
      if (!opt.use_prior && rbf->prior())
        throw InputError("--no-prior conflicts with the start model '" + a.get("--model") + "', which has a prior");
      opt.start = rbf;
    } else if (auto fp = std::dynamic_pointer_cast<const FlatPlateModel>(m)) {
      opt.prior = fp->params();
    } else {
      throw InputError("--model must be an RBF or flat-plate model file");
    }
  }

  const std::string dataset_path = a.positional[0];
  const Dataset d = load_dataset(dataset_path);
  Dataset holdout;
  const bool has_holdout = a.has("--holdout");
  if (has_holdout) holdout = load_dataset(a.get("--holdout"));
  {
    std::vector<NamedPath> in;
    for (const auto& f : dataset_files(dataset_path, d)) in.push_back({"an input of the dataset", f});
    if (has_holdout)
      for (const auto& f : dataset_files(a.get("--holdout"), holdout)) in.push_back({"an input of --holdout", f});
    if (a.has("--model")) in.push_back({"the start model", a.get("--model")});
    std::vector<NamedPath> out{{"the model", a.get("-o")}};
    if (a.has("--json")) out.push_back({"the report", a.get("--json")});
    check_distinct_outputs(out, in);
  }

  const bool quiet = a.flag("--quiet");
  if (!quiet)
    std::cerr << "pteromys fit: " << d.flights.size() << " flights of " << d.gliders.size() << " gliders, up to "
              << opt.max_centres << " centres\n";
  const FitCallback progress = [quiet](const FitProgress& p) {
    if (quiet) return;
    char head[32];
    std::snprintf(head, sizeof head, "[%7.1f s] ", p.elapsed_s);
    std::cerr << head << p.message << "\n";
  };
  const FitResult r = fit_coefficients(d, opt, progress);

  nlohmann::json report = fit_report_json(r, opt);
  report["dataset"] = dataset_path;
  report["model_file"] = a.get("-o");
  report["pteromys_version"] = kVersion;
  if (has_holdout) {
    // Held-out flights (paper Fig. 13): launches fitted to the first 10
    // points, as the paper, and to all points; the rest predicted.
    if (!quiet) std::cerr << "pteromys fit: predicting " << holdout.flights.size() << " held-out flights\n";
    nlohmann::json h;
    h["dataset"] = a.get("--holdout");
    h["flights"] = holdout.flights.size();
    const std::shared_ptr<const CoefficientModel> flat = r.model->prior()
        ? std::static_pointer_cast<const CoefficientModel>(r.model->prior())
        : std::make_shared<FlatPlateModel>(opt.prior);
    for (int m : {10, 0}) {
      FitOptions po = opt;
      po.launch.points = m;
      const auto fitted = predict_flights(holdout, r.model, po);
      const auto fp = predict_flights(holdout, flat, po);
      const auto bal = predict_flights(holdout, nullptr, po);
      nlohmann::json k = {{"launch_points", m == 0 ? nlohmann::json("all") : nlohmann::json(m)},
                          {"fitted", prediction_summary(fitted)},
                          {"flat_plate", prediction_summary(fp)},
                          {"ballistic", prediction_summary(bal)}};
      k["per_flight"] = nlohmann::json::array();
      for (std::size_t i = 0; i < fitted.size(); ++i)
        k["per_flight"].push_back({{"flight", fitted[i].flight},
                                   {"glider", fitted[i].glider},
                                   {"fitted_rmse_m", fitted[i].rmse_m},
                                   {"flat_plate_rmse_m", fp[i].rmse_m},
                                   {"ballistic_rmse_m", bal[i].rmse_m}});
      h[m == 0 ? "launch_all_points" : "launch_first_10"] = k;
      if (m == 10) report["holdout_rmse_m"] = predictions_rmse(fitted);
    }
    report["holdout"] = h;
  }

  nlohmann::json model = model_to_json(*r.model);
  std::ostringstream cmd;
  cmd << "pteromys fit";
  for (const auto& s : argv) cmd << " " << s;
  model["provenance"] = {{"dataset", dataset_path},
                         {"command", cmd.str()},
                         {"pteromys_version", kVersion},
                         {"created_utc", utc_now()},
                         {"fit_rmse_m", r.rmse_m},
                         {"prior_rmse_m", r.prior_rmse_m},
                         {"centres", r.model->centres().size()},
                         {"flights", r.flights.size()},
                         {"points", r.points}};
  if (a.has("--note")) model["provenance"]["note"] = a.get("--note");
  // the model and its report together: a report that cannot be written
  // (a full disk) leaves no new model either
  std::vector<std::pair<std::string, std::string>> outputs{{a.get("-o"), model.dump(2) + "\n"}};
  if (a.has("--json")) outputs.emplace_back(a.get("--json"), report.dump(2) + "\n");
  write_files_together(outputs);
  if (!quiet) {
    std::cout << "fitted " << r.model->centres().size() << " centres to " << r.flights.size() << " flights ("
              << r.points << " points): RMSE " << r.rmse_m << " m (flat-plate prior " << r.prior_rmse_m << " m) in "
              << r.seconds << " s\n";
    if (report.contains("holdout_rmse_m"))
      std::cout << "held-out flights: RMSE " << report["holdout_rmse_m"].get<double>() << " m\n";
  }
  return 0;
}

const bool registered_fit = register_command(60,
      {"fit", 0, "aerodynamic coefficients (RBF model) fitted to tracked flights",
       "usage: pteromys fit DATASET.json -o MODEL.json [--json REPORT.json] [options]\n\n"
       "Learns the coefficients of the wing elements from tracked flights (paper section\n"
       "5.2): the launch of every flight (eq. 5) and the coefficient values at the RBF\n"
       "centres (eq. 6) are fitted together; centres are added one at a time where the\n"
       "error is largest (greedy, Bickel et al. 2009) until the error stops falling.\n"
       "Progress goes to stderr. Writes the model (format pteromys-model/1, with a\n"
       "provenance object) and, with --json, the report (format pteromys-fit/1:\n"
       "fit_rmse_m, centres, flights, history, per_flight, timings). See docs/fitting.md.\n\n"
       "options:\n"
       "  -o MODEL.json          fitted model (required)\n"
       "  --json REPORT.json     fit report\n"
       "  --max-centres N        most RBF centres (default 10, as the paper)\n"
       "  --model START.json     an RBF model to continue from, or a flat-plate model to\n"
       "                         use as the prior (default: the built-in flat-plate element)\n"
       "  --no-prior             plain RBF as in the paper (no flat-plate fallback)\n"
       "  --launch-points M      fit each launch to the first M points (default 0 = all;\n"
       "                         the paper uses 10)\n"
       "  --fit-pitch-rate       also fit the pitch rate at the first point\n"
       "  --stop RULE            bic (default): keep a new centre only if it lowers the\n"
       "                         Bayesian information criterion, i.e. the error falls by more\n"
       "                         than three more parameters would fit noise; none: always\n"
       "                         go on to --max-centres (the paper's fixed count)\n"
       "  --min-improvement F    also require the RMSE to fall by this fraction (default 0)\n"
       "  --rounds N             launch/coefficient alternations per centre count (default 3)\n"
       "  --iterations N         solver iterations per coefficient fit (default 12)\n"
       "  --candidates N         candidate centres scored per insertion (default 24)\n"
       "  --insertion-tries N    experimental: where the best-scored centre is dropped while the fit\n"
       "                         is over twice the tracking noise, try the next-best ones, N in all\n"
       "                         (default 1: the greedy rule)\n"
       "  --robust M             Huber threshold on a point's distance [m] (default 0.3; 0 = off)\n"
       "  --regularisation M     pull of the values toward the prior [m] (default 0.01)\n"
       "  --holdout DATASET.json predict these flights with the fitted model, the flat-plate\n"
       "                         element and ballistic motion; adds holdout to the report\n"
       "  --threads N            worker threads (default: all cores)\n"
       "  --note TEXT            stored in the model's provenance\n"
       "  --quiet                no progress\n"
       "  --dz M                 spacing of the wing-element cut lines [m] (default 0.005)\n"
       "  --dt S                 simulation time step [s] (default 0.002)\n"
       "  --integrator NAME      verlet (default) or rk4\n",
       run_fit});

}  // namespace
}  // namespace pteromys::cli
