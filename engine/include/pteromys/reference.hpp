// The reference ("reality") simulator: a higher-fidelity aerodynamic model of
// the same flat-plate gliders, with every physical effect the paper's
// wing-element model leaves out switchable on and off with a strength
// (issue 6; docs/reference_simulator.md has the formulas and sources).
//
// - Lifting surfaces: a vortex lattice of all wings together (horseshoe
//   vortices, half span by symmetry), made nonlinear per spanwise strip by
//   decambering (Mukherjee & Gopalarathnam, J. Aircraft 43(3), 2006) against a
//   2D sharp-flat-plate section law valid to +-180 deg (attached thin-plate
//   normal force, Lindenburg's separated normal force, Kirchhoff-type logistic
//   blend), with laminar Blasius friction at the local Reynolds number.
// - Speed from structure: in pitch-plane flight of a rigid glider the lattice
//   is fixed to the body, so its influence matrix is constant per glider (per
//   wake angle and height when downwash and ground effect are on: a small grid
//   of precomputed solutions, interpolated). The right-hand side is linear in
//   (u, w, pitch rate), so each force evaluation costs a few strip-level
//   matrix-vector products and a small nonlinear solve for the decambering.
//
// Frames and signs as in docs/theory.md: glider frame x toward the nose, y up,
// z along the span; world frame x along the flight, y up; pitch beta and
// moments nose-up positive; angle of attack positive with the flow from below.
// SI units; angles in radians unless the name ends in _deg.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "pteromys/dataset.hpp"
#include "pteromys/flight.hpp"
#include "pteromys/glider.hpp"
#include "pteromys/mass.hpp"

namespace pteromys {

// ---------------------------------------------------------------- effects

/// One switchable effect: `on` and a strength multiplier. The effect enters
/// with factor() = on ? strength : 0 (strength 1 = the documented nominal).
struct EffectSwitch {
  bool on = false;
  double strength = 1.0;
  double factor() const { return on ? strength : 0.0; }
};

/// The effects of the reference simulator, named as the diagnosis library
/// names them (spec/formats.md). Aerodynamic effects (strength 1 = the full
/// physics of docs/reference_simulator.md):
///   pitch_damping  panel velocities include omega x r (scaled by strength)
///   downwash       wing-to-wing interference (off: each wing solved alone)
///   finite_span    a wing's own trailing vortices and 3D separated normal
///                  force (off: 2D strip theory per section)
///   fuselage_drag  friction and edge drag of the fuselage plate
///   ground_effect  image vortex system mirrored in the ground y = 0
///   added_mass     non-circulatory (apparent-mass) forces of the plates
/// Session effects (strength 1 = the nominal magnitude below):
///   launch_rotation  pitch rate at release, mean LauncherModel::rotation_deg_s
///   wind             steady horizontal wind, GenerateOptions::wind_m_s per unit strength
///   camera           scale error CameraModel::scale_error and roll
///                    CameraModel::roll_deg per unit strength
struct Effects {
  EffectSwitch pitch_damping, downwash, finite_span, fuselage_drag, ground_effect, added_mass;
  EffectSwitch launch_rotation, wind, camera;

