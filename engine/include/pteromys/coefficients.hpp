// Aerodynamic coefficient models of a wing element (paper section 4.2).
//
// One interface, several models: the paper's RBF model (eq. 3, parity by ghost
// centres), the empirical flat-plate element (paper section 7.1), and any later
// model. Every model maps eps = (alpha, Re, xi_l, xi_t) to c = (c_d, c_l, c_m)
// with c_d even and c_l, c_m odd in alpha, exactly.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "pteromys/types.hpp"

namespace pteromys {

/// Input of a coefficient model. alpha, xi_l, xi_t in radians; re dimensionless.
struct ElementState {
  double alpha = 0;
  double re = 0;
  double xi_l = 0;
  double xi_t = 0;
};

/// Dimensionless coefficients: drag, lift, pitching moment about the quarter chord
/// (nose-up positive, reference length = element chord).
struct Coefficients {
  double cd = 0, cl = 0, cm = 0;
};

/// Geometry of an element as the force sums need it.
struct ElementShape {
  double area = 0;   ///< a [m^2]
  double chord = 0;  ///< l [m]
  double arm = 0;    ///< d: x of the quarter-chord point relative to the mounting point, wing frame [m]
  double xi_l = 0, xi_t = 0;  ///< [rad]
};

/// Per-unit-dynamic-pressure force sums of a whole wing on a (V, alpha) grid,
/// each an nv x na row-major array (index iv * na + ia):
///   cd_a   = sum_i a_i c_d          [m^2]
///   cl_a   = sum_i a_i c_l          [m^2]
///   cm_la  = sum_i a_i l_i c_m      [m^3]
///   cd_da  = sum_i a_i d_i c_d      [m^3]
///   cl_da  = sum_i a_i d_i c_l      [m^3]
/// The wing's forces at its mounting point are q = rho V^2 / 2 times
/// (cd_a, cl_a, cm_la + sin(alpha) cd_da + cos(alpha) cl_da)  (eq. 2 summed).
struct CoefficientSums {
  int nv = 0, na = 0;
  std::vector<double> cd_a, cl_a, cm_la, cd_da, cl_da;
  void resize(int nv_, int na_);
};

class CoefficientModel {
 public:
  virtual ~CoefficientModel() = default;
  /// Coefficients of one element.
  virtual Coefficients eval(const ElementState& e) const = 0;
  /// The model is valid for |alpha| <= alpha_limit() [rad]; flights that leave
  /// this range are reported unstable.
  virtual double alpha_limit() const = 0;
  /// "rbf", "flat_plate", ...
  virtual std::string kind() const = 0;
  /// Force sums over elements for every (speed, alpha) pair of a grid.
  /// `re_per_chord[iv]` = rho V / mu for speed iv [1/m]; alphas [rad].
  /// The default evaluates each element; models override it with faster
  /// structure-aware sums that give the same values up to rounding.
  virtual void sum_over_elements(const std::vector<ElementShape>& elements,
                                 const std::vector<double>& re_per_chord,
                                 const std::vector<double>& alphas,
                                 CoefficientSums& out) const;
};

/// Parameters of the empirical flat-plate element (docs/theory.md, "Empirical
/// flat-plate element"). Every element gets the coefficients of a flat-plate
/// wing of aspect ratio `aspect_ratio`; only alpha and Re matter.
struct FlatPlateParams {
  double aspect_ratio = 5.0;                 ///< A of the representative wing
  double section_lift_slope = 0.9 * 2 * kPi;  ///< a0 [1/rad], thin plate at low Re
  double stall_deg = 10.0;                   ///< centre of the attached-to-separated blend
  double stall_width_deg = 2.0;              ///< half width of the blend (smoothstep)
  /// C_N of the plate broadside to the flow; 0 = from the aspect ratio
  /// (Hoerner, Fluid-Dynamic Drag 1965, 3-16: 1.17 at A = 1, 1.20 at 5, 1.29 at
  /// 10, 1.50 at 20, 1.98 for the 2-D plate; interpolated in 1/A).
  double normal_force_90 = 0.0;
  double edge_drag = 0.005;                  ///< pressure drag of the edges at alpha = 0
  double alpha_valid_deg = 40.0;             ///< model validity limit
};

class FlatPlateModel final : public CoefficientModel {
 public:
  explicit FlatPlateModel(FlatPlateParams p = {});
  Coefficients eval(const ElementState& e) const override;
  double alpha_limit() const override { return deg2rad(p_.alpha_valid_deg); }
  std::string kind() const override { return "flat_plate"; }
  void sum_over_elements(const std::vector<ElementShape>& elements,
                         const std::vector<double>& re_per_chord,
                         const std::vector<double>& alphas,
                         CoefficientSums& out) const override;
  const FlatPlateParams& params() const { return p_; }
  /// Skin-friction drag (laminar, both faces) at Reynolds number re.
  static double friction_drag(double re);
  /// Coefficients without the Re-dependent friction drag.
  Coefficients eval_alpha(double alpha) const;
  /// The broadside normal force in use (given or from the aspect ratio).
  double normal_force_90() const { return cn90_; }

