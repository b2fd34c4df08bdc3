// Candidate effects of the sim-to-real diagnosis (issue 7; spec/formats.md,
// "Diagnosis result"): small parametric corrections of the fast wing-element
// model, one or two strength parameters each, every one zero = the baseline
// model exactly. They are NOT copies of the reference simulator's physics:
// each keeps the baseline's per-wing force tables over (V, alpha) and only
// changes where a table is looked up (a wing's local speed and angle of
// attack), adds a classical closed-form force, or acts on the launch, the air
// or the camera (docs/diagnosis.md gives formulas and sources).
//
//   pitch_damping   k_pd: wing j is looked up with the air velocity at its
//                   3/4-chord point, a - k_pd omega z x r_j (Pistolesi's
//                   3/4-chord rule; full rigid-body kinematics at k_pd = 1)
//   downwash        k_dw: every other wing i is a horseshoe vortex (bound leg
//                   on its 1/4-chord line over the elliptic-loading span
//                   pi b_i / 4, Gamma_i = V L_i / (2 b'_i) from its table
//                   lift, legs along the free stream); its Biot-Savart
//                   velocity, times k_dw, is added to wing j's air
//                   (downwash behind a wing, upwash ahead of it)
//   finite_span     k_fs: each wing's own induced angle
//                   eps_j = k_fs C_L,j / (pi A_j e_j) lowers its angle of
//                   attack and tilts its force back (induced drag
//                   C_L eps); e_j matches Helmbold's lift slope of aspect
//                   ratio A_j for the table's section slope (lifting line
//                   at large A, Helmbold at small A)
//   fuselage_drag   k_fd: laminar friction of the fuselage plate, both
//                   faces, k_fd q 2 S_fus 1.328 / sqrt(Re_L) (Blasius), along
//                   the flow at the plate's centroid
//   ground_effect   k_ge: the induced angle falls near the ground,
//                   eps_j -= k_ge (1 - phi(h / b_j)) C_L,j / (pi A_j e_j),
//                   phi = (16 h/b)^2 / (1 + (16 h/b)^2) (McCormick 1979);
//                   h = height of the CG above the ground
//   launch_rotation omega_0 [rad/s]: every flight's pitch rate at its first
//                   tracked point (the launch fit leaves it at 0)
//   added_mass      k_am: apparent mass k_am rho pi l^2 dz / 4 and rotary
//                   inertia k_am rho pi l^4 dz / 128 of each wing's strips
//                   (l chord, dz width), normal to the plate at the wing's
//                   mid-chord point (AeroForces::added_mass)
//   wind            w_x [m/s]: steady horizontal wind of the session
//                   (SimOptions::wind; negative = headwind)
//   camera          kappa, phi [rad]: recorded = (1 + kappa) R(phi) true
//                   (+ a constant offset, absorbed by the launch positions)
//
// Frames and signs as in docs/theory.md: glider frame x to the nose, y up;
// world frame x along the flight, y up; pitch, moments and angles of attack
// nose-up positive. SI units; angles in radians.
#pragma once

#include <array>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "pteromys/aero.hpp"
#include "pteromys/dataset.hpp"
#include "pteromys/flight.hpp"

