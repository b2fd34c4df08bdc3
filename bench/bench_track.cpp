// Issue 8 benchmark: tracking speed on 1280 x 720 video, calibration time.
//
// A 10 s synthetic video (300 frames at 30 fps, MJPG, three launches of a
// training glider seen from 4.5 m) is rendered once into /tmp; then
//   detect/background, detect/marker   decoding + detection of every frame
//                                      (counter frames_per_second; real time is 30)
//   track_flights                      association, pitch, CG, uncertainty
//   calibrate/N                        calibration from N reference points
//                                      (distortion chosen by leave-one-out)
// Target: tracking faster than real time (> 30 frames/s) on the 2-core machine.
// Run: build/bench/bench_track [--benchmark_repetitions=3]
#include <benchmark/benchmark.h>

#include <cstdio>
#include <string>
#include <unistd.h>

#include "pteromys/capture_render.hpp"
#include "pteromys/flight.hpp"
#include "pteromys/io.hpp"
#include "pteromys/track.hpp"

using namespace pteromys;
using namespace pteromys::capture;

namespace {

struct Video {
  std::string path;
  Calibration truth, calib;
  Glider glider;
  int frames = 0;
};

const Video& video() {
  static Video v = [] {
    Video r;
    r.glider = load_glider(std::string(PTEROMYS_SOURCE_DIR) + "/examples/training/t04-tapered-mild.glider.json");
    const MountedGlider mg = mount(r.glider, default_model());
    std::vector<KnownFlight> flights;
    for (const auto& [sp, cl] : std::vector<std::pair<double, double>>{{7.5, 6}, {9, 3}, {11, 0}}) {
      Launch l;
      l.speed = sp;
      l.climb_deg = cl;
      SimOptions so;
      so.t_max = 1.6;
      const Flight f = simulate(QuasiStaticAero(mg), {mg.mass().mass, mg.mass().inertia}, l, so);
      KnownFlight k;
      for (const auto& s : f.samples) k.t.push_back(s.t), k.x.push_back(s.x), k.y.push_back(s.y), k.pitch.push_back(s.pitch);
      flights.push_back(k);
    }
    SyntheticCamera cam;
    cam.position = {3.0, 1.5, 4.5};
    r.truth = synthetic_calibration(cam);
    RenderOptions ro;
    ro.gap_frames = 40;
    ro.lead_frames = 30;
    // pad to 300 frames (10 s) with the tail
    ro.tail_frames = 0;
    r.path = "/tmp/pteromys-bench-track-" + std::to_string(::getpid()) + ".avi";
    RenderResult rr = render_video(r.path, r.truth, r.glider, flights, ro);
    if (rr.frames < 300) {
      ro.tail_frames = 300 - rr.frames;
      rr = render_video(r.path, r.truth, r.glider, flights, ro);
    }
    r.frames = rr.frames;
    r.calib = calibrate(synthetic_reference_points(r.truth, 4, 3, 0.3, 1, 0.001, 4.5));
    std::printf("video: %s, %d frames 1280x720 at 30 fps (%.1f s), rendered in %.1f s\n", r.path.c_str(), rr.frames,
                rr.frames / 30.0, rr.seconds);
    return r;
  }();
  return v;
}

void detect_bench(benchmark::State& st, Detector det) {
  const Video& v = video();
  DetectOptions o;
  o.detector = det;
  double frames = 0, seconds = 0;
  for (auto _ : st) {
    const Detections d = detect(v.path, o);
    frames += d.frames.size();
    seconds += d.seconds;
    benchmark::DoNotOptimize(d.frames.size());
  }
  st.counters["frames_per_second"] = frames / seconds;
  st.counters["real_time_factor"] = frames / seconds / 30.0;
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::RegisterBenchmark("detect/background", [](benchmark::State& st) { detect_bench(st, Detector::Background); })
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime();
  benchmark::RegisterBenchmark("detect/marker", [](benchmark::State& st) { detect_bench(st, Detector::Marker); })
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime();
  benchmark::RegisterBenchmark("track_flights", [](benchmark::State& st) {
    const Video& v = video();
    const Detections d = detect(v.path, {});
    std::size_t n = 0;
    for (auto _ : st) {
      const TrackResult r = track_flights(d, v.calib, v.glider, {});
      n = r.flights.size();
      benchmark::DoNotOptimize(n);
    }
    st.counters["flights"] = static_cast<double>(n);
  })->Unit(benchmark::kMillisecond);
  for (const auto& [nx, ny] : std::vector<std::pair<int, int>>{{2, 2}, {4, 3}, {6, 5}}) {
    benchmark::RegisterBenchmark(("calibrate/" + std::to_string(nx * ny) + "_points").c_str(), [nx = nx, ny = ny](benchmark::State& st) {
      const Video& v = video();
      const CalibrationInput in = synthetic_reference_points(v.truth, nx, ny, 0.3, 1, 0.001, 4.5);
      for (auto _ : st) benchmark::DoNotOptimize(calibrate(in).rms_px);
    })->Unit(benchmark::kMillisecond);
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  std::remove(video().path.c_str());
  return 0;
}
