// `candela bench --suite denoise`: wall time of the cross-bilateral filter and of SVGF (steady state: a
// still camera, the history full; with the 3x3 a-trous kernel, the default, and with the paper's 5x5) on a
// rendered builtin:cornell frame at 640x360 and 1280x720.
#include <benchmark/benchmark.h>

#include <memory>

#include "apps/bench.h"
#include "apps/renderer.h"
#include "denoise/denoiser.h"
#include "engine/builtin_scenes.h"

namespace candela {

namespace {

// One noisy frame (direct light, 1 spp) and its G-buffer.
struct DenoiseFrame {
  GBuffer gbuffer;
  Image noisy;
  std::string size;
  DenoiseFrame(int w, int h) : size(std::to_string(w) + "x" + std::to_string(h)) {
    RenderSettings settings;
    settings.width = w;
    settings.height = h;
    settings.method = Method::Direct;
    Scene scene = make_cornell_scene();
    CameraDesc camera = scene.default_camera();
    Renderer renderer(std::move(scene), settings);
    renderer.render_frame(0, 0.0f, camera);
    gbuffer = renderer.gbuffer();
    noisy = renderer.image();
  }
};

// Registers `kind` on `frame`. The denoiser and its output image live as long as the benchmark, as a frame loop
// keeps them, and are warmed up first: SVGF's history is full and every plane touched before the clock starts. (A
// cold first frame at 1280x720 takes ~0.4 s, mostly first-touch page faults; Google Benchmark then sized every
// repetition to one iteration, and each paid a fresh output image's faults: 57-98 ms against a steady 35-40.)
void register_denoiser(const std::string& name, const DenoiserParams& params, const DenoiseFrame& frame,
                       const BenchOptions& o) {
  auto denoiser = std::make_shared<Denoiser>(params);
  auto out = std::make_shared<Image>();
  for (int warm_up = 0; warm_up < 4; ++warm_up) {
    FrameStats stats;
    denoiser->denoise(frame.gbuffer, frame.gbuffer, frame.noisy, stats, *out);
  }
  benchmark::RegisterBenchmark((name + "/" + frame.size).c_str(),
                               [denoiser, out, &frame](benchmark::State& state) {
                                 FrameStats stats;
                                 for (auto _ : state) {
                                   denoiser->denoise(frame.gbuffer, frame.gbuffer, frame.noisy, stats, *out);
                                   benchmark::DoNotOptimize(out->pixels.data());
                                 }
                               })
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime()
      ->MinTime(o.min_time)
      ->Repetitions(o.repetitions);
}

// Per-stage milliseconds of `kind`, medians over 21 frames after 4 warm-up frames.
void print_stages(DenoiserKind kind, const DenoiseFrame& frame) {
  Denoiser denoiser(DenoiserParams{kind});
  std::map<std::string, std::vector<double>> ms;
  Image out;
  for (int f = 0; f < 25; ++f) {
    FrameStats stats;
    denoiser.denoise(frame.gbuffer, frame.gbuffer, frame.noisy, stats, out);
    if (f >= 4)
      for (const StageStats& s : stats.stages) ms[s.name].push_back(s.ms);
  }
  for (const auto& [name, values] : ms) std::printf("  %-20s %8.2f ms\n", name.c_str(), BenchResults::median(ms, name));
}

}  // namespace

int run_denoise_bench(const BenchOptions& o) {
  std::vector<std::unique_ptr<DenoiseFrame>> frames;
  frames.push_back(std::make_unique<DenoiseFrame>(640, 360));
  frames.push_back(std::make_unique<DenoiseFrame>(1280, 720));
  for (const auto& f : frames) {
    register_denoiser("bilateral", DenoiserParams{DenoiserKind::Bilateral}, *f, o);
    register_denoiser("svgf", DenoiserParams{DenoiserKind::Svgf}, *f, o);
    DenoiserParams svgf5{DenoiserKind::Svgf};
    svgf5.svgf.atrous_radius = 2;
    register_denoiser("svgf5x5", svgf5, *f, o);
  }
  BenchResults r = run_registered_benchmarks(o);
  std::printf("\nSummary (medians of %d repetitions, ms per frame):\n%-12s %12s %12s %12s\n", o.repetitions, "size",
              "bilateral", "svgf", "svgf 5x5");
  for (const auto& f : frames)
    std::printf("%-12s %12.2f %12.2f %12.2f\n", f->size.c_str(),
                BenchResults::median(r.ns_per_iteration, "bilateral/" + f->size) * 1e-6,
                BenchResults::median(r.ns_per_iteration, "svgf/" + f->size) * 1e-6,
                BenchResults::median(r.ns_per_iteration, "svgf5x5/" + f->size) * 1e-6);
  for (const auto& f : frames)
    for (DenoiserKind kind : {DenoiserKind::Bilateral, DenoiserKind::Svgf}) {
      std::printf("stages of %s at %s (medians over 21 frames):\n", kind == DenoiserKind::Svgf ? "svgf" : "bilateral",
                  f->size.c_str());
      print_stages(kind, *f);
    }
  return 0;
}

}  // namespace candela