namespace pteromys {

/// The candidate effects, in the order of spec/formats.md.
enum class Effect {
  PitchDamping, Downwash, FiniteSpan, FuselageDrag, GroundEffect, LaunchRotation, AddedMass, Wind, Camera
};

/// Where an effect acts.
enum class EffectLevel {
  Aerodynamic,  ///< forces of the glider (an AeroForces wrapper)
  Launch,       ///< the launch state of every flight
  Session,      ///< the air of the recording session
  Observation   ///< the camera's recording
};

/// One strength parameter of an effect.
struct EffectParameter {
  std::string name;      ///< JSON key, ends in its unit where it has one (e.g. "omega_deg_s")
  std::string unit;      ///< "-", "rad/s", "m/s", "rad"
  double scale = 1;      ///< typical size (solver units) [unit]
  double lower = -1e9;   ///< bounds of the fit [unit]
  double upper = 1e9;
  double to_report = 1;  ///< factor from the internal unit to the reported one (rad -> deg: 180/pi)
  /// Values the fit also starts from (besides zero, the baseline) [unit]:
  /// trajectories depend on a strength far from linearly (a damped and an
  /// undamped flight differ by metres), so a solver started at zero alone
  /// can stop in the baseline's basin.
  std::vector<double> starts;
  /// The largest size (|value|, [unit]) the effect plausibly has in a real
  /// recording; a fit beyond it is not taken as that effect
  /// (EffectSpec::plausibility says why). Infinity: no limit but the bounds.
  double plausible = std::numeric_limits<double>::infinity();
};

struct EffectSpec {
  Effect effect;
  std::string name;          ///< spec name ("pitch_damping", ...)
  std::string description;   ///< one line for a person
  EffectLevel level;
  std::vector<EffectParameter> parameters;  ///< 1 or 2
  /// Why the parameters' plausible sizes are what they are (empty: no limits).
  std::string plausibility{};
};

/// Every effect, in the spec's order.
const std::vector<Effect>& all_effects();
const EffectSpec& effect_spec(Effect e);
const std::string& effect_name(Effect e);
/// Throws InputError naming the unknown effect and the known ones.
Effect effect_from_name(const std::string& name);
/// The first of `values` (effect_spec(e) order, internal units) whose size
/// exceeds its plausible one, or -1 when all are plausible. `limits`
/// (internal units, one per parameter) replaces the parameters' own
/// EffectParameter::plausible when given.
int implausible_parameter(Effect e, const std::vector<double>& values, const std::vector<double>* limits = nullptr);

/// Strengths of every candidate effect; all zero = the baseline model. Any
/// combination may be on at once (two-effect checks, the oracle).
struct EffectValues {
  double pitch_damping = 0;    ///< k_pd [-]
  double downwash = 0;         ///< k_dw [-]
  double finite_span = 0;      ///< k_fs [-]
  double fuselage_drag = 0;    ///< k_fd [-]
  double ground_effect = 0;    ///< k_ge [-]
  double launch_rotation = 0;  ///< omega_0, pitch rate at the first tracked point [rad/s], nose-up positive
  double added_mass = 0;       ///< k_am [-]
  double wind = 0;             ///< w_x, world x wind [m/s] (negative: headwind)
  double camera_scale = 0;     ///< kappa: recorded = (1 + kappa) R(phi) true [-]
  double camera_roll = 0;      ///< phi, counter-clockwise [rad]
  /// launch_rotation as a launch parameter: every flight's pitch rate at its
  /// first tracked point is fitted with the rest of its launch (a thrower
  /// gives each flight its own rate); launch_rotation is then their mean, for
  /// reporting and as the start of a fresh launch fit.
  bool launch_rotation_per_flight = false;

