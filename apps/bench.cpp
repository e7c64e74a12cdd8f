#include "apps/bench.h"

#include <CLI/CLI.hpp>
#include <benchmark/benchmark.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>

#include "apps/scene_source.h"
#include "engine/camera.h"
#include "engine/gbuffer.h"
#include "engine/lights.h"
#include "engine/rng.h"
#include "engine/simd_targets.h"
#include "engine/surface.h"
#include "engine/tiles.h"
#include "engine/tracer.h"

namespace candela {

void add_bench_options(CLI::App& app, BenchOptions& o) {
  app.add_option(
         "--suite", o.suite,
         "rays: primary/shadow ray throughput per scene; samplers: light selection cost (per sample, pmf and "
         "region-tile entry) and light tree build/refit; "
         "restir: a ReSTIR DI frame and its stages next to its own rays traced alone (use --width 640 --height 360); "
         "denoise: cross-bilateral and SVGF time per frame at 640x360 and 1280x720; soak: --frames frames of "
         "restir + svgf on builtin:city with an orbiting camera, counting non-finite pixels and reporting VmRSS")
      ->check(CLI::IsMember({"rays", "samplers", "restir", "denoise", "soak"}))
      ->capture_default_str();
  app.add_option("--scenes", o.scenes,
                 "Scenes to measure (default: builtin:cornell builtin:manylights builtin:city "
                 "and StainedGlassLamp from ../shared/scenes when present)");
  app.add_option("--width", o.width, "Image width (default 1280; soak: 64)")->check(CLI::Range(16, 16384));
  app.add_option("--height", o.height, "Image height (default 720; soak: 36)")->check(CLI::Range(16, 16384));
  app.add_option("--frames", o.soak_frames, "soak: frames to render")
      ->check(CLI::Range(1, 100000000))
      ->capture_default_str();
  app.add_option("--threads", o.threads, "Worker threads; 0 = all cores")
      ->check(CLI::Range(0, 1024))
      ->capture_default_str();
  app.add_option("--min-time", o.min_time, "Minimum seconds per benchmark repetition")
      ->check(CLI::Range(0.01, 600.0))
      ->capture_default_str();
  app.add_option("--repetitions", o.repetitions, "Repetitions; the summary quotes medians")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  app.add_option("--time-step", o.time_step,
                 "restir: scene seconds between frames, so that animated lights and instances move (the camera "
                 "stays still; 0: every frame at time 0)")
      ->check(CLI::Range(0.0, 3600.0))
      ->capture_default_str();
  app.add_option("--filter", o.filter, "Regular expression selecting benchmarks by name")->capture_default_str();
}

std::vector<std::string> default_bench_scenes() {
  std::vector<std::string> s = {"builtin:cornell", "builtin:manylights", "builtin:city"};
  std::string lamp = std::string(CANDELA_SHARED_SCENES) + "/StainedGlassLamp/glTF-JPG-PNG/StainedGlassLamp.gltf";
  if (std::filesystem::exists(lamp)) s.push_back(lamp);
  return s;
}

std::string bench_scene_name(const std::string& source) {
  if (source.rfind("builtin:", 0) == 0) return source.substr(8);
  return std::filesystem::path(source).stem().string();
}

// Primary rays of the whole image in 4x4 packets through rtcIntersect16 only: the raw Embree ceiling.
uint64_t raw_primary_packets(const Tracer& tracer, const Camera& cam) {
  RayCounter rays;
  for_each_tile(cam.width(), cam.height(), [&](const Tile& tile) {
    RayPacket16 packet;
    uint64_t n = 0;
    for (int by = tile.y0; by < tile.y1; by += 4)
      for (int bx = tile.x0; bx < tile.x1; bx += 4) {
        for (int lane = 0; lane < 16; ++lane) {
          int x = bx + (lane & 3), y = by + (lane >> 2);
          if (x >= tile.x1 || y >= tile.y1) {
            packet.set_inactive(lane);
            continue;
          }
          packet.set(lane, Ray{cam.position(), cam.direction(x + 0.5f, y + 0.5f), 0.0f, kInfinity});
          ++n;
        }
        tracer.intersect16(packet, true);
        benchmark::DoNotOptimize(packet.rayhit.hit.primID[0]);
      }
    rays.add(n);
  });
  return rays.count.load();
}

namespace {

// A loaded scene with its tracer, lights, camera and the primary hits used as shadow-ray origins.
struct BenchScene {
  Scene scene;
  std::unique_ptr<Tracer> tracer;
  std::unique_ptr<LightList> lights;
  Camera camera;
  GBuffer gbuffer;
  GBuffer packed_gbuffer;  // the gbuffer_packed benchmark's
};

// One shadow ray per G-buffer hit towards a point on a light chosen by pixel hash (uniformly);
// packets of 16 (rtcOccluded16) or single rays (rtcOccluded1).
uint64_t shadow_rays(const BenchScene& s, bool packets) {
  RayCounter rays;
  const GBuffer& g = s.gbuffer;
  size_t light_count = s.lights->size();
  if (light_count == 0) return 0;
  for_each_tile(g.width, g.height, [&](const Tile& tile) {
    RayPacket16 packet;
    int lane = 0;
    uint64_t n = 0;
    auto flush = [&] {
      for (int k = lane; k < 16; ++k) packet.set_inactive(k);
      s.tracer->occluded16(packet);
      benchmark::DoNotOptimize(packet.rayhit.ray.tfar[0]);
      lane = 0;
    };
    for (int y = tile.y0; y < tile.y1; ++y)
      for (int x = tile.x0; x < tile.x1; ++x) {
        size_t i = size_t(y) * g.width + x;
        if (!g.hit(i)) continue;
        Rng rng = Rng::for_key(3, i, 0, 0x5d);
        size_t light = std::min(size_t(rng.next_float() * light_count), light_count - 1);
        LightSample ls = s.lights->sample(s.scene, light, g.position[i], vec2(rng.next_float(), rng.next_float()));
        if (ls.distance <= 0.0f) continue;
        Ray ray = shadow_ray(*s.tracer, g.position[i], g.geometric_normal[i], ls);
        ++n;
        if (!packets) {
          benchmark::DoNotOptimize(s.tracer->occluded(ray));
          continue;
        }
        packet.set(lane++, ray);
        if (lane == 16) flush();
      }
    if (packets && lane > 0) flush();
    rays.add(n);
  });
  return rays.count.load();
}

}  // namespace

void register_rays_benchmark(const std::string& name, const BenchOptions& o, std::function<uint64_t()> body) {
  benchmark::RegisterBenchmark(name.c_str(),
                               [body](benchmark::State& state) {
                                 uint64_t rays = 0;
                                 for (auto _ : state) rays += body();
                                 state.counters["rays/s"] =
                                     benchmark::Counter(double(rays), benchmark::Counter::kIsRate);
                               })
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime()
      ->MinTime(o.min_time)
      ->Repetitions(o.repetitions);
}

namespace {

// Remembers every repetition so the summary can quote medians and ratios from this one process.
class CollectingReporter : public benchmark::ConsoleReporter {
 public:
  explicit CollectingReporter(OutputOptions options, BenchResults& results)
      : ConsoleReporter(options), results_(results) {}
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& run : runs) {
      if (run.run_type != Run::RT_Iteration || run.iterations == 0) continue;
      std::string name = run.run_name.function_name;
      results_.ns_per_iteration[name].push_back(run.real_accumulated_time * 1e9 / double(run.iterations));
      auto it = run.counters.find("rays/s");
      if (it != run.counters.end()) results_.rays_per_second[name].push_back(it->second.value);
    }
    ConsoleReporter::ReportRuns(runs);
  }

