// Where the gap lies: residuals by phase, glider and geometry feature, flight
// state, and their whiteness (diagnose.hpp, gap_analysis).
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <random>

#include "pteromys/diagnose.hpp"

namespace pteromys {
namespace {

using nlohmann::json;

struct Point {
  int glider = 0;
  std::string phase;
  double t_rel = 0, height = 0, alpha_deg = 0, omega_deg_s = 0;
  double e2 = 0, e2_after = -1, expect = 0;
};

struct Acc {
  long n = 0;
  double e2 = 0, e2_after = 0, expect = 0;
  bool has_after = false;
  void add(const Point& p) {
    ++n;
    e2 += p.e2;
    expect += p.expect;
    if (p.e2_after >= 0) {
      e2_after += p.e2_after;
      has_after = true;
    }
  }
  json to_json() const {
    json j = {{"points", n},
              {"rmse_m", n ? std::sqrt(e2 / n) : 0.0},
              {"chi2_ratio", expect > 0 ? e2 / expect : 0.0},
              {"excess_m2", e2 - expect}};
    if (has_after) j["rmse_after_m"] = n ? std::sqrt(e2_after / n) : 0.0;
    return j;
  }
};

std::vector<double> ranks(const std::vector<double>& v) {
  std::vector<int> idx(v.size());
  std::iota(idx.begin(), idx.end(), 0);
  std::sort(idx.begin(), idx.end(), [&](int a, int b) { return v[a] < v[b]; });
  std::vector<double> r(v.size());
  for (std::size_t i = 0; i < idx.size();) {
    std::size_t j = i;
    while (j + 1 < idx.size() && v[idx[j + 1]] == v[idx[i]]) ++j;
    for (std::size_t k = i; k <= j; ++k) r[idx[k]] = 0.5 * (i + j);
    i = j + 1;
  }
  return r;
}

double pearson(const std::vector<double>& a, const std::vector<double>& b) {
  const double n = static_cast<double>(a.size());
  if (n < 3) return 0;
  const double ma = std::accumulate(a.begin(), a.end(), 0.0) / n, mb = std::accumulate(b.begin(), b.end(), 0.0) / n;
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  return saa > 0 && sbb > 0 ? sab / std::sqrt(saa * sbb) : 0.0;
}

/// Spearman's rank correlation and its two-sided permutation p-value.
std::pair<double, double> spearman(const std::vector<double>& x, const std::vector<double>& y) {
  const auto rx = ranks(x), ry = ranks(y);
  const double rho = pearson(rx, ry);
  if (x.size() < 4) return {rho, 1.0};
  std::mt19937 rng(12345);
  std::vector<double> p = ry;
  int beyond = 0;
  const int perms = 2000;
  for (int k = 0; k < perms; ++k) {
    std::shuffle(p.begin(), p.end(), rng);
    if (std::abs(pearson(rx, p)) >= std::abs(rho) - 1e-12) ++beyond;
  }
  return {rho, (beyond + 1.0) / (perms + 1.0)};
}

json binned(const std::vector<Point>& pts, double Point::*field, const std::string& key, int bins) {
  std::vector<double> v;
  for (const auto& p : pts) v.push_back(p.*field);
  std::sort(v.begin(), v.end());
  json out = json::array();
  if (v.empty()) return out;
  std::vector<double> edges;
  for (int b = 0; b <= bins; ++b) edges.push_back(v[std::min<std::size_t>(v.size() - 1, b * (v.size() - 1) / bins)]);
  for (int b = 0; b < bins; ++b) {
    if (b > 0 && edges[b] == edges[b + 1]) continue;
    Acc a;
    for (const auto& p : pts) {
      const double x = p.*field;
      if (x >= edges[b] && (x < edges[b + 1] || (b == bins - 1 && x <= edges[b + 1]))) a.add(p);
    }
    json j = a.to_json();
    j[key] = {edges[b], edges[b + 1]};
    out.push_back(j);
  }
  return out;
}

}  // namespace

json gap_analysis(const DiagnosisData& D, const std::vector<const FlightOutcome*>& flights,
                  const std::vector<const FlightOutcome*>& after, const DiagnoseOptions& o, double sigma) {
  const bool has_after = after.size() == flights.size();
  std::vector<Point> pts;
  // Whiteness: lag-1 products and sign runs of each coordinate's residual sequence.
  double s01 = 0, s00 = 0;
  long pairs = 0;
  double runs = 0, runs_expect = 0, runs_var = 0;
  for (std::size_t k = 0; k < flights.size(); ++k) {
    const FlightOutcome& f = *flights[k];
    const int n = static_cast<int>(f.residual.size());
    if (n == 0) continue;
    const int g = D.glider_of(f.flight);
    const double c = std::max(0.0, 1.0 - 5.0 / (2.0 * n));
    for (int i = 0; i < n; ++i) {
      Point p;
      p.glider = g;
      const FlightSample& s = f.states[i];
      p.t_rel = s.t - f.states[0].t;
      p.height = s.y - D.options().ground_y;
      p.alpha_deg = rad2deg(s.alpha);
      p.omega_deg_s = rad2deg(s.omega);
      p.phase = p.height < o.near_ground_m ? "near_ground" : (p.t_rel < o.launch_window_s ? "launch" : "glide");
      p.e2 = f.residual[i].x * f.residual[i].x + f.residual[i].y * f.residual[i].y;
      p.expect = 2 * sigma * sigma * c;
      if (has_after && after[k]->residual.size() == f.residual.size())
        p.e2_after = std::pow(after[k]->residual[i].x, 2) + std::pow(after[k]->residual[i].y, 2);
      pts.push_back(p);
    }
    for (int axis = 0; axis < 2; ++axis) {
      auto r = [&](int i) { return axis == 0 ? f.residual[i].x : f.residual[i].y; };
      int pos = 0, neg = 0, changes = 0;
      for (int i = 0; i < n; ++i) {
        s00 += r(i) * r(i);
        if (i + 1 < n) {
          s01 += r(i) * r(i + 1);
          ++pairs;
          if ((r(i) >= 0) != (r(i + 1) >= 0)) ++changes;
        }
        (r(i) >= 0 ? pos : neg)++;
      }
      if (pos > 0 && neg > 0 && n > 2) {
        const double N = n;
        const double e = 1 + 2.0 * pos * neg / N;
        const double v = 2.0 * pos * neg * (2.0 * pos * neg - N) / (N * N * (N - 1));
        runs += changes + 1;
        runs_expect += e;
        runs_var += v;
      }
    }
  }
  json out;
  // Phases.
  std::map<std::string, Acc> phase;
  Acc all;
  for (const auto& p : pts) {
    phase[p.phase].add(p);
    all.add(p);
  }
  out["definitions"] = {{"launch", "the first " + std::to_string(o.launch_window_s) + " s after the first tracked point"},
                        {"near_ground", "height above the ground below " + std::to_string(o.near_ground_m) + " m"},
                        {"glide", "every other point"},
                        {"chi2_ratio", "squared error / squared error expected from tracking noise alone"}};
  out["all"] = all.to_json();
  json ph = json::array();
  double total_excess = 0;
  for (const auto& [k, a] : phase) total_excess += std::max(0.0, a.e2 - a.expect);
  for (const char* name : {"launch", "glide", "near_ground"}) {
    auto it = phase.find(name);
    if (it == phase.end()) continue;
    json j = it->second.to_json();
    j["phase"] = name;
    j["excess_share"] = total_excess > 0 ? std::max(0.0, it->second.e2 - it->second.expect) / total_excess : 0.0;
    ph.push_back(j);
  }
  out["phases"] = ph;
  // Gliders and geometry features.
  std::map<int, Acc> per;
  for (const auto& p : pts) per[p.glider].add(p);
  json gl = json::array();
  std::vector<double> ratio;
  std::map<std::string, std::vector<double>> feat;
  const char* names[] = {"main_aspect_ratio", "tail_aspect_ratio", "tail_arm_m", "tail_volume",
                         "wing_loading_n_m2", "fuselage_ratio"};
  for (const auto& [g, a] : per) {
    const auto& G = D.gliders()[g];
    const auto& F = G.features;
    json j = a.to_json();
    j["glider"] = G.key;
    j["flights"] = static_cast<int>(G.flights.size());
    const double fv[] = {F.main_aspect_ratio, F.tail_aspect_ratio, F.tail_arm, F.tail_volume, F.wing_loading,
                         F.fuselage_ratio};
    json fj;
    for (int i = 0; i < 6; ++i) {
      fj[names[i]] = fv[i];
      feat[names[i]].push_back(fv[i]);
    }
    j["features"] = fj;
    ratio.push_back(a.expect > 0 ? a.e2 / a.expect : 0.0);
    gl.push_back(j);
  }
  out["gliders"] = gl;
  json fe = json::array();
  for (const char* n : names) {
    const auto [rho, p] = spearman(feat[n], ratio);
    fe.push_back({{"feature", n}, {"spearman_rho", rho}, {"p_value", p}});
  }
  out["features"] = fe;
  // Flight state.
  out["states"] = {{"alpha_deg", binned(pts, &Point::alpha_deg, "alpha_deg", 4)},
                   {"pitch_rate_deg_s", binned(pts, &Point::omega_deg_s, "pitch_rate_deg_s", 4)},
                   {"height_m", binned(pts, &Point::height, "height_m", 4)},
                   {"time_s", binned(pts, &Point::t_rel, "time_s", 4)}};
  // Whiteness.
  const double rho1 = s00 > 0 ? s01 / s00 : 0.0;
  const double z_rho = rho1 * std::sqrt(static_cast<double>(std::max<long>(pairs, 1)));
  const double z_runs = runs_var > 0 ? (runs - runs_expect) / std::sqrt(runs_var) : 0.0;
  const bool structured = z_rho > 3 || z_runs < -3;
  out["whiteness"] = {{"lag1_autocorrelation", rho1},
                      {"lag1_z", z_rho},
                      {"runs", runs},
                      {"runs_expected", runs_expect},
                      {"runs_z", z_runs},
                      {"structured", structured},
                      {"note", structured ? "neighbouring residuals share their sign far more often than tracking noise "
                                            "would: the misfit is a systematic drift, not noise"
                                          : "the residuals change sign about as often as independent tracking noise "
                                            "would"}};
  // Points for the report's scatter plots.
  json pj = {{"t_s", json::array()}, {"error_m", json::array()}, {"phase", json::array()}, {"glider", json::array()}};
  if (has_after) pj["error_after_m"] = json::array();
  for (const auto& p : pts) {
    pj["t_s"].push_back(p.t_rel);
    pj["error_m"].push_back(std::sqrt(p.e2));
    pj["phase"].push_back(p.phase);
    pj["glider"].push_back(D.gliders()[p.glider].key);
    if (has_after) pj["error_after_m"].push_back(p.e2_after >= 0 ? std::sqrt(p.e2_after) : 0.0);
  }
  out["points"] = pj;
  return out;
}

}  // namespace pteromys
