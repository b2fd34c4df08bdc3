// Sim-to-real gap diagnosis: leave-gliders-out cross-validation of the
// baseline and of every candidate effect, significance tests, verdict,
// summary (diagnose.hpp; docs/diagnosis.md).
#include "pteromys/diagnose.hpp"

#include <boost/math/distributions/students_t.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <set>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "pteromys/io.hpp"

namespace pteromys {
namespace {

// Fractions of a linearised step tried in turn (DiagnoseOptions::profile):
// the full step, then damped ones where it overshoots.
constexpr double kStepFractions[] = {1.0, 0.5, 0.25};
// A profiled start whose first fit (strengths and trims, up to
// DiagFitOptions::iterations Levenberg-Marquardt steps) still misfits this
// many times the fixed-coefficient fit's SSE is not settled further: the
// settling passes crawl (downwash's overshooting full step on blind pitch
// damping at 2, fold 2: 4.9 cm against 1.5 cm after 704 s, under 1 % a
// step) and the result is discarded unless it beats that fit. At 1 (it was
// 3): a first fit that does not beat the fixed-coefficient fit goes on to
// the next damped step at once, and the joint refit with the centre values
// starts from the best first fit (blind downwash at 1, seed 22, all
// gliders: the half step's settling passes took it from 4.9 to 4.7 cm in
// about 210 s; the same strength 0.717 and 1.9 cm either way, the
// candidate's fits 482 s against 723 s).
constexpr double kGiveUpFactor = 1.0;
// A theoretical-size start (DiagnoseOptions::theory_starts) whose
// launches-and-trims fit at strength 1 misfits this many times the baseline's SSE
// is not refitted with the centre values: the joint fit from there crawls
// and lands in a poorer basin (blind pitch damping at 1, seed 28, all
// gliders: downwash 392 s to 31 cm, finite span 64 s to 5.3 cm, against the
// baseline's 1.4 cm; pitch damping itself 1.9 cm at 1 before its refit in
// the oracle's folds, 1.6 cm baseline).
constexpr double kTheoryStartFactor = 4.0;
// Steps in which the oracle's effects and a theoretical-size start's
// strength are switched on (a quarter, a half, ...).
constexpr int kRampSteps = 4;

using nlohmann::json;
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// One-sample t statistic of a mean against 0: mean / (s / sqrt(n)). With no
// spread (every value the same) the t is +-kBigT by the mean's sign, 0 for a
// mean of 0; with fewer than two values it is 0 (nothing to test).
constexpr double kBigT = 1e12;
struct MeanT {
  double mean = 0, t = 0;
};
MeanT mean_and_t(const std::vector<double>& x) {
  MeanT r;
  const double n = static_cast<double>(x.size());
  if (x.empty()) return r;
  r.mean = std::accumulate(x.begin(), x.end(), 0.0) / n;
  if (x.size() < 2) return r;
  double v = 0;
  for (double y : x) v += (y - r.mean) * (y - r.mean);
  const double se = std::sqrt(v / (n - 1) / n);
  r.t = se > 0 ? std::clamp(r.mean / se, -kBigT, kBigT) : (r.mean > 0 ? kBigT : (r.mean < 0 ? -kBigT : 0.0));
  return r;
}

std::string fmt(double v, int prec = 3) {
  std::ostringstream s;
  s.precision(prec);
  s << v;
  return s.str();
}

std::string pct(double f) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(std::abs(f) < 0.1 ? 1 : 0);
  s << 100 * f << " %";
  return s.str();
}

std::string cm(double m, int digits = 1) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(digits);
  s << 100 * m << " cm";
  return s.str();
}

Dataset subset(const Dataset& d, const std::set<std::string>& keys) {
  Dataset s;
  s.flights_csv = d.flights_csv;
  s.frame_rate_hz = d.frame_rate_hz;
  s.tracking_sigma_m = d.tracking_sigma_m;
  s.air_density = d.air_density;
  s.air_viscosity = d.air_viscosity;
  s.gravity = d.gravity;
  s.extra_columns = d.extra_columns;
  for (const auto& k : keys) {
    s.gliders[k] = d.gliders.at(k);
    auto it = d.glider_files.find(k);
    if (it != d.glider_files.end()) s.glider_files[k] = it->second;
  }
  for (const auto& f : d.flights)
    if (keys.count(f.glider)) s.flights.push_back(f);
  return s;
}

// Regularised incomplete gamma functions (Numerical Recipes, 3rd ed., 6.2).
double gamma_p_series(double a, double x) {
  double ap = a, sum = 1.0 / a, del = sum;
  for (int n = 0; n < 1000; ++n) {
    ap += 1;
    del *= x / ap;
    sum += del;
    if (std::abs(del) < std::abs(sum) * 1e-15) break;
  }
  return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}

double gamma_q_fraction(double a, double x) {
  const double tiny = 1e-300;
  double b = x + 1 - a, c = 1 / tiny, d = 1 / b, h = d;
  for (int i = 1; i < 1000; ++i) {
    const double an = -i * (i - a);
    b += 2;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1 / d;
    const double del = d * c;
    h *= del;
    if (std::abs(del - 1) < 1e-15) break;
  }
  return std::exp(-x + a * std::log(x) - std::lgamma(a)) * h;
}

}  // namespace

std::string cm_against(double a_m, double b_m) {
  if (!std::isfinite(a_m) || !std::isfinite(b_m)) throw InputError("an RMSE to compare is not finite");
  int d = 1;
  while (d < 4 && cm(a_m, d) == cm(b_m, d)) ++d;
  const std::string a = cm(a_m, d);
  return a.substr(0, a.size() - 3) + " against " + cm(b_m, d);
}

double chi2_sf(double x, double k) {
  if (!(k > 0)) return 1.0;
  if (!(x > 0)) return 1.0;
  const double a = k / 2, y = x / 2;
  if (y < a + 1) return std::clamp(1.0 - gamma_p_series(a, y), 0.0, 1.0);
  return std::clamp(gamma_q_fraction(a, y), 0.0, 1.0);
}

double chi2_isf(double p, double k) {
  if (!(p > 0) || !(p < 1)) throw InputError("chi-square tail probability must be in (0, 1)");
  double lo = 0, hi = std::max(10.0, 10 * k);
  while (chi2_sf(hi, k) > p) hi *= 2;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (chi2_sf(mid, k) > p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

TheoryHold theory_hold(double held_sse, double freed_sse, double other_sse, double s2, double needed) {
  TheoryHold t;
  t.delta_chi2 = s2 > 0 ? std::max(0.0, held_sse - freed_sse) / s2 : 0.0;
  t.rejected = !(t.delta_chi2 <= needed);
  t.outdone = !t.rejected && !(held_sse < other_sse) && freed_sse < other_sse;
  return t;
}

namespace {

/// Free parameters: the trims of the gliders flown by `flights`.
std::vector<FreeParam> trims_of(const DiagnosisData& D, const std::vector<int>& flights, bool on) {
  std::vector<FreeParam> out;
  if (!on) return out;
  std::set<int> g;
  for (int f : flights) g.insert(D.glider_of(f));
  for (int k : g)
    if (D.gliders()[k].features.trim_wing >= 0) out.push_back(FreeParam::trim(k));
  return out;
}

std::vector<FreeParam> params_of(Effect e) {
  std::vector<FreeParam> out;
  for (std::size_t i = 0; i < effect_spec(e).parameters.size(); ++i)
    out.push_back(FreeParam::effect_param(e, static_cast<int>(i)));
  return out;
}

std::vector<LaunchParams> launches_of(const FitOutcome& f) {
  std::vector<LaunchParams> L;
  for (const auto& x : f.flights) L.push_back(x.launch);
  return L;
}

std::vector<double> effect_values(const EffectValues& v, Effect e) {
  std::vector<double> out;
  for (std::size_t i = 0; i < effect_spec(e).parameters.size(); ++i) out.push_back(v.at(e, static_cast<int>(i)));
  return out;
}

// "scale_error 0.175 (plausible up to 0.15)" for the first parameter of v
// beyond its limit (internal units), empty when all are plausible.
std::string describe_implausible(Effect e, const std::vector<double>& v, const std::vector<double>& limits) {
  const int i = implausible_parameter(e, v, &limits);
  if (i < 0) return {};
  const auto& p = effect_spec(e).parameters[i];
  return p.name + " " + fmt(v[i] * p.to_report, 3) + " (plausible up to " + fmt(limits[i] * p.to_report, 3) + ")";
}

std::string describe_parameters(Effect e, const std::vector<double>& v) {
  const auto& sp = effect_spec(e);
  std::string s;
  for (std::size_t i = 0; i < sp.parameters.size() && i < v.size(); ++i) {
    if (!s.empty()) s += ", ";
    const auto& p = sp.parameters[i];
    s += p.name + " " + fmt(v[i] * p.to_report, 3);
  }
  return s;
}

// "strength 0, 2.88, 3, 3 in the folds, range 0 to 3": each parameter's
// value in every fold and the fit's range of that parameter.
std::string describe_fold_range(Effect e, const std::vector<std::vector<double>>& folds) {
  const auto& sp = effect_spec(e);
  std::string out;
  for (std::size_t i = 0; i < sp.parameters.size(); ++i) {
    const auto& p = sp.parameters[i];
    if (!out.empty()) out += "; ";
    out += p.name + " ";
    for (std::size_t k = 0; k < folds.size(); ++k)
      out += (k ? ", " : "") + (i < folds[k].size() ? fmt(folds[k][i] * p.to_report, 3) : std::string("?"));
    out += " in the folds, range " + fmt(p.lower * p.to_report, 3) + " to " + fmt(p.upper * p.to_report, 3);
  }
  return out;
}

/// Holm's step-down at family-wise level alpha over the p-values p: the
/// level each p-value was compared with, and whether it passed.
void holm(const std::vector<double>& p, double alpha, std::vector<double>& level, std::vector<bool>& pass) {
  const int n = static_cast<int>(p.size());
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return p[a] < p[b]; });
  level.assign(n, 0.0);
  pass.assign(n, false);
  bool stop = false;
  for (int i = 0; i < n; ++i) {
    level[order[i]] = alpha / (n - i);
    if (!stop && p[order[i]] <= level[order[i]]) pass[order[i]] = true;
    else stop = true;
  }
}

int centre_count(const std::shared_ptr<const CoefficientModel>& m) {
  auto r = std::dynamic_pointer_cast<const RbfModel>(m);
  return r ? static_cast<int>(r->centres().size()) : 0;
}

/// Every RBF centre value of m (3 coefficients per centre) as free parameters.
std::vector<FreeParam> centre_values(const std::shared_ptr<const CoefficientModel>& m) {
  std::vector<FreeParam> out;
  for (int k = 0; k < 3 * centre_count(m); ++k) out.push_back(FreeParam::coefficient(k));
  return out;
}

}  // namespace

namespace {
/// The second round's reverse tests, in order: `also` (the effects
/// significant given the verdict's, best shrink first), then the effects
/// significant on their own that add nothing given the verdict's. One list
/// for the tests diagnose() runs and for the decision made from them.
std::vector<int> reverse_tests(const std::vector<EffectResult>& effects, int verdict, std::vector<int>* also_out) {
  const int n = static_cast<int>(effects.size());
  std::vector<int> also;
  for (int e = 0; e < n; ++e)
    if (e != verdict && effects[e].given_verdict.tested && effects[e].given_verdict.significant) also.push_back(e);
  std::stable_sort(also.begin(), also.end(), [&](int a, int b) {
    return effects[a].given_verdict.shrink > effects[b].given_verdict.shrink;
  });
  std::vector<int> reverse = also;
  for (int e = 0; e < n; ++e)
    if (e != verdict && effects[e].given_verdict.tested && effects[e].significant &&
        !effects[e].given_verdict.significant)
      reverse.push_back(e);
  if (also_out) *also_out = std::move(also);
  return reverse;
}

// Two per-glider lists of sums of squared residuals, one entry per glider:
// the same length, every sum finite and non-negative (InputError naming
// `what` otherwise).
void check_glider_sums(const std::string& what, const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size())
    throw InputError(what + ": " + std::to_string(a.size()) + " and " + std::to_string(b.size()) + " gliders' sums");
  for (std::size_t g = 0; g < a.size(); ++g)
    if (!(std::isfinite(a[g]) && a[g] >= 0 && std::isfinite(b[g]) && b[g] >= 0))
      throw InputError(what + ": glider " + std::to_string(g) + "'s sum of squared residuals is negative or not finite");
}
}  // namespace

std::pair<double, int> leave_one_glider_out_shrink(const std::vector<double>& baseline_sse,
                                                   const std::vector<double>& effect_sse) {
  check_glider_sums("leave-one-glider-out shrink", baseline_sse, effect_sse);
  double b = 0, e = 0;
  for (std::size_t g = 0; g < baseline_sse.size(); ++g) {
    b += baseline_sse[g];
    e += effect_sse[g];
  }
  auto shrink = [](double eff, double base) { return base > 0 ? 1 - std::sqrt(std::max(0.0, eff) / base) : 0.0; };
  if (baseline_sse.size() < 2) return {shrink(e, b), -1};
  std::pair<double, int> worst{std::numeric_limits<double>::infinity(), -1};
  for (std::size_t g = 0; g < baseline_sse.size(); ++g) {
    const double x = shrink(e - effect_sse[g], b - baseline_sse[g]);
    if (x < worst.first) worst = {x, static_cast<int>(g)};
  }
  return worst;
}

bool glider_guard_pass(double robust_shrink, double margin, int improved, int total) {
  if (improved < 0 || total < 0 || improved > total)
    throw InputError("glider guard: " + std::to_string(improved) + " of " + std::to_string(total) +
                     " gliders improved is not a count");
  return robust_shrink >= margin || (total > 0 && 4 * improved >= 3 * total);
}

double shrink_margin(const DiagnoseOptions& o, Effect e) {
  const bool rate_confirmed = o.launch_rates_confirm && o.launch_rotation_per_flight && e == Effect::LaunchRotation;
  return rate_confirmed ? 0.0 : o.min_shrink;
}

namespace {
// The decision rule, the same in both rounds: the likelihood-ratio test
// passed (Holm), the held-out RMSE shrank by the effect's margin
// (shrink_margin; at least above zero), and the held-out improvement
// exceeds its chi-square quantile.
bool decision_rule(const DiagnoseOptions& o, Effect e, bool lr_pass, double shrink, double holdout_delta_chi2,
                   double threshold) {
  return lr_pass && shrink > 0 && shrink >= shrink_margin(o, e) &&
         (!o.holdout_chi2_test || holdout_delta_chi2 > threshold);
}
}  // namespace

std::string effect_note(const EffectResult& r, const DiagnoseOptions& o, bool own_limit) {
  // Whether the three tests alone (not the guards) would have passed it.
  const bool decided = decision_rule(o, r.effect, r.lr_pass, r.shrink, r.holdout_delta_chi2, r.holdout_threshold);
  const double margin = shrink_margin(o, r.effect);
  std::string n;
  if (r.significant) {
    n = "significant: fits better (delta chi2 " + fmt(r.delta_chi2, 3) + ", p " + fmt(r.p_value, 2) +
        ") and predicts held-out gliders better (shrink " + pct(r.shrink) + ")";
    if (r.rate_test && r.shrink < o.min_shrink)
      n += ", under the " + pct(o.min_shrink) + " margin, which a launch value is not held to: its held-out "
           "flights' own rates share a direction (mean " + fmt(rad2deg(r.rate_mean), 3) + " deg/s, p " +
           fmt(r.rate_mean_p, 2) + "), a launcher's rotation carried over to gliders it was not fitted to";
  }
  else if (!r.bound_pass && r.shrink >= margin)
    n = "predicts held-out gliders better (shrink " + pct(r.shrink) + "), but " + pct(r.bound_share) +
        " of that gain comes from folds whose fit ran to the edge of the correction's range (" +
        describe_fold_range(r.effect, r.fold_parameters) +
        "): the correction's shape turned as far as it goes absorbs some other misfit; the folds do not agree on a "
        "size of the effect";
  else if (!r.lr_pass) n = "not significant on the training gliders (p " + fmt(r.p_value, 2) + ")";
  else if (!r.rate_mean_pass && decided)
    n = "fits and predicts better, but the flights' own rates do not share a direction (mean " +
        fmt(rad2deg(r.rate_mean), 2) + " deg/s, t " + fmt(r.rate_mean_t, 2) + ", p " + fmt(r.rate_mean_p, 2) +
        "): a free sixth launch value absorbing misfit (or throws whose rotation varies in sign), not a launcher's "
        "rotation";
  else if (!r.robust_pass && decided)
    n = "fits and predicts better (shrink " + pct(r.shrink) + "), but the held-out gain rests on one glider: without " +
        r.robust_without + " the shrink is " + pct(r.robust_shrink) + ", less than the " + pct(o.min_shrink) +
        " margin, and it improves only " + std::to_string(r.gliders_improved) + " of " +
        std::to_string(r.gliders_total) + " held-out gliders; one glider's misfit is not evidence of an effect";
  else if (!r.plausible && decided)
    n = "fits and predicts better (shrink " + pct(r.shrink) + "), but at an implausible size, " + r.implausible +
        (own_limit ? std::string(", the limit given") : ": " + effect_spec(r.effect).plausibility) +
        ". More likely it absorbs another misfit (if the recording could be that far off, check it)";
  else if (r.shrink <= 0)
    n = "fits the training gliders better but predicts held-out gliders worse (shrink " + pct(r.shrink) + ")";
  else if (r.shrink < margin && r.holdout_delta_chi2 > r.holdout_threshold)
    // Confirmed on held-out gliders, but too small a part of the gap to be
    // its cause (launch rotation data: 8 of 8 gliders better, 2.2 %; the
    // true effect added to the baseline closed 1.6 %).
    n = "fits the training gliders better and predicts held-out gliders better (" +
        std::to_string(r.gliders_improved) + " of " + std::to_string(r.gliders_total) + " gliders), but closes only " +
        pct(r.shrink) + " of the held-out error, less than the " + pct(margin) +
        " margin: it is not what leaves the gap";
  else if (r.shrink < margin)
    n = "fits the training gliders better but barely carries over to held-out gliders (shrink " + pct(r.shrink) + ")";
  else n = "held-out improvement within what fitting its strength to noise gives";
  if (r.strength_held)
    n += "; strength held at its theoretical size (freed, it fitted the training gliders no significantly better)";
  if (r.indistinguishable)
    n += "; " + pct(r.coefficient_collinearity) + " of its signature is a change of the coefficients or trims: it cannot "
         "be told apart from re-tuned coefficients";
  return n;
}

std::string given_note(const EffectResult& r, const std::string& verdict, const DiagnoseOptions& o) {
  const auto& g = r.given_verdict;
  if (!g.tested) return {};
  const std::string with = "with " + verdict + " in the model, ";
  const bool decided = decision_rule(o, r.effect, g.lr_pass, g.shrink, g.holdout_delta_chi2, g.holdout_threshold);
  const double margin = shrink_margin(o, r.effect);
  if (g.significant)
    return with + "significant: fits better (delta chi2 " + fmt(g.delta_chi2, 3) + ", p " + fmt(g.p_value, 2) +
           ") and predicts held-out gliders " + pct(g.shrink) + " better still";
  if (!g.bound_pass && g.shrink >= margin)
    return with + "predicts held-out gliders " + pct(g.shrink) + " better, but " + pct(g.bound_share) +
           " of that gain comes from folds whose fit ran to the edge of the correction's range (" +
           describe_fold_range(r.effect, g.fold_parameters) + "): not counted";
  if (!g.lr_pass) return with + "not significant on the training gliders (p " + fmt(g.p_value, 2) + ")";
  if (!r.rate_mean_pass && decided)
    return with + "fits and predicts better, but the flights' own rates do not share a direction";
  if (!g.robust_pass && decided)
    return with + "fits and predicts better (" + pct(g.shrink) + "), but the gain rests on one glider: without " +
           g.robust_without + " it is " + pct(g.robust_shrink) + ", and it improves only " +
           std::to_string(g.gliders_improved) + " of " + std::to_string(g.gliders_total) + " held-out gliders";
  if (!g.plausible && decided)
    return with + "fits and predicts better (" + pct(g.shrink) + "), but at an implausible size (" +
           describe_parameters(r.effect, g.parameters) + ")";
  if (g.shrink < margin || g.shrink <= 0)
    return with + "predicts held-out gliders " + pct(g.shrink) + " better, less than the " + pct(margin) +
           " margin";
  return with + "held-out improvement within what fitting its strength to noise gives";
}

std::string given_stopped_by(const EffectResult::Given& g, const DiagnoseOptions& o, Effect e) {
  if (!g.tested || g.significant || (g.robust_pass && g.bound_pass) ||
      !decision_rule(o, e, g.lr_pass, g.shrink, g.holdout_delta_chi2, g.holdout_threshold))
    return {};
  return g.bound_pass ? "glider" : "bound";
}

namespace {
// The bound guard's edge: within the outer tenth of a non-zero bound of the
// parameter's range, on that bound's side (a strength's lower bound 0 is
// the baseline, not an edge). Shared by fold_bound_share and
// range_edge_sentence.
bool at_range_edge(const EffectParameter& p, double v) {
  return (p.upper > 0 && v >= 0.9 * p.upper) || (p.lower < 0 && v <= 0.9 * p.lower);
}
}  // namespace

bool values_at_range_edge(Effect e, const std::vector<double>& values) {
  const auto& ps = effect_spec(e).parameters;
  if (values.size() != ps.size())
    throw InputError("range edge: " + std::to_string(values.size()) + " values, " + effect_name(e) + " has " +
                     std::to_string(ps.size()) + " parameters");
  for (std::size_t i = 0; i < ps.size(); ++i) {
    if (!std::isfinite(values[i])) throw InputError("range edge: " + effect_name(e) + "'s " + ps[i].name + " is not finite");
    if (at_range_edge(ps[i], values[i])) return true;
  }
  return false;
}

double fold_bound_share(Effect e, const std::vector<std::vector<double>>& fold_params,
                        const std::vector<double>& fold_gain) {
  if (fold_params.size() != fold_gain.size())
    throw InputError("bound guard: " + std::to_string(fold_params.size()) + " folds' parameters for " +
                     std::to_string(fold_gain.size()) + " folds' gains");
  const auto& ps = effect_spec(e).parameters;
  double at_edge = 0, all = 0;
  for (std::size_t k = 0; k < fold_gain.size(); ++k) {
    if (!std::isfinite(fold_gain[k])) throw InputError("bound guard: fold " + std::to_string(k + 1) + "'s gain is not finite");
    if (fold_params[k].size() != ps.size())
      throw InputError("bound guard: fold " + std::to_string(k + 1) + " has " + std::to_string(fold_params[k].size()) +
                       " parameters, " + effect_name(e) + " has " + std::to_string(ps.size()));
    bool edge = false;
    for (std::size_t i = 0; i < ps.size(); ++i) {
      const double v = fold_params[k][i];
      if (!std::isfinite(v))
        throw InputError("bound guard: fold " + std::to_string(k + 1) + "'s " + ps[i].name + " is not finite");
      if (at_range_edge(ps[i], v)) edge = true;
    }
    const double g = std::max(0.0, fold_gain[k]);
    all += g;
    if (edge) at_edge += g;
  }
  return all > 0 ? at_edge / all : 0.0;
}