 private:
  BenchResults& results_;
};

}  // namespace

double BenchResults::median(const std::map<std::string, std::vector<double>>& m, const std::string& name) {
  auto it = m.find(name);
  if (it == m.end() || it->second.empty()) return 0.0;
  std::vector<double> v = it->second;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

BenchResults run_registered_benchmarks(const BenchOptions& o) {
  std::string filter_flag = "--benchmark_filter=" + o.filter;
  // Every repetition of every benchmark in one random order: drift of a shared machine then hits all benchmarks
  // alike instead of whichever ran during it, which keeps the summary's ratios (G-buffer / raw rays, frame / rays
  // alone) from moving with it.
  char interleave[] = "--benchmark_enable_random_interleaving=true";
  int argc = 3;
  char arg0[] = "candela";
  char* argv[] = {arg0, filter_flag.data(), interleave, nullptr};
  benchmark::Initialize(&argc, argv);
  BenchResults results;
  CollectingReporter reporter(
      isatty(fileno(stdout)) ? benchmark::ConsoleReporter::OO_Defaults : benchmark::ConsoleReporter::OO_Tabular,
      results);
  benchmark::RunSpecifiedBenchmarks(&reporter);
  benchmark::Shutdown();
  return results;
}

// The processor's name as Linux reports it (/proc/cpuinfo's first "model name"), or "an unnamed CPU": ratios such as
// frame / rays differ between machines (docs/performance.md), so every run says which one it measured.
static std::string cpu_model() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  for (std::string line; std::getline(cpuinfo, line);)
    if (line.rfind("model name", 0) == 0 && line.find(':') != std::string::npos) {
      const size_t value = line.find_first_not_of(" \t", line.find(':') + 1);
      if (value != std::string::npos) return line.substr(value);
    }
  return "an unnamed CPU";
}

