// Issue 4 benchmark: for every example glider, time to build the slotted
// plates (joint choice, CGAL exact Booleans, marks, kerf offsets), to lay them
// out and write the DXF (dxflib), to write the STEP (OpenCASCADE, one solid per
// plate), and the whole `pteromys export` (plates + DXF + STEP).
// Target on the 2-core machine: whole export <= 1 s per example.
// Run: build/bench/bench_export [--benchmark_filter=export/]
#include <benchmark/benchmark.h>

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "pteromys/dxf_export.hpp"
#include "pteromys/fabrication.hpp"
#include "pteromys/io.hpp"
#include "pteromys/step_export.hpp"

#include "bench_common.hpp"

using namespace pteromys;

namespace {

std::string tmp(const std::string& n, const char* ext) {
  return "/tmp/pteromys_bench_export_" + std::to_string(::getpid()) + "_" + n + ext;
}

}  // namespace

int main(int argc, char** argv) {
  for (const auto& path : bench::example_paths()) {
    const Glider g = load_glider(path);
    const std::string n = bench::short_name(path);
    FabricationOptions fo;
    try {
      slotted_plates(g, fo);
    } catch (const InputError& e) {
      // Refused designs are reported, not timed (the refusal itself is fast).
      std::printf("%s: not buildable with default options: %s\n", n.c_str(), e.what());
      fo.min_web_m = 0.0013;  // time it with the relaxed web that builds it
      try {
        slotted_plates(g, fo);
        std::printf("%s: timed with --min-web 1.3\n", n.c_str());
      } catch (const InputError&) {
        continue;
      }
    }
    benchmark::RegisterBenchmark(("plates/" + n).c_str(), [g, fo](benchmark::State& st) {
      for (auto _ : st) benchmark::DoNotOptimize(slotted_plates(g, fo));
    })->Unit(benchmark::kMillisecond);
    const PlateSet s = slotted_plates(g, fo);
    benchmark::RegisterBenchmark(("dxf/" + n).c_str(), [s, n](benchmark::State& st) {
      const std::string p = tmp(n, ".dxf");
      for (auto _ : st) write_dxf(s, layout_plates(s, {}), p);
      std::remove(p.c_str());
    })->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("step/" + n).c_str(), [s, n](benchmark::State& st) {
      const std::string p = tmp(n, ".step");
      for (auto _ : st) write_step_parts(s, p);
      std::remove(p.c_str());
    })->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("export/" + n).c_str(), [g, fo, n](benchmark::State& st) {
      ExportRequest r;
      r.fabrication = fo;
      r.dxf_path = tmp(n, ".dxf");
      r.step_path = tmp(n, ".step");
      for (auto _ : st) benchmark::DoNotOptimize(export_glider(g, r));
      std::remove(r.dxf_path.c_str());
      std::remove(r.step_path.c_str());
    })->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("export_fused/" + n).c_str(), [g, fo, n](benchmark::State& st) {
      ExportRequest r;
      r.fabrication = fo;
      r.step_path = tmp(n, "_fused.step");
      r.fused = true;
      for (auto _ : st) benchmark::DoNotOptimize(export_glider(g, r));
      std::remove(r.step_path.c_str());
    })->Unit(benchmark::kMillisecond);
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
