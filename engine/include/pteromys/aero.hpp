// Wing force tables and the glider's characteristic function F(V, gamma)
// (paper eq. 1, 2, section 4.3 and section 6).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "pteromys/coefficients.hpp"
#include "pteromys/elements.hpp"
#include "pteromys/glider.hpp"
#include "pteromys/mass.hpp"

namespace pteromys {

/// Forces on one wing at its mounting point per unit dynamic pressure
/// q = rho V^2 / 2: drag D [m^2], lift L [m^2] and pitching moment about the
/// mounting point M [m^3] (nose-up positive). f_d = q D, f_l = q L, tau = q M.
struct WingCoefs {
  double drag = 0, lift = 0, moment = 0;
};

/// Grid of a wing force table: speeds uniform in log(V) over [v_min, v_max],
/// angles of attack uniform over [-alpha_limit, alpha_limit] of the model.
struct TableGrid {
  double v_min = 1.0;                   ///< m/s
  double v_max = 40.0;                  ///< m/s
  int nv = 28;
  double alpha_step = deg2rad(0.25);    ///< rad
};

/// Per-wing force table over (V, alpha), built once per wing shape: a change
/// of mounting angle or position needs no new coefficient evaluation.
/// Look-ups are bicubic (Catmull-Rom) in (log V, alpha); speeds outside the
/// grid are clamped to it.
class WingTable {
 public:
  /// Interpolation weights of one speed on the (shared) speed grid: compute
  /// once per time step, use for every wing with the same grid.
  struct SpeedWeights {
    int iv = 0;
    double w[4] = {0, 0, 0, 0};
  };
  WingTable(const WingElements& el, const CoefficientModel& model, const Environment& env,
            const TableGrid& grid = {});
  WingCoefs lookup(double v, double alpha) const;
  SpeedWeights speed_weights(double v) const;
  /// The same, written into `out` (no copy of a returned struct: in a loop
  /// that keeps one across iterations the copy stalled on its fresh stores).
  void speed_weights(double v, SpeedWeights& out) const;
  WingCoefs lookup(const SpeedWeights& sw, double alpha) const;
  /// The lift column of lookup(sw, alpha) alone and, if asked, its derivative
  /// in alpha (of the same bicubic interpolation; 0 beyond the table).
  double lift(const SpeedWeights& sw, double alpha, double* dlift_dalpha = nullptr) const;
  double alpha_limit() const { return alpha_max_; }
  int nv() const { return nv_; }
  int na() const { return na_; }

 private:
  int nv_ = 0, na_ = 0;
  double lv0_ = 0, dlv_ = 1, a0_ = 0, da_ = 1, alpha_max_ = 0;
  std::vector<double> dlm_;  // nv x na nodes, each (drag, lift, moment): one look-up reads adjacent memory
};

/// Direct evaluation of the same sums (no table): reference for the tables.
WingCoefs wing_coefs_direct(const WingElements& el, const CoefficientModel& model,
                            const Environment& env, double v, double alpha);

/// Shapes of the elements as the force sums need them (arm = x_qc, the
/// mounting point being the wing's own origin).
std::vector<ElementShape> element_shapes(const WingElements& el);

struct AeroOptions {
  double dz = 0.005;  ///< spacing of the wing-element cut lines [m]
  TableGrid grid;
};

/// Everything aerodynamic that depends on the wing shapes only: elements and
/// tables of every wing. Immutable; shared by all mountings of the same shapes.
class GliderAero {
 public:
  GliderAero(const Glider& g, std::shared_ptr<const CoefficientModel> model,
             const Environment& env = {}, const AeroOptions& opt = {});
  std::size_t wing_count() const { return tables_.size(); }
  const WingElements& elements(std::size_t j) const { return elements_[j]; }
  const WingTable& table(std::size_t j) const { return tables_[j]; }
  const CoefficientModel& model() const { return *model_; }
  std::shared_ptr<const CoefficientModel> model_ptr() const { return model_; }
  const Environment& environment() const { return env_; }
  const AeroOptions& options() const { return opt_; }
  double alpha_limit() const { return model_->alpha_limit(); }

 private:
  std::shared_ptr<const CoefficientModel> model_;
  Environment env_;
  AeroOptions opt_;
  std::vector<WingElements> elements_;
  std::vector<WingTable> tables_;
};

/// Glider totals at the centre of gravity: drag F_d and lift F_l [N] (along
/// and perpendicular to the flight direction) and pitching moment T_z [N m]
/// (nose-up positive).
struct GliderForces {
  double drag = 0, lift = 0, moment = 0;
};

/// A mounted glider: shapes (GliderAero), mounts and mass properties.
/// Evaluates the characteristic function F(V, gamma) of section 6.
class MountedGlider {
 public:
  MountedGlider(std::shared_ptr<const GliderAero> aero, const std::vector<Mount>& mounts,
                const MassProperties& mass);
  /// F(V, gamma): speed V [m/s], glider angle of attack gamma [rad].
  GliderForces forces(double v, double gamma) const;
  /// Same without tables (direct coefficient evaluation): slow, for checks.
  GliderForces forces_direct(double v, double gamma) const;
  /// Forces of wing j at the CG, split as in forces(): for the report.
  GliderForces wing_forces(std::size_t j, double v, double gamma) const;

  const GliderAero& aero() const { return *aero_; }
  std::shared_ptr<const GliderAero> aero_ptr() const { return aero_; }
  const MassProperties& mass() const { return mass_; }
  const std::vector<Mount>& mounts() const { return mounts_; }
  double alpha_limit() const { return aero_->alpha_limit(); }
  /// Largest |angle of attack| of any wing at glider angle gamma [rad].
  double max_wing_alpha(double gamma) const;

 private:
  GliderForces combine(std::size_t j, const WingCoefs& c, double q, double gamma) const;
  std::shared_ptr<const GliderAero> aero_;
  std::vector<Mount> mounts_;
  MassProperties mass_;
  std::vector<double> theta_;    // mounting angles [rad]
  std::vector<Vec2> arm_;        // mounting points relative to the CG [m]
};

/// Convenience: slice, tabulate, weigh and mount a glider file as it is.
MountedGlider mount(const Glider& g, std::shared_ptr<const CoefficientModel> model,
                    const Environment& env = {}, const AeroOptions& opt = {});

}  // namespace pteromys
