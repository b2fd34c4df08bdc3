// Shared helpers of the binding files (one bind_<area>.cpp per area).
#pragma once

#include <memory>
#include <string>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "pteromys/analysis.hpp"
#include "pteromys/coefficients.hpp"
#include "pteromys/glider.hpp"
#include "pteromys/io.hpp"
#include "pteromys/version.hpp"

namespace pteromys::python {
namespace py = pybind11;
using ModelPtr = std::shared_ptr<const CoefficientModel>;
/// pybind11 holds models as shared_ptr<CoefficientModel>; they are never mutated.
inline std::shared_ptr<CoefficientModel> mut(const ModelPtr& p) { return std::const_pointer_cast<CoefficientModel>(p); }

/// A Glider from a Glider, a dict in the glider-file format, or a file path.
Glider to_glider(const py::object& o);
/// A model from None (the shipped default), a path, or a model object.
ModelPtr to_model(const py::object& o);
/// Trajectory as an (n x 9) array: t, x, y, pitch_deg, speed, alpha_deg, omega_deg_s, vx, vy.
py::array_t<double> samples_array(const Flight& f);
/// `v` if finite; otherwise InputError "KEY must be a finite number".
double finite_value(const char* key, double v);
/// The element spacing `dz` [m] if in (0, 0.1], as the commands' --dz;
/// otherwise InputError "dz must be in (0, 0.1] m".
double element_spacing(double dz);
/// The standard launches' height [m] if in [0, 100], as the commands'
/// --height; otherwise InputError "height must be between 0 and 100 m".
double launch_height(double height);
/// A simulation step [s] if in [1e-5, 0.05], as every command's --dt (a
/// smaller one would run for hours); otherwise InputError "dt must be in
/// [1e-05, 0.05] s, got <dt>".
double time_step(double dt);
/// One launch from Python keywords (simulate, reference_simulate): every
/// value finite, speed and height not negative; pitch_deg None = along the path.
Launch one_launch(double speed, double climb_deg, double height, const py::object& pitch_deg,
                  double pitch_rate_deg_s);
/// Simulation options from Python keywords: dt in [1e-5, 0.05] s, t_max in
/// (0, 600] s, record_every >= 1, integrator "verlet" or "rk4".
SimOptions sim_options(double dt, double t_max, const std::string& integrator, int record_every);
/// A flight as the dict of pteromys.simulate (samples, stable, reason, ...).
py::dict flight_dict(const Flight& f);

/// Binders of each area, run by PYBIND11_MODULE in `order`. Each
/// bind_<area>.cpp registers itself with a static initialiser:
///   static const bool reg = register_binder(10, bind_core);
using Binder = void (*)(py::module_&);
bool register_binder(int order, Binder b);

}  // namespace pteromys::python
