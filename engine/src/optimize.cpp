#include "pteromys/optimize.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>

#include <nlopt.hpp>

#include "pteromys/geometry.hpp"
#include "pteromys/text.hpp"

namespace pteromys {

namespace {

std::pair<double, double> longest_interval(const Polygon& outline) {
  std::pair<double, double> best{0, 0};
  for (const auto& iv : root_chord_intervals(outline))
    if (iv.second - iv.first > best.second - best.first) best = iv;
  return best;
}

}  // namespace

DesignCost::DesignCost(const Glider& g, std::shared_ptr<const GliderAero> aero, const OptimizeOptions& opt)
    : glider_(g), aero_(std::move(aero)), opt_(opt), mass_(g) {
  if (aero_->wing_count() != g.wings.size()) throw InputError("aerodynamics and glider have different wings");
  if (opt.n_speeds < 2 || opt.n_gammas < 3) throw InputError("the cost needs at least 2 speeds and 3 angles");
  const auto finite = [](std::initializer_list<double> vs) {
    for (double v : vs)
      if (!std::isfinite(v)) return false;
    return true;
  };
  if (!finite({opt.region.v_min, opt.region.v_max, opt.region.gamma_min, opt.region.gamma_max}) ||
      !(opt.region.v_max > opt.region.v_min) || !(opt.region.v_min > 0) ||
      !(opt.region.gamma_max > opt.region.gamma_min))
    throw InputError("the region Omega must have finite v_max > v_min > 0 and gamma_max > gamma_min");
  if (!finite({opt.angle_min_deg, opt.angle_max_deg}) || !(opt.angle_max_deg > opt.angle_min_deg))
    throw InputError("angle bounds must be finite, with max > min");
  if (!finite({opt.w1, opt.w2}) || !(opt.w1 >= 0) || !(opt.w2 >= 0))
    throw InputError("cost weights must be finite and non-negative");
  if (!finite({opt.w4, opt.min_static_margin}) || !(opt.w4 >= 0) || !(opt.min_static_margin >= 0))
    throw InputError("static-margin weight and target must be finite and non-negative");
  if (!(opt.min_overlap_fraction >= 0 && opt.min_overlap_fraction <= 1))
    throw InputError("the minimum root overlap must be a fraction between 0 and 1");
  if (!(opt.analysis.launch_height >= 0 && opt.analysis.launch_height <= 100))
    throw InputError("the launch height must be between 0 and 100 m");
  double best_area = -1;
  for (std::size_t j = 0; j < aero_->wing_count(); ++j) {
    const auto& el = aero_->elements(j);
    if (el.planform_area > best_area) {
      best_area = el.planform_area;
      ref_chord_ = el.span > 0 ? el.planform_area / el.span : 0;
    }
  }
  const auto [flo, fhi] = bounds(g.fuselage);
  std::set<std::string> known;
  for (std::size_t j = 0; j < g.wings.size(); ++j) {
    const Wing& w = g.wings[j];
    const auto root = longest_interval(w.outline);
    root_.push_back(root);
    required_.push_back(opt.min_overlap_fraction * (root.second - root.first));
    const double mid = 0.5 * (root.first + root.second);
    // x: the root chord's middle stays over the fuselage; y within its height.
    DesignVariable a{w.name + ".angle", w.mount.angle_deg, opt.angle_min_deg, opt.angle_max_deg, false};
    DesignVariable x{w.name + ".x", w.mount.x_m, flo.x - mid, fhi.x - mid, false};
    DesignVariable y{w.name + ".y", w.mount.y_m, flo.y, fhi.y, false};
    for (auto* v : {&a, &x, &y}) {
      known.insert(v->name);
      vars_.push_back(*v);
    }
  }
  // Front-to-back order of the wings as drawn (by the middle of the root chord).
  for (std::size_t j = 0; j < g.wings.size(); ++j) order_.push_back(j);
  auto root_mid_x = [&](std::size_t j) {
    const Mount& m = g.wings[j].mount;
    return m.x_m + std::cos(deg2rad(m.angle_deg)) * 0.5 * (root_[j].first + root_[j].second);
  };
  std::stable_sort(order_.begin(), order_.end(), [&](std::size_t a, std::size_t b) { return root_mid_x(a) > root_mid_x(b); });
  if (!(opt.min_wing_gap_m >= 0) || !std::isfinite(opt.min_wing_gap_m))
    throw InputError("the minimum gap between wings must be finite and non-negative");
  if (opt.optimise_ballast) {
    if (g.ballast.empty()) throw InputError("ballast optimisation needs at least one ballast item");
    // All ballast items move together; the variable is the first item's x.
    ballast_dx0_ = g.ballast.front().x_m;
    double lo = flo.x, hi = fhi.x;
    for (const auto& b : g.ballast) {
      lo = std::max(lo, flo.x + (ballast_dx0_ - b.x_m));
      hi = std::min(hi, fhi.x + (ballast_dx0_ - b.x_m));
    }
    vars_.push_back({"ballast.x", ballast_dx0_, lo, hi, false});
    known.insert("ballast.x");
  }
  for (const auto& l : opt.locks) {
    if (!known.count(l)) {
      std::string names;
      for (const auto& v : vars_) names += (names.empty() ? "" : ", ") + v.name;
      throw InputError("cannot lock '" + l + "': no such variable (variables: " + names + ")");
    }
    for (auto& v : vars_)
      if (v.name == l) v.locked = true;
  }
  // Start values outside the bounds are moved onto them (locked ones stay).
  for (auto& v : vars_)
    if (!v.locked) v.value = std::clamp(v.value, v.lower, v.upper);
}

std::vector<Mount> DesignCost::mounts_of(const std::vector<double>& v) const {
  std::vector<Mount> m(glider_.wings.size());
  for (std::size_t j = 0; j < m.size(); ++j) m[j] = {v[3 * j + 1], v[3 * j + 2], v[3 * j]};
  return m;
}

std::vector<Vec2> DesignCost::ballast_of(const std::vector<double>& v) const {
  std::vector<Vec2> out;
  const double dx = opt_.optimise_ballast ? v[3 * glider_.wings.size()] - ballast_dx0_ : 0.0;
  for (const auto& b : glider_.ballast) out.push_back({b.x_m + dx, b.y_m});
  return out;
}

double DesignCost::overlap(std::size_t j, const std::vector<double>& v) const {
  const double th = deg2rad(v[3 * j]);
  const Vec2 P{v[3 * j + 1], v[3 * j + 2]};
  const auto& r = root_[j];
  return segment_length_inside(glider_.fuselage, P + rotate({r.first, 0}, th), P + rotate({r.second, 0}, th));
}

std::vector<double> DesignCost::wing_gaps(const std::vector<double>& v) const {
  std::vector<double> gaps;
  for (std::size_t k = 0; k + 1 < order_.size(); ++k) {
    const std::size_t a = order_[k], b = order_[k + 1];
    const double te_a = v[3 * a + 1] + std::cos(deg2rad(v[3 * a])) * root_[a].first;
    const double le_b = v[3 * b + 1] + std::cos(deg2rad(v[3 * b])) * root_[b].second;
    gaps.push_back(te_a - le_b);
  }
  return gaps;
}

Glider DesignCost::apply(const std::vector<double>& v) const {
  Glider g = glider_;
  const auto m = mounts_of(v);
  for (std::size_t j = 0; j < g.wings.size(); ++j) g.wings[j].mount = m[j];
  const auto b = ballast_of(v);
  for (std::size_t k = 0; k < g.ballast.size(); ++k) {
    g.ballast[k].x_m = b[k].x;
    g.ballast[k].y_m = b[k].y;
  }
  return g;
}

MountedGlider DesignCost::mounted(const std::vector<double>& v) const {
  const auto m = mounts_of(v);
  return MountedGlider(aero_, m, mass_.evaluate(m, ballast_of(v)));
}

CostTerms DesignCost::evaluate(const std::vector<double>& v) const {
  const auto m = mounts_of(v);
  const MassProperties mp = mass_.evaluate(m, ballast_of(v));
  const double W = mp.mass * aero_->environment().gravity;
  const std::size_t nw = m.size();
  double th[16];
  Vec2 arm[16];
  std::vector<double> thv, armx, army;
  if (nw > 16) throw InputError("at most 16 wings are supported");
  for (std::size_t j = 0; j < nw; ++j) {
    th[j] = deg2rad(m[j].angle_deg);
    arm[j] = Vec2{m[j].x_m, m[j].y_m} - mp.cg;
  }
  const int ns = opt_.n_speeds, ng = opt_.n_gammas;
  const Region& R = opt_.region;
  const double hv = (R.v_max - R.v_min) / (ns - 1);
  const double rho = aero_->environment().air_density;
  CostTerms c;
  std::vector<double> T(ng), L(ng), D(ng), G(ng);
  for (int k = 0; k < ns; ++k) {
    const double V = R.v_min + hv * k;
    const double q = 0.5 * rho * V * V;
    const double wv = (k == 0 || k == ns - 1) ? 0.5 * hv : hv;  // trapezoid rule over V
    const WingTable::SpeedWeights sw = aero_->table(0).speed_weights(V);
    for (int i = 0; i < ng; ++i) {
      const double gm = R.gamma_min + (R.gamma_max - R.gamma_min) * i / (ng - 1);
      const double cg = std::cos(gm), sg = std::sin(gm);
      double t = 0, l = 0, d = 0;
      for (std::size_t j = 0; j < nw; ++j) {
        const WingCoefs w = aero_->table(j).lookup(sw, gm + th[j]);
        const double px = cg * arm[j].x - sg * arm[j].y, py = sg * arm[j].x + cg * arm[j].y;
        t += q * (w.moment + px * w.lift + py * w.drag);
        l += q * w.lift;
        d += q * w.drag;
      }
      T[i] = t;
      L[i] = l;
      D[i] = d;
      G[i] = gm;
    }
    c.c1 += wv * (std::max(0.0, -T[0]) + std::max(0.0, T[ng - 1]));
    // The T_z = 0 line at this speed: prefer the stable crossing (+ to -).
    int cell = -1;
    for (int i = 0; i + 1 < ng && cell < 0; ++i)
      if (T[i] >= 0 && T[i + 1] < 0) cell = i;
    for (int i = 0; i + 1 < ng && cell < 0; ++i)
      if ((T[i] <= 0 && T[i + 1] > 0)) cell = i;
    double lift, drag;
    double margin = 0;
    if (cell >= 0) {
      const double f = T[cell] / (T[cell] - T[cell + 1]);
      lift = L[cell] + f * (L[cell + 1] - L[cell]);
      drag = D[cell] + f * (D[cell + 1] - D[cell]);
      // Static margin x_cg - x_np = -(dT/dg) / (dF_Y/dg) at gamma*, from slopes
      // at the grid nodes interpolated to gamma* (continuous as gamma* moves
      // from cell to cell, so the optimiser sees no jumps).
      auto fy = [&](int i) { return L[i] * std::cos(G[i]) + D[i] * std::sin(G[i]); };
      auto node_slope = [&](int i, auto&& f) {
        const int a = std::max(0, i - 1), b = std::min(ng - 1, i + 1);
        return (f(b) - f(a)) / (G[b] - G[a]);
      };
      auto t_of = [&](int i) { return T[i]; };
      const double dT = node_slope(cell, t_of) + f * (node_slope(cell + 1, t_of) - node_slope(cell, t_of));
      const double dF = node_slope(cell, fy) + f * (node_slope(cell + 1, fy) - node_slope(cell, fy));
      if (dF > 0 && ref_chord_ > 0) margin = -dT / dF / ref_chord_;
    } else {
      // No equilibrium on the grid: use the end where |T_z| is smallest.
      const int e = std::abs(T[0]) < std::abs(T[ng - 1]) ? 0 : ng - 1;
      lift = L[e];
      drag = D[e];
      ++c.speeds_without_equilibrium;
    }
    c.c2 += wv * (lift - W) * (lift - W);
    c.c3 += wv * drag * drag;
    const double short_by = std::max(0.0, opt_.min_static_margin - margin);
    c.c4 += wv * short_by * short_by;
  }
  c.total = opt_.w1 * c.c1 + opt_.w2 * c.c2 + c.c3 + opt_.w4 * c.c4;
  return c;
}

double DesignCost::objective(const std::vector<double>& v) const {
  double pen = 0;
  for (std::size_t j = 0; j < glider_.wings.size(); ++j) {
    if (required_[j] <= 0) continue;
    const double deficit = std::max(0.0, required_[j] - overlap(j, v)) / required_[j];
    pen += deficit + deficit * deficit;
  }
  // Wings keep their order along the fuselage with a gap between them.
  const auto gaps = wing_gaps(v);
  for (std::size_t k = 0; k < gaps.size(); ++k) {
    const std::size_t b = order_[k + 1];
    const double scale = std::max(opt_.min_wing_gap_m, root_[b].second - root_[b].first);
    const double deficit = std::max(0.0, opt_.min_wing_gap_m - gaps[k]) / scale;
    pen += deficit + deficit * deficit;
  }
  const CostTerms c = evaluate(v);
  // Exact penalty: a 1 % shortfall costs more than any cost the design can gain.
  return c.total + (pen > 0 ? 100.0 * (1.0 + c.total) * pen : 0.0);
}

namespace {

struct Problem {
  const DesignCost* cost;
  std::vector<double> full;     // all variable values
  std::vector<int> free;        // indices of free variables
  std::vector<double> lo, span; // scaling of free variables to [0, 1]
  int evaluations = 0;
  double best = std::numeric_limits<double>::infinity();
  std::vector<double> best_x;