  /// Parameter i of effect e (spec order of effect_spec(e).parameters).
  double& at(Effect e, int i);
  double at(Effect e, int i) const;
  /// True when every aerodynamic strength is zero (forces = the baseline's).
  bool aerodynamic_zero() const;
  bool zero() const;
};

/// Geometry of one wing as the corrections need it (glider frame, relative to
/// the centre of gravity).
struct WingFeatures {
  double area = 0;           ///< planform area S [m^2]
  double span = 0;           ///< b [m]
  double aspect_ratio = 0;   ///< A = b^2 / S
  double mean_chord = 0;     ///< S / b [m]
  double theta = 0;          ///< mounting angle [rad]
  Vec2 mount;                ///< mounting point - CG [m]
  Vec2 quarter_chord;        ///< area-weighted mean 1/4-chord point - CG [m]
  Vec2 three_quarter_chord;  ///< area-weighted mean 3/4-chord point - CG [m]
  Vec2 mid_chord;            ///< area-weighted mean mid-chord point - CG [m]
  double apparent_mass = 0;     ///< pi/4 sum l^2 dz [m^3] (times rho: kg)
  double apparent_inertia = 0;  ///< pi/128 sum l^4 dz [m^5] (times rho: kg m^2)
  /// The planform in spanwise bands (downwash): its element slices, grouped
  /// into at most kWakeBands; each band's extent, area, mean chord (area /
  /// width) and area-weighted mean 1/4- and 3/4-chord points (glider frame,
  /// - CG) [m].
  struct Band {
    double z0 = 0, z1 = 0, area = 0, chord = 0;
    Vec2 quarter, three_quarter;
  };
  std::vector<Band> bands;
};

/// At most this many spanwise bands resolve a wing's wake and its downwash targets.
constexpr int kWakeBands = 48;
/// Wake angles of the downwash table: psi (the free stream's angle in the
/// glider frame, = the glider's angle of attack in still air) from
/// kWakeAngleMin to kWakeAngleMax degrees in 1 degree steps; clamped outside.
constexpr int kWakeAngleMin = -30, kWakeAngleMax = 40;

/// Geometry, mass and the features the diagnosis reports per glider.
struct GliderFeatures {
  double mass = 0;            ///< kg
  double inertia = 0;         ///< kg m^2 about the CG
  Vec2 cg;                    ///< glider frame [m]
  std::vector<WingFeatures> wings;
  int main_wing = 0;          ///< largest area
  int trim_wing = -1;         ///< the wing a build-trim error is given to: the smallest (aft-most on ties); -1 for one wing
  double span = 0;            ///< largest span [m]
  double fuselage_area = 0;   ///< one face [m^2]
  double fuselage_length = 0; ///< x extent [m]
  Vec2 fuselage_centroid;     ///< - CG [m]
  // Reported features (docs/diagnosis.md):
  double main_aspect_ratio = 0;
  double tail_aspect_ratio = 0;   ///< of the trim wing (0 without one)
  double tail_arm = 0;            ///< |x distance| of the two wings' 1/4-chord points [m]
  double tail_volume = 0;         ///< S_t l_t / (S_w c_w) (0 without a second wing)
  double wing_loading = 0;        ///< m g / (total wing area) [N/m^2]
  double fuselage_ratio = 0;      ///< fuselage area / main wing area
  /// Downwash: the wake of wing i loaded as the strip model loads it
  /// (circulation 1/2 c(z) per unit V_i C_L,i on every band: a horseshoe per
  /// band, bound leg on its 1/4-chord line, legs along the free stream at
  /// angle psi) induces at wing j, area-weighted over j's bands' 3/4-chord
  /// points, the mean velocity wake_unit(i, j, psi) (glider frame) [m/s per
  /// (m/s)]; 0 for i == j. Tabulated per degree of psi when the features
  /// are made (the geometry is fixed to the body); linear in between.
  std::vector<Vec2> wake_influence;  ///< (i * n + j) * angles + k
  Vec2 wake_unit(std::size_t i, std::size_t j, double psi) const;
};

/// Features of a glider (wing elements at spacing dz [m]).
GliderFeatures glider_features(const Glider& g, double dz = 0.005, double gravity = 9.81);

/// Helmbold-equivalent span efficiency e of a wing of aspect ratio A for
/// section lift slope a0 [1/rad]: the lifting-line slope a0 / (1 + a0/(pi A e))
/// equals Helmbold's a0 / (sqrt(1 + (a0/(pi A))^2) + a0/(pi A)).
double helmbold_efficiency(double aspect_ratio, double section_slope);

/// McCormick's ground-effect factor phi(h/b) = (16 h/b)^2 / (1 + (16 h/b)^2)
/// of the induced drag (0 on the ground, -> 1 far from it).
double ground_factor(double height_over_span);

/// Velocity induced at point p by a horseshoe vortex of circulation gamma
/// [m^2/s] (3-D, glider frame): bound leg from a to b, legs from a and b to
/// infinity along the unit vector d (the free stream's direction, 3-D with
/// d[2] = 0), core radius rc [m] (Rankine-type smoothing 1/(h^2 + rc^2)).
/// The bound leg's vector a -> b (+z for a lifting wing) and the air's
/// velocity give lift by Kutta-Joukowski.
std::array<double, 3> horseshoe_velocity(const std::array<double, 3>& p, const std::array<double, 3>& a,
                                         const std::array<double, 3>& b, const std::array<double, 3>& d,
                                         double gamma, double rc);

/// Per-wing state of a corrected evaluation (glider frame).
struct WingFlow {
  double speed = 0;   ///< local air speed [m/s]
  double alpha = 0;   ///< angle of attack the table is looked up at [rad]
  double gamma = 0;   ///< local effective flow angle (as the glider's gamma) [rad]
  double cl = 0;      ///< table lift / area at (speed, alpha)
  WingCoefs coefs;    ///< the table's look-up at (speed, alpha), as evaluate uses it
};

/// The baseline quasi-static model of a mounted glider with the aerodynamic
/// corrections of `values` (pitch_damping, downwash, finite_span,
/// fuselage_drag, ground_effect, added_mass; the session and observation
/// parameters are ignored here). With every aerodynamic strength zero it
/// returns QuasiStaticAero's forces exactly (same code path).
/// `height_origin` [m]: the simulator's y of the ground (ground effect: the
/// height is s.p.y - height_origin). Holds references: `g` and `f` must
/// outlive it. Thread-safe (const evaluation).
class EffectAero final : public AeroForces {
 public:
  EffectAero(const MountedGlider& g, const GliderFeatures& f, const EffectValues& values, double height_origin = 0);
  Wrench evaluate(const FlightState& s) const override;
  double max_alpha(const FlightState& s) const override;
  /// One pass of the wings' flows for both (the same values as the two calls).
  Wrench evaluate_and_max_alpha(const FlightState& s, double& max_alpha_out) const override;
  double alpha_limit() const override { return g_.alpha_limit(); }
  bool has_added_mass() const override { return values_.added_mass != 0; }
  AddedMass added_mass(const FlightState& s) const override;