int likelihood_reference(const std::vector<Effect>& effects, const std::vector<std::vector<double>>& params,
                         const std::vector<double>& sse, const std::vector<bool>& per_flight, double baseline_sse,
                         double min_gain) {
  if (params.size() != effects.size() || sse.size() != effects.size() || per_flight.size() != effects.size())
    throw InputError("likelihood reference: " + std::to_string(effects.size()) + " effects, " +
                     std::to_string(params.size()) + " parameter sets, " + std::to_string(sse.size()) + " fits, " +
                     std::to_string(per_flight.size()) + " per-flight flags");
  if (!std::isfinite(baseline_sse)) throw InputError("likelihood reference: the baseline's fit is not finite");
  if (!(min_gain >= 0) || !std::isfinite(min_gain))
    throw InputError("likelihood reference: the gain a fit must make is not a finite value >= 0");
  int best = -1;
  double ref = baseline_sse - min_gain;
  for (std::size_t e = 0; e < effects.size(); ++e) {
    if (params[e].size() != effect_spec(effects[e]).parameters.size())
      throw InputError("likelihood reference: " + effect_name(effects[e]) + " has " +
                       std::to_string(effect_spec(effects[e]).parameters.size()) + " parameters, given " +
                       std::to_string(params[e].size()));
    if (!std::isfinite(sse[e])) throw InputError("likelihood reference: " + effect_name(effects[e]) + "'s fit is not finite");
    for (double v : params[e])
      if (!std::isfinite(v)) throw InputError("likelihood reference: " + effect_name(effects[e]) + "'s fit is not finite");
    if (per_flight[e]) continue;
    const bool at_baseline = std::all_of(params[e].begin(), params[e].end(), [](double v) { return v == 0.0; });
    if (at_baseline && sse[e] < ref) {
      ref = sse[e];
      best = static_cast<int>(e);
    }
  }
  return best;
}

// An aerodynamic correction's strength is a multiple of its theory, which
// is approximate to a factor of about two (the downwash correction gives
// 1.04-1.85 times the reference lattice's pitching moment across the
// training gliders): a fit beyond twice the theory is a correction
// stretched to fit something else (range_edge_sentence).
constexpr double kStrainedStrength = 2.0;

std::string range_edge_sentence(Effect e, const std::vector<double>& params) {
  const auto& ps = effect_spec(e).parameters;
  if (params.size() != ps.size())
    throw InputError("range check: " + std::to_string(params.size()) + " parameters, " + effect_name(e) + " has " +
                     std::to_string(ps.size()));
  // Fuselage drag's theory (laminar friction alone) underestimates a
  // plate's drag by construction (engine/src/effects.cpp): its range only.
  const bool aero = effect_spec(e).level == EffectLevel::Aerodynamic && e != Effect::FuselageDrag;
  std::string at;
  for (std::size_t i = 0; i < ps.size(); ++i) {
    const double v = params[i];
    if (!std::isfinite(v)) throw InputError("range check: " + effect_name(e) + "'s " + ps[i].name + " is not finite");
    const bool edge = at_range_edge(ps[i], v);
    const bool strained = aero && v > kStrainedStrength;
    if (!edge && !strained) continue;
    const std::string range = fmt(ps[i].lower * ps[i].to_report, 3) + " to " + fmt(ps[i].upper * ps[i].to_report, 3);
    at += std::string(at.empty() ? "" : " and ") + ps[i].name + " " + fmt(v * ps[i].to_report, 3) + ", " +
          (!aero      ? "near the end of the range allowed (" + range + ")"
           : strained ? "more than " + fmt(kStrainedStrength, 3) + " times its theoretical size (range " + range + ")"
                      : "near its theoretical size (range " + range + ")");
  }
  if (at.empty()) return {};
  return " Caution on its size: " + at +
         ". A correction stretched that far may be absorbing a misfit of another kind rather than measuring " +
         effect_name(e) + "; weigh the other candidates before taking it as the cause.";
}

HeldOutGuards held_out_guards(Effect e, const std::vector<double>& baseline_sse, const std::vector<double>& effect_sse,
                              const std::vector<std::vector<double>>& fold_params, const std::vector<double>& fold_gain,
                              const DiagnoseOptions& o) {
  HeldOutGuards h;
  const auto [rs, rg] = leave_one_glider_out_shrink(baseline_sse, effect_sse);  // checks the sums
  h.total = static_cast<int>(baseline_sse.size());
  for (std::size_t g = 0; g < baseline_sse.size(); ++g)
    if (effect_sse[g] < baseline_sse[g]) ++h.improved;
  h.robust_shrink = rs;
  h.robust_without = rg;
  h.robust_pass = !o.glider_guard || glider_guard_pass(rs, o.min_shrink, h.improved, h.total);
  h.bound_share = fold_bound_share(e, fold_params, fold_gain);
  h.bound_pass = !o.bound_guard || h.bound_share <= 0.5;
  return h;
}

namespace {
// Launch rotation when it passed its likelihood-ratio test, is not
// significant and (per-flight rates) its rates share a direction at
// `alpha`: the condition of the launch caution and the launch withhold.
const EffectResult* launch_rotation_that_fits(const std::vector<EffectResult>& effects, double alpha) {
  for (const auto& r : effects) {
    if (r.effect != Effect::LaunchRotation || !r.lr_pass || r.significant) continue;
    if (r.rate_test && !(r.rate_mean_p < alpha)) continue;  // rates scattered both ways: no launcher's rotation
    return &r;
  }
  return nullptr;
}
}  // namespace

LaunchDominance launch_dominance(const std::vector<EffectResult>& effects, const std::string& verdict,
                                 double baseline_fit_rmse_m, double dominance) {
  LaunchDominance d;
  const auto v = std::find_if(effects.begin(), effects.end(), [&](const EffectResult& r) { return r.name == verdict; });
  const auto lr = std::find_if(effects.begin(), effects.end(),
                               [](const EffectResult& r) { return r.effect == Effect::LaunchRotation; });
  if (v == effects.end() || lr == effects.end() || !(dominance > 0) || !(baseline_fit_rmse_m > 0)) return d;
  d.applies = true;
  d.verdict_gain = 1 - v->fit_rmse_m / baseline_fit_rmse_m;
  d.launch_gain = 1 - lr->fit_rmse_m / baseline_fit_rmse_m;
  d.dominates = d.verdict_gain > 0 && d.verdict_gain > dominance * std::max(d.launch_gain, 0.0);
  return d;
}

std::string launch_withheld(const std::vector<EffectResult>& effects, const std::string& verdict, double alpha,
                            double baseline_fit_rmse_m, double dominance) {
  const auto v = std::find_if(effects.begin(), effects.end(), [&](const EffectResult& r) { return r.name == verdict; });
  if (v == effects.end()) return {};  // none, unexplained
  const EffectLevel lv = effect_spec(v->effect).level;
  if (lv != EffectLevel::Session && lv != EffectLevel::Observation) return {};
  // Far more of the training flights explained than launch rotation, with
  // every flight's own rate, explains: not a launch habit's imitation.
  if (launch_dominance(effects, verdict, baseline_fit_rmse_m, dominance).dominates) return {};
  for (const auto& r : effects)
    if (r.effect == Effect::LaunchRotation && r.significant) return r.name;
  return launch_rotation_that_fits(effects, alpha) ? "unexplained" : "";
}

std::string withheld_sentence(const std::vector<EffectResult>& effects, const std::string& withheld, double margin,
                              double alpha) {
  const auto v = std::find_if(effects.begin(), effects.end(), [&](const EffectResult& r) { return r.name == withheld; });
  const auto lr = std::find_if(effects.begin(), effects.end(),
                               [](const EffectResult& r) { return r.effect == Effect::LaunchRotation; });
  if (v == effects.end() || lr == effects.end()) return {};
  const std::string why =
      " A launcher's habitual rotation at release is taken up by each held-out flight's own rate, so launch "
      "rotation gains little there, while a correction applied alike to every flight carries the habit over to the "
      "held-out gliders: on the blind benchmark to 2026-11-30 wind or the camera was so named on 4 of 4 "
      "launch-rotation datasets where launch rotation fitted this way. There such an imitation's fit to all "
      "gliders closed 0.4 to 2.2 times launch rotation's share of the training flights' misfit, and a true wind "
      "(seed 22) 46 times: beyond 5 times it is named (--launch-withhold-dominance; docs/diagnosis.md, The "
      "launch withhold).";
  const std::string cause = "left the hand without pitching, " + withheld +
                            " is the likely cause (--no-launch-withhold names it).";
  if (lr->significant)
    return " " + withheld + " predicts the held-out gliders better still (" + pct(v->shrink) + ", fitted " +
           describe_parameters(v->effect, v->parameters) + ") but is not named: the held-out flights' own launch "
           "rates share a direction (mean " + fmt(rad2deg(lr->rate_mean), 3) + " deg/s, p " +
           fmt(lr->rate_mean_p, 2) + ")." + why + " If the gliders " + cause;
  if (!launch_rotation_that_fits(effects, alpha)) return {};
  return " " + withheld + " would cut it by " + pct(v->shrink) + " (fitted " +
         describe_parameters(v->effect, v->parameters) + ") and passes every test, but it is not named: " + lr->name +
         " fits the training flights significantly better too (p " + fmt(lr->p_value, 2) + "; " +
         describe_parameters(lr->effect, lr->parameters) + "), the flights' own rates turning one way, yet closes " +
         (lr->shrink < margin ? "only " : "") + pct(lr->shrink) + " of the held-out error." + why +
         " Check how the gliders were launched: if they " + cause;
}

std::string launch_dominance_sentence(const std::vector<EffectResult>& effects, const std::string& verdict,
                                     double alpha, double baseline_fit_rmse_m, double dominance) {
  if (launch_withheld(effects, verdict, alpha).empty()) return {};  // the withhold would not have applied
  const LaunchDominance d = launch_dominance(effects, verdict, baseline_fit_rmse_m, dominance);
  if (!d.dominates) return {};
  return " " + verdict + " is named though launch rotation fits the training flights too: fitted to all gliders it "
         "closes " + pct(d.verdict_gain) + " of the baseline's misfit there, launch rotation " + pct(d.launch_gain) +
         ", more than " + fmt(dominance, 3) + " times as much. A launch habit, fitted flight by flight, would explain "
         "the training flights about as well as a correction applied alike to every flight, so " + verdict +
         " is not its imitation (--launch-withhold-dominance 0 withholds it).";
}

std::string launch_caution(const std::vector<EffectResult>& effects, const std::string& verdict, double margin,
                           double alpha) {
  if (verdict == "none" || verdict == effect_name(Effect::LaunchRotation)) return {};
  if (const EffectResult* lr = launch_rotation_that_fits(effects, alpha)) {
    const EffectResult& r = *lr;
    std::string s = " " + r.name + (verdict == "unexplained" ? "" : " also") +
                    " fits the training flights significantly better (p " + fmt(r.p_value, 2) + "; " +
                    describe_parameters(r.effect, r.parameters) + ") but closes " +
                    (r.shrink < margin ? "only " : "") + pct(r.shrink) + " of the held-out error";
    if (verdict == "unexplained")
      s += ": the gap may lie in the launches (a rotation at release that the five fitted launch values do not "
           "take up).";
    else
      s += ". A launch effect the model leaves out may be behind the verdict: on blind launch-rotation data a "
           "correction applied to every flight took the verdict this way (docs/diagnosis.md, Limits). Check how "
           "the gliders were launched before taking " + verdict + " as the cause.";
    return s;
  }
  return {};
}

std::string dominant_glider_sentence(const json& where, const std::vector<EffectResult>& effects) {
  if (!where.contains("gliders") || !where.contains("all")) return {};
  const double all = where["all"].value("excess_m2", 0.0);
  if (!(all > 0)) return {};
  std::ostringstream s;
  for (const auto& g : where["gliders"]) {
    const double share = g["excess_m2"].get<double>() / all;
    if (!(share >= 0.5)) continue;
    const std::string key = g["glider"].get<std::string>();
    const double r0 = g["rmse_m"].get<double>();
    double best_r = r0;
    for (const auto& e : effects)
      for (const auto& [k, r] : e.glider_holdout_rmse_m)
        if (k == key) best_r = std::min(best_r, r);
    if (best_r < 0.9 * r0) continue;
    s << " Most of the excess over the noise (" << pct(share) << ") is one glider, " << key
      << ", predicted from the others at " << cm(r0) << " held out (" << fmt(g["chi2_ratio"].get<double>(), 2)
      << " times the noise's squared error) and no better by any candidate (best " << cm(best_r)
      << "): the model does not carry over to its geometry from the other gliders.";
  }
  return s.str();
}

SecondRoundOutcome second_round_outcome(const std::vector<EffectResult>& effects, int verdict, int passed_over) {
  SecondRoundOutcome out;
  out.verdict = verdict;
  const int n = static_cast<int>(effects.size());
  if (verdict < 0 || verdict >= n) throw InputError("second round: no verdict to test against");
  if (passed_over < -1 || passed_over >= n || passed_over == verdict)
    throw InputError("second round: the passed-over effect must be another effect of the library or none");
  std::vector<int> also;
  const std::vector<int> reverse = reverse_tests(effects, verdict, &also);
  int replacement = -1;
  std::vector<int> alternatives;
  for (int e : reverse) {
    const auto& g = effects[e].given_verdict;
    if (!g.reverse_tested) continue;
    if (g.significant && replacement < 0 && !g.verdict_still_needed && effects[e].significant && e != passed_over)
      replacement = e;
    if (!g.significant && !g.verdict_still_needed) alternatives.push_back(e);
  }
  if (replacement >= 0) {
    // The verdict's effect only imitated this one; `also` and the
    // alternatives were tested against the replaced verdict, not this one.
    out.replaced = verdict;
    out.verdict = replacement;
  } else {
    out.also = also;
    out.alternatives = alternatives;
  }
  return out;
}

// The mean over folds of each of a candidate's `pe` fitted parameters.
static std::vector<double> fold_mean(const std::vector<std::vector<double>>& fold_params, int pe) {
  std::vector<double> m(pe, 0.0);
  for (const auto& fp : fold_params)
    for (int i = 0; i < pe; ++i) m[i] += fp.at(i) / static_cast<double>(fold_params.size());
  return m;
}

bool heldout_step_eligible(const EffectResult& r, const DiagnoseOptions& o, bool stepped, bool per_flight) {
  return !stepped && !per_flight && r.shrink >= o.min_shrink &&
         (!o.holdout_chi2_test || r.holdout_delta_chi2 > r.holdout_threshold) && r.robust_pass && r.plausible &&
         r.bound_pass;
}

IdentifiablePreference prefer_identifiable(const std::vector<EffectResult>& effects, int best,
                                           const std::vector<std::vector<double>>& glider_sse, double alpha) {
  const int n = static_cast<int>(effects.size());
  if (best < 0 || best >= n) throw InputError("identifiability preference: no best effect to compare with");
  if (glider_sse.size() != effects.size())
    throw InputError("identifiability preference: " + std::to_string(glider_sse.size()) + " per-glider sums for " +
                     std::to_string(n) + " effects");
  if (!(alpha > 0 && alpha < 1)) throw InputError("identifiability preference: alpha must lie in (0, 1)");
  IdentifiablePreference out;
  out.verdict = best;
  const EffectResult& b = effects[best];
  if (!b.significant || !b.indistinguishable) return out;
  int alt = -1;
  for (int e = 0; e < n; ++e)
    if (e != best && effects[e].significant && !effects[e].indistinguishable &&
        (alt < 0 || effects[e].shrink > effects[alt].shrink))
      alt = e;
  if (alt < 0) return out;
  const auto& sb = glider_sse[best];
  const auto& sa = glider_sse[alt];
  check_glider_sums("identifiability preference", sb, sa);
  std::vector<double> d;
  for (std::size_t g = 0; g < sb.size(); ++g) d.push_back(sa[g] - sb[g]);
  out.alternative = alt;
  if (d.size() < 2) return out;
  out.t = mean_and_t(d).t;
  const boost::math::students_t dist(static_cast<double>(d.size() - 1));
  out.t_critical = boost::math::quantile(boost::math::complement(dist, alpha));
  if (out.t < out.t_critical) {
    out.verdict = alt;
    out.passed_over = best;
  }
  return out;
}

bool launch_rotation_per_flight_from(const std::string& value, const std::string& option) {
  if (value != "per-flight" && value != "common")
    throw InputError(option + " must be 'per-flight' or 'common', not '" + value + "'");
  return value == "per-flight";
}

void check_candidate_effects(const std::vector<Effect>& effects, const std::string& where) {
  std::set<Effect> seen;
  for (Effect e : effects)
    if (!seen.insert(e).second) throw InputError(where + "candidate effect '" + effect_name(e) + "' is listed twice");
}

namespace {
// Every effect of an "EFFECT=V[:V2]" list once, with as many values as it
// has parameters (--oracle, --plausible).
void check_effect_list(const std::vector<std::pair<Effect, std::vector<double>>>& list, const std::string& option) {
  std::set<Effect> seen;
  for (const auto& [e, v] : list) {
    const auto& sp = effect_spec(e);
    if (!seen.insert(e).second) throw InputError(option + ": effect '" + effect_name(e) + "' is given twice");
    if (v.size() != sp.parameters.size())
      throw InputError(option + ": effect '" + effect_name(e) + "' takes " + std::to_string(sp.parameters.size()) +
                       " value(s), given " + std::to_string(v.size()));
  }
}

// check_effect_list, and each value inside the effect's bounds (reported units).
void check_oracle(const std::vector<std::pair<Effect, std::vector<double>>>& oracle, const std::string& option) {
  check_effect_list(oracle, option);
  for (const auto& [e, v] : oracle) {
    const auto& sp = effect_spec(e);
    for (std::size_t i = 0; i < v.size(); ++i) {
      const auto& p = sp.parameters[i];
      const double x = v[i] / p.to_report;
      if (!std::isfinite(x) || x < p.lower || x > p.upper)
        throw InputError(option + ": " + effect_name(e) + " " + p.name + " " + fmt(v[i], 6) +
                         " is outside the effect's range [" + fmt(p.lower * p.to_report, 6) + ", " +
                         fmt(p.upper * p.to_report, 6) + "]");
    }
  }
}
}  // namespace