  std::vector<double> unscale(const std::vector<double>& x) const {
    std::vector<double> v = full;
    for (std::size_t i = 0; i < free.size(); ++i) v[free[i]] = lo[i] + span[i] * x[i];
    return v;
  }
  double operator()(const std::vector<double>& x) {
    ++evaluations;
    const double f = cost->objective(unscale(x));
    if (f < best) {
      best = f;
      best_x = x;
    }
    return f;
  }
};

double nlopt_objective(const std::vector<double>& x, std::vector<double>&, void* data) {
  return (*static_cast<Problem*>(data))(x);
}

// The paper's method: steepest descent, gradients by forward differences,
// with a backtracking line search (the paper does not state its step rule).
std::string steepest_descent(Problem& p, std::vector<double>& x, double step0, int max_eval, double xtol) {
  const std::size_t n = x.size();
  const double h = 1e-4;
  double f = p(x);
  double step = step0;
  while (p.evaluations < max_eval) {
    std::vector<double> g(n);
    for (std::size_t i = 0; i < n; ++i) {
      std::vector<double> xh = x;
      xh[i] = std::min(1.0, xh[i] + h);
      const double d = xh[i] - x[i];
      g[i] = d > 0 ? (p(xh) - f) / d : 0.0;
    }
    double gn = 0;
    for (double gi : g) gn += gi * gi;
    gn = std::sqrt(gn);
    if (gn == 0) return "zero gradient";
    bool moved = false;
    while (step > xtol && p.evaluations < max_eval) {
      std::vector<double> xn(n);
      for (std::size_t i = 0; i < n; ++i) xn[i] = std::clamp(x[i] - step * g[i] / gn, 0.0, 1.0);
      const double fn = p(xn);
      if (fn < f) {
        x = xn;
        f = fn;
        step *= 1.5;
        moved = true;
        break;
      }
      step *= 0.5;
    }
    if (!moved) return "step below tolerance";
  }
  return "evaluation limit";
}

}  // namespace

OptimizeResult optimize(const Glider& g, std::shared_ptr<const GliderAero> aero, const OptimizeOptions& opt,
                        const OptimizeResult* warm) {
  const auto t0 = std::chrono::steady_clock::now();
  if (opt.max_evaluations < 1) throw InputError("the number of evaluations must be at least 1");
  DesignCost cost(g, aero, opt);
  Problem p;
  p.cost = &cost;
  for (const auto& v : cost.variables()) p.full.push_back(v.value);
  // Warm start: the previous optimum's values for variables of the same name.
  bool warm_used = false;
  if (warm) {
    for (std::size_t i = 0; i < cost.variables().size(); ++i) {
      const auto& v = cost.variables()[i];
      if (v.locked) continue;
      for (const auto& w : warm->variables)
        if (w.name == v.name) {
          p.full[i] = std::clamp(w.value, v.lower, v.upper);
          warm_used = true;
        }
    }
  }
  for (std::size_t i = 0; i < cost.variables().size(); ++i) {
    const auto& v = cost.variables()[i];
    if (v.locked || !(v.upper > v.lower)) continue;
    p.free.push_back(static_cast<int>(i));
    p.lo.push_back(v.lower);
    p.span.push_back(v.upper - v.lower);
  }
  OptimizeResult r;
  r.algorithm = opt.algorithm;
  r.cost_start = cost.evaluate(p.full);
  std::vector<double> x(p.free.size());
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = (p.full[p.free[i]] - p.lo[i]) / p.span[i];
  const double step0 = warm_used ? 0.02 : 0.15;
  if (!x.empty()) {
    if (opt.algorithm == "steepest") {
      r.stop_reason = steepest_descent(p, x, step0, opt.max_evaluations, opt.xtol);
    } else {
      nlopt::algorithm alg;
      if (opt.algorithm == "bobyqa") alg = nlopt::LN_BOBYQA;
      else if (opt.algorithm == "cobyla") alg = nlopt::LN_COBYLA;
      else if (opt.algorithm == "sbplx") alg = nlopt::LN_SBPLX;
      else if (opt.algorithm == "neldermead") alg = nlopt::LN_NELDERMEAD;
      else throw InputError("unknown optimisation algorithm '" + opt.algorithm +
                            "' (bobyqa, cobyla, sbplx, neldermead or steepest)");
      double f = p(x);
      // A warm start begins near the optimum: one restart is enough.
      const int restarts = warm_used ? std::min(opt.restarts, 1) : opt.restarts;
      for (int round = 0; round <= std::max(0, restarts); ++round) {
        const int left = opt.max_evaluations - p.evaluations;
        if (left <= 0) {
          r.stop_reason = "evaluation limit";
          break;
        }
        nlopt::opt o(alg, static_cast<unsigned>(x.size()));
        o.set_lower_bounds(std::vector<double>(x.size(), 0.0));
        o.set_upper_bounds(std::vector<double>(x.size(), 1.0));
        o.set_min_objective(nlopt_objective, &p);
        o.set_xtol_abs(opt.xtol);
        o.set_maxeval(left);
        o.set_initial_step(round == 0 ? step0 : 0.5 * step0);
        const double before = f;
        try {
          const nlopt::result res = o.optimize(x, f);
          r.stop_reason = res == nlopt::XTOL_REACHED ? "converged (step below tolerance)"
                          : res == nlopt::MAXEVAL_REACHED ? "evaluation limit"
                          : res == nlopt::FTOL_REACHED ? "converged (cost change below tolerance)"
                                                       : "stopped (nlopt code " + std::to_string(static_cast<int>(res)) + ")";
        } catch (const nlopt::roundoff_limited&) {
          r.stop_reason = "converged (round-off limited)";
        } catch (const std::exception& e) {
          r.stop_reason = std::string("optimiser stopped: ") + e.what();
          break;
        }
        if (!p.best_x.empty()) {
          x = p.best_x;
          f = p.best;
        }
        if (!(f < before * (1 - 1e-3))) break;  // a restart no longer helps
      }
    }
    if (!p.best_x.empty()) x = p.best_x;
  } else {
    r.stop_reason = "every variable is locked";
  }
  std::vector<double> best = x.empty() ? p.full : p.unscale(x);
  {
    // Keep the start when the gain is immaterial and the start is feasible.
    const double f_start = cost.objective(p.full), f_best = cost.objective(best);
    const double c_start = cost.evaluate(p.full).total;
    const bool start_feasible = f_start <= c_start * (1 + 1e-12);
    if (start_feasible && !(f_best < f_start * (1 - opt.min_improvement))) {
      best = p.full;
      r.stop_reason += "; kept the starting mounts (improvement below " + fmt_number(100 * opt.min_improvement) + " %)";
    }
  }
  r.evaluations = p.evaluations;
  r.cost = cost.evaluate(best);
  r.variables = cost.variables();
  for (std::size_t i = 0; i < best.size(); ++i) r.variables[i].value = best[i];
  r.glider = cost.apply(best);
  std::vector<std::string> names;
  for (const auto& w : g.wings) names.push_back(w.name);
  r.report = analyse(cost.mounted(best), names, opt.analysis);
  // Say plainly when the optimiser could not make it fly within the bounds.
  if (!r.report.flyable) {
    std::vector<std::string> extra;
    if (r.cost.c1 > 0)
      extra.push_back(
          "no pitch-stable mounting exists within the bounds (mounting angles " + fmt_number(opt.angle_min_deg) + " to " +
          fmt_number(opt.angle_max_deg) + " deg, wings kept on the fuselage" +
          (opt.locks.empty() ? std::string() : ", with the locked variables fixed") +
          "): the pitching moment does not restore the angle of attack over Omega");
    for (std::size_t j = 0; j < g.wings.size(); ++j)
      if (cost.required_overlap(j) > 0 && cost.overlap(j, best) < cost.required_overlap(j) * 0.999)
        extra.push_back("wing '" + g.wings[j].name + "' could not be kept on the fuselage at its best position");
    const auto gaps = cost.wing_gaps(best);
    for (std::size_t k = 0; k < gaps.size(); ++k)
      if (gaps[k] < opt.min_wing_gap_m - 1e-6)
        extra.push_back("wings '" + g.wings[cost.wing_order()[k]].name + "' and '" + g.wings[cost.wing_order()[k + 1]].name +
                        "' could not be kept apart along the fuselage (gap " + fmt_number(1000 * gaps[k]) + " mm)");
    r.report.reasons.insert(r.report.reasons.begin(), extra.begin(), extra.end());
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

OptimizeResult optimize(const Glider& g, std::shared_ptr<const CoefficientModel> model, const OptimizeOptions& opt,
                        const Environment& env, const AeroOptions& ao, const OptimizeResult* warm) {
  validate(g);
  auto aero = std::make_shared<const GliderAero>(g, std::move(model), env, ao);
  return optimize(g, aero, opt, warm);
}

}  // namespace pteromys
