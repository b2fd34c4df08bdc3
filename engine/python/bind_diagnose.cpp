// Bindings: the sim-to-real diagnosis (diagnose.hpp) and its candidate effects
// (effects.hpp). The Python wrappers with keyword documentation are in
// pteromys/diagnose.py.
#include <algorithm>
#include <cmath>
#include <optional>

#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "pteromys/dataset.hpp"
#include "pteromys/diagnose.hpp"
#include "pteromys/effects.hpp"
#include "pteromys/io.hpp"
#include "pteromys/mass.hpp"

namespace pteromys::python {
namespace {

using nlohmann::json;

/// EffectValues from a dict of reported parameters: {"pitch_damping": k, ...,
/// "launch_rotation": deg/s, "wind": m/s, "camera": [scale_error, roll_deg]}.
EffectValues values_from(const py::dict& d) {
  EffectValues v;
  for (const auto& item : d) {
    const std::string name = item.first.cast<std::string>();
    const Effect e = effect_from_name(name);
    const auto& sp = effect_spec(e);
    std::vector<double> x;
    if (py::isinstance<py::list>(item.second) || py::isinstance<py::tuple>(item.second)) x = item.second.cast<std::vector<double>>();
    else x.push_back(item.second.cast<double>());
    if (x.size() != sp.parameters.size())
      throw InputError("effect '" + name + "' takes " + std::to_string(sp.parameters.size()) + " value(s)");
    for (std::size_t i = 0; i < x.size(); ++i) {
      if (!std::isfinite(x[i])) throw InputError("effect values must be finite numbers");
      v.at(e, static_cast<int>(i)) = x[i] / sp.parameters[i].to_report;
    }
  }
  return v;
}

py::dict values_to(const EffectValues& v) {
  py::dict d;
  for (Effect e : all_effects()) {
    const auto& sp = effect_spec(e);
    if (sp.parameters.size() == 1) d[sp.name.c_str()] = v.at(e, 0) * sp.parameters[0].to_report;
    else {
      py::list l;
      for (std::size_t i = 0; i < sp.parameters.size(); ++i) l.append(v.at(e, static_cast<int>(i)) * sp.parameters[i].to_report);
      d[sp.name.c_str()] = l;
    }
  }
  return d;
}

// Whether a result given as `first` holds a second search (its
// escalation.ran); a `ran` that is not true or false is refused by name.
bool escalation_ran(const json& j) {
  if (!j.contains("escalation") || !j["escalation"].is_object() || !j["escalation"].contains("ran")) return false;
  const json& ran = j["escalation"]["ran"];
  if (!ran.is_boolean()) throw InputError("first's escalation.ran is not true or false");
  return ran.get<bool>();
}

json features_json(const GliderFeatures& f) {
  json w = json::array();
  for (const auto& x : f.wings)
    w.push_back({{"area_m2", x.area}, {"span_m", x.span}, {"aspect_ratio", x.aspect_ratio},
                 {"mean_chord_m", x.mean_chord}, {"theta_deg", rad2deg(x.theta)},
                 {"quarter_chord_m", {x.quarter_chord.x, x.quarter_chord.y}},
                 {"three_quarter_chord_m", {x.three_quarter_chord.x, x.three_quarter_chord.y}},
                 {"mid_chord_m", {x.mid_chord.x, x.mid_chord.y}},
                 {"apparent_mass_m3", x.apparent_mass}, {"apparent_inertia_m5", x.apparent_inertia}});
  return {{"mass_kg", f.mass}, {"inertia_kg_m2", f.inertia}, {"cg_m", {f.cg.x, f.cg.y}}, {"wings", w},
          {"main_wing", f.main_wing}, {"trim_wing", f.trim_wing}, {"span_m", f.span},
          {"fuselage_area_m2", f.fuselage_area}, {"fuselage_length_m", f.fuselage_length},
          {"fuselage_centroid_m", {f.fuselage_centroid.x, f.fuselage_centroid.y}},
          {"main_aspect_ratio", f.main_aspect_ratio}, {"tail_aspect_ratio", f.tail_aspect_ratio},
          {"tail_arm_m", f.tail_arm}, {"tail_volume", f.tail_volume}, {"wing_loading_n_m2", f.wing_loading},
          {"fuselage_ratio", f.fuselage_ratio}};
}

DiagnoseOptions options_from(const py::dict& kw) {
  DiagnoseOptions o;
  auto num = [&](const char* k, double def) {
    if (!kw.contains(k) || kw[k].is_none()) return def;
    const py::object v = kw[k];
    // a number (numpy's too), not text or a bool that would pass for one
    auto refuse = [&]() {
      return InputError(std::string(k) + " must be a number, not " +
                        py::str(v.get_type().attr("__name__")).cast<std::string>() + " " + py::repr(v).cast<std::string>());
    };
    if (py::isinstance<py::bool_>(v) || py::isinstance<py::str>(v) || py::isinstance<py::bytes>(v)) throw refuse();
    try {
      return v.cast<double>();
    } catch (const py::cast_error&) {
      throw refuse();
    }
  };
  auto whole = [&](const char* k, int def, int lo, int hi) { return whole_number(k, num(k, def), lo, hi); };
  o.folds = whole("folds", o.folds, 2, 1000);
  if (kw.contains("effects") && !kw["effects"].is_none()) {
    o.effects.clear();
    for (const auto& n : kw["effects"].cast<std::vector<std::string>>()) o.effects.push_back(effect_from_name(n));
  }
  if (kw.contains("trim")) o.trim = kw["trim"].cast<bool>();
  if (kw.contains("full_fit")) o.full_fit = kw["full_fit"].cast<bool>();
  if (kw.contains("holdout_chi2_test")) o.holdout_chi2_test = kw["holdout_chi2_test"].cast<bool>();
  if (kw.contains("second_effect")) o.second_effect = kw["second_effect"].cast<bool>();
  if (kw.contains("glider_guard")) o.glider_guard = kw["glider_guard"].cast<bool>();
  if (kw.contains("bound_guard")) o.bound_guard = kw["bound_guard"].cast<bool>();
  if (kw.contains("launch_withhold")) o.launch_withhold = kw["launch_withhold"].cast<bool>();
  if (kw.contains("launch_withhold_dominance")) {
    o.launch_withhold_dominance = num("launch_withhold_dominance", o.launch_withhold_dominance);
    if (!(o.launch_withhold_dominance >= 0) || !std::isfinite(o.launch_withhold_dominance))
      throw InputError("launch_withhold_dominance must be a finite number >= 0 (0: always withhold)");
  }
  if (kw.contains("launch_rates_confirm")) o.launch_rates_confirm = kw["launch_rates_confirm"].cast<bool>();
  if (kw.contains("prefer_identifiable")) o.prefer_identifiable = kw["prefer_identifiable"].cast<bool>();
  if (kw.contains("carry_steps")) o.carry_steps = kw["carry_steps"].cast<bool>();
  if (kw.contains("leader_start")) o.leader_start = kw["leader_start"].cast<bool>();
  if (kw.contains("leader_reached")) {
    o.leader_reached = num("leader_reached", o.leader_reached);
    if (!(o.leader_reached >= 0)) throw InputError("leader_reached must be a number >= 0");
  }
  if (kw.contains("heldout_steps")) o.heldout_steps = kw["heldout_steps"].cast<bool>();
  if (kw.contains("heldout_fold_start")) o.heldout_fold_start = kw["heldout_fold_start"].cast<bool>();
  if (kw.contains("zeroed_reference")) o.zeroed_reference = kw["zeroed_reference"].cast<bool>();
  if (kw.contains("theory_starts")) o.theory_starts = kw["theory_starts"].cast<bool>();
  if (kw.contains("hold_theory")) o.hold_theory = kw["hold_theory"].cast<bool>();
  if (kw.contains("escalate")) o.escalate = kw["escalate"].cast<bool>();
  if (kw.contains("step_per_flight")) o.step_per_flight = kw["step_per_flight"].cast<bool>();
  if (kw.contains("refit_unstepped")) o.refit_unstepped = kw["refit_unstepped"].cast<bool>();
  if (kw.contains("profile")) o.profile = kw["profile"].cast<bool>();
  o.alpha = num("alpha", o.alpha);
  o.min_shrink = num("min_shrink", o.min_shrink);
  o.none_tolerance = num("none_tolerance", o.none_tolerance);
  o.collinearity_limit = num("collinearity_limit", o.collinearity_limit);
  o.fit.max_centres = whole("max_centres", o.fit.max_centres, 1, 200);
  o.fit.insertion_tries = whole("insertion_tries", o.fit.insertion_tries, 1, 1000);
  o.polish = whole("polish", o.polish, 0, 100);
  o.profile_min_gliders = whole("profile_min_gliders", o.profile_min_gliders, 1, 100000);
  o.profiled_candidates = whole("profiled_candidates", o.profiled_candidates, 0, 100);
  if (kw.contains("step_alpha")) {
    o.step_alpha = num("step_alpha", o.step_alpha);
    if (!(o.step_alpha > 0 && o.step_alpha <= 1)) throw InputError("step_alpha must be in (0, 1]");
  }
  if (kw.contains("launch_rotation"))
    o.launch_rotation_per_flight =
        launch_rotation_per_flight_from(kw["launch_rotation"].cast<std::string>(), "launch_rotation");
  if (kw.contains("oracle") && !kw["oracle"].is_none()) o.oracle = oracle_from(kw["oracle"].cast<std::string>(), "oracle");
  if (kw.contains("plausible") && !kw["plausible"].is_none())
    o.plausible = plausible_from(kw["plausible"].cast<std::string>(), "plausible");
  o.threads = whole("threads", 0, 0, 256);
  o.sim.ground_y = num("ground_y", 0.0);
  if (!std::isfinite(o.sim.ground_y)) throw InputError("ground_y must be a finite number (m)");
  if (!(o.collinearity_limit > 0 && o.collinearity_limit <= 1))
    throw InputError("collinearity_limit must be in (0, 1] (an R-squared)");
  o.sim.dt = num("dt", o.sim.dt);
  o.sim.aero.dz = element_spacing(num("dz", o.sim.aero.dz));
  o.sim.max_iterations = whole("iterations", o.sim.max_iterations, 1, 1000);
  o.launch_window_s = num("launch_window_s", o.launch_window_s);
  o.near_ground_m = num("near_ground_m", o.near_ground_m);
  o.worst_flights = whole("worst_flights", o.worst_flights, 0, 1000);
  time_step(o.sim.dt);
  if (kw.contains("model") && !kw["model"].is_none()) {
    const ModelPtr m = to_model(kw["model"]);
    if (auto rbf = std::dynamic_pointer_cast<const RbfModel>(m)) o.start = rbf;
    else if (auto fp = std::dynamic_pointer_cast<const FlatPlateModel>(m)) o.fit.prior = fp->params();
    else throw InputError("model must be an RBF or flat-plate model");
  } else if (auto fp = std::dynamic_pointer_cast<const FlatPlateModel>(default_model())) {
    o.fit.prior = fp->params();
  }
  return o;
}

void bind_diagnose(py::module_& m) {
  m.def("_effect_specs", []() {
    json out = json::array();
    for (Effect e : all_effects()) {
      const auto& s = effect_spec(e);
      json p = json::array();
      for (const auto& x : s.parameters)
        p.push_back({{"name", x.name}, {"scale", x.scale * x.to_report}, {"lower", x.lower * x.to_report},
                     {"upper", x.upper * x.to_report}});
      const char* lv[] = {"aerodynamic", "launch", "session", "observation"};
      out.push_back({{"name", s.name}, {"description", s.description}, {"level", lv[static_cast<int>(s.level)]},
                     {"parameters", p}});
    }
    return out.dump();
  });

  m.def("_glider_features", [](const py::object& go, double dz) {
    const Glider g = to_glider(go);
    validate(g);
    return features_json(glider_features(g, dz)).dump();
  }, py::arg("glider"), py::arg("dz") = 0.005);

  m.def("_effect_wrench", [](const py::object& go, const py::object& model, const py::dict& values,
                             const py::dict& state, double height_origin, double dz) {
    const Glider g = to_glider(go);
    validate(g);
    AeroOptions ao;
    ao.dz = element_spacing(dz);
    const ModelPtr mp = to_model(model);
    const MountedGlider mg = mount(g, mp, {}, ao);
    const GliderFeatures f = glider_features(g, dz);
    const EffectAero ea(mg, f, values_from(values), height_origin);
    auto get = [&](const char* k, double def) { return state.contains(k) ? state[k].cast<double>() : def; };
    FlightState s;
    s.p = {get("x_m", 0), get("y_m", 1.5)};
    s.v = {get("vx_m_s", 8), get("vy_m_s", 0)};
    s.beta = deg2rad(get("pitch_deg", 0));
    s.omega = deg2rad(get("pitch_rate_deg_s", 0));
    const Wrench w = ea.evaluate(s);
    const AddedMass am = ea.added_mass(s);
    py::dict out;
    out["force_n"] = py::make_tuple(w.force.x, w.force.y);
    out["moment_n_m"] = w.moment;
    out["max_alpha_deg"] = rad2deg(ea.max_alpha(s));
    py::list M, bias;
    for (int i = 0; i < 3; ++i) {
      M.append(py::make_tuple(am.m[i][0], am.m[i][1], am.m[i][2]));
      bias.append(am.bias[i]);
    }
    out["added_mass"] = M;
    out["added_mass_bias"] = bias;
    py::list flows;
    for (const auto& x : ea.wing_flows(s)) {
      py::dict d;
      d["speed_m_s"] = x.speed;
      d["alpha_deg"] = rad2deg(x.alpha);
      d["cl"] = x.cl;
      flows.append(d);
    }
    out["wings"] = flows;
    return out;
  }, py::arg("glider"), py::arg("model"), py::arg("values"), py::arg("state"), py::arg("height_origin") = 0.0,
     py::arg("dz") = 0.005);

  m.def("_diagnosis_fit", [](const std::string& dataset, const py::object& model, const py::dict& values,
                             const std::vector<std::string>& free_names, const py::object& flights, bool warm_baseline,
                             double dt, double iterations, double threads) {
    DiagFitOptions fo;
    fo.dt = time_step(dt);
    fo.threads = whole_number("threads", threads, 0, 256);  // the bounds of diagnose()
    fo.max_iterations = whole_number("iterations", iterations, 1, 1000);
    const Dataset d = load_dataset(dataset);
    const DiagnosisData D(d, fo);
    std::vector<int> fl;
    if (flights.is_none()) {
      for (std::size_t i = 0; i < d.flights.size(); ++i) fl.push_back(static_cast<int>(i));
    } else {
      const auto names = flights.cast<std::vector<std::string>>();
      for (const auto& n : names) {
        int k = -1;
        for (std::size_t i = 0; i < d.flights.size(); ++i)
          if (d.flights[i].name == n) k = static_cast<int>(i);
        if (k < 0) throw InputError("unknown flight '" + n + "'");
        fl.push_back(k);
      }
    }
    DiagModel start{to_model(model), values_from(values), {}};
    std::vector<FreeParam> free;
    for (const auto& n : free_names) {
      if (n == "trim") {
        std::set<int> gs;
        for (int f : fl) gs.insert(D.glider_of(f));
        for (int g : gs)
          if (D.gliders()[g].features.trim_wing >= 0) free.push_back(FreeParam::trim(g));
      } else if (n == "coefficients") {
        auto rbf = std::dynamic_pointer_cast<const RbfModel>(start.coefficients);
        if (!rbf) throw InputError("'coefficients' needs an RBF model");
        for (std::size_t k = 0; k < 3 * rbf->centres().size(); ++k) free.push_back(FreeParam::coefficient(static_cast<int>(k)));
      } else {
        const Effect e = effect_from_name(n);
        for (std::size_t i = 0; i < effect_spec(e).parameters.size(); ++i)
          free.push_back(FreeParam::effect_param(e, static_cast<int>(i)));
      }
    }
    FitOutcome r;
    {
      py::gil_scoped_release nogil;
      if (warm_baseline) {
        const FitOutcome b = D.fit({start.coefficients, {}, {}}, fl, {});
        std::vector<LaunchParams> L;
        for (const auto& x : b.flights) L.push_back(x.launch);
        r = D.fit(start, fl, free, &L);
      } else {
        r = D.fit(start, fl, free);
      }
    }
    py::dict out;
    out["sse_m2"] = r.sse;
    out["rmse_m"] = r.rmse();
    out["points"] = r.points;
    out["iterations"] = r.iterations;
    out["simulations"] = r.simulations;
    out["effects"] = values_to(r.model.effects);
    py::dict trims;
    for (std::size_t g = 0; g < D.gliders().size() && g < r.model.trim.size(); ++g)
      trims[D.gliders()[g].key.c_str()] = rad2deg(r.model.trim[g]);
    out["trim_deg"] = trims;
    py::list pf;
    for (const auto& x : r.flights) {
      py::dict f;
      f["flight"] = d.flights[x.flight].name;
      f["sse_m2"] = x.sse;
      f["points"] = static_cast<int>(x.residual.size());
      py::list res;
      for (const auto& v : x.residual) res.append(py::make_tuple(v.x, v.y));
      f["residual_m"] = res;
      pf.append(f);
    }
    out["flights"] = pf;
    out["model"] = mut(r.model.coefficients);
    return out;
  }, py::arg("dataset"), py::arg("model"), py::arg("values"), py::arg("free"), py::arg("flights") = py::none(),
     py::arg("warm_baseline") = true, py::arg("dt") = 0.002, py::arg("iterations") = 8, py::arg("threads") = 0);

  m.def("_diagnose", [](const std::string& dataset, const py::dict& kw, const py::object& progress) {
    const Dataset d = load_dataset(dataset);
    const DiagnoseOptions o = options_from(kw);
    // Every progress report also lets Python handle its signals: Ctrl-C
    // (KeyboardInterrupt) stops the engine there, as an exception raised by
    // `progress` does, instead of after the whole diagnosis.
    const DiagnoseCallback cb = [progress](const DiagnoseProgress& p) {
        py::gil_scoped_acquire gil;
        if (PyErr_CheckSignals() != 0) throw py::error_already_set();
        if (progress.is_none()) return;
        py::dict x;
        x["stage"] = p.stage;
        x["step"] = p.step;
        x["steps"] = p.steps;
        x["elapsed_s"] = p.elapsed_s;
        x["message"] = p.message;
        progress(x);
      };
    // stability: runs in all of a stability check (0: none; 2-7).
    int stability = 0;
    if (kw.contains("stability") && !kw["stability"].is_none()) {
      const double v = kw["stability"].cast<double>();
      if (v != 0 && (v != std::floor(v) || v < 2 || v > 7))
        throw InputError("stability must be 0 (no check) or a whole number between 2 and 7");
      stability = static_cast<int>(v);
    }
    // first: a result of this dataset made before (its JSON text); with
    // stability it stands for the first run, so only the re-runs are made
    // (the FreeCAD command's check after a named verdict); with
    // theory_starts it is the first search whose `unexplained` this second
    // search follows (the command's second search), which is then concluded
    // as diagnose() with escalate concludes its own (conclude_second_search).
    if (kw.contains("first") && !kw["first"].is_none()) {
      if (stability == 0 && !o.theory_starts)
        throw InputError("first is a result to check for stability (it needs stability 2 to 7) or the first search "
                         "before a second one (it needs theory_starts)");
      json j;
      try {
        j = json::parse(kw["first"].cast<std::string>());
      } catch (const std::exception&) {
        throw InputError("first is not a diagnosis result (not JSON)");
      }
      if (!j.is_object() || j.value("format", "") != "pteromys-diagnosis/1" || !j.contains("verdict") ||
          !j["verdict"].is_string() || !j.contains("effects") || !j["effects"].is_array())
        throw InputError("first is not a diagnosis result (format pteromys-diagnosis/1 with a verdict and effects)");
      if (stability > 0 && j.contains("stability")) throw InputError("first already holds a stability check");
      const std::string path = j.contains("dataset") && j["dataset"].is_object() ? j["dataset"].value("path", "") : "";
      if (path != dataset)
        throw InputError("first is a result of another dataset ('" + path + "', not '" + dataset + "')");
      const double first_s =
          j.contains("timings") && j["timings"].is_object() ? j["timings"].value("total_s", 0.0) : 0.0;
      if (stability == 0) {
        if (j["verdict"] != "unexplained")
          throw InputError("first must be an `unexplained` result for a second search (its verdict is '" +
                           j["verdict"].get<std::string>() + "')");
        if (escalation_ran(j))
          throw InputError("first already holds a second search");
        const json* base = j.contains("baseline") && j["baseline"].is_object() && j["baseline"].contains("holdout_rmse_m")
                               ? &j["baseline"]["holdout_rmse_m"] : nullptr;
        if (!base || !base->is_number() || !(base->get<double>() > 0))
          throw InputError("first has no baseline.holdout_rmse_m (a positive number) to measure the second search against");
        if (j.contains("summary") && !j["summary"].is_string()) throw InputError("first's summary is not text");
        // The searches diagnose() with escalate would not follow: a
        // withheld verdict (a candidate closes the gap; the launches are in
        // question), a first search that already had theoretical-size
        // starts, a second search without the profiled starts they need.
        if (j.contains("withheld") && !j["withheld"].is_null())
          throw InputError("first's verdict was withheld from a candidate that closes the gap (withheld): a second "
                           "search does not follow it");
        if (!o.profile) throw InputError("a second search needs profiled starts (profile)");
        // Its baseline is comparable only if it was made as this search is,
        // but for the theoretical-size starts.
        if (!j.contains("options") || !j["options"].is_object())
          throw InputError("first has no options to compare with this second search's");
        if (j["options"].value("theory_starts", false))
          throw InputError("first was itself made with theory_starts: it is not a first search");
        const json here = diagnosis_options_json(o);
        // dz_m, iterations and model are recorded since 2026-12-07; a first
        // result written before lacks them. It is taken as made with their
        // defaults (the runs archived in bench/diagnosis were) when this
        // search uses the defaults too, and refused otherwise.
        const json defaults = diagnosis_options_json(options_from(py::dict()));
        std::string differ;
        for (const auto& [key, value] : here.items()) {
          if (key == "theory_starts" || key == "escalate") continue;
          if (!j["options"].contains(key) && (key == "dz_m" || key == "iterations" || key == "model") &&
              value == defaults[key])
            continue;
          const json there = j["options"].contains(key) ? j["options"][key] : json();
          if (there != value)
            differ += (differ.empty() ? "" : "; ") + key + " " + (there.is_null() ? "missing" : there.dump()) +
                      " there, " + value.dump() + " here";
        }
        std::vector<std::string> names_here, names_there;
        for (Effect E : o.effects) names_here.push_back(effect_name(E));
        for (const auto& e : j["effects"])
          if (e.is_object() && e.contains("name") && e["name"].is_string()) names_there.push_back(e["name"]);
        std::sort(names_here.begin(), names_here.end());
        std::sort(names_there.begin(), names_there.end());
        if (names_here != names_there) differ += std::string(differ.empty() ? "" : "; ") + "other candidate effects";
        if (!differ.empty())
          throw InputError("first was made with other options than this second search (" + differ +
                           "): its baseline cannot be compared with this search's");
        std::string first_best;
        double first_best_shrink = 0;
        if (!j["effects"].empty() && j["effects"][0].is_object()) {
          first_best = j["effects"][0].value("name", "");
          const json& sh = j["effects"][0].contains("shrink") ? j["effects"][0]["shrink"] : json();
          first_best_shrink = sh.is_number() ? sh.get<double>() : 0.0;
        }
        // The second search's "done" is held back until it is concluded.
        std::optional<DiagnoseProgress> done;
        DiagnoseCallback held;
        if (cb)
          held = [&](const DiagnoseProgress& p) {
            if (p.stage == "done") done = p;
            else cb(p);
          };
        DiagnoseResult r;
        std::string fell;
        {
          py::gil_scoped_release nogil;
          r = diagnose(d, o, held);
          fell = conclude_second_search(r, "unexplained", first_best, first_best_shrink, first_s,
                                        base->get<double>(), o);
        }
        json out;
        if (fell.empty()) {
          out = diagnosis_json(r, o);
          out["dataset"]["path"] = dataset;
        } else {
          // the first result stands; its pointer to a second search is
          // answered
          out = j;
          out["escalation"] = diagnosis_json(r, o)["escalation"];
          out["summary"] = summary_after_second_search(j.value("summary", std::string()), fell);
          if (!out.contains("timings") || !out["timings"].is_object()) out["timings"] = json::object();
        }
        // both searches, as diagnose() with escalate times them
        out["timings"]["first_search_s"] = first_s;
        out["timings"]["second_search_s"] = r.seconds;
        out["timings"]["total_s"] = first_s + r.seconds;
        if (cb) {
          DiagnoseProgress p = done ? *done : DiagnoseProgress{};
          p.stage = "done";
          p.message = out["verdict"].get<std::string>() + ": " + out["summary"].get<std::string>();
          cb(p);
        }
        return out.dump();
      }
      DiagnoseResult r;
      r.verdict = j["verdict"].get<std::string>();
      r.seconds = j.contains("timings") && j["timings"].is_object() ? j["timings"].value("total_s", 0.0) : 0.0;
      // a result of a second search is re-run with both searches
      // (stability_rerun_options)
      r.escalation.ran = escalation_ran(j);
      for (const auto& e : j["effects"]) {
        if (!e.is_object() || !e.contains("name") || !e.contains("shrink")) continue;
        EffectResult er;
        er.name = e["name"].get<std::string>();
        er.shrink = e["shrink"].get<double>();
        r.effects.push_back(er);
      }
      StabilityCheck st;
      {
        py::gil_scoped_release nogil;
        st = check_stability(d, o, r, stability, cb);
      }
      add_stability_json(j, st);
      return j.dump();
    }
    DiagnoseResult r;
    std::optional<StabilityCheck> st;
    {
      py::gil_scoped_release nogil;
      r = diagnose(d, o, cb);
      if (stability > 0) st = check_stability(d, o, r, stability, cb);
    }
    json j = diagnosis_json(r, o);
    if (st) add_stability_json(j, *st);
    j["dataset"]["path"] = dataset;
    return j.dump();
  }, py::arg("dataset"), py::arg("options"), py::arg("progress") = py::none());

  m.def("report_dir_problem", &report_dir_problem, py::arg("dir"),
        "Why directory `dir` may not be replaced by a diagnosis report, or '' when it may (it does not exist, is "
        "empty, or is an earlier report: index.html with only report.md, diagnosis.json and PNG plots beside it).");
  m.def("_chi2_sf", &chi2_sf, py::arg("x"), py::arg("k"));
  m.def("_chi2_isf", &chi2_isf, py::arg("p"), py::arg("k"));
}

const bool registered = register_binder(70, bind_diagnose);

}  // namespace
}  // namespace pteromys::python
