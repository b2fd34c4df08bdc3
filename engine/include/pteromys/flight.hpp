// Pitch-plane flight simulation (paper section 4.3, eq. 4).
#pragma once

#include <string>
#include <vector>

#include "pteromys/aero.hpp"

namespace pteromys {

/// State of the glider in the world frame (x horizontal along the flight,
/// y up). beta: pitch angle of the glider's x axis above the horizontal
/// (nose up positive) [rad]; omega = d beta / dt [rad/s].
struct FlightState {
  double t = 0;
  Vec2 p;      ///< centre of gravity [m]
  Vec2 v;      ///< velocity of the CG [m/s] (relative to the ground)
  double beta = 0;
  double omega = 0;
};

/// Aerodynamic force on the glider (world frame) [N] and pitching moment about
/// the CG [N m]; gravity is added by the simulator.
struct Wrench {
  Vec2 force;
  double moment = 0;
};

/// Added-mass (apparent-mass) terms of a model, in the simulator's generalised
/// coordinates q = (x, y, beta) of the world frame: the air force contains
/// -m * (x'', y'', beta'') + bias, so the simulator solves
/// (diag(M, M, I) + m) q'' = F + bias + gravity. m: symmetric positive
/// semi-definite 3 x 3 [kg, kg m, kg m^2]; bias [N, N, N m].
struct AddedMass {
  double m[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
  double bias[3] = {0, 0, 0};
};

/// What the simulator asks of an aerodynamic model. Every model (the paper's
/// quasi-static wing elements, the reference simulator, the baseline extended
/// by a candidate effect) implements it.
class AeroForces {
 public:
  virtual ~AeroForces() = default;
  /// `s.v` is the velocity relative to the air (the simulator subtracts wind).
  virtual Wrench evaluate(const FlightState& s) const = 0;
  /// Largest |angle of attack| of any wing in state `s` (air-relative) [rad].
  virtual double max_alpha(const FlightState& s) const = 0;
  /// evaluate(s) and max_alpha(s) of one state. The simulator's stall check
  /// asks for the angles where it evaluates the force (Verlet: each step's
  /// predicted state; RK4: each step's end, the next step's first force), so
  /// a model whose angles cost as much as its forces (EffectAero with its
  /// induced angles or wakes) computes them once. The default calls
  /// max_alpha, then evaluate.
  virtual Wrench evaluate_and_max_alpha(const FlightState& s, double& max_alpha_out) const {
    max_alpha_out = max_alpha(s);
    return evaluate(s);
  }
  /// Model validity: a wing angle of attack beyond this means unstable flight [rad].
  virtual double alpha_limit() const = 0;
  /// Optional added mass (default none: the simulator then integrates eq. 4
  /// exactly as before). `s.v` is relative to the air, as for evaluate().
  virtual bool has_added_mass() const { return false; }
  virtual AddedMass added_mass(const FlightState&) const { return {}; }
};

/// Flight-path angle theta (descending positive) and glider angle of attack
/// gamma = theta + beta of a state, with gamma wrapped to (-pi, pi].
double path_angle(const FlightState& s);
double angle_of_attack(const FlightState& s);

/// The paper's quasi-static model: F(V, gamma) of a MountedGlider turned into
/// the world frame (eq. 4).
class QuasiStaticAero final : public AeroForces {
 public:
  explicit QuasiStaticAero(const MountedGlider& g) : g_(g) {}
  Wrench evaluate(const FlightState& s) const override;
  double max_alpha(const FlightState& s) const override;
  double alpha_limit() const override;

