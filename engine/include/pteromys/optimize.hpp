// Design optimisation (paper section 6): move and tilt the wings (and
// optionally the ballast) so that the glider flies.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "pteromys/analysis.hpp"
#include "pteromys/mass.hpp"

namespace pteromys {

/// The three terms of the section 6 cost, our static-margin term, and their
/// weighted sum C = w1 C1 + w2 C2 + C3 + w4 C4.
///   C1 = int T_z^-(V, gamma_min) + T_z^+(V, gamma_max) dV   [N m m/s]  pitch stability (eq. 7)
///   C2 = int (F_l(V, gamma*) - M g)^2 dV                    [N^2 m/s]  lift balance (eq. 8)
///   C3 = int F_d(V, gamma*)^2 dV                            [N^2 m/s]  drag (eq. 9)
///   C4 = int max(0, h_min - h(V))^2 dV                     [m/s]      static margin (not in the paper)
/// where gamma*(V) is on the line T_z(V, gamma*) = 0, found as in the paper by
/// linear interpolation of forces sampled at fixed speeds over a gamma grid,
/// and h(V) = (x_cg - x_np) / c_ref is the static margin there (docs/theory.md).
/// C4 exists because the paper's C1 only asks for restoring moments at the
/// ends of Omega: minimised well, C1..C3 favour nearly neutral designs (static
/// margin < 1 %) that a small building error makes unstable.
struct CostTerms {
  double c1 = 0, c2 = 0, c3 = 0, c4 = 0, total = 0;
  int speeds_without_equilibrium = 0;  ///< sampled speeds where T_z has no zero on the gamma grid
};

struct OptimizeOptions {
  Region region;              ///< Omega (paper: [6, 9] m/s x [-10, 10] deg)
  double w1 = 100.0;          ///< weight of C1 (paper)
  double w2 = 1.0;            ///< weight of C2 (paper)
  double w4 = 1.0;            ///< weight of C4 (0 = the paper's cost exactly)
  double min_static_margin = 0.10;  ///< h_min of C4, fraction of the reference chord
  int n_speeds = 4;           ///< sampled speeds over [v_min, v_max]
  int n_gammas = 21;          ///< sampled angles over [gamma_min, gamma_max]
  double angle_min_deg = -10.0, angle_max_deg = 15.0;  ///< mounting-angle bounds
  /// A wing stays mounted: at least this fraction of its root chord lies
  /// inside the fuselage plate (room for its slot joint).
  double min_overlap_fraction = 0.6;
  /// Wings keep the front-to-back order in which they are drawn, with at least
  /// this gap [m] between one wing's root trailing edge and the next wing's
  /// root leading edge (room for the fuselage between their slots).
  double min_wing_gap_m = 0.01;
  /// Variables kept as they are: "WING.angle", "WING.x", "WING.y", "ballast.x".
  std::vector<std::string> locks;
  bool optimise_ballast = false;  ///< ballast x becomes a variable (all items move together)
  /// "bobyqa" (default), "cobyla", "sbplx", "neldermead" (NLopt, derivative-free)
  /// or "steepest" (the paper's steepest descent with forward differences).
  std::string algorithm = "bobyqa";
  int max_evaluations = 3000;
  /// NLopt algorithms: restart from the optimum with a fresh initial step up to
  /// this many times while the cost still falls by more than 0.1 %.
  int restarts = 3;
  /// A result that lowers the cost by less than this fraction keeps the
  /// starting mounts (when they are feasible): re-optimising an optimal design
  /// changes nothing, and wings do not jitter during small interactive edits.
  double min_improvement = 0.01;
  double xtol = 1e-5;         ///< stop when steps are below this (scaled variables)
  AnalysisOptions analysis;   ///< for the report after optimisation
};

/// One design variable.
struct DesignVariable {
  std::string name;   ///< "main.angle", "tail.x", "ballast.x", ...
  double value = 0;   ///< deg for angles, m for positions
  double lower = 0, upper = 0;
  bool locked = false;
};

/// Evaluates the section 6 cost for changing mounts of a fixed shape, on
/// table look-ups only (no coefficient evaluation): the object the optimiser
/// calls thousands of times.
class DesignCost {
 public:
  DesignCost(const Glider& g, std::shared_ptr<const GliderAero> aero, const OptimizeOptions& opt);
  /// Variables in a fixed order: per wing angle, x, y; then ballast.x if optimised.
  const std::vector<DesignVariable>& variables() const { return vars_; }
  /// Cost of the design with these variable values (all variables, locked ones included).
  CostTerms evaluate(const std::vector<double>& values) const;
  /// Length of wing j's root chord inside the fuselage for these values [m],
  /// and the length required by min_overlap_fraction.
  double overlap(std::size_t j, const std::vector<double>& values) const;
  double required_overlap(std::size_t j) const { return required_[j]; }
  /// Gap along x between consecutive wings, front to back in the drawn order
  /// (root trailing edge of the front wing minus root leading edge of the
  /// next) [m]; one entry per consecutive pair. Negative: the wings overlap.
  std::vector<double> wing_gaps(const std::vector<double>& values) const;
  /// Wing indices front to back as drawn.
  const std::vector<std::size_t>& wing_order() const { return order_; }
  /// The glider with these values written into its mounts (and ballast).
  Glider apply(const std::vector<double>& values) const;
  /// Mounted glider (tables shared) for these values.
  MountedGlider mounted(const std::vector<double>& values) const;
  /// Penalised objective the optimiser minimises: cost plus a quadratic
  /// penalty when a wing would leave the fuselage.
  double objective(const std::vector<double>& values) const;

 private:
  std::vector<Mount> mounts_of(const std::vector<double>& v) const;
  std::vector<Vec2> ballast_of(const std::vector<double>& v) const;
  Glider glider_;
  std::shared_ptr<const GliderAero> aero_;
  OptimizeOptions opt_;
  MassModel mass_;
  std::vector<DesignVariable> vars_;
  std::vector<double> required_;
  std::vector<std::pair<double, double>> root_;  // longest root chord interval per wing
  double ballast_dx0_ = 0;  // reference x of the ballast group
  double ref_chord_ = 0;    // mean chord of the largest wing (static margin reference)
  std::vector<std::size_t> order_;  // wings front to back as drawn
};

struct OptimizeResult {
  Glider glider;                 ///< with the optimised mounts (and ballast)
  Flyability report;             ///< analysis of the optimised design
  CostTerms cost_start, cost;    ///< before and after
  std::vector<DesignVariable> variables;  ///< final values and bounds
  int evaluations = 0;
  double seconds = 0;
  std::string algorithm;
  std::string stop_reason;
};

/// Optimises the mounting of `g`. With `warm_start` (a previous result for the
/// same wings, as during a drag in the editor), starts from its values with a
/// small initial step. Throws InputError for an invalid glider or options.
OptimizeResult optimize(const Glider& g, std::shared_ptr<const CoefficientModel> model,
                        const OptimizeOptions& opt = {}, const Environment& env = {},
                        const AeroOptions& aero = {}, const OptimizeResult* warm_start = nullptr);

/// Same with the shape's aerodynamics already built (interactive loop).
OptimizeResult optimize(const Glider& g, std::shared_ptr<const GliderAero> aero,
                        const OptimizeOptions& opt = {}, const OptimizeResult* warm_start = nullptr);

}  // namespace pteromys