 private:
  FlatPlateParams p_;
  double lift_slope_;  // finite-wing lift slope (Helmbold)
  double cn90_;        // broadside normal-force coefficient
};

/// One RBF centre eps^k with the coefficient values c^k the model takes there.
struct RbfCentre {
  double alpha = 0, re = 0, xi_l = 0, xi_t = 0;  ///< [rad], [-], [rad], [rad]
  Coefficients value;
};

/// Per-dimension input scaling: the kernel distance is
/// r^2 = sum_d ((eps_d - eps_d^k) / scale_d)^2.
struct RbfScales {
  double alpha = deg2rad(8.0);
  double re = 2.0e4;
  double xi_l = deg2rad(30.0);
  double xi_t = deg2rad(30.0);
};

/// The paper's RBF model (eq. 3) with Gaussian kernel psi(r) = exp(-r^2) and a
/// ghost centre (-alpha^k, Re^k, xi_l^k, xi_t^k) for every centre, carrying
/// (c_d^k, -c_l^k, -c_m^k): c_d is exactly even and c_l, c_m exactly odd in
/// alpha (bit for bit). Optionally the RBF interpolates the residual over a
/// prior model (c = prior + RBF), so that far from the centres the model falls
/// back to the prior rather than to zero. With or without a prior the model
/// reproduces its centre values.
class RbfModel final : public CoefficientModel {
 public:
  RbfModel(std::vector<RbfCentre> centres, RbfScales scales, double alpha_limit,
           std::shared_ptr<const FlatPlateModel> prior = nullptr);
  Coefficients eval(const ElementState& e) const override;
  double alpha_limit() const override { return alpha_limit_; }
  std::string kind() const override { return "rbf"; }
  void sum_over_elements(const std::vector<ElementShape>& elements,
                         const std::vector<double>& re_per_chord,
                         const std::vector<double>& alphas,
                         CoefficientSums& out) const override;

  const std::vector<RbfCentre>& centres() const { return centres_; }
  const RbfScales& scales() const { return scales_; }
  const std::shared_ptr<const FlatPlateModel>& prior() const { return prior_; }
  /// Kernel weights w^k = (w_d, w_l, w_m) solved from the centre values.
  const std::vector<std::array<double, 3>>& weights() const { return weights_; }
  /// The same centres and scales with new centre values (fitting).
  std::shared_ptr<RbfModel> with_values(const std::vector<Coefficients>& values) const;

 private:
  void solve_weights();
  std::vector<RbfCentre> centres_;
  RbfScales scales_;
  double alpha_limit_;
  std::shared_ptr<const FlatPlateModel> prior_;
  std::vector<std::array<double, 3>> weights_;
};

}  // namespace pteromys
