// Issue 2 benchmark: for every example glider, time to build the wing force
// tables (slicing included), to evaluate F(V, gamma) on the paper's 4 x 21
// grid over Omega, and to simulate the six standard launches.
// Targets on the 2-core machine: tables <= 5 ms, F grid <= 0.2 ms,
// six launches <= 1 ms (medians). Run: build/bench/bench_core
#include <benchmark/benchmark.h>

#include <algorithm>
#include <string>
#include <vector>

#include "pteromys/analysis.hpp"
#include "pteromys/io.hpp"
#include "pteromys/optimize.hpp"

#include "bench_common.hpp"

using namespace pteromys;

int main(int argc, char** argv) {
  const auto model = default_model();
  for (const auto& path : bench::example_paths()) {
    const Glider g = load_glider(path);
    const std::string n = bench::short_name(path);
    benchmark::RegisterBenchmark(("tables/" + n).c_str(), [g, model](benchmark::State& st) {
      for (auto _ : st) {
        GliderAero a(g, model);
        benchmark::DoNotOptimize(a.table(0).nv());
      }
    });
    // Launches of the optimised design (long, realistic flights), not of the
    // file's first-guess mounts (which mostly loop and end early).
    const Glider opt = optimize(g, model).glider;
    auto mg = std::make_shared<MountedGlider>(mount(opt, model));
    benchmark::RegisterBenchmark(("F_grid_4x21/" + n).c_str(), [mg](benchmark::State& st) {
      for (auto _ : st) {
        double s = 0;
        for (int k = 0; k < 4; ++k)
          for (int i = 0; i < 21; ++i) s += mg->forces(6 + k, deg2rad(-10 + i)).moment;
        benchmark::DoNotOptimize(s);
      }
    });
    benchmark::RegisterBenchmark(("six_launches/" + n).c_str(), [mg](benchmark::State& st) {
      const QuasiStaticAero qa(*mg);
      const RigidBody body{mg->mass().mass, mg->mass().inertia};
      SimOptions o;
      o.record_every = 5;
      for (auto _ : st)
        for (const Launch& l : standard_launches(1.5)) benchmark::DoNotOptimize(simulate(qa, body, l, o).distance);
    });
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