namespace {
// "EFFECT=V[:V2],..." as effects and their values (as written); `infinite`
// allows "inf".
std::vector<std::pair<Effect, std::vector<double>>> effect_values_from(const std::string& spec, const std::string& option,
                                                                       bool infinite) {
  std::vector<std::pair<Effect, std::vector<double>>> out;
  std::stringstream items(spec);
  std::string item;
  while (std::getline(items, item, ',')) {
    const auto eq = item.find('=');
    if (item.empty() || eq == std::string::npos)
      throw InputError(option + ": '" + item + "' is not EFFECT=VALUE (e.g. wind=-1, camera=0.03:2)");
    const Effect e = effect_from_name(item.substr(0, eq));
    std::vector<double> v;
    std::stringstream values(item.substr(eq + 1));
    std::string x;
    while (std::getline(values, x, ':')) {
      std::size_t used = 0;
      double y = std::numeric_limits<double>::quiet_NaN();
      try {
        y = std::stod(x, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (x.empty() || used != x.size() || std::isnan(y) || (!infinite && !std::isfinite(y)))
        throw InputError(option + ": '" + x + "' in '" + item + "' is not a " + std::string(infinite ? "number" : "finite number"));
      v.push_back(y);
    }
    out.emplace_back(e, v);
  }
  if (out.empty()) throw InputError(option + " needs EFFECT=VALUE (e.g. wind=-1)");
  return out;
}
}  // namespace

std::vector<std::pair<Effect, std::vector<double>>> oracle_from(const std::string& spec, const std::string& option) {
  auto out = effect_values_from(spec, option, false);
  check_oracle(out, option);
  return out;
}

namespace {
// check_effect_list, and every size positive.
void check_plausible(const std::vector<std::pair<Effect, std::vector<double>>>& out, const std::string& option) {
  check_effect_list(out, option);
  for (const auto& [e, v] : out) {
    const auto& sp = effect_spec(e);
    for (std::size_t i = 0; i < v.size(); ++i)
      if (!(v[i] > 0))
        throw InputError(option + ": " + effect_name(e) + " " + sp.parameters[i].name + " " + fmt(v[i], 6) +
                         " is not a positive size");
  }
}

// Effect E's plausible sizes in force (internal units): the library's, or
// the caller's (DiagnoseOptions::plausible; `own` says which).
std::vector<double> plausible_limits(Effect E, const DiagnoseOptions& o, bool* own = nullptr) {
  const auto& ps = effect_spec(E).parameters;
  std::vector<double> lim;
  for (const auto& p : ps) lim.push_back(p.plausible);
  if (own) *own = false;
  for (const auto& [F, v] : o.plausible)
    if (F == E) {
      if (own) *own = true;
      for (std::size_t i = 0; i < v.size() && i < lim.size(); ++i) lim[i] = v[i] / ps[i].to_report;
    }
  return lim;
}
}  // namespace

std::vector<std::pair<Effect, std::vector<double>>> plausible_from(const std::string& spec, const std::string& option) {
  auto out = effect_values_from(spec, option, true);
  check_plausible(out, option);
  return out;
}

namespace {
// One search (docs/diagnosis.md): diagnose() runs it, and again with
// theoretical-size starts when it leaves a real gap unexplained
// (DiagnoseOptions::escalate).
DiagnoseResult diagnose_once(const Dataset& d, const DiagnoseOptions& o, const DiagnoseCallback& progress) {
  const auto t0 = Clock::now();
  if (o.folds < 2) throw InputError("the number of folds must be at least 2");
  if (o.effects.empty()) throw InputError("no candidate effects to test");
  check_candidate_effects(o.effects);
  if (!(o.alpha > 0 && o.alpha < 1)) throw InputError("the significance level must be in (0, 1)");
  if (!(o.min_shrink >= 0 && o.min_shrink < 1)) throw InputError("the shrink margin must be in [0, 1)");
  if (!(o.none_tolerance >= 0) || !std::isfinite(o.none_tolerance))
    throw InputError("the noise tolerance must be finite and not negative");
  if (!(o.launch_window_s >= 0) || !(o.near_ground_m >= 0)) throw InputError("phase limits must not be negative");
  if (o.profiled_candidates < 0) throw InputError("the number of profiled candidates must not be negative");
  if (!(o.step_alpha >= 0 && o.step_alpha <= 1))
    throw InputError("the level of the profiled starts' screen must be in [0, 1] (0: the test's level)");
  check_oracle(o.oracle, "oracle");
  check_plausible(o.plausible, "plausible");
  DiagFitOptions so = o.sim;
  so.threads = o.threads;
  const DiagnosisData D(d, so);
  const double sigma = d.tracking_sigma_m;

  // Gliders with flights, dealt into folds by their main wing's aspect ratio.
  std::vector<int> flown;
  for (std::size_t g = 0; g < D.gliders().size(); ++g)
    if (!D.gliders()[g].flights.empty()) flown.push_back(static_cast<int>(g));
  if (flown.size() < static_cast<std::size_t>(kMinDiagnosisGliders))
    throw InputError("leave-gliders-out diagnosis needs flights of at least " + std::to_string(kMinDiagnosisGliders) +
                     " gliders; the dataset has " +
                     std::to_string(flown.size()));
  std::sort(flown.begin(), flown.end(), [&](int a, int b) {
    const double ra = D.gliders()[a].features.main_aspect_ratio, rb = D.gliders()[b].features.main_aspect_ratio;
    return ra != rb ? ra < rb : D.gliders()[a].key < D.gliders()[b].key;
  });
  const int K = std::min<int>(o.folds, static_cast<int>(flown.size()));
  std::vector<int> fold_of(D.gliders().size(), -1);
  for (std::size_t i = 0; i < flown.size(); ++i) fold_of[flown[i]] = static_cast<int>(i % K);

  FitOptions fo = o.fit;
  fo.threads = o.threads;
  fo.start = o.start;
  fo.aero = so.aero;
  fo.launch.track.sim.dt = so.dt;

  const int ne = static_cast<int>(o.effects.size());
  const int steps = (o.full_fit ? 1 : 0) * (1 + ne) + K * (1 + ne) + 3;
  int step = 0;
  auto report = [&](const std::string& stage, const std::string& msg, bool advance = true) {
    if (advance) ++step;
    if (!progress) return;
    DiagnoseProgress p;
    p.stage = stage;
    p.step = step;
    p.steps = steps;
    p.elapsed_s = since(t0);
    p.message = msg;
    progress(p);
  };
  auto coefficient_fit = [&](const std::set<std::string>& keys, const std::string& label) {
    const Dataset sub = subset(d, keys);
    report("baseline", label + ": fitting the wing-element coefficients to " + std::to_string(sub.flights.size()) +
                           " flights of " + std::to_string(keys.size()) + " gliders", false);
    const FitResult fr = fit_coefficients(sub, fo, [&](const FitProgress& p) {
      if (p.stage == "stage" || p.stage == "done") report("baseline", label + ": " + p.message, false);
    });
    return std::static_pointer_cast<const CoefficientModel>(fr.model);
  };

  auto coefficient_params = [&](const std::shared_ptr<const CoefficientModel>& m) {
    return o.polish > 0 ? centre_values(m) : std::vector<FreeParam>{};
  };
  // launch_rotation fitted per flight: no shared parameter (each flight's
  // rate is a launch value); its reported strength is the flights' mean rate.
  auto per_flight = [&](Effect e) { return e == Effect::LaunchRotation && o.launch_rotation_per_flight; };
  auto shared_params_of = [&](Effect e) { return per_flight(e) ? std::vector<FreeParam>{} : params_of(e); };
  // Degrees of freedom a candidate adds to a fit of `flights` flights: its
  // parameters, or (launch rotation per flight) one rate per flight. The
  // fold rule, the likelihood-ratio test and the held-out test all count so.
  auto added_dof = [&](Effect e, double flights) {
    return per_flight(e) ? flights : static_cast<double>(effect_spec(e).parameters.size());
  };
  auto with_rate = [](std::vector<LaunchParams> L, double rate) {
    for (auto& l : L) l.pitch_rate = rate;
    return L;
  };
  auto mean_rate = [](FitOutcome& f) {
    if (!f.model.effects.launch_rotation_per_flight || f.flights.empty()) return;
    double m = 0;
    for (const auto& x : f.flights) m += x.launch.pitch_rate;
    f.model.effects.launch_rotation = m / static_cast<double>(f.flights.size());
  };
  // A fit repeated from its own result until a further pass gains less than
  // a fifth of one unit of chi-square (nothing a test could see): the
  // baseline must be as converged as the effects that start from it, or
  // every effect is credited with the rest of the baseline's fit (seen: an
  // effect at strength 0 "explaining" a third of the baseline's error).
  const double s2_noise = d.tracking_sigma_m * d.tracking_sigma_m;
  const double step_level = o.step_level();
  // `give_up_above`: return after the first fit when its SSE is still above
  // this (a start that cannot become the fit kept; see kGiveUpFactor).
  auto settled = [&](const DiagModel& start, const std::vector<int>& flights, const std::vector<FreeParam>& free,
                     const std::vector<LaunchParams>* warm,
                     double give_up_above = std::numeric_limits<double>::infinity()) {
    FitOutcome f = D.fit(start, flights, free, warm);
    if (f.sse > give_up_above) return f;
    for (int pass = 0; pass < 4; ++pass) {
      const auto w = launches_of(f);
      FitOutcome n = D.fit(f.model, flights, free, &w);
      const bool gained = f.sse - n.sse > 0.2 * s2_noise;
      if (n.sse < f.sse) f = std::move(n);
      if (!gained) break;
    }
    return f;
  };
  // Baseline on a set of flights: launches, trims and (polish) the centre values.
  auto fit_baseline = [&](const std::shared_ptr<const CoefficientModel>& model, const std::vector<int>& flights) {
    const auto trims = trims_of(D, flights, o.trim);
    FitOutcome b = settled({model, {}, {}}, flights, trims, nullptr);
    if (o.polish > 0 && centre_count(model) > 0) {
      auto free = coefficient_params(model);
      free.insert(free.end(), trims.begin(), trims.end());
      const auto warm = launches_of(b);
      b = D.fit(b.model, flights, free, &warm);
    }
    return b;
  };
  // Every candidate on a set of flights, coefficients fixed at the baseline's;
  // then the `polish` candidates that gained most refitted with the coefficients.
  // `extra`: parameters freed with every candidate's (the second round: the
  // verdict's effect's strengths); such fits are not polished.
  // `profiled`: per candidate, starts from the linearised step on its
  // strengths and the centre values, the full step first, then damped ones
  // (DiagnoseOptions::profile; none where the list is empty).
  constexpr int kProfileIterations = 0;  // Levenberg-Marquardt iterations of a profiled candidate's joint refit (0: as every fit)
  // One step is not the joint optimum (pitch damping on flights of the
  // model with it at full size: strength 0.33 after the step, 0.95
  // polished): a short joint refit of `p` with the centre values and `free`
  // follows, kept when better.
  // `p` with its centre values and `trims` refitted at its effects (the
  // oracle's, and a theoretical-size start's at strength 1), from its
  // launches; the caller keeps it when better.
  auto refit_centres = [&](const FitOutcome& p, const std::vector<int>& flights, const std::vector<FreeParam>& trims) {
    std::vector<FreeParam> free = centre_values(p.model.coefficients);
    free.insert(free.end(), trims.begin(), trims.end());
    const auto w = launches_of(p);
    return D.fit(p.model, flights, free, &w);
  };
  auto joint_refit = [&](FitOutcome& p, const std::vector<int>& flights, const std::vector<FreeParam>& free) {
    auto joint = centre_values(p.model.coefficients);
    joint.insert(joint.end(), free.begin(), free.end());
    const auto wp = launches_of(p);
    FitOutcome q = D.fit(p.model, flights, joint, &wp, kProfileIterations);
    if (q.sse < p.sse) p = std::move(q);
    mean_rate(p);
  };
  // (carry_steps) In the folds, the aerodynamic correction that led the
  // profiled screen on all gliders is also started at the strength the fit
  // to all gliders found for it, reached as a theoretical-size start is
  // (below): -1 outside the folds' first fits.
  int lead_effect = -1;
  std::vector<double> lead_values;
  // (heldout_fold_start) lead_values are the folds' mean strength, reached
  // from the baseline in steps (there are no launches fitted at them).
  bool lead_from_base = false;
  std::map<int, LaunchParams> lead_launches;  // the leader's fit to all gliders: each flight's launch
  std::vector<double> lead_trim;              // and each glider's trim
  auto fit_effects = [&](const FitOutcome& base, const std::vector<int>& flights, const std::string& label,
                         bool counted = true, std::vector<int> which = {}, const std::vector<FreeParam>& extra = {},
                         bool conditional = false, const std::vector<std::vector<DiagModel>>* profiled = nullptr) {
    std::vector<FitOutcome> out(ne);
    const auto warm = launches_of(base);
    const auto trims = trims_of(D, flights, o.trim);
    if (which.empty())
      for (int e = 0; e < ne; ++e) which.push_back(e);
    for (int e : which) {
      auto free = shared_params_of(o.effects[e]);
      free.insert(free.end(), extra.begin(), extra.end());
      free.insert(free.end(), trims.begin(), trims.end());
      // (DiagnoseOptions::theory_starts) An aerodynamic correction also
      // starts at its theoretical size (strength 1, reached in steps with
      // its launches and trims refitted: below) with the centre values refitted with
      // it: the step from strength 0 stays in the baseline's basin when the
      // centre values absorb the effect to first order (blind pitch damping
      // at 1, seed 28, fold 4: strength 0.00, 1.4 cm on the training
      // gliders; the oracle, at 1 with its centre values refitted, 1.3 cm).
      const bool ramp_possible = profiled && !conditional &&
                                 effect_spec(o.effects[e]).level == EffectLevel::Aerodynamic &&
                                 centre_count(base.model.coefficients) > 0;
      // The all-gliders leader's start (lead_effect): where other misfits of
      // a fold's training gliders lead its screen, the step from strength 0
      // lands in the baseline's basin (blind finite span at 1 on 20 gliders,
      // seed 41, fold 2: strength 0.0001 from its step, where the other
      // folds fitted 0.74-1.08 and the oracle, at 1, fits the fold's
      // training gliders at 1.4 cm against 1.7).
      const bool to_lead = ramp_possible && !o.theory_starts && e == lead_effect;
      const bool theory_start = (o.theory_starts && ramp_possible) || to_lead;
      const bool has_step = profiled && !(*profiled)[e].empty();  // a linearised step of its own in this fit
      const std::string size_name = !to_lead          ? "its theoretical size"
                                    : lead_from_base ? "its folds' mean strength"
                                                     : "its strength on all gliders";
      std::optional<FitOutcome> theory;
      // Start where a launch-only refit explains the flights best: at zero
      // (the baseline) or at one of the effect's trial values.
      DiagModel start = base.model;
      std::vector<LaunchParams> start_launches = warm;
      double start_sse = base.sse;
      const auto& sp = effect_spec(o.effects[e]);
      if (per_flight(o.effects[e])) {
        // Every flight's own rate, fitted with its launch from 0 (the
        // baseline) or from each trial rate.
        start.effects.launch_rotation_per_flight = true;
        start_sse = std::numeric_limits<double>::infinity();
        std::vector<double> rates = sp.parameters[0].starts;
        rates.push_back(0.0);
        for (double v : rates) {
          DiagModel m = start;
          m.effects.launch_rotation = v;  // the start of a multi-started launch fit
          const auto w = with_rate(warm, v);
          const FitOutcome t = D.fit(m, flights, {}, &w);
          if (t.sse < start_sse) {
            start_sse = t.sse;
            start_launches = launches_of(t);
          }
        }
      } else {
        for (std::size_t i = 0; i < sp.parameters.size(); ++i)
          for (double v : sp.parameters[i].starts) {
            DiagModel m = base.model;
            m.effects.at(o.effects[e], static_cast<int>(i)) = v;
            FitOutcome t = D.fit(m, flights, {}, &warm);
            if (t.sse < start_sse) {
              start_sse = t.sse;
              start = m;
              start_launches = launches_of(t);
            }
          }
      }
      out[e] = settled(start, flights, free, &start_launches);
      mean_rate(out[e]);
      if (has_step) {
        const auto& steps = (*profiled)[e];
        const double give_up = kGiveUpFactor * out[e].sse;
        FitOutcome p = settled(steps[0], flights, free, &warm, give_up);
        // A step that overshoots (the linearisation of flights far from
        // the noise: wind data, the full step to -0.91 m/s with the centre
        // values settled at 14.8 cm against the fixed-coefficient 7.5 cm)
        // is damped until one explains the flights better than the
        // fixed-coefficient fit.
        for (std::size_t i = 1; i < steps.size() && !(p.sse < out[e].sse); ++i) {
          FitOutcome h = settled(steps[i], flights, free, &warm, give_up);
          report("effect", label + ": " + effect_name(o.effects[e]) + " from " + fmt(kStepFractions[i], 2) +
                               " of the linearised step (" +
                               describe_parameters(o.effects[e], effect_values(h.model.effects, o.effects[e])) +
                               "): RMSE " + cm(h.rmse()) + " (the " + (i == 1 ? "full" : "larger") + " step: " +
                               cm(p.rmse()) + ")",
                 false);
          if (h.sse < p.sse) p = std::move(h);
        }
        joint_refit(p, flights, free);
        report("effect", label + ": " + effect_name(o.effects[e]) + " from the linearised step with the centre values (" +
                             describe_parameters(o.effects[e], effect_values(p.model.effects, o.effects[e])) +
                             "): RMSE " + cm(p.rmse()) + (p.sse < out[e].sse ? " (kept)" : ""), false);
        if (p.sse < out[e].sse) out[e] = std::move(p);
      }
      // (DiagnoseOptions::leader_reached) The leader's start is not made
      // where the fold's own step already fitted the leader at that
      // fraction of its strength on all gliders: where both were made they
      // ended at the same RMSE, 1.4-1.5 cm (finite span at 1, 20 gliders,
      // 30-45 points: steps 0.59-1.42 against 0.963-1.35 on all gliders;
      // the start kept in three folds of seven, 0.01-0.05 from the step's
      // strength), while it cost 60-200 s a fold. Steps that
      // returned to 0 (finite span s41-g20 and s42, fold 2) still get it.
      bool lead_reached = false;
      if (to_lead && has_step) {
        const auto v = effect_values(out[e].model.effects, o.effects[e]);
        lead_reached = v.size() == lead_values.size();
        for (std::size_t i = 0; lead_reached && i < v.size(); ++i)
          lead_reached = v[i] * lead_values[i] > 0 && std::abs(v[i]) >= o.leader_reached * std::abs(lead_values[i]);
        if (lead_reached)
          report("effect", label + ": " + effect_name(o.effects[e]) + "'s linearised step here fitted " +
                               describe_parameters(o.effects[e], v) + ", at least " + fmt(o.leader_reached, 2) +
                               " of " + size_name + " (" + describe_parameters(o.effects[e], lead_values) +
                               "): not started there",
                 false);
      }
      if (theory_start && !lead_reached) {
        // A theoretical-size start is reached the oracle's way (the
        // leader's start from the fit to all gliders, below): the strength
        // switched on in quarter steps with the launches and trims settled
        // at each from the step before, so that at full size the flights are not started from
        // the baseline's launches in a poor basin (blind pitch damping at
        // 1, seed 26: the jump to strength 1 with the baseline's launches
        // refitted to 0.43 on all gliders and lost to the baseline, where
        // the oracle, so reached, explained fold 3's training gliders by
        // delta chi2 187 over it).
        // A step that already misfits kTheoryStartFactor times the
        // baseline's squared error ends the ramp: the misfit grows with the
        // strength (a null dataset's pitch damping: 6.2 cm at full size
        // against the baseline's 1.4 cm), and the start would be skipped
        // at full size anyway; its settling passes are skipped too.
        const double too_far = kTheoryStartFactor * base.sse;
        FitOutcome r = base;
        std::string how;
        bool ramp = !to_lead || lead_from_base;
        bool step_instead = false;  // the leader's start too far, its linearised step its start instead
        if (to_lead && !lead_from_base) {
          // The leader's start first takes the launches and trims of the
          // fit to all gliders, which has the fold's training flights at the
          // leader's strength already, with the fold's centre values: one
          // settled fit (ramped from the fold's baseline in four settled
          // steps it took 613-1386 s a fold on 20 gliders: blind finite
          // span s29-g20, fold 1). Where the fold's centre values lie in
          // another basin those launches do not fit them (s29-g20, fold 2:
          // its baseline 2.9 cm, from the all-glider launches 12.0 cm),
          // and the ramp below is made instead (there: strength 0.891,
          // 1.4 cm).
          DiagModel m = base.model;
          for (std::size_t i = 0; i < sp.parameters.size(); ++i)
            m.effects.at(o.effects[e], static_cast<int>(i)) = lead_values.at(i);
          for (const auto& t : trims) {
            if (t.kind != FreeParam::Trim) continue;
            if (m.trim.size() < lead_trim.size()) m.trim.resize(lead_trim.size(), 0.0);
            m.trim.at(t.index) = lead_trim.at(t.index);
          }
          std::vector<LaunchParams> w;
          for (int f : flights) w.push_back(lead_launches.at(f));
          r = settled(m, flights, trims, &w, too_far);
          how = "started at its strength on all gliders (" + describe_parameters(o.effects[e], lead_values) +
                ") from the launches and trims fitted there";
          // Where the fold's screen gave the leader a linearised step of its
          // own, that step is its start there and no ramp is made: at the
          // issue's size, 30-45 tracked points a flight, the ramp cost
          // 330-540 s a fold (about half of it) and ended near where the
          // step did (finite span at 1, 20 gliders, 120 flights, commit
          // 862c527: folds 2 and 3 fitted 0.885 and 1.02 from the ramp, 1.4
          // and 1.3 cm, and 0.51 and 1.02 from the step, 1.4 cm each;
          // s29-g20's fold 2 held out 1.5 cm either way).
          if (r.sse > too_far) {
            report("effect", label + ": " + effect_name(o.effects[e]) + " " + how + ": RMSE " + cm(r.rmse()) +
                                 ", too far from the baseline's " + cm(base.rmse()) +
                                 (has_step ? "; its linearised step here is its start instead"
                                           : "; ramped from the baseline instead"),
                   false);
            step_instead = has_step;
            if (!has_step) {
              r = base;
              ramp = true;
            }
          }
        }
        if (ramp) {
          int reached = 0;
          for (int k = 1; k <= kRampSteps; ++k) {
            DiagModel m = r.model;
            for (std::size_t i = 0; i < sp.parameters.size(); ++i)
              m.effects.at(o.effects[e], static_cast<int>(i)) =
                  (to_lead ? lead_values.at(i) : 1.0) * static_cast<double>(k) / kRampSteps;
            const auto w = launches_of(r);
            r = settled(m, flights, trims, &w, too_far);
            reached = k;
            if (r.sse > too_far) break;
          }
          how = r.sse > too_far ? "switched on: at " + std::to_string(reached) + "/" + std::to_string(kRampSteps) +
                                      " of " + size_name
                                : "switched on to " + size_name +
                                      (to_lead ? " (" + describe_parameters(o.effects[e], lead_values) + ")" : "") +
                                      " in " + std::to_string(kRampSteps) + " steps, launches and trims refitted";
        }
        if (step_instead) {
          // reported above
        } else if (r.sse > too_far) {
          report("effect", label + ": " + effect_name(o.effects[e]) + " " + how + " already RMSE " + cm(r.rmse()) +
                               ", too far from the baseline's " + cm(base.rmse()) + "; no start from there",
                 false);
        } else {
          report("effect", label + ": " + effect_name(o.effects[e]) + " " + how + ": RMSE " + cm(r.rmse()), false);
          theory = std::move(r);
        }
      }
      if (theory && theory->sse > kTheoryStartFactor * base.sse) {
        report("effect", label + ": " + effect_name(o.effects[e]) + " at " + size_name + ": RMSE " +
                             cm(theory->rmse()) + ", too far from the baseline's " + cm(base.rmse()) +
                             " to refit the centre values from there", false);
        theory.reset();
      }
      if (theory) {
        FitOutcome& q = *theory;
        // The centre values refitted at full size (as the oracle's).
        FitOutcome c = refit_centres(q, flights, trims);
        if (c.sse < q.sse) q = std::move(c);
        // Then with the strength free (as the profiled steps' joint refit).
        // (DiagnoseOptions::hold_theory) Or held at its theoretical size
        // unless the training flights reject it: freed, it is kept only when
        // it fits them better by more than the chi-square quantile of its
        // parameters at the test's level (a likelihood-ratio test against
        // the theoretical value). Freed without that test, the centre values
        // re-tuned with it predict a held-out glider the theoretical size
        // carries over to worse (blind pitch damping at 1, seed 28:
        // strengths 0.69-0.92 in the folds, held-out shrink -7.1 % from one
        // swept wing; the oracle, at exactly 1, 21.3 %). Both from the same
        // fit and with one more pass each, the held strength's with the
        // centre values and trims, the freed one's with its strength too:
        // the test sees the strength, not the extra pass (blind finite span
        // s28 compared with the first pass: freed to 0.981 by delta chi2
        // 4.97 on all gliders, nearly all of it the pass).
        FitOutcome freed = q;
        joint_refit(freed, flights, free);
        bool hold = false;
        if (o.hold_theory && !to_lead) {
          FitOutcome h = refit_centres(q, flights, trims);
          if (h.sse < q.sse) q = std::move(h);
          const double s2_fit = std::max(
              s2_noise, freed.sse / std::max(1, freed.points - freed.launch_parameters - freed.free_parameters));
          const double needed = chi2_isf(o.alpha, static_cast<double>(sp.parameters.size()));
          const TheoryHold t = theory_hold(q.sse, freed.sse, out[e].sse, s2_fit, needed);
          hold = t.held();
          report("effect", label + ": " + effect_name(o.effects[e]) + " freed from its theoretical size (" +
                               describe_parameters(o.effects[e], effect_values(freed.model.effects, o.effects[e])) +
                               "): RMSE " + cm(freed.rmse()) + ", delta chi2 " + fmt(t.delta_chi2, 3) + " against " +
                               fmt(needed, 3) + (t.rejected ? ": the theoretical size is rejected"
                                                            : ": held at its theoretical size"),
                 false);
          // (blind finite span s28, fold 4: held at 1 the fit lost to
          // strength 0; freed to 0.645 it had won, and the verdict with it)
          if (t.outdone)
            report("effect", label + ": " + effect_name(o.effects[e]) +
                                 " held at its theoretical size fits the training flights no better than from the "
                                 "other start (delta chi2 " + fmt((q.sse - out[e].sse) / s2_fit, 3) +
                                 " against it), freed it does: freed instead",
                   false);
        }
        if (!hold) q = std::move(freed);
        else q.strength_held = true;
        const bool kept = q.sse < out[e].sse;
        report("effect", label + ": " + effect_name(o.effects[e]) + " from " + size_name + " with the centre values (" +
                             describe_parameters(o.effects[e], effect_values(q.model.effects, o.effects[e])) +
                             "): RMSE " + cm(q.rmse()) + (kept ? " (kept)" : ""), false);
        if (kept) out[e] = std::move(q);
      }
      report("effect", label + ": " + effect_name(o.effects[e]) + " (" +
                           describe_parameters(o.effects[e], effect_values(out[e].model.effects, o.effects[e])) +
                           "): RMSE " + cm(out[e].rmse()) + " (baseline " + cm(base.rmse()) + ")", counted);
    }
    if (o.polish > 0 && centre_count(base.model.coefficients) > 0 && !conditional) {
      std::vector<int> order = which;
      std::sort(order.begin(), order.end(), [&](int a, int b) { return out[a].sse < out[b].sse; });
      // Every candidate (polish >= the number of candidates) or the most
      // promising ones. With the coefficients fixed, an effect they already
      // absorbed looks useless (pitch damping on damped flights: best at
      // strength 0 with fixed coefficients, 0.64 and near the noise when
      // refitted together), so when all are polished an aerodynamic
      // correction starts from its theoretical size (strength 1).
      const bool all = o.polish >= ne;
      for (int i = 0; i < std::min<int>(o.polish, static_cast<int>(order.size())); ++i) {
        const int e = order[i];
        if (!all && !(out[e].sse < base.sse)) continue;
        auto free = coefficient_params(base.model.coefficients);
        const auto p = shared_params_of(o.effects[e]);
        free.insert(free.end(), p.begin(), p.end());
        free.insert(free.end(), trims.begin(), trims.end());
        const auto w = launches_of(out[e]);
        DiagModel start = out[e].model;
        if (all && effect_spec(o.effects[e]).level == EffectLevel::Aerodynamic)
          for (std::size_t k = 0; k < p.size(); ++k) {
            double& v = start.effects.at(o.effects[e], static_cast<int>(k));
            v = std::max(v, 1.0);
          }
        FitOutcome polished = D.fit(start, flights, free, &w);
        mean_rate(polished);
        if (polished.sse < out[e].sse) out[e] = std::move(polished);
        report("effect", label + ": " + effect_name(o.effects[e]) + " refitted with the coefficients (" +
                             describe_parameters(o.effects[e], effect_values(out[e].model.effects, o.effects[e])) +
                             "): RMSE " + cm(out[e].rmse()), false);
      }
    }
    return out;
  };

  // A launch can sit in a poor basin that another fit's start escaped (an
  // effect's trial strengths move every launch): the baseline is refitted
  // from the launches and trims of every fit that explains the same flights
  // clearly better, and the best is kept.
  auto improve_baseline = [&](FitOutcome& base, const std::vector<FitOutcome>& others, const std::vector<int>& flights) {
    const auto trims = trims_of(D, flights, o.trim);
    bool improved = false;
    for (const auto& other : others) {
      if (!(other.sse < base.sse - 0.2 * s2_noise)) continue;
      DiagModel m = base.model;
      m.trim = other.model.trim;
      const auto w = launches_of(other);
      FitOutcome n = settled(m, flights, trims, &w);
      if (n.sse < base.sse - 0.2 * s2_noise) {
        base = std::move(n);
        improved = true;
      }
    }
    return improved;
  };
  // Every candidate on a set of flights from a baseline that no other fit
  // beats at its own strengths; an effect nests the baseline (strength 0),
  // so its fit is never worse than the baseline's.
  // Polished fits: a candidate refitted with the coefficients may land in a
  // basin of centre values that explains the flights better whatever its
  // strength (seen on downwash data: pitch damping polished to strength
  // 0.005 "explained" a third of the held-out error, and to 0.09 a quarter
  // of the training error). That gain belongs to the coefficients, not to
  // the effect: the baseline is refitted from every such candidate's centre
  // values and trims with its strength at zero, and kept when it is better.
  // The same for the profiled starts (DiagnoseOptions::profile): their
  // candidates' re-tuned centre values go to the baseline at strength 0 with
  // its launches and trims refitted (not the centre values: a profiled
  // diagnosis does not polish its baseline), so that only what the centre
  // values cannot do is credited to the effect. `fixed`: coefficients of
  // fits that did not re-tune them besides the baseline's (profiled: those
  // from before the baseline's own step; polished: none).
  auto improve_coefficient_baseline = [&](FitOutcome& base, const std::vector<FitOutcome>& others,
                                          const std::vector<int>& flights, const std::string& label,
                                          const std::shared_ptr<const CoefficientModel>& fixed) {
    const bool polished = o.polish > 0;
    if (centre_count(base.model.coefficients) == 0) return false;
    const auto trims = trims_of(D, flights, o.trim);
    bool improved = false;
    std::vector<int> order(others.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return others[a].sse < others[b].sse; });
    for (int e : order) {
      const auto& other = others[e];
      // Fixed coefficients: not polished, or not re-tuned by a profiled start.
      if (other.model.coefficients == base.model.coefficients || other.model.coefficients == fixed) continue;
      if (!(other.sse < base.sse - 0.2 * s2_noise)) continue;
      const auto v = effect_values(other.model.effects, o.effects[e]);
      if (polished && !per_flight(o.effects[e]) &&
          std::all_of(v.begin(), v.end(), [](double x) { return x == 0.0; })) {
        // At strength 0 the candidate's fit is a baseline fit.
        report("baseline", label + ": " + effect_name(o.effects[e]) + " at strength 0 with its own centre values: RMSE " +
                               cm(other.rmse()) + " (baseline " + cm(base.rmse()) + "; kept)", false);
        base = other;
        improved = true;
        continue;
      }
      const DiagModel m{other.model.coefficients, {}, other.model.trim};
      const auto w = launches_of(other);
      FitOutcome n;
      if (polished) {
        auto free = coefficient_params(other.model.coefficients);
        free.insert(free.end(), trims.begin(), trims.end());
        n = D.fit(m, flights, free, &w);
      } else {
        n = settled(m, flights, trims, &w);
      }
      const bool better = n.sse < base.sse - 0.2 * s2_noise;
      report("baseline", label + (polished ? ": baseline refitted from " + effect_name(o.effects[e]) +
                                                 "'s centre values at strength 0: RMSE "
                                           : ": baseline at " + effect_name(o.effects[e]) +
                                                 "'s re-tuned centre values, strength 0: RMSE ") +
                             cm(n.rmse()) + " (baseline " + cm(base.rmse()) + (better ? "; kept)" : ")"), false);
      if (better) {
        base = std::move(n);
        improved = true;
      }
    }
    return improved;
  };
  // DiagnoseOptions::profile: one projected Jacobian at the baseline on the
  // trims, the centre values and every candidate's strengths; the baseline
  // takes the regularised step on the trims and centre values (kept when its
  // refitted launches and trims fit better), every candidate's start is the
  // step with its strengths as well.
  // Profiled starts re-tune the centre values with each candidate; on too
  // few gliders they overfit them (DiagnoseOptions::profile_min_gliders).
  auto gliders_of = [&](const std::vector<int>& flights) {
    std::set<int> g;
    for (int f : flights) g.insert(D.glider_of(f));
    return static_cast<int>(g.size());
  };
  auto profiled_on = [&](int gliders) { return gliders >= o.profile_min_gliders; };
  // What a linearised step moves from `base`: the trims, the centre values
  // and `extra` (the verdict's strengths in the second round), the columns
  // of all of them (the baseline's own step), and the trims alone.
  struct StepSpace {
    std::vector<FreeParam> free, trims;
    std::vector<int> base_cols;
  };
  auto step_space = [&](const FitOutcome& base, const std::vector<int>& flights,
                        const std::vector<FreeParam>& extra = {}) {
    StepSpace s;
    s.trims = trims_of(D, flights, o.trim);
    s.free = s.trims;
    const auto centres = centre_values(base.model.coefficients);
    s.free.insert(s.free.end(), centres.begin(), centres.end());
    s.free.insert(s.free.end(), extra.begin(), extra.end());
    s.base_cols.resize(s.free.size());
    std::iota(s.base_cols.begin(), s.base_cols.end(), 0);
    return s;
  };
  // The baseline's own step on `s.base_cols`, settled with `settle_free`,
  // damped as the candidates' are until one explains the flights better
  // than `from` by more than a fifth of a unit of chi-square; that fit, or
  // none. Each try is reported under `label` unless it is empty.
  auto own_step = [&](const FitOutcome& from, const StepSpace& s, const Eigen::MatrixXd& J,
                      const std::vector<int>& flights, const std::vector<FreeParam>& settle_free,
                      const std::string& label) -> std::optional<FitOutcome> {
    const auto w = launches_of(from);
    for (double fraction : kStepFractions) {
      FitOutcome n = settled(D.linear_step(from, s.free, J, s.base_cols, nullptr, fraction), flights, settle_free, &w);
      const bool better = n.sse < from.sse - 0.2 * s2_noise;
      if (!label.empty())
        report("baseline", label + ": baseline from " +
                               (fraction == 1.0 ? std::string("the") : fmt(fraction, 2) + " of the") +
                               " linearised step on its centre values and trims: RMSE " + cm(n.rmse()) + " (was " +
                               cm(from.rmse()) + (better ? "; kept)" : ")"),
               false);
      if (better) return n;
    }
    return std::nullopt;
  };
  // One candidate's starts from its own linearised step at `base` (the
  // trims, the centre values, `extra` and its strengths), at each fraction
  // of kStepFractions, in its slot of the per-candidate list fit_effects
  // takes; with the step space and Jacobian, for the baseline's own step.
  struct CandidateStep {
    StepSpace space;
    Eigen::MatrixXd J;
    std::vector<std::vector<DiagModel>> starts;
  };
  auto candidate_step = [&](const FitOutcome& base, const std::vector<int>& flights, int e,
                            const std::vector<FreeParam>& extra = {}) {
    CandidateStep c;
    c.space = step_space(base, flights, extra);
    std::vector<int> cols = c.space.base_cols;
    for (const auto& p : params_of(o.effects[e])) {
      cols.push_back(static_cast<int>(c.space.free.size()));
      c.space.free.push_back(p);
    }
    c.J = D.projected_jacobian(base, c.space.free);
    c.starts.resize(ne);
    for (double fraction : kStepFractions)
      c.starts[e].push_back(D.linear_step(base, c.space.free, c.J, cols, nullptr, fraction));
    return c;
  };
  // `stepped` (optional): set for every candidate refitted from its step.
  // `carried` (optional): candidates refitted from their step whatever
  // their gain here (DiagnoseOptions::carry_steps).
  // `leader` (optional): set to the candidate with the largest linearised
  // gain that passes the test's screen (-1: none).
  // Where the screen's gains are kept (EffectResult::linearised_delta_chi2):
  // set around the all-glider and fold fits, one value per candidate.
  std::vector<double>* screen_gains = nullptr;
  auto profile_starts = [&](FitOutcome& base, const std::vector<int>& flights, const std::string& label,
                            std::vector<bool>* stepped = nullptr, const std::vector<bool>* carried = nullptr,
                            int* leader = nullptr) {
    StepSpace space = step_space(base, flights);
    std::vector<FreeParam>& free = space.free;  // the candidates' strengths follow the baseline's columns
    const std::vector<int>& base_cols = space.base_cols;
    std::vector<std::vector<int>> cols(ne);
    for (int e = 0; e < ne; ++e) {
      if (per_flight(o.effects[e])) continue;  // no shared strength to step
      for (const auto& p : params_of(o.effects[e])) {
        cols[e].push_back(static_cast<int>(free.size()));
        free.push_back(p);
      }
    }
    const Eigen::MatrixXd J = D.projected_jacobian(base, free);
    double sse_base = 0;
    D.linear_step(base, free, J, base_cols, &sse_base);
    // Only candidates whose linearised gain over the baseline's step passes
    // the likelihood-ratio threshold are refitted from their step (the fits
    // cost about as much as the fixed-coefficient ones), at most
    // DiagnoseOptions::profiled_candidates, the largest gains first.
    std::vector<std::vector<DiagModel>> starts(ne);
    // Those that pass first, then (carried) the others stepped on all
    // gliders, in the free places: a carried candidate never displaces one
    // this fit's own gains support (blind finite span at 1, seed 24: three
    // carried candidates displaced finite span, whose gains of 26 and 81 in
    // two folds had named it, and the verdict was lost).
    // With a screen laxer than the test (DiagnoseOptions::step_alpha), the
    // gains that pass only it come last: they never displace a carried
    // candidate (blind finite span at 1, seed 25, at step_alpha 1: fold 1's
    // gains of 0.68 and 0.56 displaced the carried finite span, and the
    // verdict was lost).
    std::vector<std::pair<double, int>> gains, carried_gains, weak_gains;
    std::pair<double, int> largest_left{0.0, -1};  // the largest positive gain under the screen, for the progress line
    for (int e = 0; e < ne; ++e) {
      if (cols[e].empty()) continue;
      std::vector<int> c = base_cols;
      c.insert(c.end(), cols[e].begin(), cols[e].end());
      double sse_e = 0;
      starts[e].push_back(D.linear_step(base, free, J, c, &sse_e));
      const double gain = (sse_base - sse_e) / s2_noise;
      if (screen_gains) (*screen_gains)[e] = gain;
      const double dof = static_cast<double>(cols[e].size());
      // The laxer screen only in the folds (`carried` is given there): on all
      // gliders the baseline takes the extra candidates' re-tuned centre
      // values, and the likelihood-ratio test there loses its power (blind
      // finite span at 1, seed 25: Delta chi2 0.12 and `none`, against 23.8
      // and named with the screen in the folds only).
      const double level = carried ? step_level : o.alpha;
      const bool passes = gain > (level >= 1 ? 0.0 : chi2_isf(level / ne, dof));
      const bool carry = carried && (*carried)[e];
      if (passes && gain > chi2_isf(o.alpha / ne, dof))
        gains.push_back({gain, e});
      else if (carry)
        carried_gains.push_back({gain, e});
      else if (passes)
        weak_gains.push_back({gain, e});
      else if (gain > 0 && !(largest_left.first >= gain))
        largest_left = {gain, e};
      if (passes || carry)
        for (std::size_t i = 1; i < std::size(kStepFractions); ++i)
          starts[e].push_back(D.linear_step(base, free, J, c, nullptr, kStepFractions[i]));
    }
    std::sort(gains.rbegin(), gains.rend());
    std::sort(carried_gains.rbegin(), carried_gains.rend());
    std::sort(weak_gains.rbegin(), weak_gains.rend());
    if (leader) *leader = gains.empty() ? -1 : gains.front().second;
    std::vector<bool> keep(ne, false);
    std::string kept;
    int places = o.profiled_candidates;
    for (const auto& [list, note] : {std::pair{&gains, ""}, std::pair{&carried_gains, "; stepped on all gliders"},
                                     std::pair{&weak_gains, "; under the test's threshold"}})
      for (std::size_t i = 0; i < list->size() && places > 0; ++i, --places) {
        const auto [gain, e] = (*list)[i];
        keep[e] = true;
        kept += (kept.empty() ? "" : ", ") + effect_name(o.effects[e]) + " (linearised delta chi2 " + fmt(gain, 3) +
                note + ")";
      }
    for (int e = 0; e < ne; ++e)
      if (!keep[e]) starts[e].clear();
    if (stepped) *stepped = keep;
    std::string left;
    if (largest_left.second >= 0)
      left = "; largest under the threshold: " + effect_name(o.effects[largest_left.second]) + " (" +
             fmt(largest_left.first, 3) + ")";
    report("baseline", label + ": candidates refitted from the linearised step with the centre values: " +
                           (kept.empty() ? std::string("none passes the threshold") : kept) + left, false);
    // The baseline's own step (on its columns of the same Jacobian).
    if (auto n = own_step(base, space, J, flights, space.trims, label)) base = std::move(*n);
    return starts;
  };
  auto fit_effects_from = [&](FitOutcome& base, const std::vector<int>& flights, const std::string& label,
                              std::vector<bool>* stepped = nullptr, const std::vector<bool>* carried = nullptr,
                              int* leader = nullptr) {
    if (stepped) stepped->assign(ne, false);
    if (leader) *leader = -1;
    const bool profiled = o.profile && o.polish <= 0 && centre_count(base.model.coefficients) > 0 &&
                          profiled_on(gliders_of(flights));
    // The fixed-coefficient fits keep the coefficients the baseline had
    // before its own linearised step: re-tuned at strength 0, the centre
    // values absorb more of an effect (pitch damping on flights of the model
    // with it at full size: strength 0.33 instead of 1.0 from the stepped
    // baseline's coefficients). The candidates are compared with the better
    // baseline all the same.
    const FitOutcome before = base;
    std::vector<std::vector<DiagModel>> starts;
    if (profiled) starts = profile_starts(base, flights, label, stepped, carried, leader);
    std::vector<FitOutcome> out = fit_effects(before, flights, label, true, {}, {}, false, profiled ? &starts : nullptr);
    // A per-flight candidate (every flight's own launch pitch rate) has no
    // shared strength to step: its centre values are stepped from its own
    // fit instead, as the baseline's are from the baseline
    // (DiagnoseOptions::step_per_flight).
    constexpr int kRateSteps = 3;
    if (profiled && o.step_per_flight)
      for (int e = 0; e < ne; ++e) {
        if (!per_flight(o.effects[e]) || !(out[e].sse < before.sse)) continue;
        const double was = out[e].rmse();
        // The rates move with the centre values: the step is taken again
        // from where it landed while it gains (at most kRateSteps times).
        for (int step = 0; step < kRateSteps; ++step) {
          const StepSpace s = step_space(out[e], flights);
          const Eigen::MatrixXd J = D.projected_jacobian(out[e], s.free);
          auto settle = shared_params_of(o.effects[e]);
          settle.insert(settle.end(), s.trims.begin(), s.trims.end());
          auto n = own_step(out[e], s, J, flights, settle, "");
          if (!n) break;
          joint_refit(*n, flights, settle);  // as every profiled candidate
          out[e] = std::move(*n);
        }
        report("effect", label + ": " + effect_name(o.effects[e]) + " with its centre values from the linearised step: RMSE " +
                             fmt(100 * out[e].rmse(), 3) + " cm (was " + fmt(100 * was, 3) + " cm" +
                             (out[e].rmse() < was ? "; kept)" : ")"),
               false);
      }
    // Until the baseline stops improving (at most three rounds): a refitted
    // candidate can find yet another basin of centre values.
    const int rounds = o.polish > 0 ? 3 : 1;  // basins of centre values exist only when they are fitted
    for (int round = 0; round < rounds; ++round) {
      const bool launches_better = improve_baseline(base, out, flights);
      const bool coefficients_better =
          (o.polish > 0 || profiled) &&
          improve_coefficient_baseline(base, out, flights, label, profiled ? before.model.coefficients : nullptr);
      if (!launches_better && !coefficients_better) break;
      report("baseline", label + ": baseline refitted from the candidates' launches" +
                             std::string(coefficients_better ? " and centre values" : "") + ": RMSE " + cm(base.rmse()) +
                             "; candidates refitted from it", false);
      // Candidates that beat even the new baseline keep their fits; the
      // others start again from it.
      std::vector<int> redo;
      for (int e = 0; e < ne; ++e)
        if (!(out[e].sse < base.sse - 0.2 * s2_noise)) redo.push_back(e);
      const std::vector<FitOutcome> again = fit_effects(base, flights, label + " (again)", false, redo);
      for (int e : redo)
        if (again[e].sse < out[e].sse) out[e] = again[e];
    }
    // A candidate fitted at the coefficients from before the baseline's own
    // step (not among the stepped ones) is compared with a baseline that
    // took the step, and perhaps another candidate's re-tuned centre values,
    // without ever having had them itself: it does not nest the baseline it
    // is tested against, and its gain over the old coefficients is lost
    // where the new ones gain as much by another route (blind launch
    // rotation at 1, seed 35, all gliders: 98 deg/s, 1.6 -> 1.4 cm from the
    // old coefficients, as much as the baseline at pitch damping's re-tuned
    // centre values; likelihood ratio 0.75 against the truth's 306). Every
    // such candidate that gained over the old coefficients by the
    // likelihood-ratio threshold is fitted again at the final baseline's
    // centre values, started at its own values and launches, and the better
    // fit is kept. The centre values are not refitted with it: jointly
    // refitted, candidates near strength 0 re-tuned them to the training
    // gliders, the baseline took them (as it must, or the effect is credited
    // with what they do alone) and predicted the held-out gliders worse
    // (blind pitch damping at 1, seed 34, fold 4: 1.8 -> 2.3 cm), which
    // inflates every other candidate's shrink.
    if (o.refit_unstepped && profiled && base.model.coefficients != before.model.coefficients) {
      const auto trims = trims_of(D, flights, o.trim);
      for (int e = 0; e < ne; ++e) {
        const Effect E = o.effects[e];
        if (out[e].model.coefficients != before.model.coefficients) continue;  // stepped or re-tuned
        const double dof = added_dof(E, static_cast<double>(flights.size()));
        if (!((before.sse - out[e].sse) / s2_noise > chi2_isf(o.alpha / ne, dof))) continue;
        DiagModel m = base.model;
        m.effects = out[e].model.effects;
        auto free = shared_params_of(E);
        free.insert(free.end(), trims.begin(), trims.end());
        const auto w = launches_of(out[e]);
        FitOutcome n = settled(m, flights, free, &w);
        mean_rate(n);
        const bool better = n.sse < out[e].sse;
        report("effect", label + ": " + effect_name(E) + " refitted at the baseline's final centre values (" +
                             describe_parameters(E, effect_values(n.model.effects, E)) + "): RMSE " + cm(n.rmse()) +
                             " (at the old ones: " + cm(out[e].rmse()) + (better ? "; kept)" : ")"),
               false);
        if (better) out[e] = std::move(n);
      }
    }
    for (auto& x : out)
      if (x.sse > base.sse) x = base;  // strength 0
    return out;
  };

  // A held-out glider's launches and trim are its own nuisance values, fitted
  // to its own points; from a warm start they can stay in a basin where the
  // glider tumbles (seen: a forward-swept glider held out, its trim stuck at
  // 0 and every flight leaving the model's range, 22 cm, while a trim of
  // -2.3 degrees flew it). When a flight of a held-out glider leaves the
  // model's range, the glider's trim is restarted from -4, -2, 2 and 4
  // degrees with fresh multi-start launches, and the best fit is kept.
  auto held_out_fit = [&](const DiagModel& m, const std::vector<int>& test, const std::vector<FreeParam>& ho_trims,
                          const std::vector<LaunchParams>* warm) {
    FitOutcome best = settled(m, test, ho_trims, warm);
    // Only polished diagnoses: there the centre values can move into basins
    // where a held-out glider needs another trim to fly. With fixed
    // coefficients a glider that leaves the range usually cannot be flown
    // by the model at all, and the restarts cost minutes for nothing (a
    // 15-flight diagnosis went from under 2 to over 15 minutes).
    // The same with profiled starts, whose candidates re-tune the centre
    // values too (seen on the wind blind dataset: wind at -0.96 m/s
    // predicted one fold's held-out gliders at 8.8 cm against the
    // baseline's 5.2 cm, the camera another's at 58 cm).
    std::set<int> bad;
    if (o.polish > 0 || (o.profile && profiled_on(static_cast<int>(flown.size()) - gliders_of(test))))
      for (const auto& f : best.flights)
        if (f.left_model_range) bad.insert(D.glider_of(f.flight));
    for (int g : bad) {
      if (D.gliders()[g].features.trim_wing < 0 || !o.trim) continue;
      // Only this glider's flights and trim are refitted.
      std::vector<int> mine, at;
      for (std::size_t i = 0; i < best.flights.size(); ++i)
        if (D.glider_of(best.flights[i].flight) == g) {
          mine.push_back(best.flights[i].flight);
          at.push_back(static_cast<int>(i));
        }
      double sse_now = 0;
      for (int i : at) sse_now += best.flights[i].sse;
      const std::vector<FreeParam> trim{FreeParam::trim(g)};
      for (double deg : {-4.0, -2.0, 2.0, 4.0}) {
        DiagModel r = best.model;
        if (r.trim.size() < D.gliders().size()) r.trim.resize(D.gliders().size(), 0.0);
        r.trim[g] = deg2rad(deg);
        // A restart whose first fit does not beat the glider's best so far
        // is not settled further (as kGiveUpFactor's starts): settling
        // every restart took a held-out fit under downwash on blind wind
        // data (seed 24, fold 1; a glider the model cannot fly, 13-22 cm)
        // over 20 minutes, up to five fits of each of four trims, for every
        // step of the carry-in.
        FitOutcome t = settled(r, mine, trim, nullptr, sse_now);
        if (!(t.sse < sse_now)) continue;
        sse_now = t.sse;
        best.model.trim[g] = t.model.trim[g];
        for (std::size_t k = 0; k < at.size(); ++k) best.flights[at[k]] = t.flights[k];
      }
    }
    if (!bad.empty()) {
      best.sse = 0;
      for (const auto& f : best.flights) best.sse += f.sse;
    }
    return best;
  };

  // Held-out gliders under a model fitted to training gliders: their launches
  // and trims are fitted to their own points, starting from `from`'s.
  // Where that predicts them clearly worse than `from` (by more than the
  // margin an effect must win by), they are also carried there in steps, the
  // effects at a quarter of their values, a half, ..., launches and trims
  // refitted at each from the step before (as the oracle's are), and the
  // better fit is kept: a model far from `from`'s starts its launches in a
  // poor basin (seen on blind downwash at 1, seed 22, fold 1: downwash at
  // strength 0.7 with its re-tuned centre values predicted the held-out
  // gliders at 6.3 cm, the baseline at the same centre values at 2.2 cm).
  // Both are fits of the held-out launches and trims under one model, so
  // the better one is simply the better optimum.
  constexpr int kHeldOutSteps = 4;
  auto ho_fit_on = [&](const FitOutcome& tr, const FitOutcome& from, const std::vector<int>& test,
                       const std::vector<FreeParam>& ho_trims, const std::string& what = {}) {
    DiagModel m = from.model;
    m.coefficients = tr.model.coefficients;
    m.effects = tr.model.effects;
    auto start = [&](const DiagModel& at, const FitOutcome& prev) {
      auto w = launches_of(prev);
      // Per-flight launch rotation: the held-out flights' rates start from
      // the training gliders' mean (from.model, the baseline, has none).
      if (at.effects.launch_rotation_per_flight && !prev.model.effects.launch_rotation_per_flight)
        w = with_rate(w, at.effects.launch_rotation);
      return w;
    };
    const auto w = start(m, from);
    FitOutcome direct = held_out_fit(m, test, ho_trims, &w);
    const double margin = 1 / ((1 - o.min_shrink) * (1 - o.min_shrink));
    if (m.effects.zero() || !(direct.sse > margin * from.sse)) return direct;
    FitOutcome staged = from;
    for (int k = 1; k <= kHeldOutSteps; ++k) {
      DiagModel at = m;
      const double f = static_cast<double>(k) / kHeldOutSteps;
      for (Effect E : all_effects())
        for (std::size_t i = 0; i < effect_spec(E).parameters.size(); ++i)
          at.effects.at(E, static_cast<int>(i)) *= f;
      const auto ws = start(at, staged);
      staged = held_out_fit(at, test, ho_trims, &ws);
    }
    report("fold", (what.empty() ? std::string() : what + ": ") + "held-out gliders carried to the model in steps: " +
                       cm(staged.rmse()) + " (directly " +
                       cm(direct.rmse()) + ", from " + cm(from.rmse()) + ")",
           false);
    return staged.sse < direct.sse ? staged : direct;
  };

  DiagnoseResult res;
  res.sigma_m = sigma;
  res.gliders = static_cast<int>(flown.size());
  res.folds = K;
  for (const auto& g : D.gliders()) res.glider_keys.push_back(g.key);
  std::vector<int> all_flights;
  for (int g : flown)
    for (int f : D.gliders()[g].flights) all_flights.push_back(f);
  std::sort(all_flights.begin(), all_flights.end());
  res.flights = static_cast<int>(all_flights.size());
  for (int f : all_flights) res.points += static_cast<int>(d.flights[f].points.size());
  json timings;

  // ------------------------------------------------------------ all gliders
  FitOutcome base_full;
  std::vector<FitOutcome> eff_full(ne);
  std::vector<bool> full_stepped(ne, false);  // candidates refitted from their linearised step on all gliders
  int full_leader = -1;  // the largest linearised gain there that passes the test's screen (-1: none)
  constexpr double kNoScreen = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> full_screen(ne, kNoScreen);  // the screen's linearised gains on all gliders
  int full_centres = 0;
  if (o.full_fit) {
    const auto tf = Clock::now();
    std::set<std::string> keys;
    for (int g : flown) keys.insert(D.gliders()[g].key);
    const auto model = coefficient_fit(keys, "all gliders");
    full_centres = centre_count(model);
    timings["coefficients_all_s"] = since(tf);
    base_full = fit_baseline(model, all_flights);
    full_centres = centre_count(base_full.model.coefficients);
    report("baseline", "all gliders: baseline RMSE " + cm(base_full.rmse()) + " (" + std::to_string(full_centres) +
                           " centres, launches and trims fitted)");
    screen_gains = &full_screen;
    eff_full = fit_effects_from(base_full, all_flights, "all gliders", &full_stepped, nullptr, &full_leader);
    screen_gains = nullptr;
    res.model = base_full.model.coefficients;
    res.trim = base_full.model.trim;
    timings["all_gliders_s"] = since(tf);
  }

  // ------------------------------------------------------------ folds
  res.heldout.resize(d.flights.size());
  std::vector<std::vector<std::vector<double>>> fold_params(ne);
  std::vector<std::vector<bool>> fold_held(ne);
  std::vector<std::vector<double>> fold_screen(ne);  // the screen's linearised gains per fold
  std::vector<double> train_dsse(ne, 0.0);  // summed over folds (for the LR test without a full fit)
  double train_sse0 = 0;
  int train_dof0 = 0;
  FitOutcome first_train;
  // The oracle's held-out error (DiagnoseOptions::oracle), summed over folds.
  double oracle_sse_ho = 0;
  std::vector<double> oracle_fold_rmse, oracle_fold_base_rmse, oracle_fold_train_dchi2;
  // Every fold's fits, kept for the second round (given the verdict's effect).
  std::vector<std::vector<int>> fold_train(K), fold_test(K);
  std::vector<std::vector<FitOutcome>> fold_trs(K), fold_hos(K);
  res.fold_gliders.resize(K);
  auto fold_label = [&](int k) { return "fold " + std::to_string(k + 1) + "/" + std::to_string(K); };
  const auto tfolds = Clock::now();
  for (int k = 0; k < K; ++k) {
    std::set<std::string> keys;
    std::vector<int> train, test;
    for (int g : flown) {
      if (fold_of[g] == k) {
        res.fold_gliders[k].push_back(D.gliders()[g].key);
        for (int f : D.gliders()[g].flights) test.push_back(f);
      } else {
        keys.insert(D.gliders()[g].key);
        for (int f : D.gliders()[g].flights) train.push_back(f);
      }
    }
    const std::string label = fold_label(k);
    const auto model = coefficient_fit(keys, label);
    FitOutcome base_tr = fit_baseline(model, train);
    // The held-out gliders under the baseline's coefficients, their own
    // launches and trims.
    auto baseline_held_out = [&] {
      return held_out_fit({base_tr.model.coefficients, {}, {}}, test, trims_of(D, test, o.trim), nullptr);
    };
    FitOutcome base_ho = baseline_held_out();
    report("fold", label + ": baseline RMSE " + cm(base_tr.rmse()) + " on training gliders, " + cm(base_ho.rmse()) +
                       " on held-out gliders");
    const auto coefficients_before = base_tr.model.coefficients;
    if (o.carry_steps && o.leader_start && o.full_fit && full_leader >= 0 && full_stepped[full_leader]) {
      lead_values = effect_values(eff_full[full_leader].model.effects, o.effects[full_leader]);
      if (std::any_of(lead_values.begin(), lead_values.end(), [](double v) { return v != 0.0; })) {
        // A strength fitted at the edge of its range on all gliders would
        // fail the bound guard where the folds followed it, so the ramp
        // there (four fits per fold) cannot lead to a verdict for it (blind
        // pitch damping at 1, seed 28: ground effect at 3 of its range's 3
        // led all gliders' screen and was ramped there in every fold, for
        // nothing).
        if (values_at_range_edge(o.effects[full_leader], lead_values))
          report("fold", label + ": " + effect_name(o.effects[full_leader]) +
                             "'s fit on all gliders is at the edge of its range: not started there", false);
        else {
          lead_effect = full_leader;
          lead_launches.clear();
          for (const auto& f : eff_full[full_leader].flights) lead_launches[f.flight] = f.launch;
          lead_trim = eff_full[full_leader].model.trim;
        }
      }
    }
    std::vector<double> screen(ne, kNoScreen);
    screen_gains = &screen;
    std::vector<FitOutcome> trs =
        fit_effects_from(base_tr, train, label, nullptr, o.carry_steps && o.full_fit ? &full_stepped : nullptr);
    screen_gains = nullptr;
    for (int e = 0; e < ne; ++e) fold_screen[e].push_back(screen[e]);
    lead_effect = -1;
    if (base_tr.model.coefficients != coefficients_before) {
      // The baseline took a polished candidate's centre values: predict the
      // held-out gliders with them.
      base_ho = baseline_held_out();
      report("fold", label + ": refitted baseline: " + cm(base_ho.rmse()) + " on held-out gliders", false);
    }
    // A candidate whose fit keeps other centre values than the baseline's
    // (those from before the baseline's own linearised step) but which its
    // training gliders do not support (its gain under the chi-square
    // quantile of its degrees of freedom at the test's level) predicts the
    // held-out gliders as the baseline does: otherwise its held-out error
    // measures the two sets of centre values, not the effect (blind finite
    // span at 1, seed 24, fold 3: strength 0.02 with the earlier centre
    // values predicted the canard at 2.9 cm against the baseline's 1.8 cm,
    // and turned the effect's held-out shrink from about +10 % to -0.6 %).
    // The choice uses the training gliders only, as cross-validation of
    // the whole procedure must.
    for (int e = 0; e < ne; ++e) {
      if (trs[e].model.coefficients == base_tr.model.coefficients) continue;
      const double dof = added_dof(o.effects[e], static_cast<double>(train.size()));
      const double gain = (base_tr.sse - trs[e].sse) / s2_noise;
      if (gain > chi2_isf(o.alpha, dof)) continue;
      report("fold", label + ": " + effect_name(o.effects[e]) + " is not supported by the training gliders (delta chi2 " +
                         fmt(gain, 3) + "): the held-out gliders are predicted with the baseline's fit", false);
      trs[e] = base_tr;
    }
    if (k == 0) first_train = base_tr;
    train_sse0 += base_tr.sse;
    train_dof0 += 2 * base_tr.points - base_tr.launch_parameters - base_tr.free_parameters;
    // Held-out gliders: their launches and trims are fitted to their own
    // points under each model (the training gliders' coefficients and
    // strengths); the held-out baseline, too, takes the best launches found.
    const auto ho_trims = trims_of(D, test, o.trim);
    auto ho_fit = [&](const FitOutcome& tr, const FitOutcome& from, const std::string& what = {}) {
      return ho_fit_on(tr, from, test, ho_trims, what);
    };
    std::vector<FitOutcome> hos(ne);
    auto of_ne = [&](int e) { return " (" + std::to_string(e + 1) + "/" + std::to_string(ne) + ")"; };
    // One line per candidate as its held-out gliders are fitted: with
    // re-tuned centre values a held-out glider can need its trim restarted
    // (held_out_fit), which can take minutes. (On the blind finite-span data
    // at strength 2 these lines showed the 9 fits at 15 s of a fold; the
    // oracle and an overshooting profiled step were the slow parts.)
    for (int e = 0; e < ne; ++e) {
      hos[e] = ho_fit(trs[e], base_ho, label + ", " + effect_name(o.effects[e]));
      report("fold", label + ": held-out gliders under " + effect_name(o.effects[e]) + ": " + cm(hos[e].rmse()) + of_ne(e),
             false);
    }
    // A held-out baseline improved from the candidates' launches and trims
    // starts every candidate's held-out fit again, one line each as well (on
    // blind wind at strength 1, seed 24, fold 4: over 500 s without a line).
    if (improve_baseline(base_ho, hos, test)) {
      report("fold", label + ": held-out baseline from the candidates' launches and trims: " + cm(base_ho.rmse()) +
                         "; every candidate's held-out gliders fitted again from it",
             false);
      for (int e = 0; e < ne; ++e) {
        FitOutcome again = ho_fit(trs[e], base_ho, label + ", " + effect_name(o.effects[e]));
        report("fold", label + ": held-out gliders under " + effect_name(o.effects[e]) + " again: " +
                           cm(again.rmse()) + (again.sse < hos[e].sse ? " (kept)" : " (was " + cm(hos[e].rmse()) + ")") +
                           of_ne(e),
               false);
        if (again.sse < hos[e].sse) hos[e] = std::move(again);
      }
    }
    if (!o.oracle.empty()) {
      // The baseline plus the known effects at their given values, reached
      // in steps (a quarter of every value, a half, ...), the launches and
      // trims refitted at each from the step before: at full size an effect
      // can move the flights so far that the baseline's launches and trims
      // start them in a poor basin (seen: downwash at strength 1 straight
      // from the baseline's, 9.3 cm against the baseline's 3.1 cm on
      // training gliders). Then the centre values with them, as the
      // baseline's were fitted; the held-out gliders' launches and trims are
      // carried through the same steps under those centre values.
      auto scaled = [&](DiagModel m, double f) {
        for (const auto& [E, v] : o.oracle) {
          const auto& sp = effect_spec(E);
          for (std::size_t i = 0; i < v.size(); ++i)
            m.effects.at(E, static_cast<int>(i)) = f * v[i] / sp.parameters[i].to_report;
          if (per_flight(E)) m.effects.launch_rotation_per_flight = true;  // the value starts every flight's rate
        }
        return m;
      };
      const auto trims = trims_of(D, train, o.trim);
      FitOutcome otr = base_tr;
      for (int k = 1; k <= kRampSteps; ++k) {
        const DiagModel m = scaled(otr.model, static_cast<double>(k) / kRampSteps);
        auto w = launches_of(otr);
        if (m.effects.launch_rotation_per_flight && !otr.model.effects.launch_rotation_per_flight)
          w = with_rate(w, m.effects.launch_rotation);
        otr = settled(m, train, trims, &w);
        // The oracle's fits can take many minutes on data far from the
        // model (blind downwash, seed 24: about 14 min a fold, silent before).
        report("fold", label + ", the oracle: training gliders at " + std::to_string(k) + "/" + std::to_string(kRampSteps) +
                           " of the known effects: RMSE " + cm(otr.rmse()) +
                           (k == kRampSteps && centre_count(otr.model.coefficients) > 0 ? "; refitting the centre values"
                                                                                    : ""),
               false);
      }
      if (centre_count(otr.model.coefficients) > 0) {
        FitOutcome p = refit_centres(otr, train, trims);
        const bool better = p.sse < otr.sse;
        report("fold", label + ", the oracle: centre values refitted: RMSE " + cm(p.rmse()) + " on training gliders" +
                           std::string(better ? " (kept)" : " (not kept)") + "; its held-out gliders follow",
               false);
        if (better) otr = std::move(p);
      }
      mean_rate(otr);
      FitOutcome oho = base_ho;
      for (int k = 1; k <= kRampSteps; ++k) {
        FitOutcome at = otr;
        at.model = scaled(otr.model, static_cast<double>(k) / kRampSteps);
        oho = ho_fit_on(at, oho, test, ho_trims, label + ", the oracle");
      }
      oracle_sse_ho += oho.sse;
      oracle_fold_rmse.push_back(oho.rmse());
      oracle_fold_base_rmse.push_back(base_ho.rmse());
      // What the known effects at their known sizes explain on the training
      // gliders beyond the fold's final baseline: the evidence a diagnosis
      // that fitted them exactly would have (where it is under the
      // likelihood-ratio threshold, no search can name the effect on these
      // flights, whatever the held-out oracle closes).
      oracle_fold_train_dchi2.push_back((base_tr.sse - otr.sse) / s2_noise);
      report("fold", label + ": oracle (the baseline plus the known effects, centre values refitted): RMSE " +
                         cm(otr.rmse()) + " on training gliders, " + cm(oho.rmse()) + " on held-out gliders (baseline " +
                         cm(base_ho.rmse()) + ")", false);
    }
    if (const char* dir = std::getenv("PTEROMYS_DIAG_DUMP"); dir && *dir) {
      // Development aid: every fold's fits (models, strengths, held-out
      // errors per flight and the states they reach) as JSON.
      auto outcome = [&](const FitOutcome& f) {
        json j;
        j["sse_m2"] = f.sse;
        j["effects"] = json::object();
        for (Effect E : all_effects()) j["effects"][effect_name(E)] = effect_values(f.model.effects, E);
        j["trim"] = f.model.trim;
        json fl = json::array();
        for (const auto& x : f.flights) {
          double amin = 1e9, amax = -1e9, qmax = 0;
          for (const auto& s : x.states) {
            amin = std::min(amin, s.alpha);
            amax = std::max(amax, s.alpha);
            qmax = std::max(qmax, std::abs(s.omega));
          }
          fl.push_back({{"flight", d.flights[x.flight].name}, {"sse_m2", x.sse}, {"points", x.residual.size()},
                        {"alpha_min", amin}, {"alpha_max", amax}, {"omega_max", qmax},
                        {"left_range", x.left_model_range}});
        }
        j["flights"] = fl;
        return j;
      };
      json j;
      j["train_gliders"] = json(keys);
      j["test_gliders"] = res.fold_gliders[k];
      j["baseline_train"] = outcome(base_tr);
      j["baseline_train"]["model"] = model_to_json(*base_tr.model.coefficients);
      j["baseline_heldout"] = outcome(base_ho);
      for (int e = 0; e < ne; ++e) {
        j["candidates"][effect_name(o.effects[e])]["train"] = outcome(trs[e]);
        j["candidates"][effect_name(o.effects[e])]["train"]["model"] = model_to_json(*trs[e].model.coefficients);
        j["candidates"][effect_name(o.effects[e])]["heldout"] = outcome(hos[e]);
      }
      const std::string path = std::string(dir) + "/fold" + std::to_string(k) + ".json";
      std::ofstream out(path);
      out << j.dump(1);
      if (!out) report("fold", "PTEROMYS_DIAG_DUMP: could not write " + path + " (does the directory exist?)", false);
    }
    fold_train[k] = train;
    fold_test[k] = test;
    fold_trs[k] = trs;
    fold_hos[k] = hos;
    for (std::size_t i = 0; i < test.size(); ++i) {
      auto& h = res.heldout[test[i]];
      h.flight = test[i];
      h.fold = k;
      h.baseline = base_ho.flights[i];
      h.effects.resize(ne);
    }
    for (int e = 0; e < ne; ++e) {
      const Effect E = o.effects[e];
      const FitOutcome& tr = trs[e];
      const FitOutcome& ho = hos[e];
      fold_params[e].push_back(effect_values(tr.model.effects, E));
      fold_held[e].push_back(tr.strength_held);
      train_dsse[e] += base_tr.sse - tr.sse;
      for (std::size_t i = 0; i < test.size(); ++i) res.heldout[test[i]].effects[e] = ho.flights[i];
      report("effect", label + ": " + effect_name(E) + " (" + describe_parameters(E, fold_params[e].back()) +
                           (tr.free_parameters > 20 || (tr.model.coefficients != base_tr.model.coefficients &&
                                                       tr.model.coefficients != coefficients_before)
                                ? ", polished"
                                : "") +
                           "): held-out RMSE " + cm(ho.rmse()) + " (baseline " + cm(base_ho.rmse()) + ")", false);
    }
  }
  timings["folds_s"] = since(tfolds);
  {
    std::vector<HeldOutFlight> kept;
    for (auto& h : res.heldout)
      if (h.flight >= 0) kept.push_back(std::move(h));
    res.heldout = std::move(kept);
  }

  // ------------------------------------------------------------ statistics
  const double s2 = sigma * sigma;
  double sse0_ho = 0;
  int n_ho = 0, f_ho = 0;
  std::vector<double> sse_ho(ne, 0.0);
  std::map<int, double> g0;
  std::map<int, int> gn;
  std::vector<std::map<int, double>> ge(ne);
  std::vector<std::vector<double>> fold_gain(ne, std::vector<double>(K, 0.0));  // held-out gain per fold
  for (const auto& h : res.heldout) {
    sse0_ho += h.baseline.sse;
    n_ho += static_cast<int>(h.baseline.residual.size());
    ++f_ho;
    const int g = D.glider_of(h.flight);
    g0[g] += h.baseline.sse;
    gn[g] += static_cast<int>(h.baseline.residual.size());
    for (int e = 0; e < ne; ++e) {
      sse_ho[e] += h.effects[e].sse;
      ge[e][g] += h.effects[e].sse;
      fold_gain[e][h.fold] += h.baseline.sse - h.effects[e].sse;
    }
  }
  int trims_total = 0;
  for (int g : flown)
    if (o.trim && D.gliders()[g].features.trim_wing >= 0) ++trims_total;
  const double dof_ho = std::max(1, 2 * n_ho - 5 * f_ho - trims_total);
  res.holdout_rmse_m = std::sqrt(sse0_ho / n_ho);
  res.holdout_chi2_ratio = sse0_ho / (s2 * dof_ho);
  res.noise_rmse_m = std::sqrt(s2 * dof_ho / n_ho);
  if (!o.oracle.empty()) {
    // The oracle predicted the same held-out flights: n_ho points.
    OracleResult orc;
    orc.effects = o.oracle;
    orc.holdout_rmse_m = std::sqrt(oracle_sse_ho / n_ho);
    orc.shrink = 1 - orc.holdout_rmse_m / res.holdout_rmse_m;
    orc.holdout_chi2_ratio = oracle_sse_ho / (s2 * dof_ho);
    orc.fold_holdout_rmse_m = oracle_fold_rmse;
    orc.fold_baseline_holdout_rmse_m = oracle_fold_base_rmse;
    orc.fold_train_delta_chi2 = oracle_fold_train_dchi2;
    orc.train_delta_chi2 = std::accumulate(oracle_fold_train_dchi2.begin(), oracle_fold_train_dchi2.end(), 0.0) /
                           std::max(1, K - 1);  // each glider trains in K - 1 folds
    res.oracle = orc;
  }
  double sse0_fit = 0, dof_fit = 1;
  if (o.full_fit) {
    sse0_fit = base_full.sse;
    dof_fit = std::max(1, 2 * base_full.points - base_full.launch_parameters - base_full.free_parameters -
                              (o.polish > 0 ? 0 : 3 * full_centres));
    res.fit_rmse_m = base_full.rmse();
  } else {
    sse0_fit = train_sse0 / std::max(1, K - 1);
    dof_fit = std::max(1.0, train_dof0 / std::max(1.0, K - 1.0));
    res.fit_rmse_m = std::sqrt(train_sse0 / std::max(1, K - 1) / res.points);
  }
  res.fit_chi2_ratio = sse0_fit / (s2 * dof_fit);

  // Degrees of freedom a candidate adds: its parameters, or (launch rotation
  // per flight) one rate per flight of the fit and of the held-out set.
  const double train_flights = o.full_fit ? static_cast<double>(all_flights.size())
                                          : static_cast<double>(all_flights.size()) * (K - 1) / K;
  auto dof_fit_of = [&](Effect E) { return added_dof(E, train_flights); };
  auto dof_ho_of = [&](Effect E) { return added_dof(E, static_cast<double>(f_ho)); };
  // An effect's likelihood ratio against the baseline: its fit's gain `dsse`
  // over the residual variance of its fit `sse_e` (at least the noise's).
  auto set_likelihood_ratio = [&](EffectResult& r, Effect E, double dsse, double sse_e) {
    const double s2_eff = std::max(s2, sse_e / std::max(1.0, dof_fit - dof_fit_of(E)));
    r.delta_chi2 = std::max(0.0, dsse) / s2_eff;
    r.p_value = chi2_sf(r.delta_chi2, dof_fit_of(E));
  };
  res.effects.resize(ne);
  // Each effect's plausible sizes (internal units): the library's, or the
  // caller's (DiagnoseOptions::plausible).
  std::vector<std::vector<double>> limits(ne);
  std::vector<bool> own_limits(ne, false);
  for (int e = 0; e < ne; ++e) {
    bool own = false;
    limits[e] = plausible_limits(o.effects[e], o, &own);
    own_limits[e] = own;
  }
  // Every effect's held-out sums of squared residuals per glider (in g0's
  // order), for the glider guard and the identifiability preference.
  std::vector<std::vector<double>> glider_sse(ne);
  for (int e = 0; e < ne; ++e) {
    const Effect E = o.effects[e];
    EffectResult& r = res.effects[e];
    r.effect = E;
    r.name = effect_name(E);
    const int pe = static_cast<int>(effect_spec(E).parameters.size());
    const double pe_ho = dof_ho_of(E);
    r.holdout_rmse_m = std::sqrt(sse_ho[e] / n_ho);
    r.shrink = 1 - r.holdout_rmse_m / res.holdout_rmse_m;
    r.fold_parameters = fold_params[e];
    r.fold_strength_held = fold_held[e];
    r.linearised_delta_chi2 = full_screen[e];
    r.fold_linearised_delta_chi2 = fold_screen[e];
    double dsse = 0, sse_e = 0;
    if (o.full_fit) {
      r.fit_rmse_m = eff_full[e].rmse();
      r.parameters = effect_values(eff_full[e].model.effects, E);
      r.strength_held = eff_full[e].strength_held;
      dsse = base_full.sse - eff_full[e].sse;
      sse_e = eff_full[e].sse;
    } else {
      dsse = train_dsse[e] / std::max(1, K - 1);
      sse_e = sse0_fit - dsse;
      r.fit_rmse_m = std::sqrt(std::max(0.0, sse_e) / res.points);
      r.parameters = fold_mean(fold_params[e], pe);
    }
    set_likelihood_ratio(r, E, dsse, sse_e);
    // Held-out confirmation.
    const double s2_ho = std::max(s2, sse_ho[e] / std::max(1.0, dof_ho - (pe_ho - pe)));
    r.holdout_delta_chi2 = (sse0_ho - sse_ho[e]) / s2_ho;
    r.holdout_threshold = chi2_isf(o.alpha / ne, pe_ho);
    std::vector<double> dg, b_sse, e_sse;
    std::vector<int> keys;
    for (const auto& [g, s0] : g0) {
      b_sse.push_back(s0);
      e_sse.push_back(ge[e][g]);
      keys.push_back(g);
      dg.push_back((s0 - ge[e][g]) / s2);
      const double n = std::max(1, gn[g]);
      r.glider_holdout_rmse_m.push_back({D.gliders()[g].key, std::sqrt(ge[e][g] / n)});
      r.glider_baseline_holdout_rmse_m.push_back({D.gliders()[g].key, std::sqrt(s0 / n)});
    }
    r.glider_t = mean_and_t(dg).t;
    glider_sse[e] = e_sse;
    const HeldOutGuards hg = held_out_guards(E, b_sse, e_sse, fold_params[e], fold_gain[e], o);
    r.gliders_improved = hg.improved;
    r.gliders_total = hg.total;
    r.robust_shrink = hg.robust_shrink;
    r.robust_without = hg.robust_without >= 0 ? D.gliders()[keys[hg.robust_without]].key : std::string();
    r.robust_pass = hg.robust_pass;
    r.implausible = describe_implausible(E, r.parameters, limits[e]);
    r.plausible = r.implausible.empty();
    r.bound_share = hg.bound_share;
    r.bound_pass = hg.bound_pass;
  }
  // Candidate e refitted from its own linearised step with the centre values
  // on all gliders, from the final all-glider baseline (`label`: the
  // progress lines' prefix, `why`: what the first line adds to the
  // effect's name). The refit replaces the candidate's fit (its strength,
  // fit error and likelihood ratio) when it explains the flights better
  // and plausibly (a strength beyond the plausible sizes would contradict a
  // decision made on the plausible one). Returns whether it did. Used where
  // only profiled starts on all gliders make the step (step_refit_possible).
  const bool step_refit_possible = o.full_fit && o.profile && o.polish <= 0 &&
                                   centre_count(base_full.model.coefficients) > 0 &&
                                   profiled_on(gliders_of(all_flights));
  // `fold_start` (DiagnoseOptions::heldout_fold_start): also started at the
  // mean of its folds' strengths, switched on from the baseline in steps.
  auto step_refit = [&](int e, const std::string& label, const std::string& why, bool fold_start = false) {
    const Effect E = o.effects[e];
    EffectResult& r = res.effects[e];
    report("analysis", label + ": " + effect_name(E) + why + " refitted from its linearised step with the centre values",
           false);
    const CandidateStep step = candidate_step(base_full, all_flights, e);
    if (fold_start && !r.fold_parameters.empty()) {
      const auto mean = fold_mean(r.fold_parameters, static_cast<int>(r.fold_parameters.front().size()));
      const bool nonzero = std::any_of(mean.begin(), mean.end(), [](double v) { return v != 0.0; });
      if (nonzero && !values_at_range_edge(E, mean)) {
        lead_effect = e;
        lead_values = mean;
        lead_from_base = true;
      }
    }
    FitOutcome n = fit_effects(base_full, all_flights, label, false, {e}, {}, false, &step.starts)[e];
    lead_effect = -1;
    lead_from_base = false;
    const auto before = effect_values(eff_full[e].model.effects, E);
    const auto after = effect_values(n.model.effects, E);
    const std::string implausible = describe_implausible(E, after, limits[e]);
    const bool better = n.sse < eff_full[e].sse && implausible.empty();
    report("analysis", label + ": " + effect_name(E) + " " + describe_parameters(E, after) + ", RMSE " + cm(n.rmse()) +
                           (implausible.empty() ? std::string() : " (" + implausible + ")") + "; the candidates' fit: " +
                           describe_parameters(E, before) + ", RMSE " + cm(eff_full[e].rmse()) +
                           (better ? " (the refit kept)" : " (kept)"),
           false);
    if (better) {
      eff_full[e] = std::move(n);
      r.fit_rmse_m = eff_full[e].rmse();
      r.parameters = after;
      r.strength_held = eff_full[e].strength_held;
      set_likelihood_ratio(r, E, base_full.sse - eff_full[e].sse, eff_full[e].sse);
    }
    return better;
  };
  // ------------------------------------------------------------ held-out-led steps
  // (DiagnoseOptions::heldout_steps) A candidate the held-out gliders confirm
  // but that kept the baseline's centre values on all gliders (its gain
  // there was under the screen) is refitted from its linearised step there,
  // as the screen would have done, and its likelihood ratio is taken from
  // that fit when it explains the flights better (and plausibly). The
  // baseline stays as it is; the decisions below are the same rule.
  if (o.heldout_steps && step_refit_possible) {
    const auto ts = Clock::now();
    for (int e = 0; e < ne; ++e)
      if (heldout_step_eligible(res.effects[e], o, full_stepped[e], per_flight(o.effects[e])) &&
          step_refit(e, "all gliders, held-out-led",
                     " (held-out shrink " + fmt(100 * res.effects[e].shrink, 3) + " %)", o.heldout_fold_start))
        full_stepped[e] = true;
    timings["heldout_steps_s"] = since(ts);
  }
  // ------------------------------------------------------------ the training test's reference
  // A candidate fitted at the baseline's values that explains the flights
  // better than the baseline's own fit is a better baseline fit: every
  // likelihood ratio is measured from it (likelihood_reference). The
  // held-out baseline is not changed.
  if (o.full_fit) {
    std::vector<std::vector<double>> params(ne);
    std::vector<double> sse(ne);
    std::vector<bool> pf(ne);
    for (int e = 0; e < ne; ++e) {
      params[e] = res.effects[e].parameters;  // eff_full[e]'s, set above and by step_refit
      sse[e] = eff_full[e].sse;
      pf[e] = per_flight(o.effects[e]);
    }
    // Better by more than the 0.2 chi-square units a converged baseline fit
    // may still gain in a pass: a candidate at 0 whose fit matched the
    // baseline's to 1e-10 m of RMSE was not a better fit (blind finite span
    // at 1, 20 gliders, seed 41: pitch damping, "1.6 cm against 1.6 cm").
    const int ref = likelihood_reference(o.effects, params, sse, pf, base_full.sse, 0.2 * s2_noise);
    // The reference fit: -1 the baseline's own; its squared error and how
    // it was reached (zeroed: DiagnoseOptions::zeroed_reference).
    int ref_effect = ref;
    double ref_sse = ref >= 0 ? eff_full[ref].sse : base_full.sse, ref_rmse = ref >= 0 ? eff_full[ref].rmse() : 0.0;
    bool zeroed = false;
    if (o.zeroed_reference) {
      // Each candidate's fit with its values at 0, the launches refitted:
      // a baseline-model fit (those exactly at 0 are already weighed above).
      const auto tz = Clock::now();
      double best = ref_sse - 0.2 * s2_noise;
      for (int e = 0; e < ne; ++e) {
        if (pf[e] || std::all_of(params[e].begin(), params[e].end(), [](double v) { return v == 0.0; })) continue;
        DiagModel m = eff_full[e].model;
        for (std::size_t i = 0; i < params[e].size(); ++i) m.effects.at(o.effects[e], static_cast<int>(i)) = 0.0;
        const auto w = launches_of(eff_full[e]);
        const FitOutcome z = D.fit(m, all_flights, {}, &w);
        report("analysis", "all gliders: " + effect_name(o.effects[e]) + "'s fit with its values at 0, launches refitted: RMSE " +
                               cm_against(z.rmse(), base_full.rmse()) + " (with them " + cm(eff_full[e].rmse()) + ")",
               false);
        if (z.sse < best) {
          best = ref_sse = z.sse;
          ref_rmse = z.rmse();
          ref_effect = e;
          zeroed = true;
        }
      }
      timings["zeroed_reference_s"] = since(tz);
    }
    if (ref_effect >= 0) {
      res.likelihood_reference = effect_name(o.effects[ref_effect]);
      res.likelihood_reference_rmse_m = ref_rmse;
      res.likelihood_reference_zeroed = zeroed;
      report("analysis", "all gliders: " + res.likelihood_reference +
                             (zeroed ? "'s fit with its values at 0 (the baseline model), launches refitted,"
                                     : " fitted at 0 (the baseline model) with its centre values re-tuned") +
                             " explains the flights better than the baseline's fit (RMSE " +
                             cm_against(ref_rmse, base_full.rmse()) + "): the likelihood ratios are measured from that fit",
             false);
      for (int e = 0; e < ne; ++e)
        set_likelihood_ratio(res.effects[e], o.effects[e], ref_sse - eff_full[e].sse, eff_full[e].sse);
    }
  }
  // The decision rule (decision_rule), the same in both rounds.
  auto decided = [&](Effect e, bool lr_pass, double shrink, double holdout_delta_chi2, double threshold) {
    return decision_rule(o, e, lr_pass, shrink, holdout_delta_chi2, threshold);
  };
  // Holm's step-down over the library.
  {
    std::vector<double> p, level;
    std::vector<bool> pass;
    for (const auto& r : res.effects) p.push_back(r.p_value);
    holm(p, o.alpha, level, pass);
    for (int e = 0; e < ne; ++e) {
      res.effects[e].holm_level = level[e];
      res.effects[e].lr_pass = pass[e];
    }
  }
  // Per-flight launch rotation is a launcher's rotation only when the
  // flights' own rates share a direction.
  for (int e = 0; e < ne; ++e) {
    if (!per_flight(o.effects[e])) continue;
    auto& r = res.effects[e];
    std::vector<double> rates;
    for (const auto& h : res.heldout) rates.push_back(h.effects[e].launch.pitch_rate);
    r.rate_test = true;
    const double n = static_cast<double>(rates.size());
    if (rates.size() < 2) {
      r.rate_mean_pass = false;
      continue;
    }
    const MeanT mt = mean_and_t(rates);
    r.rate_mean = mt.mean;
    r.rate_mean_t = mt.t;
    const boost::math::students_t dist(n - 1);
    r.rate_mean_p = std::min(1.0, 2 * boost::math::cdf(boost::math::complement(dist, std::min(std::abs(r.rate_mean_t), kBigT))));
    r.rate_mean_pass = r.rate_mean_p < o.alpha / ne;
  }
  for (auto& r : res.effects)
    r.significant =
        decided(r.effect, r.lr_pass, r.shrink, r.holdout_delta_chi2, r.holdout_threshold) && r.rate_mean_pass &&
        r.robust_pass &&
        r.plausible && r.bound_pass;

  // ------------------------------------------------------------ identifiability
  report("analysis", "identifiability: effects against re-tuned coefficients and trims");
  {
    const auto ti = Clock::now();
    // Without a fit to all gliders, the first fold's training fit stands in.
    const FitOutcome& at = o.full_fit ? base_full : first_train;
    std::vector<int> at_flights;
    for (const auto& f : at.flights) at_flights.push_back(f.flight);
    std::vector<FreeParam> free = trims_of(D, at_flights, o.trim);
    const int nt = static_cast<int>(free.size());
    const auto centres = centre_values(at.model.coefficients);
    const int nc = static_cast<int>(centres.size());
    free.insert(free.end(), centres.begin(), centres.end());
    std::vector<int> col0(ne);
    for (int e = 0; e < ne; ++e) {
      col0[e] = static_cast<int>(free.size());
      const auto p = params_of(o.effects[e]);
      free.insert(free.end(), p.begin(), p.end());
    }
    const Eigen::MatrixXd J = D.projected_jacobian(at, free);
    auto residualise = [](const Eigen::MatrixXd& B, const Eigen::MatrixXd& X) -> Eigen::MatrixXd {
      if (B.cols() == 0) return X;
      return X - B * B.colPivHouseholderQr().solve(X);
    };
    const Eigen::MatrixXd T = J.leftCols(nt);
    const Eigen::MatrixXd U = residualise(T, J.middleCols(nt, nc));
    std::vector<Eigen::MatrixXd> Ej(ne);
    for (int e = 0; e < ne; ++e) {
      const int pe = static_cast<int>(effect_spec(o.effects[e]).parameters.size());
      Ej[e] = residualise(T, J.middleCols(col0[e], pe));
      double worst = 0;
      for (int c = 0; c < pe; ++c) {
        const Eigen::VectorXd x = Ej[e].col(c);
        const double n2 = x.squaredNorm();
        if (!(n2 > 0)) {
          worst = 1;
          continue;
        }
        const Eigen::VectorXd left = nc > 0 ? Eigen::VectorXd(x - U * U.colPivHouseholderQr().solve(x)) : x;
        worst = std::max(worst, 1 - left.squaredNorm() / n2);
      }
      res.effects[e].coefficient_collinearity = std::clamp(worst, 0.0, 1.0);
      res.effects[e].indistinguishable = worst > o.collinearity_limit;
    }
    for (int a = 0; a < ne; ++a)
      for (int b = 0; b < ne; ++b) {
        if (a == b) continue;
        double best = 0;
        for (int i = 0; i < Ej[a].cols(); ++i)
          for (int j = 0; j < Ej[b].cols(); ++j) {
            const double na = Ej[a].col(i).norm(), nb = Ej[b].col(j).norm();
            if (na > 0 && nb > 0) best = std::max(best, std::abs(Ej[a].col(i).dot(Ej[b].col(j))) / (na * nb));
          }
        if (best > 0.8) res.effects[a].confusable.push_back({effect_name(o.effects[b]), best});
      }
    timings["identifiability_s"] = since(ti);
  }

  // ------------------------------------------------------------ verdict
  std::vector<int> order(ne);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    const auto &ra = res.effects[a], &rb = res.effects[b];
    if (ra.significant != rb.significant) return ra.significant;
    return ra.shrink > rb.shrink;
  });
  int best = order[0];
  // The identifiability preference: a significant effect the coefficients
  // cannot imitate is named before one they can, unless the latter predicts
  // the held-out gliders significantly better (paired over gliders, the
  // cross-validation's independent units).
  int passed_over = -1;
  if (o.prefer_identifiable) {
    const IdentifiablePreference ip = prefer_identifiable(res.effects, best, glider_sse, o.alpha);
    if (ip.passed_over >= 0) {
      passed_over = ip.passed_over;
      res.passed_over = res.effects[passed_over].name;
      res.passed_over_t = ip.t;
      res.passed_over_t_critical = ip.t_critical;
      best = ip.verdict;
      report("analysis", res.passed_over + " is indistinguishable from re-tuned coefficients and predicts the held-out "
                         "gliders not significantly better than " + res.effects[best].name + " (paired t " +
                         fmt(ip.t, 2) + " < " + fmt(ip.t_critical, 2) + "): the verdict names " +
                         res.effects[best].name, false);
    }
  }
  if (res.effects[best].significant) res.verdict = res.effects[best].name;
  else res.verdict = res.holdout_chi2_ratio <= 1 + o.none_tolerance ? "none" : "unexplained";