 private:
  const MountedGlider& g_;
};

/// No air at all: ballistic flight (for checks and for the paper's Fig. 13).
class NoAero final : public AeroForces {
 public:
  Wrench evaluate(const FlightState&) const override { return {}; }
  double max_alpha(const FlightState&) const override { return 0; }
  double alpha_limit() const override { return 1e9; }
};

/// A hand launch. The glider leaves the hand at `height` above the ground with
/// speed `speed` along a path `climb_deg` above the horizontal; its pitch is
/// `pitch_deg` (nose up positive; by default equal to the path, so that the
/// glider's x axis points along the velocity) and it turns at `pitch_rate_deg_s`.
struct Launch {
  double speed = 7.0;            ///< m/s
  double climb_deg = 0.0;        ///< flight-path angle, upward positive [deg]
  double pitch_deg = 0.0;        ///< [deg]
  bool pitch_from_path = true;   ///< when true, pitch_deg is ignored and equals climb_deg
  double pitch_rate_deg_s = 0.0; ///< [deg/s]
  double height = 1.5;           ///< m
};

/// The paper's six standard hand launches: 7, 9, 11 m/s, each at 0 and 10
/// degrees upward, from `height`. Order: (7,0) (7,10) (9,0) (9,10) (11,0) (11,10).
std::vector<Launch> standard_launches(double height = 1.5);

enum class Integrator { Verlet, RK4 };

/// The simulation steps [s] that every command's --dt and every binding's
/// dt accept: a smaller one would run for hours (a diagnosis flies each
/// flight tens of thousands of times), a larger one no longer resolves the
/// pitch oscillation of a small glider.
inline constexpr double kMinTimeStep = 1e-5, kMaxTimeStep = 0.05;
/// dt if it is in [kMinTimeStep, kMaxTimeStep]; otherwise InputError
/// "<name> must be in [1e-05, 0.05] s, got <dt>" (NaN included; the bounds
/// in the message are written from the constants).
double check_time_step(double dt, const std::string& name);

struct SimOptions {
  double dt = 0.002;          ///< time step [s]
  double t_max = 20.0;        ///< flight ends at this time [s]
  Integrator integrator = Integrator::Verlet;
  int record_every = 1;       ///< keep every k-th step in the trajectory (and the last)
  Vec2 wind;                  ///< steady wind, world frame [m/s]
  double max_pitch_deg = 90.0;  ///< |pitch| beyond this counts as a flip
  /// Fill every sample's `speed` and `alpha`. false: they are left 0 for a
  /// caller that needs them at a few samples only (simulate_track: a
  /// flight's tracked points among its hundreds of steps), which fills
  /// those with fill_air and the same wind: the same values.
  bool sample_air = true;
};

struct FlightSample {
  double t = 0;
  double x = 0, y = 0;   ///< CG [m]
  double pitch = 0;      ///< beta [rad]
  double speed = 0;      ///< |v| relative to the air [m/s]
  double alpha = 0;      ///< glider angle of attack gamma [rad]
  double omega = 0;      ///< pitch rate [rad/s]
  double vx = 0, vy = 0; ///< [m/s]
};

enum class FlightEnd { Ground, TimeLimit, Unstable };

struct Flight {
  std::vector<FlightSample> samples;
  FlightEnd end = FlightEnd::Ground;
  bool stable = true;        ///< false when alpha left the model range or the glider flipped
  std::string reason;        ///< why unstable, in words
  double distance = 0;       ///< horizontal distance from the launch point at ground contact (or at the end) [m]
  double flight_time = 0;    ///< [s]
  double max_alpha = 0;      ///< largest wing |alpha| (AeroForces::max_alpha) where the force was evaluated [rad]
};

struct RigidBody {
  double mass = 0;     ///< kg
  double inertia = 0;  ///< pitch inertia about the CG [kg m^2]
};

/// Integrates eq. 4 from a launch until ground contact (y <= 0, interpolated),
/// the time limit, or unstable flight. The launch point is x = 0.
Flight simulate(const AeroForces& aero, const RigidBody& body, const Launch& launch,
                const SimOptions& opt = {}, double gravity = 9.81);

/// Same, starting from an arbitrary state (used by fitting).
Flight simulate_from(const AeroForces& aero, const RigidBody& body, const FlightState& start,
                     const SimOptions& opt = {}, double gravity = 9.81);

/// Initial state of a launch.
FlightState launch_state(const Launch& launch);

/// Sets s.speed and s.alpha from its velocity and pitch in steady `wind`, as
/// the simulator does for the samples it records.
void fill_air(FlightSample& s, Vec2 wind);

}  // namespace pteromys
