// Issue 6 benchmark: coefficient fitting from tracked flights (fit.hpp).
//  - fit/experiment: the paper's experiment (docs/fitting.md): 20 training
//    gliders (examples/training) x 6 launches = 120 flights from the reference
//    simulator (every aerodynamic effect, launches 5-9 m/s and 0-10 deg, 15-20
//    points at 30 fps, +-5 cm noise, seed 1), greedy fit with the default
//    stopping rule. Target: the whole fit <= 2 min on the 2-core machine.
//  - fit/ten_centres: the same with the stopping rule off (all 10 centres,
//    the paper's final count): the slowest case.
//  - fit/ten_centres_exact: noise-free flights (0.1 mm), 10 centres: the
//    solver works hardest when the residuals are smallest.
//  - launch_fit: eq. 5 for one flight, multi-start (cold) and warm.
//  - simulate_track: one 20-point flight; _effect: the same with one of the
//    diagnosis's aerodynamic corrections (none, finite_span, downwash,
//    ground_effect at strength 1).
//  - tables: force tables of all 20 gliders for a 10-centre model (the table
//    part of one residual evaluation).
// Counters: rmse_m, centres, iterations, s/iteration (solver iterations of
// the coefficient fit), the time split. Per-stage figures go to stdout once.
// Run: build/bench/bench_fit [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "bench_common.hpp"
#include "pteromys/effects.hpp"
#include "pteromys/fit.hpp"
#include "pteromys/io.hpp"
#include "pteromys/mass.hpp"
#include "pteromys/reference.hpp"

using namespace pteromys;

