#include "pteromys/coefficients.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace pteromys {

void CoefficientSums::resize(int nv_, int na_) {
  nv = nv_;
  na = na_;
  const std::size_t n = static_cast<std::size_t>(nv_) * static_cast<std::size_t>(na_);
  for (auto* v : {&cd_a, &cl_a, &cm_la, &cd_da, &cl_da}) v->assign(n, 0.0);
}

void CoefficientModel::sum_over_elements(const std::vector<ElementShape>& els,
                                         const std::vector<double>& re_per_chord,
                                         const std::vector<double>& alphas,
                                         CoefficientSums& out) const {
  const int nv = static_cast<int>(re_per_chord.size()), na = static_cast<int>(alphas.size());
  out.resize(nv, na);
  for (int iv = 0; iv < nv; ++iv)
    for (int ia = 0; ia < na; ++ia) {
      const std::size_t idx = static_cast<std::size_t>(iv) * na + ia;
      for (const auto& e : els) {
        const Coefficients c = eval({alphas[ia], re_per_chord[iv] * e.chord, e.xi_l, e.xi_t});
        out.cd_a[idx] += e.area * c.cd;
        out.cl_a[idx] += e.area * c.cl;
        out.cm_la[idx] += e.area * e.chord * c.cm;
        out.cd_da[idx] += e.area * e.arm * c.cd;
        out.cl_da[idx] += e.area * e.arm * c.cl;
      }
    }
}

// ---------------------------------------------------------------- flat plate

FlatPlateModel::FlatPlateModel(FlatPlateParams p) : p_(p) {
  // Helmbold's lift slope of a wing of aspect ratio A from the section slope a0.
  const double k = p_.section_lift_slope / (kPi * p_.aspect_ratio);
  lift_slope_ = p_.section_lift_slope / (std::sqrt(1 + k * k) + k);
  if (p_.normal_force_90 > 0) {
    cn90_ = p_.normal_force_90;
  } else {
    // Hoerner's finite flat plates broadside to the flow, piecewise linear in 1/A.
    static const double inv_a[] = {0.0, 1.0 / 20, 1.0 / 10, 1.0 / 5, 1.0};
    static const double cn[] = {1.98, 1.50, 1.29, 1.20, 1.17};
    const double x = std::min(1.0, 1.0 / std::max(1.0, p_.aspect_ratio));
    int i = 0;
    while (i < 3 && x > inv_a[i + 1]) ++i;
    const double t = (x - inv_a[i]) / (inv_a[i + 1] - inv_a[i]);
    cn90_ = cn[i] + t * (cn[i + 1] - cn[i]);
  }
}

double FlatPlateModel::friction_drag(double re) {
  // Blasius laminar skin friction on both faces: 2 x 1.328 / sqrt(Re).
  const double r = std::max(re, 100.0);
  return 2.0 * 1.328 / std::sqrt(r);
}

Coefficients FlatPlateModel::eval_alpha(double alpha) const {
  // The air force of a sharp flat plate acts normal to the plate (no leading-
  // edge suction): C_L = C_N cos a, C_D = C_N sin a (+ edge and friction drag).
  // C_N blends attached flow (finite-wing slope) into separated flow
  // (flat-plate normal force, C_N90 sin a / (0.56 + 0.44 sin a)).
  const double s = alpha < 0 ? -1.0 : 1.0;
  const double a = std::abs(alpha);
  const double sa = std::sin(a), ca = std::cos(a);
  const double cn_att = lift_slope_ * sa;
  // Separation can only lose normal force, never gain it.
  const double cn_sep = std::min(cn90_ * sa / (0.56 + 0.44 * sa), cn_att);
  // C1 smoothstep over [stall - width, stall + width]: exactly attached flow
  // below, exactly separated flow above.
  const double u = std::clamp((a - deg2rad(p_.stall_deg - p_.stall_width_deg)) / deg2rad(2 * p_.stall_width_deg), 0.0, 1.0);
  const double sig = u * u * (3 - 2 * u);
  const double cn = (1 - sig) * cn_att + sig * cn_sep;
  Coefficients c;
  c.cl = s * (cn * ca);
  c.cd = p_.edge_drag + cn * sa;
  // Centre of pressure at the quarter chord in attached flow, moving aft
  // toward mid-chord as the flow separates.
  c.cm = s * (-cn * sig * 0.25 * sa);
  return c;
}

Coefficients FlatPlateModel::eval(const ElementState& e) const {
  Coefficients c = eval_alpha(e.alpha);
  c.cd += friction_drag(e.re);
  return c;
}