  /// Everything the baseline wing-element model assumes: all effects off
  /// (quasi-static 2D strips, no interference, no fuselage, no ground, no
  /// added mass, no release rotation, still air, ideal camera up to noise).
  static Effects baseline();
  /// The six aerodynamic effects on at strength 1; session effects off.
  static Effects physics();
  /// Every effect on at strength 1.
  static Effects all();
  /// The nine names in a fixed order.
  static const std::vector<std::string>& names();
  /// Access by name; throws InputError naming the unknown effect.
  EffectSwitch& operator[](const std::string& name);
  const EffectSwitch& operator[](const std::string& name) const;
  /// "pitch_damping=1,downwash=0.5" (effects that are on) or "none".
  std::string describe() const;
};

/// Effects from a specification: "physics" (default set), "baseline" or
/// "none" (everything off), "all", or a comma-separated list of names (exactly
/// those on, at strength 1). Throws InputError naming an unknown word.
Effects parse_effects(const std::string& spec);

/// Applies "name=value,name=value": sets each strength and switches the
/// effect on (value 0 switches it off). Throws InputError on an unknown name,
/// a malformed pair or a non-finite value.
void apply_strengths(Effects& e, const std::string& spec);

// ----------------------------------------------------------- section law

/// 2D section law of a sharp flat plate (normal force, centre of pressure,
/// friction) at any angle of attack alpha in (-pi, pi] (flow from below
/// positive). The pressure force of a sharp plate is normal to it (its
/// leading-edge suction is lost):
///   attached   c_n,att = a0 sin(a) |cos(a)|        (thin-plate potential flow)
///   separated  c_n,sep = C_N90 sin(a) / (0.56 + 0.44 |sin(a)|)   (Lindenburg 2004)
///   blend      c_n = f c_n,att + (1 - f) c_n,sep,
///              f = 1 / (1 + exp((a_f - a_s) / w)),  a_f = min(|a|, pi - |a|)
/// Centre of pressure (fraction of the chord from the leading edge): 1/4
/// (3/4 when the flow comes from behind) attached; 0.5 - 0.25 cos(a) separated.
/// Friction: laminar Blasius 2 x 1.328 / sqrt(Re) on both faces, Prandtl-
/// Schlichting mixed flow above the transition Reynolds number; edge pressure
/// drag edge_drag x (thickness / chord).
struct SectionLaw {
  double lift_slope = 2 * kPi;     ///< a0 [1/rad], thin-plate theory
  double stall_deg = 9.0;          ///< a_s: 2D stall of a thin sharp plate at low Re
  double stall_width_deg = 2.0;    ///< w of the logistic blend
  double normal_force_90 = 1.98;   ///< C_N90 of a 2D plate broadside to the flow (Hoerner)
  double edge_drag = 0.5;          ///< pressure drag coefficient of the square edges, on edge area
  double transition_re = 5e5;      ///< chord Reynolds number of transition

