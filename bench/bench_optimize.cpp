// Issue 3 benchmark: the interactive loop and the choice of optimiser.
//  1. For every example: the whole loop from a changed shape to optimised
//     mounts and the six trajectories (tables + optimisation + simulation),
//     cold from all-zero mounting angles; and the warm-started re-optimisation
//     after a small shape change (2 % longer main-wing chord). Medians of 15 runs.
//     Targets: loop <= 20 ms, warm <= 5 ms.
//  2. Algorithms on the same cost and start (all angles zero): cost reached
//     relative to the best any algorithm found, evaluations and time, including
//     the paper's steepest descent with forward differences.
// Run: build/bench/bench_optimize
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "pteromys/io.hpp"
#include "pteromys/optimize.hpp"

#include "bench_common.hpp"

using namespace pteromys;
using Clock = std::chrono::steady_clock;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

}  // namespace

int main() {
  const auto model = default_model();
  const auto paths = bench::example_paths();
  std::printf("Interactive loop (median of 15 runs, ms)\n");
  std::printf("%-18s %10s %10s %8s %8s\n", "example", "loop_cold", "warm", "evals", "w_evals");
  std::vector<double> all_cold, all_warm;
  for (const auto& p : paths) {
    Glider g = load_glider(p);
    for (auto& w : g.wings) w.mount.angle_deg = 0;
    std::vector<double> cold, warm;
    int ev = 0, wev = 0;
    OptimizeResult first;
    for (int rep = 0; rep < 15; ++rep) {
      auto t = Clock::now();
      first = optimize(g, model);  // slicing + tables + optimisation + 6 launches
      cold.push_back(ms_since(t));
      ev = first.evaluations;
      Glider h = first.glider;
      for (auto& q : h.wings[0].outline) q.x *= 1.02;
      t = Clock::now();
      const OptimizeResult w = optimize(h, model, {}, {}, {}, &first);
      warm.push_back(ms_since(t));
      wev = w.evaluations;
    }
    std::printf("%-18s %10.2f %10.2f %8d %8d\n", bench::short_name(p).c_str(), median(cold), median(warm), ev, wev);
    all_cold.push_back(median(cold));
    all_warm.push_back(median(warm));
  }
  std::printf("%-18s %10.2f %10.2f   (median over examples)\n", "ALL", median(all_cold), median(all_warm));
  std::printf("%-18s %10.2f %10.2f   (worst example)\n\n", "MAX", *std::max_element(all_cold.begin(), all_cold.end()),
              *std::max_element(all_warm.begin(), all_warm.end()));

  const std::vector<std::string> algs{"bobyqa", "cobyla", "sbplx", "neldermead", "steepest"};
  std::map<std::string, std::vector<double>> rel, time, evals;
  std::map<std::string, int> flyable;
  for (const auto& p : paths) {
    Glider g = load_glider(p);
    for (auto& w : g.wings) w.mount.angle_deg = 0;
    std::map<std::string, OptimizeResult> res;
    std::map<std::string, double> t_ms;
    double best = 1e300;
    for (const auto& a : algs) {
      OptimizeOptions o;
      o.algorithm = a;
      std::vector<double> ts;
      for (int rep = 0; rep < 3; ++rep) {
        const auto t = Clock::now();
        res[a] = optimize(g, model, o);
        ts.push_back(ms_since(t));
      }
      t_ms[a] = median(ts);
      best = std::min(best, res[a].cost.total);
    }
    for (const auto& a : algs) {
      rel[a].push_back(res[a].cost.total / best);
      time[a].push_back(t_ms[a]);
      evals[a].push_back(res[a].evaluations);
      flyable[a] += res[a].report.flyable ? 1 : 0;
    }
  }
  std::printf("Algorithms from all-zero angles over %zu examples (cost relative to the best found by any)\n", paths.size());
  std::printf("%-12s %12s %12s %12s %12s %10s\n", "algorithm", "cost_median", "cost_worst", "evals_med", "ms_median", "flyable");
  for (const auto& a : algs)
    std::printf("%-12s %12.4f %12.4f %12.0f %12.2f %7d/%zu\n", a.c_str(), median(rel[a]),
                *std::max_element(rel[a].begin(), rel[a].end()), median(evals[a]), median(time[a]), flyable[a],
                paths.size());
  return 0;
}