void FlatPlateModel::sum_over_elements(const std::vector<ElementShape>& els,
                                       const std::vector<double>& re_per_chord,
                                       const std::vector<double>& alphas,
                                       CoefficientSums& out) const {
  const int nv = static_cast<int>(re_per_chord.size()), na = static_cast<int>(alphas.size());
  out.resize(nv, na);
  double sa = 0, sla = 0, sda = 0;
  for (const auto& e : els) {
    sa += e.area;
    sla += e.area * e.chord;
    sda += e.area * e.arm;
  }
  std::vector<Coefficients> ca(na);
  for (int ia = 0; ia < na; ++ia) ca[ia] = eval_alpha(alphas[ia]);
  for (int iv = 0; iv < nv; ++iv) {
    double fa = 0, fda = 0;
    for (const auto& e : els) {
      const double f = friction_drag(re_per_chord[iv] * e.chord);
      fa += e.area * f;
      fda += e.area * e.arm * f;
    }
    for (int ia = 0; ia < na; ++ia) {
      const std::size_t idx = static_cast<std::size_t>(iv) * na + ia;
      out.cd_a[idx] = sa * ca[ia].cd + fa;
      out.cl_a[idx] = sa * ca[ia].cl;
      out.cm_la[idx] = sla * ca[ia].cm;
      out.cd_da[idx] = sda * ca[ia].cd + fda;
      out.cl_da[idx] = sda * ca[ia].cl;
    }
  }
}

// ---------------------------------------------------------------------- RBF

RbfModel::RbfModel(std::vector<RbfCentre> centres, RbfScales scales, double alpha_limit,
                   std::shared_ptr<const FlatPlateModel> prior)
    : centres_(std::move(centres)), scales_(scales), alpha_limit_(alpha_limit), prior_(std::move(prior)) {
  if (centres_.empty()) throw InputError("an RBF model needs at least one centre");
  for (double s : {scales_.alpha, scales_.re, scales_.xi_l, scales_.xi_t})
    if (!(s > 0) || !std::isfinite(s)) throw InputError("RBF scales must be positive numbers");
  for (const auto& c : centres_)
    for (double v : {c.alpha, c.re, c.xi_l, c.xi_t, c.value.cd, c.value.cl, c.value.cm})
      if (!std::isfinite(v)) throw InputError("an RBF centre has a NaN or infinite number");
  solve_weights();
}

namespace {
// Kernel pair of centre k at input e: psi(|e - e^k|) and psi(|e - ghost^k|).
struct KernelPair {
  double g, gb;
};
inline KernelPair kernel_pair(const ElementState& e, const RbfCentre& k, const RbfScales& s) {
  const double dr = (e.re - k.re) / s.re;
  const double dl = (e.xi_l - k.xi_l) / s.xi_l;
  const double dt = (e.xi_t - k.xi_t) / s.xi_t;
  const double base = dr * dr + dl * dl + dt * dt;
  const double da = (e.alpha - k.alpha) / s.alpha;
  const double db = (e.alpha + k.alpha) / s.alpha;
  return {std::exp(-(base + da * da)), std::exp(-(base + db * db))};
}
}  // namespace

void RbfModel::solve_weights() {
  const int K = static_cast<int>(centres_.size());
  Eigen::MatrixXd even(K, K), odd(K, K);
  Eigen::MatrixXd rhs(K, 3);
  for (int j = 0; j < K; ++j) {
    const RbfCentre& cj = centres_[j];
    const ElementState e{cj.alpha, cj.re, cj.xi_l, cj.xi_t};
    for (int k = 0; k < K; ++k) {
      const KernelPair kp = kernel_pair(e, centres_[k], scales_);
      even(j, k) = kp.g + kp.gb;
      odd(j, k) = kp.g - kp.gb;
    }
    Coefficients r = cj.value;
    if (prior_) {
      const Coefficients p = prior_->eval(e);
      r.cd -= p.cd;
      r.cl -= p.cl;
      r.cm -= p.cm;
    }
    rhs(j, 0) = r.cd;
    rhs(j, 1) = r.cl;
    rhs(j, 2) = r.cm;
  }
  // Minimum-norm least squares: robust to centres on alpha = 0 (whose odd
  // kernel vanishes) and to near-duplicate centres.
  const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> de(even), dodd(odd);
  const Eigen::VectorXd wd = de.solve(rhs.col(0));
  const Eigen::VectorXd wl = dodd.solve(rhs.col(1));
  const Eigen::VectorXd wm = dodd.solve(rhs.col(2));
  weights_.resize(K);
  for (int k = 0; k < K; ++k) weights_[k] = {wd(k), wl(k), wm(k)};
}

