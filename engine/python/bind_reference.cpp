// Bindings: the reference simulator (forces, polars, flights, datasets).
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "pteromys/io.hpp"
#include "pteromys/reference.hpp"

namespace pteromys::python {
namespace {

Effects effects_of(const std::string& spec, const py::object& strengths) {
  Effects e = parse_effects(spec);
  if (strengths.is_none()) return e;
  if (py::isinstance<py::str>(strengths)) {
    apply_strengths(e, strengths.cast<std::string>());
    return e;
  }
  for (const auto& kv : strengths.cast<py::dict>()) {
    const std::string name = kv.first.cast<std::string>();
    const double v = kv.second.cast<double>();
    if (!std::isfinite(v)) throw InputError("strength of '" + name + "' must be finite");
    e[name].strength = v;
    e[name].on = v != 0;
  }
  return e;
}

ReferenceOptions options(const std::string& effects, const py::object& strengths, int span_panels,
                         int chord_panels) {
  ReferenceOptions o;
  o.effects = effects_of(effects, strengths);
  o.span_panels = span_panels;
  o.chord_panels = chord_panels;
  return o;
}

py::array_t<double> as_array(const py::object& o) {
  return py::module_::import("numpy").attr("ascontiguousarray")(o, "float64").cast<py::array_t<double>>();
}

void bind_reference(py::module_& m) {
  m.def("effect_names", []() { return Effects::names(); },
        "Names of the reference simulator's effects (the diagnosis library's names).");
  m.def("effect_switches", [](const std::string& effects, const py::object& strengths) {
        const Effects e = effects_of(effects, strengths);
        py::dict d;
        for (const auto& n : Effects::names()) d[py::str(n)] = e[n].factor();
        return d;
      }, py::arg("effects") = "physics", py::arg("strengths") = py::none(),
      "Effective factor (on ? strength : 0) of every effect for a specification.");

  m.def("reference_forces", [](const py::object& go, const py::object& speed, const py::object& alpha_deg,
                               const py::object& pitch_rate_deg_s, const py::object& height_m,
                               const std::string& effects, const py::object& strengths, int span_panels,
                               int chord_panels) {
        const Glider g = to_glider(go);
        validate(g);
        const ReferenceOptions o = options(effects, strengths, span_panels, chord_panels);
        auto np = py::module_::import("numpy");
        py::tuple bt = np.attr("broadcast_arrays")(speed, alpha_deg, pitch_rate_deg_s,
                                                   height_m.is_none() ? py::float_(1e9) : height_m);
        std::vector<py::array_t<double>> in;
        for (int k = 0; k < 4; ++k) in.push_back(as_array(bt[k]));
        std::vector<py::ssize_t> shape(in[0].shape(), in[0].shape() + in[0].ndim());
        py::array_t<double> lift(shape), drag(shape), moment(shape);
        const double *v = in[0].data(), *a = in[1].data(), *q = in[2].data(), *h = in[3].data();
        double *L = lift.mutable_data(), *D = drag.mutable_data(), *M = moment.mutable_data();
        const py::ssize_t n = lift.size();
        {
          py::gil_scoped_release nogil;
          const ReferenceAero ref(g, o);
          for (py::ssize_t i = 0; i < n; ++i) {
            const GliderForces f = ref.forces(v[i], deg2rad(a[i]), deg2rad(q[i]), h[i]);
            L[i] = f.lift;
            D[i] = f.drag;
            M[i] = f.moment;
          }
        }
        return py::make_tuple(drag, lift, moment);
      }, py::arg("glider"), py::arg("speed"), py::arg("alpha_deg"), py::arg("pitch_rate_deg_s") = 0.0,
      py::arg("height_m") = py::none(), py::arg("effects") = "physics", py::arg("strengths") = py::none(),
      py::arg("span_panels") = 10, py::arg("chord_panels") = 4,
      "Reference air force on a glider flying level at `speed` [m/s] with angle of attack alpha_deg "
      "(arrays broadcast): (drag, lift, moment about the CG) [N, N, N m]; height_m None = no ground.");

  m.def("reference_loads", [](const py::object& go, double speed, double alpha_deg, double pitch_rate_deg_s,
                              const py::object& height_m, const std::string& effects, const py::object& strengths,
                              int span_panels, int chord_panels) {
        const Glider g = to_glider(go);
        validate(g);
        const ReferenceOptions o = options(effects, strengths, span_panels, chord_panels);
        const ReferenceAero ref(g, o);
        FlightState s;
        s.v = {speed, 0.0};
        s.beta = deg2rad(alpha_deg);
        s.omega = deg2rad(pitch_rate_deg_s);
        s.p = {0.0, height_m.is_none() ? 1e9 : height_m.cast<double>()};
        const ReferenceLoads L = ref.loads(s);
        py::dict d;
        d["force_body_n"] = py::make_tuple(L.force_body.x, L.force_body.y);
        d["moment_n_m"] = L.moment;
        py::list wf, wm;
        for (std::size_t j = 0; j < L.wing_force.size(); ++j) {
          wf.append(py::make_tuple(L.wing_force[j].x, L.wing_force[j].y));
          wm.append(L.wing_moment[j]);
        }
        d["wing_force_body_n"] = wf;
        d["wing_moment_n_m"] = wm;
        d["fuselage_force_body_n"] = py::make_tuple(L.fuselage_force.x, L.fuselage_force.y);
        d["fuselage_moment_n_m"] = L.fuselage_moment;
        std::vector<double> ae, zc, zw;
        std::vector<int> wing;
        for (std::size_t i = 0; i < L.strip_alpha_eff.size(); ++i) {
          ae.push_back(rad2deg(L.strip_alpha_eff[i]));
          const auto& st = ref.strips()[i];
          zc.push_back(0.5 * (st.z0 + st.z1));
          wing.push_back(st.wing);
        }
        d["strip_alpha_eff_deg"] = ae;
        d["strip_cn"] = L.strip_cn;
        d["strip_z_m"] = zc;
        d["strip_wing"] = wing;
        d["iterations"] = L.iterations;
        d["converged"] = L.converged;
        d["panels"] = ref.panel_count();
        d["grid_nodes"] = ref.node_count();
        d["plate_added_mass_kg"] = ref.plate_added_mass();
        return d;
      }, py::arg("glider"), py::arg("speed"), py::arg("alpha_deg"), py::arg("pitch_rate_deg_s") = 0.0,
      py::arg("height_m") = py::none(), py::arg("effects") = "physics", py::arg("strengths") = py::none(),
      py::arg("span_panels") = 10, py::arg("chord_panels") = 4,
      "Breakdown of one reference evaluation (glider frame): per wing, fuselage, per strip.");

  m.def("reference_polar", [](const py::array_t<double, py::array::c_style | py::array::forcecast> outline,
                              const py::object& alpha_deg, double reynolds, double thickness_m,
                              const std::string& effects, const py::object& strengths, int span_panels,
                              int chord_panels) {
        if (outline.ndim() != 2 || outline.shape(1) != 2) throw InputError("outline must be an (n, 2) array of (x, z)");
        if (!(reynolds > 0) || !std::isfinite(reynolds)) throw InputError("reynolds must be positive");
        if (!(thickness_m > 0) || !std::isfinite(thickness_m)) throw InputError("thickness_m must be positive");
        Glider g;
        g.name = "wing";
        g.material = {thickness_m, 1000.0};
        Wing w;
        w.name = "wing";
        auto r = outline.unchecked<2>();
        for (py::ssize_t i = 0; i < r.shape(0); ++i) w.outline.push_back({r(i, 0), r(i, 1)});
        w.mount = {0.0, 0.0, 0.0};
        g.wings.push_back(w);
        ReferenceOptions o = options(effects, strengths, span_panels, chord_panels);
        o.alpha_limit_deg = 180;
        const auto a = as_array(alpha_deg);
        std::vector<py::ssize_t> shape(a.shape(), a.shape() + a.ndim());
        py::array_t<double> cl(shape), cd(shape), cm(shape);
        double zmax = 0, xmax = -1e300, xmin = 1e300;
        for (const auto& p : w.outline) {
          zmax = std::max(zmax, p.y);
          xmax = std::max(xmax, p.x);
          xmin = std::min(xmin, p.x);
        }
        const Environment env;
        double S = 0;
        {
          py::gil_scoped_release nogil;
          // Moments about the root quarter chord; reference length the mean chord S / b.
          const auto root = root_chord_intervals(w.outline);
          const double xq = root.empty() ? 0.5 * (xmin + xmax) : root.front().second - 0.25 * (root.front().second - root.front().first);
          const ReferenceAero ref(g, Vec2{xq, 0.0}, o, env);
          PotentialSolution ps = ref.potential(0.0);
          S = ps.area;
          const double cbar = S / (2 * zmax);
          const double V = reynolds * env.air_viscosity / (env.air_density * cbar);
          const double q = 0.5 * env.air_density * V * V;
          const double* pa = a.data();
          double *L = cl.mutable_data(), *D = cd.mutable_data(), *M = cm.mutable_data();
          for (py::ssize_t i = 0; i < a.size(); ++i) {
            const GliderForces f = ref.forces(V, deg2rad(pa[i]));
            L[i] = f.lift / (q * S);
            D[i] = f.drag / (q * S);
            M[i] = f.moment / (q * S * cbar);
          }
        }
        return py::make_tuple(cl, cd, cm);
      }, py::arg("outline"), py::arg("alpha_deg"), py::arg("reynolds") = 1e5, py::arg("thickness_m") = 0.001,
      py::arg("effects") = "physics", py::arg("strengths") = py::none(), py::arg("span_panels") = 10,
      py::arg("chord_panels") = 4,
      "Wind-tunnel polar of a bare flat-plate wing (outline (n, 2) of (x, z) [m]) at Reynolds number "
      "`reynolds` on the mean chord S/b: (CL, CD, Cm about the root quarter chord, on S and S/b).");

  m.def("reference_potential", [](const py::array_t<double, py::array::c_style | py::array::forcecast> outline,
                                  double alpha_deg, int span_panels, int chord_panels) {
        if (outline.ndim() != 2 || outline.shape(1) != 2) throw InputError("outline must be an (n, 2) array of (x, z)");
        Glider g;
        g.name = "wing";
        Wing w;
        w.name = "wing";
        auto r = outline.unchecked<2>();
        for (py::ssize_t i = 0; i < r.shape(0); ++i) w.outline.push_back({r(i, 0), r(i, 1)});
        g.wings.push_back(w);
        ReferenceOptions o;
        o.span_panels = span_panels;
        o.chord_panels = chord_panels;
        PotentialSolution ps;
        {
          py::gil_scoped_release nogil;
          const ReferenceAero ref(g, Vec2{0.0, 0.0}, o);
          ps = ref.potential(deg2rad(alpha_deg));
        }
        py::dict d;
        d["cl"] = ps.cl;
        d["cdi"] = ps.cdi;
        d["area_m2"] = ps.area;
        d["span_m"] = ps.span;
        d["z_m"] = ps.z;
        d["gamma_m2_s"] = ps.gamma;
        return d;
      }, py::arg("outline"), py::arg("alpha_deg"), py::arg("span_panels") = 20, py::arg("chord_panels") = 4,
      "Linear vortex-lattice solution of a bare wing at unit speed: lift coefficient (Kutta-Joukowski) "
      "and induced drag (Trefftz plane).");

  m.def("reference_simulate", [](const py::object& go, double speed, double climb_deg, double height,
                                 const py::object& pitch_deg, double pitch_rate_deg_s, double wind_m_s,
                                 const std::string& effects, const py::object& strengths, double dt, double t_max,
                                 int record_every, int span_panels, int chord_panels) {
        const Glider g = to_glider(go);
        validate(g);
        const ReferenceOptions o = options(effects, strengths, span_panels, chord_panels);
        const Launch l = one_launch(speed, climb_deg, height, pitch_deg, pitch_rate_deg_s);
        SimOptions so = sim_options(dt, t_max, "verlet", record_every);
        so.wind = {o.effects.wind.factor() * finite_value("wind_m_s", wind_m_s), 0.0};
        Flight f;
        {
          py::gil_scoped_release nogil;
          const MassProperties mp = mass_properties(g);
          const ReferenceAero ref(g, mp.cg, o);
          f = simulate(ref, {mp.mass, mp.inertia}, l, so, Environment{}.gravity);
        }
        return flight_dict(f);
      }, py::arg("glider"), py::arg("speed") = 7.0, py::arg("climb_deg") = 0.0, py::arg("height") = 1.5,
      py::arg("pitch_deg") = py::none(), py::arg("pitch_rate_deg_s") = 0.0, py::arg("wind_m_s") = -1.0,
      py::arg("effects") = "physics", py::arg("strengths") = py::none(), py::arg("dt") = 0.002,
      py::arg("t_max") = 20.0, py::arg("record_every") = 1, py::arg("span_panels") = 10,
      py::arg("chord_panels") = 4,
      "One launch with the reference simulator; dict as pteromys.simulate. wind_m_s is the wind along x "
      "at wind strength 1 (used only when the 'wind' effect is on).");

  m.def("generate_dataset", [](const py::list& gliders, const std::string& out_dir, int flights_per_glider,
                               std::uint64_t seed, double noise_m, double frame_rate, std::pair<int, int> points,
                               const std::string& effects, const py::object& strengths, const std::string& window,
                               std::pair<double, double> speed, std::pair<double, double> climb_deg, double height,
                               double wind_m_s, int threads, double dt) {
        std::vector<std::pair<std::string, Glider>> gs;
        for (const auto& item : gliders) {
          if (py::isinstance<py::tuple>(item)) {
            auto t = item.cast<py::tuple>();
            Glider g = to_glider(t[1]);
            validate(g);
            gs.emplace_back(t[0].cast<std::string>(), g);
          } else {
            const std::string p = item.cast<std::string>();
            gs.emplace_back(glider_key_of(p), load_glider(p));
          }
        }
        if (!(noise_m > 0)) throw InputError("noise_m must be positive (the dataset states the tracking sigma)");
        GenerateOptions o;
        o.effects = effects_of(effects, strengths);
        o.flights_per_glider = flights_per_glider;
        o.seed = seed;
        o.camera.noise_sigma_m = noise_m;
        o.camera.frame_rate_hz = frame_rate;
        o.points_min = points.first;
        o.points_max = points.second;
        if (window == "launch") o.window = TrackWindow::Launch;
        else if (window == "landing") o.window = TrackWindow::Landing;
        else if (window == "whole") o.window = TrackWindow::Whole;
        else throw InputError("window must be 'launch', 'landing' or 'whole'");
        o.launcher.speed_min = speed.first;
        o.launcher.speed_max = speed.second;
        o.launcher.climb_min_deg = climb_deg.first;
        o.launcher.climb_max_deg = climb_deg.second;
        o.launcher.height = height;
        o.wind_m_s = wind_m_s;
        o.threads = threads;
        o.dt = time_step(dt);
        GenerateStats st;
        {
          py::gil_scoped_release nogil;
          const Dataset d = generate_dataset(gs, o, &st);
          save_dataset(d, out_dir);
        }
        py::dict r;
        r["flights"] = st.flights;
        r["redrawn"] = st.redrawn;
        r["unstable"] = st.unstable;
        r["dropped"] = st.dropped;
        r["dropped_gliders"] = st.dropped_gliders;
        r["setup_s"] = st.setup_seconds;
        r["simulate_s"] = st.simulate_seconds;
        r["effects"] = o.effects.describe();
        r["dataset_json"] = out_dir + "/dataset.json";
        return r;
      }, py::arg("gliders"), py::arg("out_dir"), py::arg("flights_per_glider") = 6, py::arg("seed") = 1,
      py::arg("noise_m") = 0.05, py::arg("frame_rate") = 30.0, py::arg("points") = std::make_pair(15, 20),
      py::arg("effects") = "physics", py::arg("strengths") = py::none(), py::arg("window") = "launch",
      py::arg("speed") = std::make_pair(7.0, 11.0), py::arg("climb_deg") = std::make_pair(0.0, 10.0),
      py::arg("height") = 1.5, py::arg("wind_m_s") = -1.0, py::arg("threads") = 2, py::arg("dt") = 0.002,
      "Synthetic flight dataset from the reference simulator (as `pteromys generate`). gliders: "
      "paths or (key, glider) tuples. Writes out_dir/dataset.json, flights.csv, gliders/; returns stats.");
}

const bool registered = register_binder(60, bind_reference);
}  // namespace
}  // namespace pteromys::python
