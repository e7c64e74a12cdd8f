// `candela bench --suite restir`: one ReSTIR DI frame with the default parameters (light candidates from the
// default sampler, `auto`: the light tree's region tiles for restir-di, the power sampler for restir; temporal and one
// spatial pass, pairwise MIS, two shaded samples per pixel), still camera, after 8 warm-up frames (all at scene time
// 0, or with --time-step frame n at n steps: animated lights and instances move); next to it, the
// same frame's rays traced alone: its primary rays (4x4 packets through pixel centres), its BSDF-candidate rays and
// its shadow rays (single rays), generated before the clock starts. Then the whole ReSTIR frame, DI + GI (`--method
// restir`, paths up to 8 bounces), with its stages. For both methods, a frame's own queries recorded
// (engine/ray_log.h) and replayed alone: every packet and single ray as the frame traced it, the whole frame's and each
// stage's alone. The ratios frame / rays are what the stages between the rays cost; the summary gives them twice, from
// the benchmarks' medians and from rounds in which frames and their rays alternate (print_interleaved_ratios).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <functional>
#include <map>
#include <memory>

#include "apps/bench.h"
#include "apps/renderer.h"
#include "apps/scene_source.h"
#include "engine/parallel.h"
#include "engine/ray_log.h"

namespace candela {

namespace {

struct RestirBenchScene {
  Method method = Method::RestirDi;
  std::unique_ptr<Renderer> renderer;
  CameraDesc camera;
  int frame = 0;
  double time_step = 0.0;  // --time-step: frame n is rendered at scene time n * time_step
  std::vector<Ray> bsdf_rays, shadow_rays;
  RayLog log;                                           // one frame's queries, after the warm-up
  uint64_t frame_rays = 0;                              // the rays that frame counted in its stats
  std::map<std::string, std::vector<double>> stage_ms;  // per stage, one entry per measured frame
  std::string name;
};

// The next frame, at its scene time.
FrameStats render_next(RestirBenchScene& s) {
  const int frame = s.frame++;
  return s.renderer->render_frame(frame, float(frame * s.time_step), s.camera);
}

// The rays of the renderer's last frame, rebuilt from its G-buffer and final reservoirs: per hit pixel one
// BSDF-sampled ray (what each BSDF candidate traces) and one shadow ray to the final sample.
void capture_rays(RestirBenchScene& s) {
  const Renderer& r = *s.renderer;
  const GBuffer& g = r.gbuffer();
  const Camera camera(s.camera, g.width, g.height);
  for (size_t i = 0; i < g.size(); ++i) {
    if (!g.hit(i)) continue;
    ReuseReceiver receiver = exact_receiver(g, camera.position(), r.lights(), i);
    Rng rng = Rng::for_key(7, i, 0, 0xbe);
    BsdfSample bs;
    if (receiver.bsdf.sample(receiver.wo, vec2(rng.next_float(), rng.next_float()), rng.next_float(), bs))
      s.bsdf_rays.push_back(r.tracer().spawn_ray(receiver.position, receiver.geometric_normal, bs.wi));
    const ReuseReservoir& reservoir = r.di_reservoirs()[i];
    if (reservoir.W <= 0.0f) continue;
    LightSample ls = sample_contribution(receiver, reservoir.y).light;
    s.shadow_rays.push_back(shadow_ray(r.tracer(), receiver.position, receiver.geometric_normal, ls));
  }
}

uint64_t trace_alone(const RestirBenchScene& s) {
  const Tracer& tracer = s.renderer->tracer();
  const GBuffer& g = s.renderer->gbuffer();
  uint64_t rays = raw_primary_packets(tracer, Camera(s.camera, g.width, g.height));
  parallel_for_ranges(size_t(0), s.bsdf_rays.size(), size_t(1024), [&](size_t b, size_t e) {
    for (size_t k = b; k < e; ++k) benchmark::DoNotOptimize(tracer.intersect(s.bsdf_rays[k]));
  });
  parallel_for_ranges(size_t(0), s.shadow_rays.size(), size_t(1024), [&](size_t b, size_t e) {
    for (size_t k = b; k < e; ++k) benchmark::DoNotOptimize(tracer.occluded(s.shadow_rays[k]));
  });
  return rays + s.bsdf_rays.size() + s.shadow_rays.size();
}

// One more frame with its ray queries recorded into s.log.
void record_frame(RestirBenchScene& s) {
  s.renderer->set_ray_log(&s.log);
  s.frame_rays = render_next(s).rays();
  s.renderer->set_ray_log(nullptr);
}

// Wall-clock milliseconds of one call of `body`.
double time_ms(const std::function<void()>& body) {
  const auto start = std::chrono::steady_clock::now();
  body();
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

// Each stage's recorded rays replayed alone (median of 5 replays) beside the stage's median time: how much of the
// stage is its rays. Cost: 5 replays of the frame's rays.
void print_stage_replays(const RestirBenchScene& s) {
  std::printf("%-30s rays of each stage replayed alone / the stage, ms:", "");
  for (int k = 0; k < int(s.log.stages().size()); ++k) {
    if (s.log.rays(k) == 0) continue;
    std::vector<double> times;
    for (int rep = 0; rep < 5; ++rep) times.push_back(time_ms([&] { s.log.replay(s.renderer->tracer(), k); }));
    const std::string& name = s.log.stages()[size_t(k)];
    const auto stage = s.stage_ms.find(name);
    std::printf(" %s %.1f / %.1f", name.empty() ? "(no stage)" : name.c_str(), median(times),
                stage == s.stage_ms.end() ? 0.0 : median(stage->second));
  }
  std::printf("\n");
}

// The ratios again, from frames and replays that alternate: per round one frame, one replay of its rays (and for
// restir-di the rays alone), each timed once, and the median and range of the rounds' ratios. The benchmarks above run
// all repetitions of the frame before those of its rays, so a drift of the machine between them (up to 20% in a
// minute, docs/performance.md) moves their ratio; a round's two timings are a second apart. Cost: `rounds` frames and
// replays.
void print_interleaved_ratios(RestirBenchScene& s, int rounds) {
  const bool di = s.method == Method::RestirDi;
  std::vector<double> replayed, alone;
  for (int round = 0; round < rounds; ++round) {
    const double frame = time_ms([&] { render_next(s); });
    replayed.push_back(frame / time_ms([&] { s.log.replay(s.renderer->tracer()); }));
    if (di) alone.push_back(frame / time_ms([&] { benchmark::DoNotOptimize(trace_alone(s)); }));
  }
  auto print = [](const char* what, std::vector<double> ratios) {
    std::sort(ratios.begin(), ratios.end());
    std::printf(" %s %5.2f (%.2f-%.2f)", what, median(ratios), ratios.front(), ratios.back());
  };
  std::printf("%-30s interleaved (%d rounds; median, range):", "", rounds);
  print("frame / replayed", replayed);
  if (di) print("| frame / rays alone", alone);
  std::printf("\n");
}

// A renderer of `source` with `method` at the bench's size, after 8 warm-up frames of a still camera.
std::unique_ptr<RestirBenchScene> warm_scene(const std::string& source, Method method, const BenchOptions& o) {
  auto s = std::make_unique<RestirBenchScene>();
  s->method = method;
  s->name = bench_scene_name(source);
  RenderSettings settings;
  settings.width = o.width;
  settings.height = o.height;
  settings.method = method;
  settings.accumulate = false;
  Scene scene = load_scene(source);
  s->camera = scene.default_camera();
  s->renderer = std::make_unique<Renderer>(std::move(scene), settings);
  s->time_step = o.time_step;
  while (s->frame < 8) render_next(*s);
  return s;
}

}  // namespace

int run_restir_bench(const BenchOptions& o) {
  std::vector<std::string> sources = o.scenes.empty() ? default_bench_scenes() : o.scenes;
  std::vector<std::unique_ptr<RestirBenchScene>> scenes;
  for (const std::string& source : sources) {
    for (Method method : {Method::RestirDi, Method::Restir}) {
      scenes.push_back(warm_scene(source, method, o));
      RestirBenchScene* p = scenes.back().get();
      const std::string prefix = method == Method::Restir ? "restir_" : "restir_di_";
      register_rays_benchmark(prefix + "frame/" + p->name, o, [p] {
        FrameStats stats = render_next(*p);
        for (const StageStats& stage : stats.stages) p->stage_ms[stage.name].push_back(stage.ms);
        return stats.rays();
      });
      record_frame(*p);
      register_rays_benchmark(prefix + "rays_replayed/" + p->name, o,
                              [p] { return p->log.replay(p->renderer->tracer()); });
      if (method == Method::Restir) continue;
      capture_rays(*p);
      register_rays_benchmark("restir_di_rays_alone/" + p->name, o, [p] { return trace_alone(*p); });
    }
  }
  BenchResults results = run_registered_benchmarks(o);

  std::printf("\nSummary at %dx%d (medians of %d repetitions; stages: medians over all measured frames), ms:\n",
              o.width, o.height, o.repetitions);
  if (o.time_step > 0.0)
    std::printf("Frame n at scene time n x %g s: animated lights and instances move, the camera stays still.\n",
                o.time_step);
  for (const auto& s : scenes) {
    const bool di = s->method == Method::RestirDi;
    double frame =
        BenchResults::median(results.ns_per_iteration, (di ? "restir_di_frame/" : "restir_frame/") + s->name) * 1e-6;
    const double replayed =
        BenchResults::median(results.ns_per_iteration,
                             (di ? "restir_di_" : "restir_") + std::string("rays_replayed/") + s->name) *
        1e-6;
    std::printf("%-20s %-9s frame %8.1f | rays replayed %7.1f (%llu recorded, %llu counted) | frame / replayed %5.2f |",
                s->name.c_str(), di ? "restir-di" : "restir", frame, replayed, (unsigned long long)s->log.rays(),
                (unsigned long long)s->frame_rays, replayed > 0.0 ? frame / replayed : 0.0);
    if (di) {
      double alone = BenchResults::median(results.ns_per_iteration, "restir_di_rays_alone/" + s->name) * 1e-6;
      std::printf(" its rays alone %7.1f | frame / rays %5.2f |", alone, alone > 0.0 ? frame / alone : 0.0);
    }
    for (const auto& [stage, ms] : s->stage_ms) std::printf(" %s %.1f", stage.c_str(), median(ms));
    std::printf("\n");
    print_stage_replays(*s);
    print_interleaved_ratios(*s, 7);
    if (s->time_step > 0.0)
      std::printf("%-30s %d frames rendered, the last at scene time %.2f s\n", "", s->frame,
                  (s->frame - 1) * s->time_step);
  }
  return 0;
}

}  // namespace candela
