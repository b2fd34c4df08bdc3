// Bindings: glider, mass, elements, coefficient models, forces, flight, report.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "pteromys/io.hpp"

namespace pteromys::python {

namespace {

std::vector<std::string> wing_names(const Glider& g) {
  std::vector<std::string> n;
  for (const auto& w : g.wings) n.push_back(w.name);
  return n;
}

}  // namespace

namespace {
void bind_core(py::module_& m) {
  // ------------------------------------------------------------- glider
  py::class_<Glider>(m, "Glider", "A glider design (spec/formats.md). Build it with pteromys.glider().")
      .def_static("from_json", &glider_from_json_text, py::arg("text"),
                  "Parse glider-file JSON text (no geometry validation).")
      .def("to_json", [](const Glider& g) { return glider_to_json(g).dump(2); })
      .def_readwrite("name", &Glider::name)
      .def_property_readonly("wing_names", [](const Glider& g) { return wing_names(g); })
      .def("__repr__", [](const Glider& g) {
        return "<pteromys.Glider '" + g.name + "' with " + std::to_string(g.wings.size()) + " wings>";
      });
  m.def("load_glider", &load_glider, py::arg("path"), "Read and validate a .glider.json file.");
  m.def("save_glider", &save_glider, py::arg("glider"), py::arg("path"), "Write a .glider.json file atomically.");
  m.def("validation_problems", [](const py::object& g) { return validation_problems(to_glider(g)); },
        py::arg("glider"), "Every problem of a glider design, as sentences (empty when valid).");
  m.def("mass_properties", [](const py::object& go) {
        const MassProperties mp = mass_properties(to_glider(go));
        py::dict d;
        d["mass_kg"] = mp.mass;
        d["cg_m"] = py::make_tuple(mp.cg.x, mp.cg.y);
        d["inertia_kg_m2"] = mp.inertia;
        return d;
      }, py::arg("glider"), "Mass, centre of gravity and pitch inertia about the CG.");

  // ----------------------------------------------------------- elements
  m.def("slice_wing", [](py::array_t<double, py::array::c_style | py::array::forcecast> outline, double dz) {
        if (outline.ndim() != 2 || outline.shape(1) != 2) throw InputError("outline must be an (n, 2) array of (x, z)");
        Polygon p;
        auto r = outline.unchecked<2>();
        for (py::ssize_t i = 0; i < r.shape(0); ++i) p.push_back({r(i, 0), r(i, 1)});
        const WingElements we = slice_wing(p, dz);
        const auto n = static_cast<py::ssize_t>(we.elements.size());
        py::dict d;
        const char* keys[] = {"z0", "z1", "area", "chord", "x_le", "x_qc", "xi_l_deg", "xi_t_deg", "rank"};
        std::vector<py::array_t<double>> cols;
        for (int k = 0; k < 9; ++k) cols.emplace_back(n);
        for (py::ssize_t i = 0; i < n; ++i) {
          const auto& e = we.elements[i];
          const double v[9] = {e.z0, e.z1, e.area, e.chord, e.x_le, e.x_qc, rad2deg(e.xi_l), rad2deg(e.xi_t),
                               static_cast<double>(e.streamline_rank)};
          for (int k = 0; k < 9; ++k) cols[k].mutable_at(i) = v[k];
        }
        for (int k = 0; k < 9; ++k) d[keys[k]] = cols[k];
        d["planform_area"] = we.planform_area;
        d["span"] = we.span;
        d["multiple_in_streamline"] = we.multiple_in_streamline;
        d["multiple_ranges"] = we.multiple_ranges;
        return d;
      }, py::arg("outline"), py::arg("dz") = 0.005,
      "Wing elements (paper 4.2) of a planform given as an (n, 2) array of (x, z) [m].");

  // ------------------------------------------------------------- models
  py::class_<CoefficientModel, std::shared_ptr<CoefficientModel>>(m, "Model", "Aerodynamic coefficient model of a wing element.")
      .def_property_readonly("kind", &CoefficientModel::kind)
      .def_property_readonly("alpha_limit_deg", [](const CoefficientModel& c) { return rad2deg(c.alpha_limit()); })
      .def("to_json", [](const CoefficientModel& c) { return model_to_json(c).dump(2); })
      .def("save", [](const CoefficientModel& c, const std::string& p) { save_model(c, p); }, py::arg("path"))
      .def("eval", [](const CoefficientModel& c, py::object alpha_deg, py::object re,
                      py::object xi_l_deg, py::object xi_t_deg) {
        auto np = py::module_::import("numpy");
        py::tuple bt = np.attr("broadcast_arrays")(alpha_deg, re, xi_l_deg, xi_t_deg);
        std::vector<py::array_t<double>> in;
        for (int k = 0; k < 4; ++k) in.push_back(np.attr("ascontiguousarray")(bt[k], "float64").cast<py::array_t<double>>());
        std::vector<py::ssize_t> shape(in[0].shape(), in[0].shape() + in[0].ndim());
        py::array_t<double> cd(shape), cl(shape), cm(shape);
        const double *a = in[0].data(), *r = in[1].data(), *l = in[2].data(), *t = in[3].data();
        double *od = cd.mutable_data(), *ol = cl.mutable_data(), *om = cm.mutable_data();
        const py::ssize_t n = cd.size();
        {
          py::gil_scoped_release nogil;
          for (py::ssize_t i = 0; i < n; ++i) {
            const Coefficients k = c.eval({deg2rad(a[i]), r[i], deg2rad(l[i]), deg2rad(t[i])});
            od[i] = k.cd;
            ol[i] = k.cl;
            om[i] = k.cm;
          }
        }
        return py::make_tuple(cd, cl, cm);
      }, py::arg("alpha_deg"), py::arg("re"), py::arg("xi_l_deg") = 0.0, py::arg("xi_t_deg") = 0.0,
      "Coefficients (cd, cl, cm) for arrays of inputs (broadcast).");
  m.def("default_model", []() { return mut(default_model()); }, "The model shipped with the project.");
  m.def("default_model_path", &default_model_path);
  m.def("load_model", [](const std::string& p) { return mut(load_model(p)); }, py::arg("path"));
  m.def("model_from_json", [](const std::string& text) { return mut(model_from_json(parse_json(text, "model"))); },
        py::arg("text"));
  m.def("flat_plate_model", [](double aspect_ratio, double section_lift_slope, double stall_deg,
                               double stall_width_deg, double normal_force_90, double edge_drag,
                               double alpha_valid_deg) -> std::shared_ptr<CoefficientModel> {
        FlatPlateParams p{aspect_ratio, section_lift_slope, stall_deg, stall_width_deg, normal_force_90, edge_drag, alpha_valid_deg};
        return std::make_shared<FlatPlateModel>(p);
      }, py::arg("aspect_ratio") = FlatPlateParams{}.aspect_ratio,
      py::arg("section_lift_slope") = FlatPlateParams{}.section_lift_slope,
      py::arg("stall_deg") = FlatPlateParams{}.stall_deg,
      py::arg("stall_width_deg") = FlatPlateParams{}.stall_width_deg,
      py::arg("normal_force_90") = FlatPlateParams{}.normal_force_90,
      py::arg("edge_drag") = FlatPlateParams{}.edge_drag,
      py::arg("alpha_valid_deg") = FlatPlateParams{}.alpha_valid_deg,
      "The empirical flat-plate wing element (docs/theory.md).");

  // ------------------------------------------------------ forces, flight
  py::class_<MountedGlider, std::shared_ptr<MountedGlider>>(m, "MountedGlider",
      "A glider with its wing tables, mounts and mass: evaluates F(V, gamma).")
      .def("forces", [](const MountedGlider& g, py::array_t<double> v, py::array_t<double> gamma_deg, bool direct) {
        auto np = py::module_::import("numpy");
        py::tuple bt = np.attr("broadcast_arrays")(v, gamma_deg);
        auto V = np.attr("ascontiguousarray")(bt[0], "float64").cast<py::array_t<double>>();
        auto G = np.attr("ascontiguousarray")(bt[1], "float64").cast<py::array_t<double>>();
        std::vector<py::ssize_t> shape(V.shape(), V.shape() + V.ndim());
        py::array_t<double> fd(shape), fl(shape), tz(shape);
        const double *pv = V.data(), *pg = G.data();
        double *a = fd.mutable_data(), *b = fl.mutable_data(), *c = tz.mutable_data();
        {
          py::gil_scoped_release nogil;
          for (py::ssize_t i = 0; i < V.size(); ++i) {
            const GliderForces f = direct ? g.forces_direct(pv[i], deg2rad(pg[i])) : g.forces(pv[i], deg2rad(pg[i]));
            a[i] = f.drag;
            b[i] = f.lift;
            c[i] = f.moment;
          }
        }
        return py::make_tuple(fd, fl, tz);
      }, py::arg("speed"), py::arg("gamma_deg"), py::arg("direct") = false,
      "Characteristic function F(V, gamma) = (F_d, F_l, T_z) [N, N, N m]; direct=True skips the tables.")
      .def_property_readonly("mass_kg", [](const MountedGlider& g) { return g.mass().mass; })
      .def_property_readonly("cg_m", [](const MountedGlider& g) { return py::make_tuple(g.mass().cg.x, g.mass().cg.y); })
      .def_property_readonly("inertia_kg_m2", [](const MountedGlider& g) { return g.mass().inertia; })
      .def_property_readonly("alpha_limit_deg", [](const MountedGlider& g) { return rad2deg(g.alpha_limit()); });
  m.def("mount", [](const py::object& go, const py::object& mo, double dz) {
        const Glider g = to_glider(go);
        validate(g);
        const ModelPtr model = to_model(mo);
        AeroOptions ao;
        ao.dz = element_spacing(dz);
        py::gil_scoped_release nogil;
        return std::make_shared<MountedGlider>(mount(g, model, {}, ao));
      }, py::arg("glider"), py::arg("model") = py::none(), py::arg("dz") = 0.005,
      "Slice, tabulate and mount a glider as its file places the wings.");

  m.def("evaluate", [](const py::object& go, const py::object& mo, double height, double dz, double dt,
                       const std::string& integrator, int record_every) {
        const Glider g = to_glider(go);
        validate(g);
        const ModelPtr model = to_model(mo);
        AeroOptions ao;
        ao.dz = element_spacing(dz);
        AnalysisOptions opt;
        opt.launch_height = launch_height(height);
        opt.sim = sim_options(dt, 20.0, integrator, record_every);
        Flyability f;
        {
          py::gil_scoped_release nogil;
          const MountedGlider mg = mount(g, model, {}, ao);
          f = analyse(mg, wing_names(g), opt);
        }
        nlohmann::json j = report_to_json(f);
        j["glider"] = g.name;
        j["model"] = model->kind();
        py::list flights;
        for (const auto& l : f.launches) flights.append(samples_array(l.flight));
        return py::make_tuple(j.dump(), flights);
      }, py::arg("glider"), py::arg("model") = py::none(), py::arg("height") = 1.5, py::arg("dz") = 0.005,
      py::arg("dt") = 0.002, py::arg("integrator") = "verlet", py::arg("record_every") = 5,
      "Flyability report (JSON text) and the six launch trajectories (arrays).");

  m.def("simulate", [](const py::object& go, double speed, double climb_deg, double height,
                       const py::object& pitch_deg, double pitch_rate_deg_s, const py::object& mo,
                       double dz, double dt, double t_max, const std::string& integrator, int record_every,
                       bool ballistic) {
        const Glider g = to_glider(go);
        validate(g);
        const ModelPtr model = to_model(mo);
        AeroOptions ao;
        ao.dz = element_spacing(dz);
        const Launch l = one_launch(speed, climb_deg, height, pitch_deg, pitch_rate_deg_s);
        const SimOptions so = sim_options(dt, t_max, integrator, record_every);
        Flight f;
        {
          py::gil_scoped_release nogil;
          const MountedGlider mg = mount(g, model, {}, ao);
          const RigidBody body{mg.mass().mass, mg.mass().inertia};
          if (ballistic) f = simulate(NoAero(), body, l, so, mg.aero().environment().gravity);
          else f = simulate(QuasiStaticAero(mg), body, l, so, mg.aero().environment().gravity);
        }
        return flight_dict(f);
      }, py::arg("glider"), py::arg("speed") = 7.0, py::arg("climb_deg") = 0.0, py::arg("height") = 1.5,
      py::arg("pitch_deg") = py::none(), py::arg("pitch_rate_deg_s") = 0.0, py::arg("model") = py::none(),
      py::arg("dz") = 0.005, py::arg("dt") = 0.002, py::arg("t_max") = 20.0, py::arg("integrator") = "verlet",
      py::arg("record_every") = 1, py::arg("ballistic") = false,
      "One launch. Returns a dict with 'samples' (n x 9: t, x, y, pitch_deg, speed, alpha_deg, "
      "omega_deg_s, vx, vy), 'stable', 'reason', 'distance_m', 'flight_time_s', 'end'.");
}

const bool registered = register_binder(10, bind_core);
}  // namespace

}  // namespace pteromys::python
