#pragma once
// `candela bench`: ray throughput of the G-buffer pass and of shadow rays, next to raw Embree packet
// throughput on the same scene and rays, measured with Google Benchmark.
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace CLI {
class App;  // CLI11 (CLI/CLI.hpp), included where options are added: it costs ~8 s per translation unit
}

namespace candela {

struct BenchOptions {
  std::string suite = "rays";       // rays: ray throughput; samplers: light selection cost; restir: ReSTIR DI frame;
                                    // denoise: denoiser time; soak: a long restir + svgf run, NaN/Inf and memory
  std::vector<std::string> scenes;  // empty: the built-in scenes plus StainedGlassLamp when ../shared exists
  int width = 0, height = 0;        // 0: the suite's default (1280x720; soak: 64x36)
  int soak_frames = 10000;          // soak: frames to render
  int threads = 0;
  double min_time = 0.5;
  int repetitions = 3;
  double time_step = 0.0;  // restir: scene seconds between frames (0: every frame at time 0, a still scene)
  std::string filter = ".";
};

void add_bench_options(CLI::App& app, BenchOptions& options);
int run_bench(const BenchOptions& options);

// Medians over repetitions of what Google Benchmark measured, per benchmark name.
struct BenchResults {
  std::map<std::string, std::vector<double>> rays_per_second, ns_per_iteration;
  static double median(const std::map<std::string, std::vector<double>>& m, const std::string& name);
};
// Registers `name`: each iteration runs `body` once, which returns the rays it traced (rays/s counter).
void register_rays_benchmark(const std::string& name, const BenchOptions& options, std::function<uint64_t()> body);
// Runs every registered benchmark matching options.filter, printing Google Benchmark's table.
BenchResults run_registered_benchmarks(const BenchOptions& options);
// The samplers suite (bench_samplers.cpp).
int run_sampler_bench(const BenchOptions& options);
// The denoise suite (bench_denoise.cpp).
int run_denoise_bench(const BenchOptions& options);
// The restir suite (bench_restir.cpp).
int run_restir_bench(const BenchOptions& options);
// The soak suite (bench_soak.cpp); exits 1 when a non-finite pixel or a dropped NaN/Inf value was seen.
int run_soak_bench(const BenchOptions& options);

// Shared by the suites: the default scenes (built-ins, plus StainedGlassLamp when ../shared exists), a
// short name for a scene source, and primary rays through pixel centres in 4x4 packets through
// rtcIntersect16 alone (returns the rays traced).
class Tracer;
class Camera;
std::vector<std::string> default_bench_scenes();
std::string bench_scene_name(const std::string& source);
uint64_t raw_primary_packets(const Tracer& tracer, const Camera& camera);

}  // namespace candela