Coefficients RbfModel::eval(const ElementState& e) const {
  Coefficients c;
  for (std::size_t k = 0; k < centres_.size(); ++k) {
    const KernelPair kp = kernel_pair(e, centres_[k], scales_);
    const double ev = kp.g + kp.gb, od = kp.g - kp.gb;
    c.cd += weights_[k][0] * ev;
    c.cl += weights_[k][1] * od;
    c.cm += weights_[k][2] * od;
  }
  if (prior_) {
    const Coefficients p = prior_->eval(e);
    c.cd += p.cd;
    c.cl += p.cl;
    c.cm += p.cm;
  }
  return c;
}

void RbfModel::sum_over_elements(const std::vector<ElementShape>& els,
                                 const std::vector<double>& re_per_chord,
                                 const std::vector<double>& alphas, CoefficientSums& out) const {
  // The Gaussian kernel factorises over the input dimensions:
  // psi = exp(-da^2) exp(-dRe^2) exp(-dxi_l^2 - dxi_t^2). The alpha factor is
  // shared by all elements, the xi factor by all speeds, so the sums cost
  // O(K (N_el nv + nv na)) instead of O(K N_el nv na).
  const int nv = static_cast<int>(re_per_chord.size()), na = static_cast<int>(alphas.size());
  const std::size_t K = centres_.size(), N = els.size();
  if (prior_) prior_->sum_over_elements(els, re_per_chord, alphas, out);
  else out.resize(nv, na);
  std::vector<double> G(N * K);
  for (std::size_t i = 0; i < N; ++i)
    for (std::size_t k = 0; k < K; ++k) {
      const double dl = (els[i].xi_l - centres_[k].xi_l) / scales_.xi_l;
      const double dt = (els[i].xi_t - centres_[k].xi_t) / scales_.xi_t;
      G[i * K + k] = std::exp(-(dl * dl + dt * dt));
    }
  std::vector<double> Ep(static_cast<std::size_t>(na) * K), Em(static_cast<std::size_t>(na) * K);
  for (int ia = 0; ia < na; ++ia)
    for (std::size_t k = 0; k < K; ++k) {
      const double da = (alphas[ia] - centres_[k].alpha) / scales_.alpha;
      const double db = (alphas[ia] + centres_[k].alpha) / scales_.alpha;
      const double g = std::exp(-da * da), gb = std::exp(-db * db);
      Ep[ia * K + k] = g + gb;
      Em[ia * K + k] = g - gb;
    }
  std::vector<double> Ba(K), Bl(K), Bd(K);
  for (int iv = 0; iv < nv; ++iv) {
    std::fill(Ba.begin(), Ba.end(), 0.0);
    std::fill(Bl.begin(), Bl.end(), 0.0);
    std::fill(Bd.begin(), Bd.end(), 0.0);
    for (std::size_t i = 0; i < N; ++i) {
      const double re = re_per_chord[iv] * els[i].chord;
      for (std::size_t k = 0; k < K; ++k) {
        const double dr = (re - centres_[k].re) / scales_.re;
        const double gh = G[i * K + k] * std::exp(-dr * dr) * els[i].area;
        Ba[k] += gh;
        Bl[k] += gh * els[i].chord;
        Bd[k] += gh * els[i].arm;
      }
    }
    for (int ia = 0; ia < na; ++ia) {
      const std::size_t idx = static_cast<std::size_t>(iv) * na + ia;
      double cd = 0, cl = 0, cm = 0, cdd = 0, cld = 0;
      for (std::size_t k = 0; k < K; ++k) {
        const double ep = Ep[ia * K + k], em = Em[ia * K + k];
        const auto& w = weights_[k];
        cd += w[0] * Ba[k] * ep;
        cl += w[1] * Ba[k] * em;
        cm += w[2] * Bl[k] * em;
        cdd += w[0] * Bd[k] * ep;
        cld += w[1] * Bd[k] * em;
      }
      out.cd_a[idx] += cd;
      out.cl_a[idx] += cl;
      out.cm_la[idx] += cm;
      out.cd_da[idx] += cdd;
      out.cl_da[idx] += cld;
    }
  }
}

std::shared_ptr<RbfModel> RbfModel::with_values(const std::vector<Coefficients>& values) const {
  if (values.size() != centres_.size()) throw InputError("RBF: one value per centre expected");
  auto c = centres_;
  for (std::size_t k = 0; k < c.size(); ++k) c[k].value = values[k];
  return std::make_shared<RbfModel>(std::move(c), scales_, alpha_limit_, prior_);
}

}  // namespace pteromys