  /// Attached-flow fraction f(alpha) in (0, 1]; derivative in df_dalpha if not null.
  double attached_fraction(double alpha, double* df_dalpha = nullptr) const;
  /// Attached-flow normal force a0 sin(a) |cos(a)|; derivative in d if not null.
  double attached_normal_force(double alpha, double* d = nullptr) const;
  /// Separated-flow normal force C_N90 sin(a) / (0.56 + 0.44 |sin(a)|).
  double separated_normal_force(double alpha, double cn90) const;
  /// Normal-force coefficient c_n(alpha) with C_N90 = cn90; derivative in dcn_dalpha if not null.
  double normal_force(double alpha, double cn90, double* dcn_dalpha = nullptr) const;
  /// Centre of pressure as a fraction of the chord from the leading edge.
  double centre_of_pressure(double alpha, double cn90) const;
  /// Skin-friction coefficient of both faces at chord Reynolds number re.
  double friction(double re) const;
};

/// Normal force of a finite flat plate of aspect ratio A broadside to the
/// flow: C_N90(A) = 1.98 - 0.81 (1 - exp(-20 / A)) (Lindenburg's fit of
/// Hoerner's data: 1.17 at A = 1, 1.19 at A = 5, 1.98 as A -> infinity).
double normal_force_90(double aspect_ratio);

// --------------------------------------------------------- the simulator

struct ReferenceOptions {
  Effects effects = Effects::physics();   ///< only the six aerodynamic switches are used here
  SectionLaw section;
  int span_panels = 10;        ///< spanwise strips per half wing (cosine spacing, finer at the tip)
  int chord_panels = 4;        ///< chordwise panels per strip (uniform, 1/4-3/4 rule)
  /// Wake angle grid for wing-to-wing interference: the wakes trail along the
  /// free stream at the glider's angle of attack, clamped to this range [deg].
  double wake_angle_min_deg = -20.0, wake_angle_max_deg = 30.0, wake_angle_step_deg = 5.0;
  int ground_heights = 7;      ///< finite heights of the ground-effect grid (plus infinity)
  double ground_height_max_spans = 3.0;  ///< beyond this height (x largest span) no ground effect
  /// Edge-vortex lift (Polhamus' leading-edge and Lamar's side-edge suction
  /// analogies), a 3D effect: it enters with vortex_lift x finite_span.
  double vortex_lift = 1.0;
  /// Leading-edge vortex lift grows from 0 to full between these sweeps [deg]
  /// (unswept sharp edges form a reattaching bubble, not a lifting vortex).
  double le_vortex_sweep_deg[2] = {20.0, 50.0};
  /// Vortex breakdown: edge-vortex lift fades as 1 / (1 + exp((|a| - a_b) / w_b))
  /// of the geometric angle of attack; {a_b, w_b} [deg].
  double vortex_breakdown_deg[2] = {40.0, 3.0};
  double alpha_limit_deg = 90.0;  ///< flights whose wing angle of attack exceeds this are 'unstable'
  int max_iterations = 40;     ///< decambering solve
  double tolerance = 1e-9;     ///< decambering solve, on the normalised induced velocity
};

/// Geometry of one spanwise strip of the lattice (a chordwise column of
/// panels on the z > 0 half; its mirror is implied). Glider frame, relative
/// to the reference point (the centre of gravity).
struct ReferenceStrip {
  int wing = 0;          ///< index into Glider::wings
  double z0 = 0, z1 = 0; ///< spanwise extent on the half wing [m]
  double chord = 0;      ///< mean chord [m]
  double area = 0;       ///< both halves [m^2]
  Vec2 leading_edge;     ///< mid-span leading-edge point [m]
  int panel_begin = 0, panel_end = 0;  ///< its panels in the lattice
};

/// Detailed loads of one evaluation (body frame = glider frame; forces [N],
/// moments about the reference point [N m], nose-up positive).
struct ReferenceLoads {
  Vec2 force_body;                 ///< total air force, glider frame
  double moment = 0;               ///< total pitching moment
  std::vector<Vec2> wing_force;    ///< per wing, glider frame
  std::vector<double> wing_moment; ///< per wing
  Vec2 fuselage_force;             ///< glider frame
  double fuselage_moment = 0;
  std::vector<double> strip_alpha_eff;  ///< effective angle of attack of each strip [rad]
  std::vector<double> strip_cn;         ///< normal-force coefficient of each strip (local dynamic pressure)
  double vortex_normal_force = 0;  ///< edge-vortex lift part of the plates' normal forces [N]
  int iterations = 0;              ///< of the decambering solve
  bool converged = true;
};

/// Linear (potential) lattice solution at one angle of attack, for classical
/// checks: lift coefficient from Kutta-Joukowski on the bound vortices and
/// induced drag in a planar Trefftz plane (meaningful for single wings or
/// coplanar wings). Coefficients use the total planform area of all wings.
struct PotentialSolution {
  double cl = 0;    ///< lift coefficient
  double cdi = 0;   ///< induced drag coefficient (Trefftz plane, with leading-edge suction)
  double area = 0;  ///< reference area [m^2]
  double span = 0;  ///< largest span [m]
  std::vector<double> z;      ///< strip mid-span stations on the half span [m]
  std::vector<double> gamma;  ///< spanwise circulation there [m^2/s]
};

/// The reference aerodynamics of a glider: plugs into simulate() like the
/// baseline (AeroForces). Immutable after construction; evaluate() is
/// thread-safe. Construction cost: one LU factorisation per grid node
/// (wake angle x height), a few milliseconds each.
class ReferenceAero final : public AeroForces {
 public:
  /// Moments about the glider's centre of gravity (mass_properties(g).cg).
  ReferenceAero(const Glider& g, const ReferenceOptions& opt = {}, const Environment& env = {});
  /// Moments about `reference` (glider frame [m]); a glider with an empty
  /// fuselage outline (wind-tunnel model of bare wings) is accepted.
  ReferenceAero(const Glider& g, Vec2 reference, const ReferenceOptions& opt,
                const Environment& env = {});
  ~ReferenceAero() override;

  /// World-frame air force and moment about the reference point. s.v is the
  /// velocity relative to the air, s.p.y the height above the ground (ground
  /// effect), s.omega the pitch rate (pitch damping).
  Wrench evaluate(const FlightState& s) const override;
  double max_alpha(const FlightState& s) const override;
  double alpha_limit() const override;
  bool has_added_mass() const override;
  AddedMass added_mass(const FlightState& s) const override;