  // ------------------------------------------------------------ the verdict's strength
  // The reported strength is the fit to all gliders. There only the
  // candidates with the largest linearised gains (at most
  // DiagnoseOptions::profiled_candidates) are refitted
  // from their step with the centre values; the others keep the baseline's
  // coefficients, which absorb most of an effect they resemble (blind
  // finite span at 1, seed 24: strength 0.07 on all gliders, where the two
  // folds that refitted it from its step found 1.38 and 1.56). So the
  // verdict's effect, when it was not among them, is refitted from its own
  // linearised step at the final all-glider baseline, and the better of the
  // two fits is kept (for its strength, fit error and likelihood ratio, and
  // as the start of the second round). The decisions stand: they were made
  // before, on the fits every candidate had.
  if (step_refit_possible && res.effects[best].significant && !full_stepped[best] && !per_flight(o.effects[best])) {
    const auto ts = Clock::now();
    step_refit(best, "all gliders, the verdict's strength", "");
    timings["verdict_strength_s"] = since(ts);
  }

  // ------------------------------------------------------------ a second effect
  // Given the verdict's effect, does another candidate still explain what is
  // left? Every other candidate is refitted with the verdict's effect
  // (strengths of both free, coefficients as in the verdict's fit) and tested
  // against the verdict's fit alone by the same three tests (Holm over the
  // rest). Effects that only absorb the same misfit drop out here; a second
  // real effect stays.
  std::string given_of;  // the effect the second round added the others to
  if (o.second_effect && res.effects[best].significant && ne > 1) {
    const auto t2 = Clock::now();
    const Effect B = o.effects[best];
    given_of = effect_name(B);
    report("analysis", "second round: every other candidate added to " + effect_name(B), false);
    const auto extra = shared_params_of(B);
    std::vector<int> rest;
    for (int e = 0; e < ne; ++e)
      if (e != best) rest.push_back(e);
    std::vector<FitOutcome> full2;
    if (o.full_fit) {
      full2 = fit_effects(eff_full[best], all_flights, "all gliders, with " + effect_name(B), false, rest, extra, true);
      for (int e : rest)
        if (full2[e].sse > eff_full[best].sse) full2[e] = eff_full[best];
    }
    std::vector<double> sse2_ho(ne, 0.0), dsse2_train(ne, 0.0);
    double sseB_ho = 0, sseB_train = 0;
    // For the guards (held_out_guards): per candidate, the held-out sums per
    // glider of the model it is tested against (B's fit; B re-tuned alone
    // when the folds' re-check is kept) and its own, and each fold's fitted
    // parameters and held-out gain.
    auto add_glider_sums = [&](std::map<int, double>& m, const FitOutcome& f) {
      for (const auto& fl : f.flights) m[D.glider_of(fl.flight)] += fl.sse;
    };
    std::vector<std::map<int, double>> gsum_against(ne), gsum2(ne);
    std::vector<std::vector<std::vector<double>>> fold_params2(ne, std::vector<std::vector<double>>(K));
    std::vector<std::vector<double>> fold_gain2(ne, std::vector<double>(K, 0.0));
    for (int k = 0; k < K; ++k) {
      const std::string label = fold_label(k) + ", with " + effect_name(B);
      const FitOutcome& bt = fold_trs[k][best];
      std::vector<FitOutcome> tr2 = fit_effects(bt, fold_train[k], label, false, rest, extra, true);
      const FitOutcome& bh = fold_hos[k][best];
      sseB_ho += bh.sse;
      sseB_train += bt.sse;
      const auto ho_trims = trims_of(D, fold_test[k], o.trim);
      for (int e : rest) {
        if (tr2[e].sse > bt.sse) tr2[e] = bt;
        dsse2_train[e] += bt.sse - tr2[e].sse;
        const FitOutcome ho = ho_fit_on(tr2[e], bh, fold_test[k], ho_trims, label + ", " + effect_name(o.effects[e]));
        sse2_ho[e] += ho.sse;
        add_glider_sums(gsum_against[e], bh);
        add_glider_sums(gsum2[e], ho);
        fold_params2[e][k] = effect_values(tr2[e].model.effects, o.effects[e]);
        fold_gain2[e][k] = bh.sse - ho.sse;
      }
    }
    const EffectResult& rb = res.effects[best];
    const double sseB_fit = o.full_fit ? eff_full[best].sse : sseB_train / std::max(1, K - 1);
    for (int e : rest) {
      EffectResult& r = res.effects[e];
      EffectResult::Given& g = r.given_verdict;
      const Effect E = o.effects[e];
      g.tested = true;
      const double dsse = o.full_fit ? eff_full[best].sse - full2[e].sse : dsse2_train[e] / std::max(1, K - 1);
      const double sse_e = sseB_fit - dsse;
      const double s2_eff =
          std::max(s2, sse_e / std::max(1.0, dof_fit - dof_fit_of(B) - dof_fit_of(E)));
      g.delta_chi2 = std::max(0.0, dsse) / s2_eff;
      g.p_value = chi2_sf(g.delta_chi2, dof_fit_of(E));
      if (o.full_fit) g.parameters = effect_values(full2[e].model.effects, E);
      g.plausible = implausible_parameter(E, g.parameters, &limits[e]) < 0;
      g.holdout_rmse_m = std::sqrt(sse2_ho[e] / n_ho);
      g.shrink = 1 - g.holdout_rmse_m / rb.holdout_rmse_m;
      const double s2_ho = std::max(s2, sse2_ho[e] / std::max(1.0, dof_ho - dof_ho_of(B) - dof_ho_of(E)));
      g.holdout_delta_chi2 = (sseB_ho - sse2_ho[e]) / s2_ho;
      g.holdout_threshold = chi2_isf(o.alpha / static_cast<double>(rest.size()), dof_ho_of(E));
    }
    // The second round's fits keep the verdict's coefficients, which can have
    // absorbed the second effect (blind pitch damping + wind, seed 42: pitch
    // damping given the wind predicted the held-out gliders 9.6 % better,
    // held-out delta chi2 512 against 10.4, but on all gliders it fitted at
    // strength 0.02, p 0.11; flights of the model with pitch damping and a
    // 1 m/s headwind, three gliders: the wind given pitch damping passed the
    // likelihood-ratio test, delta chi2 46, but fitted -0.04 to -0.10 m/s in
    // the folds and predicted the held-out gliders 0.4 % better). A
    // candidate that passes one of the two tests but not the other is
    // re-checked where it failed, as profiled starts do it in the first
    // round: one linearised step on the trims, the centre values, the
    // verdict's strengths and its own, a joint refit with the centre values,
    // and the verdict's fit given the same chance (its own step, and the
    // candidate's re-tuned centre values at the candidate's strength 0), so
    // that only what the centre values cannot do is credited to the
    // candidate. `retuned_pair` gives the two fits: the candidate's, and the
    // verdict's alone (`moved` false when it is `before` itself).
    struct Retuned {
      FitOutcome cand, alone;
      bool moved = false;
    };
    auto retuned_pair = [&](const FitOutcome& before, const std::vector<int>& flights, int e, const std::string& label) {
      const Effect E = o.effects[e];
      const CandidateStep step = candidate_step(before, flights, e, extra);
      std::vector<FreeParam> b_free = extra;
      b_free.insert(b_free.end(), step.space.trims.begin(), step.space.trims.end());
      Retuned r{before, before, false};
      if (auto n = own_step(before, step.space, step.J, flights, b_free, "")) {
        r.alone = std::move(*n);
        r.moved = true;
      }
      r.cand = fit_effects(before, flights, label + ", re-checked", false, {e}, extra, true, &step.starts)[e];
      if (r.cand.model.coefficients != before.model.coefficients) {
        DiagModel m = r.cand.model;
        for (std::size_t i = 0; i < params_of(E).size(); ++i) m.effects.at(E, static_cast<int>(i)) = 0.0;
        const auto wc = launches_of(r.cand);
        FitOutcome n = settled(m, flights, b_free, &wc);
        if (n.sse < r.alone.sse) {
          r.alone = std::move(n);
          r.moved = true;
        }
      }
      if (r.cand.sse > r.alone.sse) r.cand = r.alone;  // the candidate adds nothing
      return r;
    };
    const bool retunable =
        o.profile && o.polish <= 0 &&
        centre_count((o.full_fit ? eff_full[best] : fold_trs[0][best]).model.coefficients) > 0;
    auto lr_passes = [&](const EffectResult::Given& g) { return g.p_value <= o.alpha / static_cast<double>(rest.size()); };
    auto holdout_passes = [&](Effect E, const EffectResult::Given& g) {
      return decided(E, true, g.shrink, g.holdout_delta_chi2, g.holdout_threshold);
    };
    bool folds_profiled = true;
    for (int k = 0; k < K; ++k) folds_profiled = folds_profiled && profiled_on(gliders_of(fold_train[k]));
    // Passed the likelihood-ratio test, not the held-out one: each fold re-checked.
    if (retunable && folds_profiled)
      for (int e : rest) {
        EffectResult::Given& g = res.effects[e].given_verdict;
        const Effect E = o.effects[e];
        if (per_flight(E) || !lr_passes(g) || holdout_passes(E, g)) continue;
        double cand_ho = 0, alone_ho = 0;
        std::map<int, double> gs_alone, gs_cand;
        std::vector<std::vector<double>> fp(K);
        std::vector<double> gain(K, 0.0);
        for (int k = 0; k < K; ++k) {
          const std::string label = fold_label(k) + ", with " + effect_name(B);
          const Retuned r = retuned_pair(fold_trs[k][best], fold_train[k], e, label);
          const FitOutcome& bh = fold_hos[k][best];
          const auto ho_trims = trims_of(D, fold_test[k], o.trim);
          const FitOutcome a = r.moved ? ho_fit_on(r.alone, bh, fold_test[k], ho_trims, label + ", re-tuned alone") : bh;
          const bool adds = r.cand.sse < r.alone.sse;
          const FitOutcome c =
              adds ? ho_fit_on(r.cand, bh, fold_test[k], ho_trims, label + ", " + effect_name(E) + " re-checked") : a;
          cand_ho += c.sse;
          alone_ho += a.sse;
          add_glider_sums(gs_alone, a);
          add_glider_sums(gs_cand, c);
          fp[k] = adds ? effect_values(r.cand.model.effects, E) : std::vector<double>(effect_spec(E).parameters.size(), 0.0);
          gain[k] = a.sse - c.sse;
        }
        const double s2_ho_r = std::max(s2, cand_ho / std::max(1.0, dof_ho - dof_ho_of(B) - dof_ho_of(E)));
        const double d = (alone_ho - cand_ho) / s2_ho_r;
        const double shrink = alone_ho > 0 ? 1 - std::sqrt(cand_ho / alone_ho) : 0.0;
        report("analysis", "folds, with " + effect_name(B) + ": " + effect_name(E) +
                               " re-checked with the centre values re-tuned: held-out delta chi2 " + fmt(d, 3) +
                               ", shrink " + fmt(100 * shrink, 3) + " % against " + effect_name(B) +
                               " re-tuned alone (with the coefficients fixed: " + fmt(g.holdout_delta_chi2, 3) + ", " +
                               fmt(100 * g.shrink, 3) + " %)",
               false);
        g.rechecked = true;
        if (d > g.holdout_delta_chi2) {
          g.holdout_delta_chi2 = d;
          g.holdout_rmse_m = std::sqrt(cand_ho / n_ho);
          g.shrink = shrink;
          g.retuned = true;
          sse2_ho[e] = cand_ho;  // the reverse test's joint prediction
          gsum_against[e] = std::move(gs_alone);
          gsum2[e] = std::move(gs_cand);
          fold_params2[e] = std::move(fp);
          fold_gain2[e] = std::move(gain);
        }
      }
    // Passed the held-out test, not the likelihood-ratio one, or passed it
    // only once re-checked in the folds: re-checked on all gliders (the
    // strengths given the verdict are the all-glider fit's).
    if (o.full_fit && retunable && profiled_on(static_cast<int>(D.gliders().size())))
      for (int e : rest) {
        EffectResult::Given& g = res.effects[e].given_verdict;
        const Effect E = o.effects[e];
        if (per_flight(E) || !holdout_passes(E, g) || (lr_passes(g) && !g.retuned)) continue;
        const std::string label = "all gliders, with " + effect_name(B);
        const Retuned r = retuned_pair(eff_full[best], all_flights, e, label);
        const double dsse = r.alone.sse - r.cand.sse;
        const double s2_eff = std::max(s2, r.cand.sse / std::max(1.0, dof_fit - dof_fit_of(B) - dof_fit_of(E)));
        const double d2 = std::max(0.0, dsse) / s2_eff;
        report("analysis", label + ": " + effect_name(E) + " re-checked with the centre values re-tuned (" +
                               describe_parameters(E, effect_values(r.cand.model.effects, E)) + "): delta chi2 " +
                               fmt(d2, 3) + " against " + effect_name(B) + " re-tuned alone (RMSE " + cm(r.cand.rmse()) +
                               " against " + cm(r.alone.rmse()) + "; with the coefficients fixed: delta chi2 " +
                               fmt(g.delta_chi2, 3) + ")",
               false);
        g.rechecked = true;
        if (d2 > g.delta_chi2 || g.retuned) {  // the folds' re-check: the fit that goes with it
          g.delta_chi2 = std::max(d2, g.delta_chi2);  // its p-value: below, at two looks
          g.parameters = effect_values(r.cand.model.effects, E);
          g.plausible = implausible_parameter(E, g.parameters, &limits[e]) < 0;
          g.retuned = true;
          full2[e] = r.cand;  // the reverse test's joint fit
        }
      }
    // A re-checked candidate had two looks at the data, and the better of
    // the two is kept: each of its two tests is made at half the level
    // (Bonferroni over the looks), so that the chance of a candidate with
    // no effect passing stays within the level a single look has.
    for (int e : rest) {
      EffectResult::Given& g = res.effects[e].given_verdict;
      if (!g.rechecked) continue;
      const Effect E = o.effects[e];
      g.p_value = std::min(1.0, 2 * chi2_sf(g.delta_chi2, dof_fit_of(E)));
      g.holdout_threshold = chi2_isf(o.alpha / (2.0 * static_cast<double>(rest.size())), dof_ho_of(E));
    }
    {
      std::vector<double> p, level;
      std::vector<bool> pass;
      for (int e : rest) p.push_back(res.effects[e].given_verdict.p_value);
      holm(p, o.alpha, level, pass);
      for (std::size_t i = 0; i < rest.size(); ++i) {
        res.effects[rest[i]].given_verdict.holm_level = level[i];
        res.effects[rest[i]].given_verdict.lr_pass = pass[i];
      }
    }
    // The first round's guards, on the held-out figures kept: a second
    // effect must not rest on one glider either, nor on folds whose fit ran
    // to the edge of its range.
    for (int e : rest) {
      auto& g = res.effects[e].given_verdict;
      std::vector<double> against, with;
      std::vector<int> keys;
      for (const auto& [gl, s0] : gsum_against[e]) {
        keys.push_back(gl);
        against.push_back(s0);
        const auto it = gsum2[e].find(gl);
        with.push_back(it == gsum2[e].end() ? s0 : it->second);
      }
      const HeldOutGuards hg = held_out_guards(o.effects[e], against, with, fold_params2[e], fold_gain2[e], o);
      g.gliders_improved = hg.improved;
      g.gliders_total = hg.total;
      g.robust_shrink = hg.robust_shrink;
      g.robust_without = hg.robust_without >= 0 ? D.gliders()[keys[hg.robust_without]].key : std::string();
      g.robust_pass = hg.robust_pass;
      g.fold_parameters = fold_params2[e];
      g.bound_share = hg.bound_share;
      g.bound_pass = hg.bound_pass;
    }
    for (int e : rest) {
      auto& g = res.effects[e].given_verdict;
      g.significant = decided(o.effects[e], g.lr_pass, g.shrink, g.holdout_delta_chi2, g.holdout_threshold) &&
                      res.effects[e].rate_mean_pass && g.plausible && g.robust_pass && g.bound_pass;
    }
    // The reverse test for each effect of `also`: is the verdict's effect
    // still needed once that one is in the model (joint fit against that
    // effect's own first-round fit)? The best effect that makes it
    // superfluous, and is significant on its own, becomes the verdict.
    // The same reverse test for an effect that was significant on its own but
    // adds nothing given the verdict's: if the verdict's adds nothing given
    // it either, the two explain the same misfit and the data cannot tell
    // them apart (`alternatives`).
    for (int e : reverse_tests(res.effects, best, nullptr)) {
      EffectResult& r = res.effects[e];
      auto& g = r.given_verdict;
      const Effect E = o.effects[e];
      const double sseE_fit = o.full_fit ? eff_full[e].sse : sse0_fit - train_dsse[e] / std::max(1, K - 1);
      const double dsse = o.full_fit ? eff_full[e].sse - full2[e].sse : dsse2_train[e] / std::max(1, K - 1) +
                                                                            train_dsse[best] / std::max(1, K - 1) -
                                                                            train_dsse[e] / std::max(1, K - 1);
      const double sse_j = sseE_fit - dsse;
      const double s2_eff = std::max(s2, sse_j / std::max(1.0, dof_fit - dof_fit_of(B) - dof_fit_of(E)));
      g.reverse_delta_chi2 = std::max(0.0, dsse) / s2_eff;
      g.reverse_p_value = chi2_sf(g.reverse_delta_chi2, dof_fit_of(B));
      g.reverse_shrink = 1 - g.holdout_rmse_m / r.holdout_rmse_m;
      const double s2_ho = std::max(s2, sse2_ho[e] / std::max(1.0, dof_ho - dof_ho_of(B) - dof_ho_of(E)));
      g.reverse_holdout_delta_chi2 = (sse_ho[e] - sse2_ho[e]) / s2_ho;
      g.reverse_threshold = chi2_isf(o.alpha / static_cast<double>(rest.size()), dof_ho_of(B));
      g.verdict_still_needed = decided(B, g.reverse_p_value <= o.alpha / static_cast<double>(rest.size()),
                                       g.reverse_shrink, g.reverse_holdout_delta_chi2, g.reverse_threshold);
      g.reverse_tested = true;
    }
    const SecondRoundOutcome sr = second_round_outcome(res.effects, best, passed_over);
    if (sr.replaced >= 0) res.replaced = res.effects[sr.replaced].name;
    best = sr.verdict;
    res.verdict = res.effects[best].name;
    for (int e : sr.also) res.also.push_back(res.effects[e].name);
    for (int e : sr.alternatives) res.alternatives.push_back(res.effects[e].name);
    timings["second_round_s"] = since(t2);
  }
  // The launch withhold (DiagnoseOptions::launch_withhold): a session-wide
  // verdict beside a launch rotation that is significant, or that fits the
  // training flights, gives way to it or to `unexplained`. What the second
  // round said was said of it, so goes with it.
  if (const std::string to = o.launch_withhold ? launch_withheld(res.effects, res.verdict, o.alpha, res.fit_rmse_m,
                                                                 o.launch_withhold_dominance)
                                               : "";
      !to.empty()) {
    report("analysis", res.verdict + " is withheld: launch rotation fits the training flights too, with the rates "
                       "turning one way (a launch habit a session-wide correction can imitate); the verdict is " +
                       to, false);
    res.withheld = res.verdict;
    res.verdict = to;
    for (int e = 0; e < ne; ++e)
      if (res.effects[e].name == to) best = e;
    res.also.clear();
    res.alternatives.clear();
    res.replaced.clear();
    res.passed_over.clear();
  } else if (o.launch_withhold && !launch_withheld(res.effects, res.verdict, o.alpha).empty()) {
    const LaunchDominance d = launch_dominance(res.effects, res.verdict, res.fit_rmse_m, o.launch_withhold_dominance);
    report("analysis", res.verdict + " is not withheld: on all gliders it closes " + pct(d.verdict_gain) +
                       " of the baseline's misfit, launch rotation " + pct(d.launch_gain) + " (more than " +
                       fmt(o.launch_withhold_dominance, 3) + " times as much)", false);
  }

