// Aerodynamic coefficients from tracked flights (paper section 5.2).
//
// Three layers, each usable alone:
//  1. simulate_track: the simulated centre-of-gravity positions of a glider at
//     the tracked times of a flight, from launch parameters sigma_l.
//  2. fit_launch (eq. 5): the launch parameters that best explain the first M
//     tracked points of one flight, for a fixed aerodynamic model.
//  3. fit_coefficients (eq. 6 and the greedy centres of Bickel et al. 2009):
//     the coefficient values at the RBF centres that best explain every point
//     of every flight, interleaved with the launch fits, inserting centres
//     where the error is largest until the error stops falling.
// Plus predict_flights (a model's held-out error, paper Fig. 13) and
// synthetic_dataset (flights simulated with a known model, for tests and
// benchmarks).
//
// Units are SI; angles in radians in structs (degrees only in JSON reports).
// World frame of a dataset: x horizontal along the flight, y up, origin
// anywhere fixed (spec/formats.md).
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pteromys/aero.hpp"
#include "pteromys/coefficients.hpp"
#include "pteromys/dataset.hpp"
#include "pteromys/flight.hpp"

namespace pteromys {

/// Launch parameters sigma_l of one tracked flight: the glider's state at the
/// time of the flight's first tracked point. The paper's sigma = (V0, theta0,
/// beta0, t0) starts at a known launcher position at an unknown time t0; a
/// dataset gives neither the launcher's position nor the release instant
/// (tracking may start after release), so here the state is anchored at the
/// first tracked time and the position is fitted instead of t0.
struct LaunchParams {
  double t = 0;           ///< dataset time of this state (the flight's first tracked point) [s]
  double x = 0, y = 0;    ///< centre of gravity, dataset world frame [m]
  double speed = 0;       ///< |v| [m/s]
  double climb = 0;       ///< flight-path angle above the horizontal, upward positive [rad] (= -theta)
  double pitch = 0;       ///< beta: glider x axis above the horizontal, nose up positive [rad]
  double pitch_rate = 0;  ///< omega = d beta / dt [rad/s]; fitted only with LaunchFitOptions::fit_pitch_rate
};

/// How tracked flights are simulated.
struct TrackOptions {
  SimOptions sim;                 ///< time step and integrator; t_max, record_every, max_pitch are set per call
  double gravity = 9.81;          ///< m/s^2
  /// Flights are simulated this much higher than the dataset's y [m], so that
  /// the simulator's ground contact (y = 0) never cuts a fitted flight short:
  /// a dataset's origin is anywhere (usually the launcher) and the tracked
  /// points may come close to the ground. Valid because the aerodynamic
  /// models fitted here do not depend on height; use 0 for models that do.
  double height_offset = 1000.0;
  /// Keep simulating when a wing's angle of attack leaves the model's range
  /// (the table holds the coefficients at its edge) or the glider flips, so
  /// that every tracked point has a simulated position that changes smoothly
  /// with the parameters (needed by the fits). The track reports it.
  bool continue_outside_range = true;
};

/// Simulated positions of a flight at the tracked times.
struct Track {
  std::vector<Vec2> positions;        ///< n x (x, y): CG at each requested time, dataset frame [m]
  std::vector<FlightSample> states;   ///< n simulated states at those times (linear interpolation; x, y as positions)
  double max_alpha = 0;               ///< largest |angle of attack| of any wing met during the flight [rad]
  bool left_model_range = false;      ///< max_alpha exceeded the model's limit (see continue_outside_range)
  bool ended_early = false;           ///< the simulation stopped before the last time (ground, instability,
                                      ///< divergence); later positions are extrapolated ballistically
  double end_time = 0;                ///< dataset time at which the simulation stopped [s]
  FlightEnd end = FlightEnd::TimeLimit;
  std::string reason;                 ///< why it stopped early, in words
};

/// Simulated CG positions at `times` (dataset times [s], ascending, none
/// before p.t) of the flight that has state `p` at time p.t. Positions
/// between integrator steps are cubic Hermite interpolations of position and
/// velocity (fourth-order accurate).
Track simulate_track(const AeroForces& aero, const RigidBody& body, const LaunchParams& p,
                     const std::vector<double>& times, const TrackOptions& opt = {});

/// Options of the launch fit (eq. 5).
struct LaunchFitOptions {
  /// M: fit to the first M tracked points (the paper's M = 10); 0 = all points.
  int points = 10;
  bool fit_pitch = true;         ///< false for ballistic motion, where the pitch has no effect
  bool fit_pitch_rate = false;   ///< also fit omega at the first point (the paper does not)
  /// Multi-start: each start sets pitch = climb + value [deg] (the paper
  /// starts from pitch = path; a single start can end in a local minimum).
  std::vector<double> start_alpha_deg = {-3.0, 1.0, 5.0};
  int max_evaluations = 400;     ///< simulations per start
  /// Huber threshold on a point's distance [m] (0 = plain least squares):
  /// the coefficient fit sets it to its own, so that both minimise the same error.
  double robust_m = 0.0;
  TrackOptions track;
};

/// Launch-fit options with M = 0 (all points).
inline LaunchFitOptions all_points_launch_fit() {
  LaunchFitOptions o;
  o.points = 0;
  return o;
}

struct LaunchFit {
  LaunchParams launch;
  double rmse_m = 0;      ///< RMS distance over the fitted points [m]
  int evaluations = 0;    ///< simulations used
};

/// Weight w of a point at distance e [m] so that |w d|^2 is Huber's
/// rho(e) = e^2 for e <= c, 2 c e - c^2 beyond (c <= 0: always 1).
double huber_weight(double e, double c);

/// First guess of the launch parameters: position and velocity at the first
/// point from a least-squares parabola through the first `n` points, pitch
/// along the path. Throws InputError when the points do not move along +x.
LaunchParams initial_launch_guess(const std::vector<TrackedPoint>& points, int n = 6);

/// Eq. 5: launch parameters minimising the squared distances between the
/// simulated and tracked positions of the first M points. `start`, when
/// given, replaces the multi-start (warm start in the interleaved fit).
LaunchFit fit_launch(const AeroForces& aero, const RigidBody& body, const std::vector<TrackedPoint>& points,
                     const LaunchFitOptions& opt = {}, const LaunchParams* start = nullptr);

/// Progress of a fit, reported after every solver iteration and stage.
struct FitProgress {
  std::string stage;      ///< "launches", "coefficients", "insert", "stage", "done"
  int centres = 0;        ///< number of RBF centres being fitted
  int round = 0;          ///< launch/coefficient alternation within the stage (from 1)
  int iteration = 0;      ///< solver iteration within the coefficient fit
  double rmse_m = 0;      ///< current RMS distance over all points [m]
  double elapsed_s = 0;   ///< since the fit started
  std::string message;    ///< one line for a person
};
/// Called from the thread that called fit_coefficients.
using FitCallback = std::function<void(const FitProgress&)>;

struct FitOptions {
  int max_centres = 10;            ///< the paper ends with 10
  /// Greedy stopping rule ("until the error stops falling"): a new centre is
  /// kept only when it lowers the Bayesian information criterion
  /// BIC = n ln(SSE / n) + p ln(n) (n residuals, p fitted parameters:
  /// launches and values), i.e. when the squared error falls by more than
  /// three more parameters would remove from pure noise, about 3 ln(n) / n;
  /// otherwise the fit stops with the previous model. The threshold scales
  /// with the amount of data, unlike a fixed fraction.
  bool information_criterion = true;
  /// An extra, fixed threshold: the RMSE must also fall by this fraction (0 = off).
  double min_improvement = 0.0;
  int max_rounds = 3;              ///< launch/coefficient alternations per number of centres (paper's scheme, M > 0)
  double round_tolerance = 0.002;  ///< alternation stops when the RMSE falls by less than this fraction (M > 0)
  int max_iterations = 12;         ///< Levenberg-Marquardt iterations per coefficient fit
  int candidates = 24;             ///< candidate centres scored at each insertion
  /// Candidates tried at one insertion (experimental, 1 = the greedy rule):
  /// where the best-scored centre does not pass the stopping rule while the
  /// fit is still over twice the tracking noise, the next-best scored ones are
  /// fitted in turn before the fit stops. (Seen at the size: fold fits
  /// stopped at 4-5 cm against 1 cm of noise, centre 5 lowering the RMSE by
  /// 0.002 %.)
  int insertion_tries = 1;
  /// Weight of the pull of each centre value toward the prior's value, as the
  /// position error [m] one scale unit (cd 0.02, cl 0.1, cm 0.02) of
  /// deviation is worth. Keeps values that no flight constrains at the prior.
  double regularisation_m = 0.01;
  /// Huber threshold on a tracked point's distance [m]: points farther than
  /// this count linearly, not quadratically (flights the model cannot follow
  /// do not dominate). 0 = plain least squares as in the paper.
  double robust_m = 0.3;
  double cd_max = 2.5, cl_max = 2.5, cm_max = 1.0;  ///< bounds: 0 <= cd <= cd_max, |cl| <= cl_max, |cm| <= cm_max
  /// Eq. 5 (M, starts, pitch rate, time step). Here M = 0 (all points) by
  /// default, unlike the paper's M = 10: launch and coefficient fits then
  /// minimise the same error E of eq. 6 and are solved jointly by variable
  /// projection, and a launch estimated from 10 noisy points no longer
  /// leaves errors that the coefficients learn to compensate
  /// (docs/fitting.md measures both). Set launch.points = 10 for the
  /// paper's scheme (alternation, max_rounds).
  LaunchFitOptions launch = all_points_launch_fit();
  AeroOptions aero;                ///< wing-element spacing and force-table grid
  RbfScales scales;                ///< kernel widths of a new model (a start model keeps its own)
  double alpha_limit_deg = 40.0;   ///< validity range of a new model (a start model keeps its own)
  bool use_prior = true;           ///< RBF over the flat-plate prior (false: the paper's plain RBF)
  FlatPlateParams prior;           ///< the prior (a start model with a prior keeps its own)
  /// Continue from this model's centres and values (null: start with one
  /// centre at the mean wing-element parameters, valued as the prior).
  std::shared_ptr<const RbfModel> start;
  int threads = 0;                 ///< worker threads (0 = all cores)
};

/// Fit of one flight.
struct FlightFitResult {
  std::string flight, glider;
  int points = 0;
  LaunchParams launch;
  double rmse_m = 0;            ///< RMS distance over all points of the flight [m]
  double launch_rmse_m = 0;     ///< over the first M points (eq. 5) [m]
  double max_error_m = 0;       ///< largest point distance [m]
  double max_alpha = 0;         ///< largest wing |alpha| in the simulation [rad]
  bool left_model_range = false;
};

/// One step of the greedy insertion (paper Fig. 11a).
struct FitStage {
  int centres = 0;          ///< 0 = the prior alone (launches fitted)
  double rmse_m = 0;
  double bic = 0;           ///< n ln(SSE / n) + p ln(n) (see FitOptions::information_criterion)
  bool accepted = true;     ///< false: the new centre did not lower the error enough and was dropped
  double seconds = 0;       ///< wall time of the stage
  int iterations = 0;       ///< Levenberg-Marquardt iterations, all rounds
  int simulations = 0;      ///< flight simulations
  bool has_added = false;
  RbfCentre added;          ///< the centre inserted for this stage
  double predicted_gain = 0;  ///< Gauss-Newton predicted drop of the squared error that chose it [m^2]
};

struct FitResult {
  std::shared_ptr<const RbfModel> model;   ///< the fitted model
  double rmse_m = 0;                       ///< RMS distance over all points of all flights [m]
  double prior_rmse_m = 0;                 ///< the same for the starting model with fitted launches [m]
  int points = 0;
  std::vector<FlightFitResult> flights;
  std::vector<FitStage> history;
  std::string stop_reason;
  double seconds = 0, launch_seconds = 0, coefficient_seconds = 0, insertion_seconds = 0;
  long simulations = 0;
  int threads = 1;
};

/// The interleaved fit of eq. 5 and 6 with greedy centre insertion. Throws
/// InputError for datasets it cannot fit (no flights, flights not moving
/// along +x, inconsistent options).
FitResult fit_coefficients(const Dataset& d, const FitOptions& opt = {}, const FitCallback& progress = {});

/// Report of a fit, format "pteromys-fit/1" (spec/formats.md: fit_rmse_m,
/// centres, flights) plus prior_rmse_m, points, history, per_flight,
/// timings, stop_reason, options.
nlohmann::json fit_report_json(const FitResult& r, const FitOptions& opt);

/// How well a model predicts tracked flights: for each flight the launch is
/// fitted to the first M points (eq. 5) and the whole flight simulated.
struct FlightPrediction {
  std::string flight, glider;
  LaunchParams launch;
  std::vector<double> t;          ///< tracked times [s]
  std::vector<Vec2> tracked;      ///< tracked positions [m]
  std::vector<Vec2> simulated;    ///< simulated positions at the same times [m]
  double rmse_m = 0;              ///< over all points [m]
  double rmse_after_m = 0;        ///< over the points after the first M (pure prediction) [m]; 0 if none
  int launch_points = 0;          ///< M: the first points, used by the launch fit
  double max_alpha = 0;           ///< [rad]
  bool left_model_range = false;
};

/// `model` null: ballistic motion (no air), as the paper's Fig. 13.
std::vector<FlightPrediction> predict_flights(const Dataset& d, std::shared_ptr<const CoefficientModel> model,
                                              const FitOptions& opt = {});
/// RMS distance over all points of all predictions [m] (`after`: only points after the first M).
double predictions_rmse(const std::vector<FlightPrediction>& p, bool after = false);

/// Flights simulated with a known model and tracked like the paper's camera:
/// random hand launches, points at the frame rate from a random delay after
/// release, Gaussian noise, an arbitrary time origin per flight. The true
/// launch (release state) is written in the extra columns release_t_s,
/// release_speed_m_s, release_climb_deg, release_pitch_deg.
struct SyntheticOptions {
  int flights_per_glider = 5;
  double speed_min = 5.0, speed_max = 9.0;             ///< release speed [m/s]
  double climb_min_deg = -5.0, climb_max_deg = 15.0;   ///< release path angle, upward positive
  double alpha_min_deg = -2.0, alpha_max_deg = 6.0;    ///< release pitch minus path angle
  double height = 1.5;                                 ///< release height above the ground [m]
  int points_min = 15, points_max = 20;                ///< tracked points per flight
  double frame_rate_hz = 30.0;
  double delay_max_s = 0.05;                           ///< tracking starts up to this long after release
  double noise_m = 0.05;                               ///< standard deviation per axis [m]
  unsigned seed = 1;
  SimOptions sim;
  AeroOptions aero;
  Environment env;
};

Dataset synthetic_dataset(const std::map<std::string, Glider>& gliders,
                          std::shared_ptr<const CoefficientModel> model, const SyntheticOptions& opt = {});

}  // namespace pteromys
