// Issue 6 benchmark: the reference simulator.
//  - generate/training20: the fitting experiment's dataset, 20 training
//    gliders (examples/training) x 6 launches = 120 flights, 15-20 points at
//    30 fps, +-5 cm noise, every aerodynamic effect on, 2 threads.
//    Target <= 30 s on the 2-core machine.
//  - generate/training20_whole: the same, tracking whole flights to the ground.
//  - setup/<glider>: building the lattice solutions of one glider (all effects).
//  - evaluate/<glider>/<effects>: one force evaluation (target: tens of us).
// Run: build/bench/bench_reference [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "bench_common.hpp"
#include "pteromys/io.hpp"
#include "pteromys/reference.hpp"

using namespace pteromys;

namespace {

using bench::training_gliders;

void generate(benchmark::State& st, TrackWindow window) {
  const auto gliders = training_gliders();
  if (gliders.size() != 20) {
    st.SkipWithError("expected the 20 gliders of examples/training");
    return;
  }
  GenerateOptions o;
  o.flights_per_glider = 6;
  o.window = window;
  o.threads = 2;
  GenerateStats s;
  for (auto _ : st) {
    const Dataset d = generate_dataset(gliders, o, &s);
    benchmark::DoNotOptimize(d.flights.size());
  }
  st.counters["flights"] = s.flights;
  st.counters["setup_s(cpu)"] = s.setup_seconds;
  st.counters["simulate_s(cpu)"] = s.simulate_seconds;
  st.counters["unstable"] = s.unstable;
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::RegisterBenchmark("generate/training20", [](benchmark::State& st) { generate(st, TrackWindow::Launch); })
      ->Unit(benchmark::kSecond)
      ->UseRealTime()
      ->Iterations(1);
  benchmark::RegisterBenchmark("generate/training20_whole",
                               [](benchmark::State& st) { generate(st, TrackWindow::Whole); })
      ->Unit(benchmark::kSecond)
      ->UseRealTime()
      ->Iterations(1);
  const auto gl = training_gliders();
  for (const auto& [name, g] : gl) {
    if (name != "t05-tapered-strong" && name != "t11-delta" && name != "t17-canard" && name != "t18-tandem")
      continue;
    const Glider gg = g;
    benchmark::RegisterBenchmark(("setup/" + name).c_str(), [gg](benchmark::State& st) {
      for (auto _ : st) {
        const ReferenceAero r(gg, ReferenceOptions{});
        benchmark::DoNotOptimize(r.node_count());
      }
    })->Unit(benchmark::kMillisecond);
    for (const char* eff : {"physics", "baseline"}) {
      const std::string spec = eff;
      benchmark::RegisterBenchmark(("evaluate/" + name + "/" + spec).c_str(), [gg, spec](benchmark::State& st) {
        ReferenceOptions o;
        o.effects = parse_effects(spec);
        const ReferenceAero r(gg, o);
        // a sweep of flight states: speeds 5-10 m/s, angles -5..25 deg, pitch rates, heights
        std::vector<FlightState> states;
        for (int i = 0; i < 64; ++i) {
          FlightState s;
          const double a = deg2rad(-5 + 30.0 * i / 63);
          s.v = {5 + 5.0 * (i % 7) / 6, -0.3};
          s.beta = a;
          s.omega = 0.5 * ((i % 5) - 2);
          s.p = {0, 0.05 + 0.1 * (i % 11)};
          states.push_back(s);
        }
        std::size_t k = 0;
        for (auto _ : st) {
          benchmark::DoNotOptimize(r.evaluate(states[k]));
          k = (k + 1) % states.size();
        }
        st.counters["panels"] = r.panel_count();
        st.counters["strips"] = static_cast<double>(r.strips().size());
        st.counters["nodes"] = r.node_count();
      })->Unit(benchmark::kMicrosecond);
    }
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