  for (std::size_t i = 0; i < res.effects.size(); ++i) {
    res.effects[i].note = effect_note(res.effects[i], o, own_limits[i]);
    if (res.effects[i].name == res.likelihood_reference && res.likelihood_reference_zeroed)
      res.effects[i].note += "; its fit with its values set to 0 and the launches refitted fits the gliders better "
                             "than the baseline's fit (RMSE " + cm_against(res.likelihood_reference_rmse_m, res.fit_rmse_m) +
                             "): a better fit of the baseline model, and the reference of every "
                             "likelihood ratio, this effect's own included";
    else if (res.effects[i].name == res.likelihood_reference)
      res.effects[i].note += "; fitted at 0 on all gliders, with the centre values re-tuned it fits them better than "
                             "the baseline's fit (RMSE " + cm_against(res.likelihood_reference_rmse_m, res.fit_rmse_m) +
                             "): a better fit of the baseline model, not the effect, and the "
                             "reference of every likelihood ratio";
    res.effects[i].given_verdict.note = given_note(res.effects[i], given_of, o);
    res.effects[i].given_verdict.stopped_by_guard =
        given_stopped_by(res.effects[i].given_verdict, o, res.effects[i].effect);
  }

  // ------------------------------------------------------------ where
  report("analysis", "where the gap lies");
  {
    const int vi = res.effects[best].significant ? best : -1;
    std::vector<const FlightOutcome*> b, a;
    for (const auto& h : res.heldout) {
      b.push_back(&h.baseline);
      a.push_back(&h.effects[vi >= 0 ? vi : best]);
    }
    res.where = gap_analysis(D, b, a, o, sigma);
    res.where["compared_with"] = res.effects[best].name;
    // Worst flights, before and after.
    std::vector<int> idx(res.heldout.size());
    std::iota(idx.begin(), idx.end(), 0);
    auto per_point = [&](int i) { return res.heldout[i].baseline.sse / std::max<std::size_t>(1, res.heldout[i].baseline.residual.size()); };
    std::sort(idx.begin(), idx.end(), [&](int x, int y) { return per_point(x) > per_point(y); });
    json wf = json::array();
    for (int i = 0; i < std::min<int>(o.worst_flights, idx.size()); ++i) {
      const auto& h = res.heldout[idx[i]];
      const auto& f = d.flights[h.flight];
      const auto& ef = h.effects[vi >= 0 ? vi : best];
      json j = {{"flight", f.name}, {"glider", f.glider}, {"fold", h.fold + 1}};
      json t = json::array(), tr = json::array(), sb = json::array(), se = json::array();
      double s0 = 0, s1 = 0;
      for (std::size_t p = 0; p < f.points.size(); ++p) {
        t.push_back(f.points[p].t);
        tr.push_back({f.points[p].x, f.points[p].y});
        sb.push_back({f.points[p].x + h.baseline.residual[p].x, f.points[p].y + h.baseline.residual[p].y});
        if (ef.residual.size() == f.points.size())
          se.push_back({f.points[p].x + ef.residual[p].x, f.points[p].y + ef.residual[p].y});
        s0 += std::pow(norm(h.baseline.residual[p]), 2);
        if (ef.residual.size() == f.points.size()) s1 += std::pow(norm(ef.residual[p]), 2);
      }
      j["t_s"] = t;
      j["tracked_m"] = tr;
      j["baseline_m"] = sb;
      j["effect_m"] = se;
      j["baseline_rmse_m"] = std::sqrt(s0 / f.points.size());
      j["effect_rmse_m"] = std::sqrt(s1 / f.points.size());
      wf.push_back(j);
    }
    res.report["worst_flights"] = wf;
    res.report["effect"] = res.effects[best].name;
  }

