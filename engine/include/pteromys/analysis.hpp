// Flyability analysis: trim, pitch stability, static margin, glide, launches
// (spec/formats.md "Flyability report"; paper section 6).
#pragma once

#include <string>
#include <vector>

#include "pteromys/aero.hpp"
#include "pteromys/flight.hpp"

namespace pteromys {

/// The region of interest Omega = [v_min, v_max] x [gamma_min, gamma_max].
struct Region {
  double v_min = 6.0, v_max = 9.0;                       ///< m/s
  double gamma_min = deg2rad(-10.0), gamma_max = deg2rad(10.0);  ///< rad
};

/// A point of the T_z = 0 line: at speed v the glider is in pitch equilibrium
/// at angle of attack gamma.
struct TrimPoint {
  double v = 0;       ///< m/s
  double gamma = 0;   ///< rad
  double lift = 0, drag = 0;  ///< N
  double dmoment_dgamma = 0;  ///< N m / rad; negative = pitch-stable
};

/// Steady straight glide: the angle of attack where T_z = 0 and the speed
/// where the air force balances the weight.
struct Glide {
  bool exists = false;
  double gamma = 0;        ///< rad
  double speed = 0;        ///< m/s
  double ratio = 0;        ///< lift / drag
  double sink_rate = 0;    ///< m/s
  double path_angle = 0;   ///< descent angle theta [rad]
};

struct LaunchResult {
  Launch launch;
  Flight flight;
};

struct AnalysisOptions {
  Region region;
  double launch_height = 1.5;     ///< m
  SimOptions sim;
  double max_trim_speed = 12.0;   ///< a hand launch does not give more [m/s]
  double min_glide_ratio = 2.0;   ///< below this the glider does not glide
  bool keep_samples = true;       ///< keep the trajectories of the launches
};

struct Flyability {
  MassProperties mass;
  std::vector<Mount> mounts;
  std::vector<std::string> wing_names;
  bool flyable = false;
  std::vector<std::string> reasons;   ///< why not flyable, in plain words
  std::vector<std::string> warnings;  ///< model limits met by this design
  bool pitch_stable = false;
  std::vector<TrimPoint> trim;        ///< on Omega, one per sampled speed where it exists
  Glide glide;
  double neutral_point_x = 0;         ///< glider x of the neutral point [m]
  double static_margin = 0;           ///< (x_cg - x_np) / reference chord
  double reference_chord = 0;         ///< mean chord of the largest wing [m]
  std::vector<LaunchResult> launches;
};

/// Angle of attack in [lo, hi] where T_z(v, gamma) = 0 with negative slope
/// (the stable equilibrium); false when there is none.
bool find_trim(const MountedGlider& g, double v, double lo, double hi, TrimPoint* out);

/// Glider x of the neutral point [m] evaluated at (v, gamma): the point about
/// which the pitching moment does not change with the angle of attack.
/// Shifting the moment reference by delta along the glider's x axis adds
/// delta * F_Y (the air force normal to that axis) to T_z, so
/// x_np = x_cg + (dT_z/dgamma) / (dF_Y/dgamma). NaN when dF_Y/dgamma = 0.
double neutral_point(const MountedGlider& g, double v, double gamma);

/// Steady glide of the mounted glider (see Glide).
Glide steady_glide(const MountedGlider& g, double gamma_lo, double gamma_hi);

/// The characteristic function F(V, gamma) of any aerodynamic model: drag,
/// lift [N] and pitching moment about the CG [N m] in level flight at air
/// speed v [m/s] and angle of attack gamma [rad], still air, no pitch rate,
/// at `height` above the ground [m] (far enough by default that ground
/// effect is absent).
GliderForces level_forces(const AeroForces& a, double v, double gamma, double height = 100.0);

/// Steady glide of any aerodynamic model (the reference simulator, a
/// corrected model) with the same search as the mounted glider's: the stable
/// pitch equilibrium in [gamma_lo, gamma_hi] nearest gamma = 0, at the speed
/// where the air force equals the weight.
Glide steady_glide(const AeroForces& a, const RigidBody& body, double gravity = 9.81,
                   double gamma_lo = deg2rad(-15.0), double gamma_hi = deg2rad(25.0));

/// Full analysis, including the six standard launches.
Flyability analyse(const MountedGlider& g, const std::vector<std::string>& wing_names,
                   const AnalysisOptions& opt = {});

}  // namespace pteromys
