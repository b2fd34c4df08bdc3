// Bindings: coefficient fitting from tracked flights (fit.hpp). The Python
// wrappers with keyword documentation are in pteromys/fit.py.
#include <cmath>

#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "pteromys/dataset.hpp"
#include "pteromys/fit.hpp"
#include "pteromys/io.hpp"
#include "pteromys/mass.hpp"

namespace pteromys::python {
namespace {

using nlohmann::json;

json launch_to_json(const LaunchParams& p) {
  return {{"t_s", p.t},
          {"x_m", p.x},
          {"y_m", p.y},
          {"speed_m_s", p.speed},
          {"climb_deg", rad2deg(p.climb)},
          {"pitch_deg", rad2deg(p.pitch)},
          {"pitch_rate_deg_s", rad2deg(p.pitch_rate)}};
}

LaunchParams launch_from_dict(const py::dict& d) {
  auto get = [&](const char* k, double def) { return d.contains(k) ? d[k].cast<double>() : def; };
  for (const char* k : {"t_s", "x_m", "y_m", "speed_m_s", "climb_deg", "pitch_deg"})
    if (!d.contains(k)) throw InputError(std::string("launch needs key '") + k + "'");
  LaunchParams p;
  p.t = get("t_s", 0);
  p.x = get("x_m", 0);
  p.y = get("y_m", 0);
  p.speed = get("speed_m_s", 0);
  p.climb = deg2rad(get("climb_deg", 0));
  p.pitch = deg2rad(get("pitch_deg", 0));
  p.pitch_rate = deg2rad(get("pitch_rate_deg_s", 0));
  for (double v : {p.t, p.x, p.y, p.speed, p.climb, p.pitch, p.pitch_rate})
    if (!std::isfinite(v)) throw InputError("launch values must be finite numbers");
  return p;
}

std::vector<double> vec(const py::object& o, const char* what) {
  auto a = py::module_::import("numpy").attr("asarray")(o, "float64").cast<py::array_t<double>>();
  if (a.ndim() != 1) throw InputError(std::string(what) + " must be a 1-D array");
  std::vector<double> v(a.data(), a.data() + a.size());
  for (double x : v)
    if (!std::isfinite(x)) throw InputError(std::string(what) + " contains NaN or infinite values");
  return v;
}

std::vector<TrackedPoint> points_of(const py::object& t, const py::object& x, const py::object& y) {
  const auto T = vec(t, "t"), X = vec(x, "x"), Y = vec(y, "y");
  if (T.size() != X.size() || T.size() != Y.size()) throw InputError("t, x and y must have the same length");
  std::vector<TrackedPoint> p;
  for (std::size_t i = 0; i < T.size(); ++i) {
    if (i && !(T[i] > T[i - 1])) throw InputError("times must increase");
    p.push_back({T[i], X[i], Y[i]});
  }
  return p;
}

py::array_t<double> xy_array(const std::vector<Vec2>& v) {
  py::array_t<double> a({static_cast<py::ssize_t>(v.size()), static_cast<py::ssize_t>(2)});
  auto r = a.mutable_unchecked<2>();
  for (std::size_t i = 0; i < v.size(); ++i) {
    r(i, 0) = v[i].x;
    r(i, 1) = v[i].y;
  }
  return a;
}

/// Aero of a glider: the quasi-static model, or none (ballistic).
struct AeroOf {
  std::unique_ptr<MountedGlider> mg;
  std::unique_ptr<QuasiStaticAero> qa;
  NoAero none;
  RigidBody body;
  const AeroForces& get() const { return qa ? static_cast<const AeroForces&>(*qa) : none; }
};

// M of eq. 5 from a Python keyword, as --launch-points takes it (fit and
// predict_flights).
int launch_points(double v) {
  const int m = whole_number("launch_points", v, 0, 100000);
  if (m > 0 && m < 3) throw InputError("launch_points must be 0 (all points) or at least 3");
  return m;
}

std::unique_ptr<AeroOf> aero_of(const Glider& g, const py::object& model, bool ballistic, double dz) {
  validate(g);
  auto a = std::make_unique<AeroOf>();
  const MassProperties mp = mass_properties(g);
  a->body = {mp.mass, mp.inertia};
  if (!ballistic) {
    AeroOptions ao;
    ao.dz = element_spacing(dz);
    const ModelPtr m = to_model(model);
    py::gil_scoped_release nogil;
    a->mg = std::make_unique<MountedGlider>(mount(g, m, {}, ao));
    a->qa = std::make_unique<QuasiStaticAero>(*a->mg);
  }
  return a;
}

void bind_fit(py::module_& m) {
  m.def("_fit", [](const std::string& dataset, const py::dict& kw, const py::object& progress) {
        FitOptions o;  // every option checked before the dataset is read, as the command does
        auto num = [&](const char* k, double def) { return kw.contains(k) ? kw[k].cast<double>() : def; };
        auto flag = [&](const char* k, bool def) { return kw.contains(k) ? kw[k].cast<bool>() : def; };
        o.max_centres = whole_number("max_centres", num("max_centres", o.max_centres), 1, 200);
        o.launch.points = launch_points(num("launch_points", o.launch.points));
        o.launch.fit_pitch_rate = flag("fit_pitch_rate", false);
        o.min_improvement = num("min_improvement", o.min_improvement);
        if (kw.contains("stop")) {
          const std::string stop = kw["stop"].cast<std::string>();
          if (stop == "none") o.information_criterion = false;
          else if (stop != "bic") throw InputError("stop must be 'bic' or 'none'");
        }
        if (!(o.min_improvement >= 0) || o.min_improvement >= 1) throw InputError("min_improvement must be in [0, 1)");
        if (!o.information_criterion && o.min_improvement > 0)
          throw InputError("stop='none' keeps every centre; drop min_improvement");  // as --stop none
        o.max_rounds = whole_number("rounds", num("rounds", o.max_rounds), 1, 100);
        o.max_iterations = whole_number("iterations", num("iterations", o.max_iterations), 1, 10000);
        o.candidates = whole_number("candidates", num("candidates", o.candidates), 1, 1000);
        o.insertion_tries = whole_number("insertion_tries", num("insertion_tries", o.insertion_tries), 1, 1000);
        o.robust_m = num("robust_m", o.robust_m);
        o.regularisation_m = num("regularisation_m", o.regularisation_m);
        if (!(o.robust_m >= 0) || !std::isfinite(o.robust_m)) throw InputError("robust_m must be a length >= 0 (m)");
        if (!(o.regularisation_m >= 0) || !std::isfinite(o.regularisation_m))
          throw InputError("regularisation_m must be a length >= 0 (m)");
        o.threads = whole_number("threads", num("threads", 0), 0, 256);
        o.aero.dz = element_spacing(num("dz", o.aero.dz));
        o.launch.track.sim.dt = num("dt", o.launch.track.sim.dt);
        time_step(o.launch.track.sim.dt);
        o.use_prior = flag("use_prior", true);
        if (kw.contains("model") && !kw["model"].is_none()) {
          const ModelPtr sm = to_model(kw["model"]);
          if (auto rbf = std::dynamic_pointer_cast<const RbfModel>(sm)) o.start = rbf;
          else if (auto fp = std::dynamic_pointer_cast<const FlatPlateModel>(sm)) o.prior = fp->params();
          else throw InputError("model must be an RBF or flat-plate model");
        }
        const Dataset d = load_dataset(dataset);
        // Every progress report also lets Python handle its signals: Ctrl-C
        // (KeyboardInterrupt) stops the fit there instead of at its end.
        const FitCallback cb = [progress](const FitProgress& p) {
            py::gil_scoped_acquire gil;
            if (PyErr_CheckSignals() != 0) throw py::error_already_set();
            if (progress.is_none()) return;
            py::dict d;
            d["stage"] = p.stage;
            d["centres"] = p.centres;
            d["round"] = p.round;
            d["iteration"] = p.iteration;
            d["rmse_m"] = p.rmse_m;
            d["elapsed_s"] = p.elapsed_s;
            d["message"] = p.message;
            progress(d);
          };
        FitResult r;
        {
          py::gil_scoped_release nogil;
          r = fit_coefficients(d, o, cb);
        }
        json rep = fit_report_json(r, o);
        rep["dataset"] = dataset;
        return py::make_tuple(mut(r.model), rep.dump());
      }, py::arg("dataset"), py::arg("options"), py::arg("progress") = py::none());

  m.def("_fit_launch", [](const py::object& go, const py::object& t, const py::object& x, const py::object& y,
                          const py::object& model, int points, bool fit_pitch_rate, bool ballistic, double dz,
                          double dt) {
        const Glider g = to_glider(go);
        const auto pts = points_of(t, x, y);
        const auto a = aero_of(g, model, ballistic, dz);
        LaunchFitOptions o;
        o.points = points;
        o.fit_pitch_rate = fit_pitch_rate;
        o.fit_pitch = !ballistic;
        o.track.sim.dt = time_step(dt);
        LaunchFit f;
        {
          py::gil_scoped_release nogil;
          f = fit_launch(a->get(), a->body, pts, o);
        }
        json j = launch_to_json(f.launch);
        j["rmse_m"] = f.rmse_m;
        j["evaluations"] = f.evaluations;
        return j.dump();
      }, py::arg("glider"), py::arg("t"), py::arg("x"), py::arg("y"), py::arg("model") = py::none(),
      py::arg("points") = 10, py::arg("fit_pitch_rate") = false, py::arg("ballistic") = false,
      py::arg("dz") = 0.005, py::arg("dt") = 0.002);

  m.def("_simulate_track", [](const py::object& go, const py::dict& launch, const py::object& times,
                              const py::object& model, bool ballistic, double dz, double dt) {
        const Glider g = to_glider(go);
        const LaunchParams p = launch_from_dict(launch);
        const auto T = vec(times, "times");
        for (std::size_t i = 0; i < T.size(); ++i)
          if ((i && T[i] < T[i - 1]) || T[i] < p.t - 1e-12) throw InputError("times must increase from the launch time");
        const auto a = aero_of(g, model, ballistic, dz);
        TrackOptions o;
        o.sim.dt = time_step(dt);
        Track tr;
        {
          py::gil_scoped_release nogil;
          tr = simulate_track(a->get(), a->body, p, T, o);
        }
        py::dict d;
        d["positions"] = xy_array(tr.positions);
        d["max_alpha_deg"] = rad2deg(tr.max_alpha);
        d["left_model_range"] = tr.left_model_range;
        return d;
      }, py::arg("glider"), py::arg("launch"), py::arg("times"), py::arg("model") = py::none(),
      py::arg("ballistic") = false, py::arg("dz") = 0.005, py::arg("dt") = 0.002);

  m.def("_predict_flights", [](const std::string& dataset, const py::object& model, bool ballistic, double points,
                               double threads) {
        FitOptions o;  // as pteromys.fit's: whole numbers, launch_points 0 or at least 3
        o.launch.points = launch_points(points);
        o.threads = whole_number("threads", threads, 0, 256);
        const Dataset d = load_dataset(dataset);
        const ModelPtr mp = ballistic ? nullptr : to_model(model);
        std::vector<FlightPrediction> ps;
        {
          py::gil_scoped_release nogil;
          ps = predict_flights(d, mp, o);
        }
        py::list out;
        for (const auto& p : ps) {
          py::dict f;
          f["flight"] = p.flight;
          f["glider"] = p.glider;
          f["t"] = py::array_t<double>(p.t.size(), p.t.data());
          f["tracked"] = xy_array(p.tracked);
          f["simulated"] = xy_array(p.simulated);
          f["rmse_m"] = p.rmse_m;
          f["rmse_after_m"] = p.rmse_after_m;
          f["launch_points"] = p.launch_points;
          f["max_alpha_deg"] = rad2deg(p.max_alpha);
          f["left_model_range"] = p.left_model_range;
          f["launch"] = py::module_::import("json").attr("loads")(launch_to_json(p.launch).dump());
          out.append(f);
        }
        return out;
      }, py::arg("dataset"), py::arg("model") = py::none(), py::arg("ballistic") = false, py::arg("points") = 10,
      py::arg("threads") = 0);

  m.def("_synthetic_dataset", [](const py::dict& gliders, const std::string& out_dir, const py::object& model,
                                 const py::dict& kw) {
        std::map<std::string, Glider> gs;
        for (const auto& item : gliders) gs[item.first.cast<std::string>()] = to_glider(py::reinterpret_borrow<py::object>(item.second));
        const ModelPtr m = to_model(model);
        SyntheticOptions o;
        auto num = [&](const char* k, double def) { return kw.contains(k) ? kw[k].cast<double>() : def; };
        o.flights_per_glider = whole_number("flights_per_glider", num("flights_per_glider", o.flights_per_glider), 1, 10000);
        o.speed_min = num("speed_min", o.speed_min);
        o.speed_max = num("speed_max", o.speed_max);
        o.climb_min_deg = num("climb_min_deg", o.climb_min_deg);
        o.climb_max_deg = num("climb_max_deg", o.climb_max_deg);
        o.alpha_min_deg = num("alpha_min_deg", o.alpha_min_deg);
        o.alpha_max_deg = num("alpha_max_deg", o.alpha_max_deg);
        o.points_min = whole_number("points_min", num("points_min", o.points_min), 6, 100000);
        o.points_max = whole_number("points_max", num("points_max", o.points_max), 6, 100000);
        if (o.points_max < o.points_min) throw InputError("points_max is below points_min");
        o.frame_rate_hz = num("frame_rate_hz", o.frame_rate_hz);
        o.delay_max_s = num("delay_max_s", o.delay_max_s);
        o.noise_m = num("noise_m", o.noise_m);
        o.height = num("height", o.height);
        {
          const double seed = num("seed", o.seed);
          if (!(seed >= 0) || seed != std::floor(seed) || seed > 4294967295.0)
            throw InputError("seed must be a whole number from 0 to 4294967295");
          o.seed = static_cast<unsigned>(seed);
        }
        Dataset d;
        {
          py::gil_scoped_release nogil;
          d = synthetic_dataset(gs, m, o);
          save_dataset(d, out_dir);
        }
        return out_dir + "/dataset.json";
      }, py::arg("gliders"), py::arg("out_dir"), py::arg("model") = py::none(), py::arg("options") = py::dict());
}

const bool registered = register_binder(60, bind_fit);
}  // namespace
}  // namespace pteromys::python
