// Bindings: design optimisation (paper section 6).
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "pteromys/io.hpp"
#include "pteromys/optimize.hpp"

namespace pteromys::python {
namespace {

/// Opaque warm-start state handed back to Python.
struct OptimizeState {
  OptimizeResult result;
};

/// The design cost's terms C1..C4 (paper section 6; C4 the static-margin term) and their weighted total.
py::dict cost_dict(const CostTerms& c) {
  py::dict t;
  t["c1"] = c.c1;
  t["c2"] = c.c2;
  t["c3"] = c.c3;
  t["c4"] = c.c4;
  t["total"] = c.total;
  return t;
}

py::dict result_dict(const OptimizeResult& r, const Glider& g, const ModelPtr& model) {
  auto json = py::module_::import("json");
  nlohmann::json rep = report_to_json(r.report);
  rep["glider"] = g.name;
  rep["model"] = model->kind();
  py::dict d;
  d["glider"] = json.attr("loads")(glider_to_json(r.glider).dump());
  d["report"] = json.attr("loads")(rep.dump());
  py::list flights;
  for (const auto& l : r.report.launches) flights.append(samples_array(l.flight));
  d["flights"] = flights;
  d["cost"] = cost_dict(r.cost);
  d["cost_start"] = cost_dict(r.cost_start);
  py::list vars;
  for (const auto& v : r.variables) {
    py::dict e;
    e["name"] = v.name;
    e["value"] = v.value;
    e["lower"] = v.lower;
    e["upper"] = v.upper;
    e["locked"] = v.locked;
    vars.append(e);
  }
  d["variables"] = vars;
  d["evaluations"] = r.evaluations;
  d["seconds"] = r.seconds;
  d["algorithm"] = r.algorithm;
  d["stop_reason"] = r.stop_reason;
  d["state"] = std::make_shared<OptimizeState>(OptimizeState{r});
  return d;
}

void bind_optimize(py::module_& m) {
  py::class_<OptimizeState, std::shared_ptr<OptimizeState>>(
      m, "OptimizeState", "Result of a previous optimisation, to warm-start the next one.");
  m.def(
      "optimize",
      [](const py::object& go, const py::object& mo, std::vector<std::string> locks, bool optimise_ballast,
         double height, std::shared_ptr<OptimizeState> warm, const std::string& algorithm, int max_evaluations,
         py::object speed_range, py::object alpha_range_deg, py::object angle_range_deg, double w1, double w2,
         double min_overlap, double w4, double min_static_margin, double min_wing_gap_mm, double dz) {
        const Glider g = to_glider(go);
        validate(g);
        const ModelPtr model = to_model(mo);
        OptimizeOptions opt;
        opt.locks = std::move(locks);
        opt.optimise_ballast = optimise_ballast;
        opt.analysis.launch_height = launch_height(height);
        opt.analysis.sim.record_every = 5;
        opt.algorithm = algorithm;
        opt.max_evaluations = max_evaluations;
        opt.w1 = w1;
        opt.w2 = w2;
        opt.min_overlap_fraction = min_overlap;
        opt.w4 = w4;
        opt.min_wing_gap_m = min_wing_gap_mm / 1000;
        opt.min_static_margin = min_static_margin;
        if (!speed_range.is_none()) {
          auto p = speed_range.cast<std::pair<double, double>>();
          opt.region.v_min = p.first;
          opt.region.v_max = p.second;
        }
        if (!alpha_range_deg.is_none()) {
          auto p = alpha_range_deg.cast<std::pair<double, double>>();
          opt.region.gamma_min = deg2rad(p.first);
          opt.region.gamma_max = deg2rad(p.second);
        }
        if (!angle_range_deg.is_none()) {
          auto p = angle_range_deg.cast<std::pair<double, double>>();
          opt.angle_min_deg = p.first;
          opt.angle_max_deg = p.second;
        }
        AeroOptions ao;
        ao.dz = element_spacing(dz);
        OptimizeResult r;
        {
          py::gil_scoped_release nogil;
          r = optimize(g, model, opt, {}, ao, warm ? &warm->result : nullptr);
        }
        return result_dict(r, g, model);
      },
      py::arg("glider"), py::arg("model") = py::none(), py::arg("locks") = std::vector<std::string>{},
      py::arg("optimise_ballast") = false, py::arg("height") = 1.5, py::arg("warm_start") = nullptr,
      py::arg("algorithm") = "bobyqa", py::arg("max_evaluations") = 3000, py::arg("speed_range") = py::none(),
      py::arg("alpha_range_deg") = py::none(), py::arg("angle_range_deg") = py::none(), py::arg("w1") = 100.0,
      py::arg("w2") = 1.0, py::arg("min_overlap") = 0.6, py::arg("w4") = 1.0,
      py::arg("min_static_margin") = 0.10, py::arg("min_wing_gap_mm") = 10.0, py::arg("dz") = 0.005,
      "Adjust mounting angles and positions (paper section 6). Returns a dict: 'glider' (glider dict\n"
      "with the new mounts), 'report' (report dict), 'flights' (six (n, 9) arrays), 'cost' and\n"
      "'cost_start' ({c1, c2, c3, c4, total}); w4 = 0 gives the paper's cost exactly, 'variables', 'evaluations', 'seconds', 'algorithm',\n"
      "'stop_reason' and 'state' (pass it as warm_start to the next call after a small change).\n"
      "locks: names such as 'main.angle', 'tail.x', 'tail.y', 'ballast.x'.");
  m.def(
      "design_cost",
      [](const py::object& go, const py::object& mo, double dz) {
        const Glider g = to_glider(go);
        validate(g);
        const ModelPtr model = to_model(mo);
        AeroOptions ao;
        ao.dz = element_spacing(dz);
        auto aero = std::make_shared<const GliderAero>(g, model, Environment{}, ao);
        const OptimizeOptions opt;
        const DesignCost cost(g, aero, opt);
        std::vector<double> v;
        for (const auto& x : cost.variables()) v.push_back(x.value);
        const CostTerms c = cost.evaluate(v);
        py::dict t = cost_dict(c);
        t["speeds_without_equilibrium"] = c.speeds_without_equilibrium;
        return t;
      },
      py::arg("glider"), py::arg("model") = py::none(), py::arg("dz") = 0.005,
      "The section 6 cost terms of a glider as mounted (default Omega and weights).");
}

const bool registered = register_binder(30, bind_optimize);

}  // namespace
}  // namespace pteromys::python