  // ------------------------------------------------------------ summary
  {
    std::ostringstream s;
    // Where: the phase and the geometry feature that carry the excess error.
    std::string phase_words;
    double best_ratio = 0;
    for (const auto& p : res.where["phases"]) {
      const double r = p["chi2_ratio"].get<double>();
      if (r > best_ratio && p["points"].get<long>() >= 10) {
        best_ratio = r;
        const std::string n = p["phase"];
        phase_words = n == "launch" ? "the launch transient" : n == "glide" ? "the glide" : "the approach to the ground";
      }
    }
    std::string feature_words;
    double best_p = 0.05;
    for (const auto& f : res.where["features"]) {
      const double p = f["p_value"], rho = f["spearman_rho"];
      if (p < best_p && std::abs(rho) >= 0.5) {
        best_p = p;
        const std::string n = f["feature"];
        const std::map<std::string, std::string> words = {
            {"main_aspect_ratio", "aspect ratio"}, {"tail_aspect_ratio", "tail aspect ratio"},
            {"tail_arm_m", "tail arms"},          {"tail_volume", "tail volumes"},
            {"wing_loading_n_m2", "wing loadings"}, {"fuselage_ratio", "fuselages (relative to the wing)"}};
        const bool high = rho > 0;
        feature_words = std::string(high ? (n == "tail_arm_m" ? "long " : n == "fuselage_ratio" ? "large " : "high ")
                                         : (n == "tail_arm_m" ? "short " : n == "fuselage_ratio" ? "small " : "low ")) +
                        words.at(n);
      }
    }
    if (res.holdout_chi2_ratio > 1 + o.none_tolerance && !phase_words.empty()) {
      s << "The model misses most during " << phase_words;
      if (!feature_words.empty()) s << " of gliders with " << feature_words;
      s << " (held-out error " << fmt(std::sqrt(best_ratio), 2) << " times what tracking noise alone gives there). ";
    }
    const auto& b = res.effects[best];
    if (res.verdict == b.name) {
      s << "Adding " << b.name << " (" << effect_spec(b.effect).description << ") cuts the held-out error by "
        << pct(b.shrink) << ", from " << cm(res.holdout_rmse_m) << " to " << cm(b.holdout_rmse_m)
        << " (tracking noise alone: " << cm(res.noise_rmse_m) << "); fitted "
        << describe_parameters(b.effect, b.parameters);
      // An aerodynamic strength is a multiple of the correction's theory, a
      // number a person cannot read without that reference (blind pitch
      // damping s37 named added mass at 2.55; right verdicts of pitch
      // damping were fitted at 0.11-0.60, the re-tuned centre values taking
      // the rest).
      if (effect_spec(b.effect).level == EffectLevel::Aerodynamic && !b.parameters.empty())
        s << " (1 would be its theoretical size)";
      s << ".";
      if (b.parameters.size() == effect_spec(b.effect).parameters.size())
        s << range_edge_sentence(b.effect, b.parameters);
      auto named = [&](const std::string& n) -> const EffectResult& {
        return *std::find_if(res.effects.begin(), res.effects.end(), [&](const EffectResult& y) { return y.name == n; });
      };
      for (const auto& a : res.alternatives) {
        if (a == res.passed_over) continue;  // said below
        const auto& x = named(a);
        s << " " << a << " explains the same misfit nearly as well (" << pct(x.shrink)
          << " on its own); with either in the model the other adds nothing, so these data cannot tell "
          << b.name << " and " << a << " apart.";
      }
      if (!res.replaced.empty())
        s << " " << res.replaced << " predicted the held-out gliders better on its own, but adds nothing once "
          << b.name << " is in the model, while " << b.name << " still does with " << res.replaced
          << ": it only imitated " << b.name << ".";
      if (!res.passed_over.empty()) {
        const auto& x = named(res.passed_over);
        auto two = [](double v) {
          std::ostringstream t;
          t << std::fixed << std::setprecision(2) << v;
          return t.str();
        };
        s << " " << x.name << " predicted the held-out gliders better on its own (" << pct(x.shrink)
          << "), but " << pct(x.coefficient_collinearity)
          << " of its signature is a change of the coefficients or trims, and its advantage over " << b.name
          << " is not significant across the held-out gliders (paired t " << two(res.passed_over_t) << ", needed "
          << two(res.passed_over_t_critical) << "): the verdict names " << b.name
          << ", which re-tuned coefficients cannot imitate.";
        if (std::find(res.alternatives.begin(), res.alternatives.end(), x.name) != res.alternatives.end())
          s << " With either in the model the other adds nothing: these data cannot tell them apart by fit alone.";
      }
      int others = 0;
      for (int i = 0; i < ne; ++i) others += order[i] != best && res.effects[order[i]].significant ? 1 : 0;
      if (others > 0) {
        s << " Also significant on their own:";
        for (int i = 0; i < ne; ++i)
          if (order[i] != best && res.effects[order[i]].significant)
            s << " " << res.effects[order[i]].name << " (" << pct(res.effects[order[i]].shrink) << ")";
        s << ".";
      }
      if (!res.also.empty()) {
        s << " With " << b.name << " in the model, ";
        for (std::size_t i = 0; i < res.also.size(); ++i) {
          const auto& x = named(res.also[i]);
          s << (i ? (i + 1 == res.also.size() ? " and " : ", ") : "") << x.name << " ("
            << pct(x.given_verdict.shrink) << " further)";
        }
        // Not "a second effect shown": on the blind benchmark's flights of
        // one effect, most runs with an `also` held only wrong entries
        // (docs/diagnosis.md, "A second effect", keeps the count).
        s << (res.also.size() > 1 ? " also explain" : " also explains") << " what is left: perhaps a second effect, "
          << "perhaps what " << b.name << "'s fit left for another correction to take up (on simulated flights of "
          << "one effect most such entries were wrong); flights that tell them apart would decide.";
      }
      // Candidates that passed the three tests given the verdict's effect
      // but not a guard: said, since "none improves further" would not hold.
      // Not after a replacement (they were tested against the replaced
      // verdict), nor for an alternative (the sentence on alternatives says
      // what holds for it: with either in the model the other adds nothing
      // that survives the guards).
      // Not after the launch withhold either: the second round was made with
      // the withheld verdict.
      int guarded = 0;
      if (res.replaced.empty() && res.withheld.empty())
        for (const auto& x : res.effects)
          if (!x.given_verdict.stopped_by_guard.empty() &&
              std::find(res.alternatives.begin(), res.alternatives.end(), x.name) == res.alternatives.end()) {
            s << " " << x.name << ", " << x.given_verdict.note << ".";
            ++guarded;
          }
      if (res.also.empty() && res.withheld.empty() && guarded == 0 && o.second_effect && others > 0)
        s << " With " << b.name << " in the model none of them improves the prediction further: they explain the "
                                   "same misfit.";
      if (!b.confusable.empty()) {
        s << " " << b.name << "'s signature resembles";
        for (std::size_t i = 0; i < b.confusable.size(); ++i) s << (i ? ", " : " ") << b.confusable[i].first;
        if (res.passed_over.empty()) s << ", which fit" << (b.confusable.size() > 1 ? "" : "s") << " less well here.";
        else s << ".";
      }
      if (b.indistinguishable) s << " Caution: " << b.note.substr(b.note.find("; ") + 2) << ".";
      if (!res.withheld.empty()) s << withheld_sentence(res.effects, res.withheld, o.min_shrink, o.alpha);
    } else if (res.verdict == "none") {
      s << "The baseline model predicts the held-out gliders to within the tracking noise (held-out error "
        << cm(res.holdout_rmse_m) << ", noise alone " << cm(res.noise_rmse_m)
        << "); no candidate effect improves it significantly.";
    } else if (!res.withheld.empty()) {
      s << "A real gap remains (held-out error " << cm(res.holdout_rmse_m) << " against " << cm(res.noise_rmse_m)
        << " from noise alone)." << withheld_sentence(res.effects, res.withheld, o.min_shrink, o.alpha);
    } else {
      s << "A real gap remains (held-out error " << cm(res.holdout_rmse_m) << " against " << cm(res.noise_rmse_m)
        << " from noise alone) that no candidate closes: the best, " << b.name;
      if (b.shrink < o.min_shrink) s << ", cuts it by only " << pct(b.shrink) << ".";
      else s << ", cuts it by " << pct(b.shrink) << " but is not significant: " << b.note << ".";
    }
    // One glider that carries most of the held-out excess and that no
    // candidate predicts better (blind finite-span data: the canard, 4.9 cm
    // held out, 13 times the noise, with every candidate): the gap is the
    // model's carrying over to that geometry, not an effect of all flights.
    if (res.withheld.empty())
      s << launch_caution(res.effects, res.verdict, o.min_shrink, o.alpha)
        << (o.launch_withhold ? launch_dominance_sentence(res.effects, res.verdict, o.alpha, res.fit_rmse_m,
                                                          o.launch_withhold_dominance)
                              : "");
    if (res.verdict != "none") s << dominant_glider_sentence(res.where, res.effects);
    if (res.where["whiteness"]["structured"].get<bool>() && res.verdict != "none")
      s << " The baseline's residuals drift systematically along each flight rather than scattering like noise.";
    res.summary = s.str();
  }
  // The spec's order: best first, i.e. by held-out RMSE (ties: library order).
  // The verdict (a significant effect with the largest shrink) is therefore
  // the first significant entry.
  std::stable_sort(res.effects.begin(), res.effects.end(),
                   [](const EffectResult& a, const EffectResult& b) { return a.holdout_rmse_m < b.holdout_rmse_m; });
  res.seconds = since(t0);
  timings["total_s"] = res.seconds;
  timings["threads"] = D.threads();
  res.timings = timings;
  report("done", res.verdict + ": " + res.summary);
  return res;
}
}  // namespace