  /// Evaluation with the breakdown (body frame).
  ReferenceLoads loads(const FlightState& s) const;
  /// Air force in wind axes at speed v [m/s], glider angle of attack gamma
  /// [rad], pitch rate omega [rad/s] and height [m] (infinity: no ground):
  /// drag along -velocity, lift perpendicular (up), moment nose-up.
  GliderForces forces(double v, double gamma, double omega = 0, double height = 1e9) const;
  /// Linear lattice solution at angle of attack gamma (no decambering, no
  /// ground, no pitch rate, unit speed).
  PotentialSolution potential(double gamma) const;

  const std::vector<ReferenceStrip>& strips() const;
  int panel_count() const;
  int node_count() const;      ///< grid nodes (wake angle x height) factorised
  const ReferenceOptions& options() const;
  /// Total added mass of the plates normal to themselves, sum of
  /// rho pi c^2 b / 4 over strips (strength 1) [kg].
  double plate_added_mass() const;
  /// Evaluations whose decambering solve did not reach the tolerance.
  long unconverged_count() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

// ------------------------------------------------- launcher and camera

/// The launcher of a recording session (paper section 5.1: a rubber-band
/// rail). Nominal speeds and climb angles are spread evenly over the flights
/// of each glider (stratified over [min, max]); each flight then adds Gaussian
/// scatter. Release height and the release instant scatter too.
struct LauncherModel {
  double speed_min = 7.0, speed_max = 11.0;  ///< m/s (factors of the glide speed when speed_relative)
  double speed_sigma = 0.25;                 ///< m/s (a fraction of the glide speed when speed_relative)
  /// Launch speeds relative to each glider's steady glide speed in the
  /// reality being simulated (steady_glide of the reference forces): a person
  /// throws a glider at about the speed at which it glides, so that flights of
  /// different gliders and of different realities are alike (default off:
  /// absolute speeds, as the paper's standard launches).
  bool speed_relative = false;
  double climb_min_deg = 0.0, climb_max_deg = 10.0;
  double climb_sigma_deg = 1.0;
  double pitch_offset_deg = 0.0;             ///< mean pitch minus climb at release
  double pitch_sigma_deg = 1.5;
  double pitch_rate_deg_s = 0.0;             ///< mean pitch rate at release without launch_rotation
  double pitch_rate_sigma_deg_s = 0.0;
  /// launch_rotation at strength 1: mean pitch rate at release (nose-up) and its spread.
  double rotation_deg_s = 60.0, rotation_sigma_deg_s = 20.0;
  double height = 1.5, height_sigma = 0.03;  ///< m
  /// Release instant after the first camera frame of the recording [s].
  double release_delay_s = 0.1, release_sigma_s = 0.03;
};

/// Side camera looking along -z at the flight plane. A recorded point is
///   q = c + k R(phi) (p - c) + noise,
/// with c the world point on the optical axis, k the scale error of a wrong
/// flight-plane distance (k = D_calibrated / D_true), phi the camera roll and
/// Gaussian noise of sigma per coordinate.
struct CameraModel {
  double frame_rate_hz = 30.0;
  double noise_sigma_m = 0.05;
  Vec2 centre = {3.0, 1.0};       ///< world [m]
  double scale = 1.0;             ///< k
  double roll_deg = 0.0;          ///< phi, counter-clockwise
  /// camera effect at strength 1: k = 1 + scale_error, phi = roll_error_deg.
  double scale_error = 0.03, roll_error_deg = 2.0;
  /// The recorded point of world point p without noise.
  Vec2 project(Vec2 p) const;
};

/// Which frames of a flight are tracked.
enum class TrackWindow {
  Launch,   ///< from the first frame after release (as the paper's launch fit assumes)
  Landing,  ///< the last frames before ground contact
  Whole     ///< every frame from release to ground contact (points_max ignored)
};

struct GenerateOptions {
  Effects effects = Effects::physics();
  ReferenceOptions aero;   ///< its effects are replaced by `effects`
  LauncherModel launcher;
  CameraModel camera;
  double wind_m_s = -1.0;  ///< world x wind at wind strength 1 (negative: headwind)
  int flights_per_glider = 6;
  std::uint64_t seed = 1;
  int points_min = 15, points_max = 20;
  TrackWindow window = TrackWindow::Launch;
  double dt = 0.002;       ///< simulation step [s]
  int max_attempts = 20;   ///< draws per flight until it has >= 6 tracked points
  /// A launch none of whose draws gives 6 tracked points (the glider hits the
  /// ground or tumbles at once in this reality) is left out and reported in
  /// GenerateStats; a glider left without flights is left out of the dataset.
  /// strict: throw InputError instead.
  bool strict = false;
  int threads = 2;         ///< gliders are simulated in parallel
  /// Trim every glider for the reality it flies in, as a person bends the
  /// tail and adds nose weight until the glider glides (retrim_glider): its
  /// trim wing (the smallest, GliderFeatures::trim_wing) is turned so that
  /// the reference's pitch equilibrium lies at retrim_alpha_deg angle of
  /// attack, with nose weight where it would not be stable. The dataset's
  /// glider files hold the trimmed gliders (what flew). Gliders with one wing
  /// are left as they are.
  bool retrim = false;
  double retrim_alpha_deg = 4.0;
  Environment env;
  /// Called after every flight with (flights done, flights total, glider key).
  std::function<void(int, int, const std::string&)> progress;
};

/// What generation did, beside the dataset.
struct GenerateStats {
  int flights = 0;
  int redrawn = 0;          ///< draws rejected (fewer than 6 tracked points)
  int unstable = 0;         ///< kept flights that ended unstable in the reference
  int dropped = 0;          ///< launches left out (no draw gave 6 tracked points)
  std::vector<std::string> dropped_gliders;  ///< gliders left out (no flight at all)
  double setup_seconds = 0, simulate_seconds = 0;
};

/// A dataset of synthetic tracked flights (spec "Flight dataset") from the
/// reference simulator: gliders[i] = (key, glider). Flights are named
/// "<key>-<nn>"; per-flight columns give the true launch:
/// true_speed_m_s, true_climb_deg, true_pitch_deg, true_pitch_rate_deg_s,
/// true_height_m, true_release_t_s (the release instant on the t_s axis),
/// true_end (ground, time_limit or unstable). Deterministic given the seed
/// (independent of the thread count). Throws InputError on bad options.
Dataset generate_dataset(const std::vector<std::pair<std::string, Glider>>& gliders,
                         const GenerateOptions& opt, GenerateStats* stats = nullptr);

/// The glider `g` trimmed for the reality of the reference forces (options
/// `aero`), as a person trims a glider until it glides: the mounting angle of
/// its trim wing is turned so that the pitch equilibrium (level flight at
/// 5 m/s in still air far from the ground) lies at `alpha_deg` angle of
/// attack, and where that equilibrium has a static margin below 5 % of the
/// main wing's mean chord, nose weight (a ballast item "trim weight" 5 mm
/// behind the fuselage's tip) is added in steps of 5 % of the glider's mass
/// until it is stable (see GenerateOptions::retrim). `turned_deg` and
/// `nose_weight_kg`, when given, receive the changes. Throws InputError
/// naming the glider (`key`) when no turn within +-15 degrees or no nose
/// weight up to the glider's own mass does it.
Glider retrim_glider(const std::string& key, const Glider& g, double alpha_deg, const ReferenceOptions& aero,
                     const Environment& env = {}, double* turned_deg = nullptr, double* nose_weight_kg = nullptr);

/// The tracked points of one simulated flight: frames at k / frame_rate on
/// the camera clock, release at `release_t` on that clock, recorded through
/// `camera` (noise from `noise`, one standard normal per call). `n_points`
/// frames from the window; ground-relative world positions of `f`'s samples.
std::vector<TrackedPoint> track_flight(const Flight& f, double release_t, const CameraModel& camera,
                                       TrackWindow window, int n_points,
                                       const std::function<double()>& noise);

}  // namespace pteromys