  /// Local flow of every wing in state s (air-relative velocity s.v).
  std::vector<WingFlow> wing_flows(const FlightState& s) const;
  /// Section lift slope of wing j's table near alpha = 0 at 8 m/s [1/rad].
  double section_slope(std::size_t j) const { return slope_[j]; }

 private:
  /// `coefs` false: only speed, alpha and gamma are wanted (max_alpha); when
  /// no pass iterates they do not depend on the tables, which are skipped.
  /// `cb`, `sb`: cos and sin of s.beta (computed once a force evaluation and
  /// shared with wrench: the same values as computing them in each).
  void flows(const FlightState& s, WingFlow* out, bool coefs, double cb, double sb) const;
  double induced_solve(std::size_t j, const WingTable::SpeedWeights& sw, double c, double ageo, double x) const;
  /// The wrench of state s from its wings' flows `fl` (computed by flows),
  /// with cb, sb as there.
  Wrench wrench(const FlightState& s, const WingFlow* fl, double cb, double sb) const;
  const MountedGlider& g_;
  const GliderFeatures& f_;
  EffectValues values_;
  double height_origin_;
  QuasiStaticAero base_;
  std::vector<double> slope_, efficiency_;
  bool iterate_ = false;
  double rho_ = 1.2, mu_ = 1.8e-5;
};

/// Camera correction of a tracked point: the world point whose recording is q
/// (inverse of recorded = (1 + kappa) R(phi) world).
Vec2 camera_to_world(Vec2 q, const EffectValues& v);
Vec2 world_to_camera(Vec2 p, const EffectValues& v);

}  // namespace pteromys