namespace {

using bench::training_gliders;

/// The experiment's training flights (as bench/fit/run_experiment.py makes them).
const Dataset& experiment_dataset(double noise) {
  static std::map<double, Dataset> cache;
  auto it = cache.find(noise);
  if (it != cache.end()) return it->second;
  GenerateOptions o;
  o.flights_per_glider = 6;
  o.seed = 1;
  o.launcher.speed_min = 5.0;
  o.launcher.speed_max = 9.0;
  o.camera.noise_sigma_m = noise;
  o.threads = 2;
  return cache[noise] = generate_dataset(training_gliders(), o);
}

void report(benchmark::State& st, const FitResult& r, const char* name) {
  int iterations = 0;
  for (const auto& h : r.history) iterations += h.iterations;
  st.counters["rmse_m"] = r.rmse_m;
  st.counters["prior_rmse_m"] = r.prior_rmse_m;
  st.counters["centres"] = static_cast<double>(r.model->centres().size());
  st.counters["flights"] = static_cast<double>(r.flights.size());
  st.counters["iterations"] = iterations;
  st.counters["s/iteration"] = iterations ? r.coefficient_seconds / iterations : 0.0;
  st.counters["launch_fits_s"] = r.launch_seconds;
  st.counters["insertion_s"] = r.insertion_seconds;
  st.counters["simulations"] = static_cast<double>(r.simulations);
  static std::map<std::string, bool> printed;
  if (printed[name]) return;
  printed[name] = true;
  std::printf("%s: %zu flights, %d points, %.1f s; stop: %s\n", name, r.flights.size(), r.points, r.seconds,
              r.stop_reason.c_str());
  std::printf("  centres  rmse_m    iterations  simulations  seconds\n");
  for (const auto& h : r.history)
    std::printf("  %7d  %.5f  %10d  %11d  %7.2f%s\n", h.centres, h.rmse_m, h.iterations, h.simulations, h.seconds,
                h.accepted ? "" : "  (dropped)");
}

void fit_bench(benchmark::State& st, double noise, bool keep_all, const char* name) {
  const Dataset& d = experiment_dataset(noise);
  FitOptions o;
  o.threads = 2;
  o.information_criterion = !keep_all;
  FitResult r;
  for (auto _ : st) r = fit_coefficients(d, o);
  report(st, r, name);
}

void BM_FitExperiment(benchmark::State& st) { fit_bench(st, 0.05, false, "fit/experiment"); }
void BM_FitTenCentres(benchmark::State& st) { fit_bench(st, 0.05, true, "fit/ten_centres"); }
void BM_FitTenCentresExact(benchmark::State& st) { fit_bench(st, 1e-4, true, "fit/ten_centres_exact"); }

struct OneFlight {
  Dataset d;
  std::shared_ptr<MountedGlider> mg;
  RigidBody body;
  const TrackedFlight* f = nullptr;
};

OneFlight one_flight() {
  OneFlight o;
  o.d = experiment_dataset(0.05);
  o.f = &o.d.flights[0];
  const Glider& g = o.d.gliders.at(o.f->glider);
  o.mg = std::make_shared<MountedGlider>(mount(g, std::make_shared<FlatPlateModel>()));
  o.body = {o.mg->mass().mass, o.mg->mass().inertia};
  return o;
}

void BM_LaunchFitCold(benchmark::State& st) {
  const OneFlight o = one_flight();
  const QuasiStaticAero qa(*o.mg);
  const LaunchFitOptions lo = all_points_launch_fit();
  LaunchFit f;
  for (auto _ : st) f = fit_launch(qa, o.body, o.f->points, lo);
  st.counters["simulations"] = f.evaluations;
  st.counters["points"] = static_cast<double>(o.f->points.size());
}

void BM_LaunchFitWarm(benchmark::State& st) {
  const OneFlight o = one_flight();
  const QuasiStaticAero qa(*o.mg);
  const LaunchFitOptions lo = all_points_launch_fit();
  LaunchParams start = fit_launch(qa, o.body, o.f->points, lo).launch;
  start.speed += 0.05;  // the model moved a little since the last fit
  start.pitch += 0.005;
  LaunchFit f;
  for (auto _ : st) f = fit_launch(qa, o.body, o.f->points, lo, &start);
  st.counters["simulations"] = f.evaluations;
}

void BM_SimulateTrack(benchmark::State& st) {
  const OneFlight o = one_flight();
  const QuasiStaticAero qa(*o.mg);
  std::vector<double> t;
  for (int i = 0; i < 20; ++i) t.push_back(o.f->points[0].t + i / 30.0);
  LaunchParams p = initial_launch_guess(o.f->points);
  for (auto _ : st) benchmark::DoNotOptimize(simulate_track(qa, o.body, p, t).positions.back().x);
}

// The same flight with one aerodynamic correction of the diagnosis's library
// (EffectAero, strength 1): 0 none, 1 finite_span, 2 downwash, 3 ground_effect.
// The corrections that iterate the induced angle cost more per simulation.
void BM_SimulateTrackEffect(benchmark::State& st) {
  const OneFlight o = one_flight();
  const GliderFeatures f = glider_features(o.d.gliders.at(o.f->glider));
  EffectValues v;
  const int k = static_cast<int>(st.range(0));
  if (k == 1) v.finite_span = 1.0;
  if (k == 2) v.downwash = 1.0;
  if (k == 3) v.ground_effect = 1.0;
  const EffectAero ea(*o.mg, f, v);
  std::vector<double> t;
  for (int i = 0; i < 20; ++i) t.push_back(o.f->points[0].t + i / 30.0);
  LaunchParams p = initial_launch_guess(o.f->points);
  for (auto _ : st) benchmark::DoNotOptimize(simulate_track(ea, o.body, p, t).positions.back().x);
  st.SetLabel(k == 0 ? "none" : k == 1 ? "finite_span" : k == 2 ? "downwash" : "ground_effect");
}

void BM_TablesForTenCentres(benchmark::State& st) {
  const auto gl = training_gliders();
  auto prior = std::make_shared<FlatPlateModel>();
  std::vector<RbfCentre> cs;
  for (int k = 0; k < 10; ++k) {
    RbfCentre c;
    c.alpha = deg2rad(1.0 + 2.0 * k);
    c.re = 8e3 + 4e3 * k;
    c.xi_l = deg2rad(-30.0 + 7.0 * k);
    c.xi_t = deg2rad(-20.0 + 4.0 * k);
    c.value = prior->eval({c.alpha, c.re, c.xi_l, c.xi_t});
    cs.push_back(c);
  }
  const auto model = std::make_shared<RbfModel>(cs, RbfScales{}, deg2rad(40), prior);
  for (auto _ : st)
    for (const auto& [key, g] : gl) benchmark::DoNotOptimize(GliderAero(g, model).wing_count());
  st.counters["gliders"] = static_cast<double>(gl.size());
}

}  // namespace

BENCHMARK(BM_FitExperiment)->Name("fit/experiment")->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();
BENCHMARK(BM_FitTenCentres)->Name("fit/ten_centres")->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();
BENCHMARK(BM_FitTenCentresExact)->Name("fit/ten_centres_exact")->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();
BENCHMARK(BM_LaunchFitCold)->Name("launch_fit/cold")->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LaunchFitWarm)->Name("launch_fit/warm")->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SimulateTrack)->Name("simulate_track/20_points")->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SimulateTrackEffect)->Name("simulate_track/20_points_effect")->DenseRange(0, 3)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_TablesForTenCentres)->Name("tables/20_gliders_10_centres")->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