const char* const kSecondSearchHint =
    " A second search with every aerodynamic correction also started at its theoretical size "
    "(--escalate; Python escalate=True) can still find an effect the step from strength 0 "
    "misses; it takes several times as long.";

DiagnoseResult diagnose(const Dataset& d, const DiagnoseOptions& o, const DiagnoseCallback& progress) {
  const auto t0 = Clock::now();
  // The second search needs profiled starts and is one with theory_starts.
  const bool can_escalate = !o.theory_starts && o.profile;
  const bool may_escalate = o.escalate && can_escalate;
  // The first search's last report ("done") is held back until it is known
  // whether a second search follows, so that a progress dialog does not
  // close between the two.
  std::optional<DiagnoseProgress> held;
  DiagnoseCallback first = progress;
  if (may_escalate && progress)
    first = [&](const DiagnoseProgress& p) {
      if (p.stage == "done") held = p;
      else progress(p);
    };
  DiagnoseResult res = diagnose_once(d, o, first);
  // A withheld verdict (the launch withhold) is a gap a candidate closes:
  // starting the aerodynamic corrections elsewhere does not bear on it.
  if (!may_escalate || res.verdict != "unexplained" || !res.withheld.empty()) {
    if (!o.escalate && can_escalate && res.verdict == "unexplained" && res.withheld.empty())
      res.summary += kSecondSearchHint;
    if (held) progress(*held);
    return res;
  }
  // A real gap that no candidate closed from strength 0: the step from the
  // baseline can stay in the baseline's basin where the re-tuned centre
  // values absorb an effect to first order (blind finite span at 1, seed
  // 28: strength 0 on all gliders, `unexplained`; started at strength 1 the
  // oracle's way, named at 29 % held-out shrink). So the search is made
  // again with every aerodynamic correction also started at its
  // theoretical size; slower, which is why only here.
  const double first_s = res.seconds;
  const std::string first_best = res.effects.empty() ? "" : res.effects.front().name;
  if (progress) {
    DiagnoseProgress p;
    p.stage = "analysis";
    p.step = held ? held->step : 0;
    p.steps = held ? held->steps : 0;
    p.elapsed_s = since(t0);
    p.message = "no candidate closes the gap from strength 0 (best: " + (first_best.empty() ? "none" : first_best) +
                "): searching again with every aerodynamic correction also started at its theoretical size "
                "(slower)";
    progress(p);
  }
  DiagnoseOptions o2 = o;
  o2.theory_starts = true;
  // The second search's "done" is held back too: its verdict is checked
  // against the first search's baseline before it is final.
  DiagnoseCallback second;
  std::optional<DiagnoseProgress> held2;
  if (progress)
    second = [&](const DiagnoseProgress& p) {
      DiagnoseProgress q = p;
      q.elapsed_s = p.elapsed_s + first_s;
      if (q.stage == "done") {
        held2 = q;
        return;
      }
      q.message = "second search: " + q.message;
      progress(q);
    };
  DiagnoseResult res2 = diagnose_once(d, o2, second);
  const std::string fell = conclude_second_search(res2, res.verdict, first_best,
                                                  res.effects.empty() ? 0.0 : res.effects.front().shrink, first_s,
                                                  res.holdout_rmse_m, o);
  if (!fell.empty()) {
    // The named effect does not beat the first search's baseline by the
    // margin: the first search's result, `unexplained`, stands, with what
    // the second search found said in its summary.
    first_result_stands(res, res2, fell, first_s, since(t0));
  } else {
    res2.timings["second_search_s"] = res2.seconds;
    res2.seconds = since(t0);
    res2.timings["first_search_s"] = first_s;
    res2.timings["total_s"] = res2.seconds;
  }
  DiagnoseResult& out = fell.empty() ? res2 : res;
  if (progress) {
    // the one "done": the concluded verdict and summary (the second
    // search's own carried its summary before the conclusion), both searches
    DiagnoseProgress p = held2 ? *held2 : (held ? *held : DiagnoseProgress{});
    p.stage = "done";
    p.elapsed_s = out.seconds;
    p.message = out.verdict + ": " + out.summary;
    progress(p);
  }
  return out;
}

