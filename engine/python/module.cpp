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

int whole_number(const char* key, double v, int lo, int hi) {
  if (v != std::floor(v) || v < lo || v > hi)
    throw InputError(std::string(key) + " must be a whole number between " + std::to_string(lo) + " and " +
                     std::to_string(hi));
  return static_cast<int>(v);
}

ModelPtr to_model(const py::object& o) {
  if (o.is_none()) return default_model();
  if (py::isinstance<py::str>(o)) return load_model(o.cast<std::string>());
  return o.cast<std::shared_ptr<CoefficientModel>>();
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
      PyErr_SetString(input_error.ptr(), e.what());
    }
  });
  m.attr("__version__") = kVersion;
  auto& bs = binders();
  std::stable_sort(bs.begin(), bs.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [order, bind] : bs) bind(m);
}
