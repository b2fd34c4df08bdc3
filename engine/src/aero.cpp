#include "pteromys/aero.hpp"

#include <algorithm>
#include <cmath>

namespace pteromys {
namespace {

// Catmull-Rom weights for fractional position t in [0, 1] between nodes i, i+1.
inline void catmull_rom(double t, double w[4]) {
  const double t2 = t * t, t3 = t2 * t;
  w[0] = 0.5 * (-t3 + 2 * t2 - t);
  w[1] = 0.5 * (3 * t3 - 5 * t2 + 2);
  w[2] = 0.5 * (-3 * t3 + 4 * t2 + t);
  w[3] = 0.5 * (t3 - t2);
}

/// d/dt of catmull_rom's weights.
inline void catmull_rom_slope(double t, double d[4]) {
  const double t2 = t * t;
  d[0] = 0.5 * (-3 * t2 + 4 * t - 1);
  d[1] = 0.5 * (9 * t2 - 10 * t);
  d[2] = 0.5 * (-9 * t2 + 8 * t + 1);
  d[3] = 0.5 * (3 * t2 - 2 * t);
}

inline void locate(double u, int n, int* i, double* t) {
  if (u <= 0) { *i = 0; *t = 0; return; }
  if (u >= n - 1) { *i = n - 2; *t = 1; return; }
  *i = static_cast<int>(u);
  if (*i > n - 2) *i = n - 2;
  *t = u - *i;
}

}  // namespace

std::vector<ElementShape> element_shapes(const WingElements& el) {
  std::vector<ElementShape> out;
  out.reserve(el.elements.size());
  for (const auto& e : el.elements) out.push_back({e.area, e.chord, e.x_qc, e.xi_l, e.xi_t});
  return out;
}

WingTable::WingTable(const WingElements& el, const CoefficientModel& model, const Environment& env,
                     const TableGrid& grid) {
  if (!(grid.v_min > 0) || !(grid.v_max > grid.v_min) || grid.nv < 4 || !(grid.alpha_step > 0))
    throw InputError("invalid force-table grid");
  nv_ = grid.nv;
  lv0_ = std::log(grid.v_min);
  dlv_ = (std::log(grid.v_max) - lv0_) / (nv_ - 1);
  alpha_max_ = model.alpha_limit();
  // Symmetric alpha grid covering the model range plus two nodes of margin so
  // that cubic look-ups near the limit use real values.
  const int m = static_cast<int>(std::ceil(alpha_max_ / grid.alpha_step));
  da_ = alpha_max_ / m;
  const int half = m + 2;
  na_ = 2 * half + 1;
  a0_ = -half * da_;
  std::vector<double> re_per_chord(nv_), alphas(na_);
  for (int iv = 0; iv < nv_; ++iv)
    re_per_chord[iv] = env.air_density * std::exp(lv0_ + iv * dlv_) / env.air_viscosity;
  for (int ia = 0; ia < na_; ++ia) alphas[ia] = (ia - half) * da_;
  CoefficientSums s;
  model.sum_over_elements(element_shapes(el), re_per_chord, alphas, s);
  const std::size_t n = static_cast<std::size_t>(nv_) * na_;
  dlm_.resize(3 * n);
  for (int iv = 0; iv < nv_; ++iv)
    for (int ia = 0; ia < na_; ++ia) {
      const std::size_t idx = static_cast<std::size_t>(iv) * na_ + ia;
      dlm_[3 * idx] = s.cd_a[idx];
      dlm_[3 * idx + 1] = s.cl_a[idx];
      dlm_[3 * idx + 2] = s.cm_la[idx] + std::sin(alphas[ia]) * s.cd_da[idx] + std::cos(alphas[ia]) * s.cl_da[idx];
    }
}

void WingTable::speed_weights(double v, SpeedWeights& sw) const {
  double tv;
  locate((std::log(std::max(v, 1e-9)) - lv0_) / dlv_, nv_, &sw.iv, &tv);
  catmull_rom(tv, sw.w);
}

WingTable::SpeedWeights WingTable::speed_weights(double v) const {
  SpeedWeights sw;
  speed_weights(v, sw);
  return sw;
}

WingCoefs WingTable::lookup(const SpeedWeights& sw, double alpha) const {
  int ia;
  double ta;
  locate((alpha - a0_) / da_, na_, &ia, &ta);
  double wa[4];
  catmull_rom(ta, wa);
  WingCoefs c;
  const bool inner = ia >= 1 && ia + 2 < na_;
  for (int p = 0; p < 4; ++p) {
    const int jv = std::clamp(sw.iv - 1 + p, 0, nv_ - 1);
    double rd = 0, rl = 0, rm = 0;
    const std::size_t row = static_cast<std::size_t>(jv) * na_;
    if (inner) {
      const double* x = &dlm_[3 * (row + ia - 1)];  // drag, lift, moment of 4 nodes
      rd = wa[0] * x[0] + wa[1] * x[3] + wa[2] * x[6] + wa[3] * x[9];
      rl = wa[0] * x[1] + wa[1] * x[4] + wa[2] * x[7] + wa[3] * x[10];
      rm = wa[0] * x[2] + wa[1] * x[5] + wa[2] * x[8] + wa[3] * x[11];
    } else {
      for (int q = 0; q < 4; ++q) {
        const std::size_t ja = 3 * (row + std::clamp(ia - 1 + q, 0, na_ - 1));
        rd += wa[q] * dlm_[ja];
        rl += wa[q] * dlm_[ja + 1];
        rm += wa[q] * dlm_[ja + 2];
      }
    }
    c.drag += sw.w[p] * rd;
    c.lift += sw.w[p] * rl;
    c.moment += sw.w[p] * rm;
  }
  return c;
}

double WingTable::lift(const SpeedWeights& sw, double alpha, double* dlift_dalpha) const {
  const double u = (alpha - a0_) / da_;
  int ia;
  double ta;
  locate(u, na_, &ia, &ta);
  double wa[4], da[4];
  catmull_rom(ta, wa);
  catmull_rom_slope(ta, da);
  // Beyond the table the look-up is constant.
  const bool inside = u > 0 && u < na_ - 1;
  double l = 0, dl = 0;
  const bool inner = ia >= 1 && ia + 2 < na_;
  for (int p = 0; p < 4; ++p) {
    const int jv = std::clamp(sw.iv - 1 + p, 0, nv_ - 1);
    const std::size_t row = static_cast<std::size_t>(jv) * na_;
    double rl = 0, rdl = 0;
    if (inner) {
      const double* x = &dlm_[3 * (row + ia - 1) + 1];  // lift of 4 nodes
      rl = wa[0] * x[0] + wa[1] * x[3] + wa[2] * x[6] + wa[3] * x[9];
      rdl = da[0] * x[0] + da[1] * x[3] + da[2] * x[6] + da[3] * x[9];
    } else {
      for (int q = 0; q < 4; ++q) {
        const double x = dlm_[3 * (row + std::clamp(ia - 1 + q, 0, na_ - 1)) + 1];
        rl += wa[q] * x;
        rdl += da[q] * x;
      }
    }
    l += sw.w[p] * rl;
    dl += sw.w[p] * rdl;
  }
  if (dlift_dalpha) *dlift_dalpha = inside ? dl / da_ : 0.0;
  return l;
}

WingCoefs WingTable::lookup(double v, double alpha) const { return lookup(speed_weights(v), alpha); }

WingCoefs wing_coefs_direct(const WingElements& el, const CoefficientModel& model,
                            const Environment& env, double v, double alpha) {
  WingCoefs c;
  const double rpc = env.air_density * v / env.air_viscosity;
  const double sa = std::sin(alpha), ca = std::cos(alpha);
  for (const auto& e : el.elements) {
    const Coefficients k = model.eval({alpha, rpc * e.chord, e.xi_l, e.xi_t});
    c.drag += e.area * k.cd;
    c.lift += e.area * k.cl;
    c.moment += e.area * (k.cm * e.chord + k.cd * e.x_qc * sa + k.cl * e.x_qc * ca);
  }
  return c;
}

GliderAero::GliderAero(const Glider& g, std::shared_ptr<const CoefficientModel> model,
                       const Environment& env, const AeroOptions& opt)
    : model_(std::move(model)), env_(env), opt_(opt) {
  if (!model_) throw InputError("no coefficient model");
  for (const auto& w : g.wings) {
    elements_.push_back(slice_wing(w.outline, opt_.dz));
    tables_.emplace_back(elements_.back(), *model_, env_, opt_.grid);
  }
}

MountedGlider::MountedGlider(std::shared_ptr<const GliderAero> aero, const std::vector<Mount>& mounts,
                             const MassProperties& mass)
    : aero_(std::move(aero)), mounts_(mounts), mass_(mass) {
  if (mounts_.size() != aero_->wing_count()) throw InputError("one mount per wing expected");
  for (const auto& m : mounts_) {
    theta_.push_back(deg2rad(m.angle_deg));
    arm_.push_back(Vec2{m.x_m, m.y_m} - mass_.cg);
  }
}

GliderForces MountedGlider::combine(std::size_t j, const WingCoefs& c, double q, double gamma) const {
  const double fd = q * c.drag, fl = q * c.lift, tau = q * c.moment;
  const Vec2 P = rotate(arm_[j], gamma);  // (P_x, P_y) = R(gamma) (P_X, P_Y)
  return {fd, fl, tau + P.x * fl + P.y * fd};
}

GliderForces MountedGlider::wing_forces(std::size_t j, double v, double gamma) const {
  const double q = 0.5 * aero_->environment().air_density * v * v;
  return combine(j, aero_->table(j).lookup(v, wrap_angle(gamma + theta_[j])), q, gamma);
}

GliderForces MountedGlider::forces(double v, double gamma) const {
  const double q = 0.5 * aero_->environment().air_density * v * v;
  const double c = std::cos(gamma), s = std::sin(gamma);
  GliderForces f;
  // Every wing's table has the same speed grid: interpolation weights once.
  const WingTable::SpeedWeights sw = aero_->table(0).speed_weights(v);
  for (std::size_t j = 0; j < theta_.size(); ++j) {
    const WingCoefs w = aero_->table(j).lookup(sw, wrap_angle(gamma + theta_[j]));
    const double fd = q * w.drag, fl = q * w.lift;
    const double px = c * arm_[j].x - s * arm_[j].y, py = s * arm_[j].x + c * arm_[j].y;
    f.drag += fd;
    f.lift += fl;
    f.moment += q * w.moment + px * fl + py * fd;
  }
  return f;
}

GliderForces MountedGlider::forces_direct(double v, double gamma) const {
  const double q = 0.5 * aero_->environment().air_density * v * v;
  GliderForces f;
  for (std::size_t j = 0; j < theta_.size(); ++j) {
    const WingCoefs c =
        wing_coefs_direct(aero_->elements(j), aero_->model(), aero_->environment(), v, wrap_angle(gamma + theta_[j]));
    const GliderForces w = combine(j, c, q, gamma);
    f.drag += w.drag;
    f.lift += w.lift;
    f.moment += w.moment;
  }
  return f;
}

double MountedGlider::max_wing_alpha(double gamma) const {
  double m = 0;
  for (double th : theta_) m = std::max(m, std::abs(wrap_angle(gamma + th)));
  return m;
}

MountedGlider mount(const Glider& g, std::shared_ptr<const CoefficientModel> model,
                    const Environment& env, const AeroOptions& opt) {
  auto aero = std::make_shared<const GliderAero>(g, std::move(model), env, opt);
  std::vector<Mount> mounts;
  for (const auto& w : g.wings) mounts.push_back(w.mount);
  return MountedGlider(aero, mounts, mass_properties(g));
}

}  // namespace pteromys
