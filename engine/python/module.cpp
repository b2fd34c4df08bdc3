// pybind11 module pteromys._core: thin bindings of the engine. The Python
// package `pteromys` (python/pteromys/__init__.py) wraps it.
#include <algorithm>
#include <cmath>
#include <string>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "pteromys/analysis.hpp"
#include "pteromys/io.hpp"

namespace py = pybind11;
using namespace pteromys;

namespace pteromys::python {

Glider to_glider(const py::object& o) {
  if (py::isinstance<Glider>(o)) return o.cast<Glider>();
  if (py::isinstance<py::dict>(o)) {
    const std::string text = py::module_::import("json").attr("dumps")(o).cast<std::string>();
    return glider_from_json_text(text);
  }
  if (py::isinstance<py::str>(o)) return load_glider(o.cast<std::string>());
  throw InputError("expected a Glider, a glider dict (spec format) or a path to a .glider.json file");
}

double finite_value(const char* key, double v) {
  if (!std::isfinite(v)) throw InputError(std::string(key) + " must be a finite number");
  return v;
}

double element_spacing(double dz) {
  if (!(dz > 0) || dz > 0.1) throw InputError("dz must be in (0, 0.1] m");
  return dz;
}

double launch_height(double v) {
  if (!(finite_value("height", v) >= 0) || v > 100) throw InputError("height must be between 0 and 100 m");
  return v;
}

double time_step(double dt) { return check_time_step(dt, "dt"); }

Launch one_launch(double speed, double climb_deg, double height, const py::object& pitch_deg,
                  double pitch_rate_deg_s) {
  Launch l;
  l.speed = finite_value("speed", speed);
  if (l.speed < 0) throw InputError("speed must not be negative (m/s; the launch is along +x)");
  l.climb_deg = finite_value("climb_deg", climb_deg);
  l.height = finite_value("height", height);  // one launch, any height (a drop from a hill)
  if (l.height < 0) throw InputError("height must not be negative (m above the ground)");
  if (!pitch_deg.is_none()) {
    l.pitch_from_path = false;
    l.pitch_deg = finite_value("pitch_deg", pitch_deg.cast<double>());
  }
  l.pitch_rate_deg_s = finite_value("pitch_rate_deg_s", pitch_rate_deg_s);
  return l;
}

SimOptions sim_options(double dt, double t_max, const std::string& integrator, int record_every) {
  SimOptions o;
  time_step(dt);
  // (the samples are reserved for t_max / dt steps: an infinite t_max was
  // undefined behaviour, a huge one an allocation failure)
  if (!(t_max > 0) || t_max > 600) throw InputError("t_max must be in (0, 600] s");
  o.dt = dt;
  o.t_max = t_max;
  if (record_every < 1) throw InputError("record_every must be at least 1 (every step)");
  o.record_every = record_every;
  if (integrator == "verlet") o.integrator = Integrator::Verlet;
  else if (integrator == "rk4") o.integrator = Integrator::RK4;
  else throw InputError("integrator must be 'verlet' or 'rk4'");
  return o;
}

py::dict flight_dict(const Flight& f) {
  py::dict d;
  d["samples"] = samples_array(f);
  d["stable"] = f.stable;
  d["reason"] = f.reason;
  d["distance_m"] = f.distance;
  d["flight_time_s"] = f.flight_time;
  d["max_alpha_deg"] = rad2deg(f.max_alpha);
  d["end"] = f.end == FlightEnd::Ground ? "ground" : f.end == FlightEnd::TimeLimit ? "time_limit" : "unstable";
  return d;
}

ModelPtr to_model(const py::object& o) {
  if (o.is_none()) return default_model();
  if (py::isinstance<py::str>(o)) return load_model(o.cast<std::string>());
  if (py::hasattr(o, "__fspath__")) return load_model(py::str(o.attr("__fspath__")()).cast<std::string>());  // pathlib
  try {
    return o.cast<std::shared_ptr<CoefficientModel>>();
  } catch (const py::cast_error&) {
    // pybind11 says "Unable to cast Python instance", naming no parameter
    throw InputError("model must be a model file's path or a model (pteromys.load_model, flat_plate_model, ...), "
                     "not " + std::string(py::str(o.get_type().attr("__name__"))));
  }
}

py::array_t<double> samples_array(const Flight& f) {
  py::array_t<double> a({static_cast<py::ssize_t>(f.samples.size()), static_cast<py::ssize_t>(9)});
  auto r = a.mutable_unchecked<2>();
  for (std::size_t i = 0; i < f.samples.size(); ++i) {
    const auto& s = f.samples[i];
    const double row[9] = {s.t, s.x, s.y, rad2deg(s.pitch), s.speed, rad2deg(s.alpha), rad2deg(s.omega), s.vx, s.vy};
    for (int k = 0; k < 9; ++k) r(i, k) = row[k];
  }
  return a;
}

namespace {
std::vector<std::pair<int, Binder>>& binders() {
  static std::vector<std::pair<int, Binder>> b;
  return b;
}
}  // namespace

bool register_binder(int order, Binder b) {
  binders().emplace_back(order, b);
  return true;
}

}  // namespace pteromys::python

using namespace pteromys::python;

PYBIND11_MODULE(_core, m) {
  m.doc() = "Pteromys engine (compiled part). Use the `pteromys` package.";
  static py::exception<InputError> input_error(m, "InputError", PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      // as text Python can hold: a message quoting a non-UTF-8 name would
      // otherwise arrive empty
      PyErr_SetString(input_error.ptr(), printable_utf8(e.what()).c_str());
    }
  });
  m.attr("__version__") = kVersion;
  auto& bs = binders();
  std::stable_sort(bs.begin(), bs.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [order, bind] : bs) bind(m);
}