int run_bench(const BenchOptions& options) {
  // Image size: the suite's default unless given.
  BenchOptions o = options;
  if (o.width == 0) o.width = o.suite == "soak" ? 64 : 1280;
  if (o.height == 0) o.height = o.suite == "soak" ? 36 : 720;
  std::fprintf(stderr, "SIMD kernels run with %s on %s\n", simd_target_name(), cpu_model().c_str());
  if (o.suite == "soak") return run_soak_bench(o);
  if (o.suite == "samplers") return run_sampler_bench(o);
  if (o.suite == "restir") return run_restir_bench(o);
  if (o.suite == "denoise") return run_denoise_bench(o);
  std::vector<std::string> sources = o.scenes.empty() ? default_bench_scenes() : o.scenes;
  std::vector<std::unique_ptr<BenchScene>> scenes;
  for (const std::string& source : sources) {
    auto s = std::make_unique<BenchScene>();
    s->scene = load_scene(source);
    s->tracer = std::make_unique<Tracer>(s->scene);
    s->lights = std::make_unique<LightList>(s->scene);
    s->camera = Camera(s->scene.default_camera(), o.width, o.height);
    RayCounter unused;
    trace_gbuffer(s->scene, *s->tracer, s->camera, s->camera, GBufferParams{1, 0, false}, s->gbuffer, unused);
    // The packed benchmark's own G-buffer touched before the clock too: cold, its first pass at 1280x720 took ~0.3
    // s of page faults, and Google Benchmark then sized every repetition to that one iteration.
    GBufferParams packed{1, 0, true};
    packed.packed = true;
    trace_gbuffer(s->scene, *s->tracer, s->camera, s->camera, packed, s->packed_gbuffer, unused);
    std::fprintf(stderr, "%s: %zu triangles, %zu lights\n", source.c_str(), s->scene.triangle_count(),
                 s->lights->size());
    scenes.push_back(std::move(s));
  }
  std::vector<std::string> names;
  for (size_t k = 0; k < scenes.size(); ++k) {
    BenchScene* s = scenes[k].get();
    std::string name = bench_scene_name(sources[k]);
    names.push_back(name);
    auto add = [&](const std::string& kind, std::function<uint64_t()> body) {
      register_rays_benchmark(kind + "/" + name, o, std::move(body));
    };
    add("raw_intersect16", [s] { return raw_primary_packets(*s->tracer, s->camera); });
    add("gbuffer", [s] {
      RayCounter rays;
      trace_gbuffer(s->scene, *s->tracer, s->camera, s->camera, GBufferParams{1, 0, true}, s->gbuffer, rays);
      return rays.count.load();
    });
    add("gbuffer_packed", [s] {  // as ReSTIR runs it: with the packed surfaces
      RayCounter rays;
      GBufferParams params{1, 0, true};
      params.packed = true;
      trace_gbuffer(s->scene, *s->tracer, s->camera, s->camera, params, s->packed_gbuffer, rays);
      return rays.count.load();
    });
    add("shadow_occluded16", [s] { return shadow_rays(*s, true); });
    add("shadow_occluded1", [s] { return shadow_rays(*s, false); });
  }
  BenchResults results = run_registered_benchmarks(o);

  std::printf("\nSummary at %dx%d (medians of %d repetitions, Mrays/s):\n", o.width, o.height, o.repetitions);
  std::printf("%-20s %12s %10s %12s %12s %12s %12s\n", "scene", "raw_isect16", "gbuffer", "raw/gbuffer", "raw/packed",
              "occluded16", "occluded1");
  for (const std::string& name : names) {
    auto rate = [&](const std::string& kind) {
      return BenchResults::median(results.rays_per_second, kind + "/" + name) * 1e-6;
    };
    double raw = rate("raw_intersect16"), gb = rate("gbuffer"), packed = rate("gbuffer_packed");
    std::printf("%-20s %12.2f %10.2f %12.2f %12.2f %12.2f %12.2f\n", name.c_str(), raw, gb, gb > 0 ? raw / gb : 0.0,
                packed > 0 ? raw / packed : 0.0, rate("shadow_occluded16"), rate("shadow_occluded1"));
  }
  return 0;
}

}  // namespace candela
