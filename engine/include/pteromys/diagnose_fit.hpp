// The fitting core of the diagnosis: tracked flights of a dataset explained by
// the fast model (a coefficient model), corrected by candidate effects
// (effects.hpp), with per-glider build-trim nuisance parameters.
//
// Every flight's launch state (position, speed, climb, pitch at its first
// tracked point; pitch rate = the launch_rotation parameter, 0 by default) is
// fitted to all its points. Shared parameters -- effect strengths, per-glider
// trims, optionally RBF centre values -- are fitted by Levenberg-Marquardt on
// the reduced problem in which the launches are re-fitted at every trial
// (variable projection, Golub & Pereyra 1973): the Jacobian of each flight's
// residuals with respect to the shared parameters is projected onto the
// complement of its launch Jacobian (Kaufman 1975).
//
// Residuals are in the camera's frame (the dataset's): simulated world
// positions mapped by the camera correction minus the tracked positions [m],
// plain least squares (the significance tests assume Gaussian tracking noise
// of the dataset's tracking_sigma_m per coordinate).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "pteromys/coefficients.hpp"
#include "pteromys/dataset.hpp"
#include "pteromys/effects.hpp"
#include "pteromys/fit.hpp"

namespace pteromys {

/// One glider of the dataset.
struct DiagGlider {
  std::string key;
  const Glider* glider = nullptr;
  GliderFeatures features;
  RigidBody body;
  std::vector<int> flights;  ///< indices into Dataset::flights
};

/// What the fast model is: coefficients, effect corrections, trims.
struct DiagModel {
  std::shared_ptr<const CoefficientModel> coefficients;
  EffectValues effects;
  /// Build-trim error of each glider (index as DiagnosisData::gliders()):
  /// added to the mounting angle of its trim wing [rad], nose-up positive.
  std::vector<double> trim;
};

/// A parameter shared by several flights that a fit can free.
struct FreeParam {
  enum Kind { EffectParam, Trim, Coefficient };
  Kind kind = EffectParam;
  Effect effect = Effect::PitchDamping;  ///< EffectParam
  int index = 0;  ///< EffectParam: parameter of the effect; Trim: glider; Coefficient: 3 * centre + (0 cd, 1 cl, 2 cm)
  static FreeParam effect_param(Effect e, int i) { return {EffectParam, e, i}; }
  static FreeParam trim(int glider) { return {Trim, Effect::PitchDamping, glider}; }
  static FreeParam coefficient(int k) { return {Coefficient, Effect::PitchDamping, k}; }
};

/// One flight explained by a model.
struct FlightOutcome {
  int flight = -1;                 ///< index into Dataset::flights
  LaunchParams launch;             ///< fitted launch (world frame; pitch_rate from the model)
  std::vector<Vec2> residual;      ///< n x 2: recorded simulated - tracked, camera frame [m]
  std::vector<FlightSample> states;  ///< n simulated states at the tracked times (world frame, dataset y)
  double sse = 0;                  ///< sum of squared residual distances [m^2]
  bool left_model_range = false;
};

struct FitOutcome {
  DiagModel model;                     ///< with the fitted free parameters
  std::vector<FlightOutcome> flights;  ///< as requested
  double sse = 0;                      ///< [m^2]
  int points = 0;
  int launch_parameters = 0;           ///< fitted launch values (5 per flight)
  int free_parameters = 0;
  int iterations = 0;
  long simulations = 0;
  /// (diagnosis) a theoretical-size start whose strength the training
  /// flights did not reject, so kept at exactly 1 rather than fitted
  bool strength_held = false;
  double rmse() const { return points ? std::sqrt(sse / points) : 0.0; }
};

struct DiagFitOptions {
  double dt = 0.002;            ///< simulation step [s]
  double ground_y = 0.0;        ///< dataset y of the ground [m] (ground effect, phases)
  int max_iterations = 8;       ///< Levenberg-Marquardt iterations on the shared parameters
  bool trial_fallback = true;   ///< multi-start launch fits for flights a warm start fits badly, also in trials
  double tolerance = 1e-4;      ///< stop when the SSE falls by less than this fraction (or by < 0.2 sigma^2)
  int threads = 0;              ///< 0 = all cores
  AeroOptions aero;             ///< wing-element spacing, table grid
  /// When RBF centre values are free (a polished fit): each value's change
  /// from the start model, in its scale unit (cd 0.02, cl 0.1, cm 0.02), costs
  /// as much as this position error [m] (a Tikhonov pull toward the start,
  /// as FitOptions::regularisation_m pulls toward the prior): values that no
  /// flight constrains stay where they were instead of drifting to where
  /// held-out gliders then fly wild.
  double coefficient_regularisation_m = 0.01;
};

/// Flights, gliders and simulation settings of one dataset; fits of models to
/// subsets of its flights. Immutable after construction; fit() may be called
/// from one thread at a time per object (it uses its own worker threads).
class DiagnosisData {
 public:
  /// Throws InputError on an unusable dataset (no flights, flights not
  /// moving along +x, more than 8 wings, non-positive tracking sigma).
  DiagnosisData(const Dataset& d, const DiagFitOptions& o = {});

  const Dataset& dataset() const { return d_; }
  const std::vector<DiagGlider>& gliders() const { return gliders_; }
  int glider_of(int flight) const { return flight_glider_[flight]; }
  const DiagFitOptions& options() const { return o_; }
  int threads() const { return threads_; }

  /// Fits the free parameters of `start` (and every flight's launch) to the
  /// flights `flights` (indices into Dataset::flights). `warm`: launches to
  /// start from (same order as `flights`); otherwise multi-start launch fits.
  /// `max_iterations` > 0 overrides DiagFitOptions::max_iterations.
  FitOutcome fit(const DiagModel& start, const std::vector<int>& flights, const std::vector<FreeParam>& free,
                 const std::vector<LaunchParams>* warm = nullptr, int max_iterations = 0) const;

  /// Stacked residual Jacobian (2 x points of `flights` rows, one column per
  /// free parameter, in units of the parameter's scale) at the model and
  /// launches of `at`, each flight's block projected onto the complement of
  /// its launch Jacobian: what the parameters can change that no launch can.
  Eigen::MatrixXd projected_jacobian(const FitOutcome& at, const std::vector<FreeParam>& free) const;

  /// One regularised Gauss-Newton step from `at` on the free parameters
  /// `free[cols]` (launches projected out): the least-squares solution of
  /// the residuals linearised by J = projected_jacobian(at, free), the
  /// centre values pulled toward `at`'s as fit() pulls them. The model moved
  /// by that step (effect strengths and trims clamped to their bounds, drag
  /// at the centres kept >= 0); `predicted_sse`: the linearised SSE after it
  /// (without the pull). `fraction`: the model moved by that fraction of
  /// the step (a damped step where the full one overshoots; predicted_sse
  /// is then the linearised SSE at that fraction). Throws InputError on a J
  /// of the wrong shape or a fraction outside (0, 1].
  DiagModel linear_step(const FitOutcome& at, const std::vector<FreeParam>& free, const Eigen::MatrixXd& J,
                        const std::vector<int>& cols, double* predicted_sse = nullptr, double fraction = 1.0) const;

  /// Scale of a free parameter in the solver (natural units).
  double scale(const FreeParam& p) const;

  struct Impl;  ///< simulation settings (defined in diagnose_fit.cpp)

 private:
  const Dataset& d_;
  DiagFitOptions o_;
  int threads_ = 1;
  std::vector<DiagGlider> gliders_;
  std::vector<int> flight_glider_;
  std::shared_ptr<Impl> impl_;
};

}  // namespace pteromys