void first_result_stands(DiagnoseResult& first, const DiagnoseResult& second, const std::string& fell,
                         double first_s, double total_s) {
  if (fell.empty()) throw std::logic_error("first_result_stands: no sentence saying why the first result stands");
  first.escalation = second.escalation;
  first.summary = summary_after_second_search(first.summary, fell);
  first.seconds = total_s;
  if (!first.timings.is_object()) first.timings = nlohmann::json::object();
  first.timings["first_search_s"] = first_s;
  first.timings["second_search_s"] = second.seconds;
  first.timings["total_s"] = total_s;  // both searches, as when the second's result stands
}

std::string summary_after_second_search(const std::string& first_summary, const std::string& fell) {
  std::string summary = first_summary;
  if (const auto at = summary.find(kSecondSearchHint); at != std::string::npos)
    summary.erase(at, std::char_traits<char>::length(kSecondSearchHint));
  return fell + summary;
}

std::string conclude_second_search(DiagnoseResult& second, const std::string& first_verdict,
                                   const std::string& first_best, double first_best_shrink, double first_seconds,
                                   double first_holdout_rmse_m, const DiagnoseOptions& o) {
  second.escalation.ran = true;
  second.escalation.first_verdict = first_verdict;
  second.escalation.first_seconds = first_seconds;
  second.escalation.first_best = first_best;
  second.escalation.first_best_shrink = first_best_shrink;
  std::string fell = second_search_against_first(second, first_holdout_rmse_m, o);
  if (!fell.empty()) return fell;
  if (second.verdict != "unexplained")
    second.summary = "Searched from the baseline, no candidate closed the gap; started at their theoretical sizes, " +
                     std::string(second.verdict == "none" ? "none is needed" : second.verdict + " does") + ". " +
                     second.summary;
  else
    second.summary += " (Searched twice: from the baseline and from every aerodynamic correction's theoretical size.)";
  return "";
}

std::string second_search_against_first(DiagnoseResult& second, double first_holdout_rmse_m,
                                        const DiagnoseOptions& o) {
  auto& esc = second.escalation;
  esc.first_holdout_rmse_m = first_holdout_rmse_m;
  esc.shrink_against_first = std::numeric_limits<double>::quiet_NaN();
  esc.demoted.clear();
  const std::string& v = second.verdict;
  if (v == "none" || v == "unexplained" || v == effect_name(Effect::LaunchRotation)) return "";
  const auto e = std::find_if(second.effects.begin(), second.effects.end(),
                              [&](const EffectResult& r) { return r.name == v; });
  if (e == second.effects.end() || !(first_holdout_rmse_m > 0)) return "";
  esc.shrink_against_first = 1.0 - e->holdout_rmse_m / first_holdout_rmse_m;
  if (esc.shrink_against_first >= o.min_shrink) return "";
  esc.demoted = v;
  return "Searched twice, from the baseline and from every aerodynamic correction's theoretical size: the second "
         "search fitted " + v + ", which predicts the held-out gliders " + pct(e->shrink) +
         " better than its own baseline (" + cm(second.holdout_rmse_m, 2) + ") but only " +
         pct(esc.shrink_against_first) + " better than the first search's (" + cm(first_holdout_rmse_m, 2) +
         "), under the " + pct(o.min_shrink) + " margin, so the gap stays unexplained. ";
}

namespace {
json glider_map(const std::vector<std::pair<std::string, double>>& v) {
  json m = json::object();
  for (const auto& [k, x] : v) m[k] = x;
  return m;
}
// Figures, null where one was not computed (NaN).
json nums_or_null(const std::vector<double>& v) {
  json out = json::array();
  for (double x : v) out.push_back(num_or_null(x));
  return out;
}
}  // namespace

json diagnosis_options_json(const DiagnoseOptions& o) {
  json j = {{"folds", o.folds},
            {"trim", o.trim},
            {"alpha", o.alpha},
            {"min_shrink", o.min_shrink},
            {"holdout_chi2_test", o.holdout_chi2_test},
            {"glider_guard", o.glider_guard},
            {"bound_guard", o.bound_guard},
            {"launch_withhold", o.launch_withhold},
            {"launch_withhold_dominance", o.launch_withhold_dominance},
            {"launch_rates_confirm", o.launch_rates_confirm},
            {"prefer_identifiable", o.prefer_identifiable},
            {"none_tolerance", o.none_tolerance},
            {"collinearity_limit", o.collinearity_limit},
            {"launch_window_s", o.launch_window_s},
            {"near_ground_m", o.near_ground_m},
            {"ground_y_m", o.sim.ground_y},
            {"dt_s", o.sim.dt},
            {"max_centres", o.fit.max_centres},
            {"insertion_tries", o.fit.insertion_tries},
            {"full_fit", o.full_fit},
            {"polish", o.polish},
            {"profile", o.profile},
            {"profile_min_gliders", o.profile_min_gliders},
            {"profiled_candidates", o.profiled_candidates},
            {"carry_steps", o.carry_steps},
            {"leader_start", o.leader_start},
            {"leader_reached", o.leader_reached},
            {"heldout_steps", o.heldout_steps},
            {"heldout_fold_start", o.heldout_fold_start},
            {"zeroed_reference", o.zeroed_reference},
            {"theory_starts", o.theory_starts},
            {"hold_theory", o.hold_theory},
            {"escalate", o.escalate},
            {"step_per_flight", o.step_per_flight},
            {"refit_unstepped", o.refit_unstepped},
            {"step_alpha", o.step_level()},
            {"launch_rotation", o.launch_rotation_per_flight ? "per-flight" : "common"},
            {"second_effect", o.second_effect},
            {"dz_m", o.sim.aero.dz},
            {"iterations", o.sim.max_iterations}};
  // The model the coefficient fits start from (--model): its type and a
  // fingerprint of the model as model_to_json writes it (not of its file:
  // two spellings of the same numbers agree), so that a second search
  // refuses a first search made from another model, whose baseline would
  // not compare. A change of model_to_json's output changes every
  // fingerprint.
  {
    const json mj = o.start ? model_to_json(*o.start) : model_to_json(FlatPlateModel(o.fit.prior));
    std::uint64_t h = 14695981039346656037ull;  // FNV-1a, 64 bits
    for (unsigned char c : mj.dump()) h = (h ^ c) * 1099511628211ull;
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
    j["model"] = {{"type", mj.value("type", std::string())}, {"fingerprint", hex}};
  }
  // The plausible sizes in force (reported units; effects without a finite
  // one are left out).
  json lim = json::object();
  for (Effect E : all_effects()) {
    const auto& sp = effect_spec(E);
    json par = json::object();
    const auto limit = plausible_limits(E, o);
    for (std::size_t i = 0; i < sp.parameters.size(); ++i)
      if (std::isfinite(limit[i])) par[sp.parameters[i].name] = limit[i] * sp.parameters[i].to_report;
    if (!par.empty()) lim[effect_name(E)] = par;
  }
  j["plausible"] = lim;
  return j;
}

json diagnosis_json(const DiagnoseResult& r, const DiagnoseOptions& o) {
  json j;
  j["format"] = "pteromys-diagnosis/1";
  j["baseline"] = {{"fit_rmse_m", r.fit_rmse_m},
                   {"holdout_rmse_m", r.holdout_rmse_m},
                   {"fit_chi2_ratio", r.fit_chi2_ratio},
                   {"holdout_chi2_ratio", r.holdout_chi2_ratio},
                   {"noise_rmse_m", r.noise_rmse_m}};
  j["effects"] = json::array();
  for (const auto& e : r.effects) {
    const auto& sp = effect_spec(e.effect);
    // Per-fold parameters in reported units, one object per fold.
    auto fold_json = [&](const std::vector<std::vector<double>>& folds) {
      json out = json::array();
      for (const auto& fp : folds) {
        json x;
        for (std::size_t i = 0; i < sp.parameters.size() && i < fp.size(); ++i)
          x[sp.parameters[i].name] = fp[i] * sp.parameters[i].to_report;
        out.push_back(x);
      }
      return out;
    };
    json par;
    for (std::size_t i = 0; i < sp.parameters.size(); ++i)
      par[sp.parameters[i].name] = i < e.parameters.size() ? e.parameters[i] * sp.parameters[i].to_report : 0.0;
    const json fold = fold_json(e.fold_parameters);
    json conf = json::array();
    for (const auto& c : e.confusable) conf.push_back({{"effect", c.first}, {"cosine", c.second}});
    j["effects"].push_back({{"name", e.name},
                            {"holdout_rmse_m", e.holdout_rmse_m},
                            {"shrink", e.shrink},
                            {"significant", e.significant},
                            {"fit_rmse_m", e.fit_rmse_m},
                            {"parameters", par},
                            {"fold_parameters", fold},
                            {"strength_held", e.strength_held},
                            {"fold_strength_held", e.fold_strength_held},
                            {"linearised_delta_chi2", num_or_null(e.linearised_delta_chi2)},
                            {"fold_linearised_delta_chi2", nums_or_null(e.fold_linearised_delta_chi2)},
                            {"likelihood_ratio", {{"delta_chi2", e.delta_chi2},
                                                  {"p_value", e.p_value},
                                                  {"holm_level", e.holm_level},
                                                  {"pass", e.lr_pass}}},
                            {"cross_validation", {{"delta_chi2", e.holdout_delta_chi2},
                                                  {"threshold", e.holdout_threshold},
                                                  {"gliders_improved", e.gliders_improved},
                                                  {"gliders", e.gliders_total},
                                                  {"paired_t", e.glider_t},
                                                  {"robust_shrink", e.robust_shrink},
                                                  {"robust_without", e.robust_without},
                                                  {"robust_pass", e.robust_pass},
                                                  {"bound_share", e.bound_share},
                                                  {"bound_pass", e.bound_pass},
                                                  {"glider_holdout_rmse_m", glider_map(e.glider_holdout_rmse_m)},
                                                  {"glider_baseline_holdout_rmse_m",
                                                   glider_map(e.glider_baseline_holdout_rmse_m)}}},
                            {"plausible", e.plausible},
                            {"coefficient_collinearity", e.coefficient_collinearity},
                            {"indistinguishable_from_coefficients", e.indistinguishable},
                            {"confusable_with", conf},
                            {"description", effect_spec(e.effect).description},
                            {"note", e.note}});
    if (e.rate_test)
      j["effects"].back()["rate_mean"] = {{"mean_deg_s", rad2deg(e.rate_mean)},
                                          {"t", e.rate_mean_t},
                                          {"p_value", e.rate_mean_p},
                                          {"pass", e.rate_mean_pass}};
    if (e.given_verdict.tested) {
      const auto& g = e.given_verdict;
      json gp;
      for (std::size_t i = 0; i < sp.parameters.size() && i < g.parameters.size(); ++i)
        gp[sp.parameters[i].name] = g.parameters[i] * sp.parameters[i].to_report;
      j["effects"].back()["given_verdict"] = {
          {"holdout_rmse_m", g.holdout_rmse_m}, {"shrink", g.shrink}, {"significant", g.significant},
          {"parameters", gp}, {"plausible", g.plausible}, {"retuned", g.retuned}, {"rechecked", g.rechecked},
          {"likelihood_ratio", {{"delta_chi2", g.delta_chi2}, {"p_value", g.p_value}, {"holm_level", g.holm_level},
                                {"pass", g.lr_pass}}},
          {"cross_validation", {{"delta_chi2", g.holdout_delta_chi2}, {"threshold", g.holdout_threshold}}},
          {"reverse", {{"tested", g.reverse_tested}, {"shrink", g.reverse_shrink}, {"delta_chi2", g.reverse_delta_chi2},
                       {"p_value", g.reverse_p_value}, {"holdout_delta_chi2", g.reverse_holdout_delta_chi2},
                       {"threshold", g.reverse_threshold}, {"verdict_still_needed", g.verdict_still_needed}}},
          {"gliders_improved", g.gliders_improved}, {"gliders_total", g.gliders_total},
          {"robust_shrink", g.robust_shrink}, {"robust_without", g.robust_without}, {"robust_pass", g.robust_pass},
          {"fold_parameters", fold_json(g.fold_parameters)}, {"bound_share", g.bound_share},
          {"bound_pass", g.bound_pass}, {"note", g.note}, {"stopped_by_guard", g.stopped_by_guard}};
    }
  }
  j["verdict"] = r.verdict;
  j["also"] = r.also;
  if (!r.replaced.empty()) j["replaced"] = r.replaced;
  if (!r.likelihood_reference.empty())
    j["likelihood_reference"] = {
        {"effect", r.likelihood_reference},
        {"fit_rmse_m", r.likelihood_reference_rmse_m},
        {"zeroed", r.likelihood_reference_zeroed},
        {"reason", r.likelihood_reference_zeroed
                       ? "its fit with its values set to 0 and the launches refitted explains the training flights "
                         "better than the baseline's fit: a better fit of the baseline model (launches, trims and "
                         "centre values in a better basin), from which every likelihood ratio is measured"
                       : "fitted at 0 with the centre values re-tuned, it explains the training flights better than the "
                         "baseline's fit: a better fit of the baseline model, from which every likelihood ratio is measured"}};
  if (!r.withheld.empty())
    j["withheld"] = {
        {"effect", r.withheld},
        {"because", effect_name(Effect::LaunchRotation)},
        {"reason", r.verdict == effect_name(Effect::LaunchRotation)
                       ? "launch rotation is significant, its held-out flights' rates sharing a direction: a launch "
                         "habit that a correction applied alike to every flight can imitate on the held-out gliders"
                       : "launch rotation fits the training flights significantly, the flights' rates turning one "
                         "way, but is not significant: a launch habit that a correction applied alike to every "
                         "flight can carry to the held-out gliders"}};
  if (!r.passed_over.empty())
    j["passed_over"] = {{"effect", r.passed_over},
                        {"paired_t", r.passed_over_t},
                        {"t_critical", r.passed_over_t_critical},
                        {"reason", "indistinguishable from re-tuned coefficients and not significantly better "
                                   "across the held-out gliders than the verdict's effect"}};
  j["alternatives"] = r.alternatives;
  if (r.oracle) {
    json eff = json::object();
    for (const auto& [E, v] : r.oracle->effects) {
      const auto& sp = effect_spec(E);
      json par = json::object();
      for (std::size_t i = 0; i < v.size() && i < sp.parameters.size(); ++i) par[sp.parameters[i].name] = v[i];
      eff[effect_name(E)] = par;
    }
    j["oracle"] = {{"effects", eff},
                   {"holdout_rmse_m", r.oracle->holdout_rmse_m},
                   {"shrink", r.oracle->shrink},
                   {"holdout_chi2_ratio", r.oracle->holdout_chi2_ratio},
                   {"fold_holdout_rmse_m", r.oracle->fold_holdout_rmse_m},
                   {"fold_baseline_holdout_rmse_m", r.oracle->fold_baseline_holdout_rmse_m},
                   {"train_delta_chi2", r.oracle->train_delta_chi2},
                   {"fold_train_delta_chi2", r.oracle->fold_train_delta_chi2},
                   {"description", "the baseline plus the given effects at the given values, centre values and trims "
                                   "refitted with them on each fold's training gliders; held-out gliders as the "
                                   "candidates'"}};
  }
  j["summary"] = r.summary;
  j["where"] = r.where;
  j["report"] = r.report;
  json folds = json::array();
  for (const auto& f : r.fold_gliders) folds.push_back(f);
  json trims = json::object();
  for (std::size_t g = 0; g < r.trim.size() && g < r.glider_keys.size(); ++g) trims[r.glider_keys[g]] = rad2deg(r.trim[g]);
  j["dataset"] = {{"gliders", r.gliders}, {"flights", r.flights}, {"points", r.points},
                  {"tracking_sigma_m", r.sigma_m}};
  j["cross_validation"] = {{"folds", r.folds}, {"held_out_gliders", folds},
                           {"protocol", "leave-gliders-out: coefficients and effect strengths fitted to the other "
                                        "folds' gliders; each held-out flight's launch and its glider's trim fitted "
                                        "to its own points; RMSE over every held-out point"}};
  j["trim_deg"] = trims;
  j["options"] = diagnosis_options_json(o);
  j["escalation"] = {{"ran", r.escalation.ran}};
  if (r.escalation.ran) {
    j["escalation"]["first_verdict"] = r.escalation.first_verdict;
    j["escalation"]["first_best"] = r.escalation.first_best;
    j["escalation"]["first_best_shrink"] = r.escalation.first_best_shrink;
    j["escalation"]["first_seconds"] = r.escalation.first_seconds;
    j["escalation"]["first_holdout_rmse_m"] = r.escalation.first_holdout_rmse_m;
    j["escalation"]["shrink_against_first"] = num_or_null(r.escalation.shrink_against_first);
    j["escalation"]["demoted"] = r.escalation.demoted;
  }
  j["timings"] = r.timings;
  return j;
}

std::vector<double> stability_factors(int runs) {
  if (runs < 2 || runs > 7)
    throw InputError("a stability check takes 2 to 7 runs (the first and its re-runs), not " + std::to_string(runs));
  std::vector<double> f{1.0};
  for (int k = 1; k < runs; ++k) f.push_back(1.0 + (k % 2 == 1 ? -1.0 : 1.0) * 0.05 * ((k + 1) / 2));
  return f;
}

namespace {
std::string ms(double dt) { return fmt(1000 * dt, 3) + " ms"; }

double shrink_of(const DiagnoseResult& r, const std::string& name) {
  for (const auto& e : r.effects)
    if (e.name == name) return e.shrink;
  return 0.0;
}
}  // namespace

DiagnoseOptions stability_rerun_options(const DiagnoseOptions& o, const DiagnoseResult& first, double factor) {
  if (!(factor > 0) || !std::isfinite(factor))
    throw InputError("a stability re-run's step factor must be a positive number, not " + fmt(factor, 3));
  DiagnoseOptions ok = o;
  ok.sim.dt = o.sim.dt * factor;
  if (first.escalation.ran) {
    ok.theory_starts = false;
    ok.escalate = true;
  }
  return ok;
}

StabilityCheck check_stability(const Dataset& d, const DiagnoseOptions& o, const DiagnoseResult& first, int runs,
                               const DiagnoseCallback& progress) {
  const auto factors = stability_factors(runs);
  StabilityCheck out;
  out.runs.push_back({o.sim.dt, first.verdict, shrink_of(first, first.verdict), first.seconds});
  for (std::size_t k = 1; k < factors.size(); ++k) {
    const DiagnoseOptions ok = stability_rerun_options(o, first, factors[k]);
    const std::string head = "stability check " + std::to_string(k) + "/" + std::to_string(factors.size() - 1) +
                             " (step " + ms(ok.sim.dt) + "): ";
    DiagnoseCallback cb;
    if (progress)
      cb = [&](const DiagnoseProgress& p) {
        DiagnoseProgress q = p;
        q.message = head + p.message;
        progress(q);
      };
    const DiagnoseResult r = diagnose(d, ok, cb);
    out.runs.push_back({ok.sim.dt, r.verdict, shrink_of(r, first.verdict), r.seconds});
  }
  out.agree = 0;
  std::vector<std::string> other;
  for (const auto& r : out.runs) {
    if (r.verdict == first.verdict) ++out.agree;
    else other.push_back(ms(r.dt_s) + ": " + r.verdict);
  }
  out.stable = out.agree == static_cast<int>(out.runs.size());
  std::string steps;
  for (std::size_t k = 1; k < out.runs.size(); ++k) steps += (k > 1 ? ", " : "") + ms(out.runs[k].dt_s);
  const std::string n = std::to_string(out.runs.size());
  out.sentence = std::string(first.escalation.ran ? "Re-run, both searches each time," : "Re-run") +
                 " with the simulation step changed slightly (" + steps + " for " + ms(o.sim.dt) +
                 "), the verdict was " + first.verdict;
  if (out.stable) {
    out.sentence += " in all " + n + " runs.";
  } else {
    std::string others;
    for (std::size_t i = 0; i < other.size(); ++i) others += (i ? "; " : "") + other[i];
    out.sentence += " in only " + std::to_string(out.agree) + " of " + n + " runs (" + others +
                    "): it turns on the search's path rather than on the data, so treat it as tentative.";
  }
  return out;
}

void add_stability_json(nlohmann::json& j, const StabilityCheck& s) {
  nlohmann::json runs = nlohmann::json::array();
  for (const auto& r : s.runs)
    runs.push_back({{"dt_s", r.dt_s}, {"verdict", r.verdict}, {"verdict_shrink", r.verdict_shrink}, {"seconds", r.seconds}});
  j["stability"] = {{"runs", runs}, {"agree", s.agree}, {"of", s.runs.size()}, {"stable", s.stable}, {"sentence", s.sentence}};
  const std::string summary = j.value("summary", std::string());
  j["summary"] = summary.empty() ? s.sentence : summary + " " + s.sentence;
}

}  // namespace pteromys
