// `candela bench --suite samplers`: cost of light selection (ns per sample, per pmf and per entry of a region
// light tile) at 1e2..1e6 lights, the light tree's build and refit times, and the random numbers of one direct-light
// path from each sample stream.
#include <benchmark/benchmark.h>

#include <chrono>
#include <map>
#include <memory>

#include "apps/bench.h"
#include "engine/builtin_scenes.h"
#include "engine/rng.h"
#include "engine/sobol.h"
#include "restir/light_tiles.h"
#include "samplers/light_tree.h"
#include "samplers/simple_samplers.h"

namespace candela {

namespace {

// builtin:manylights with `count` emissive triangles (two per ceiling quad) and shading points in it.
struct SamplerScene {
  Scene scene;
  std::unique_ptr<LightList> lights;
  std::vector<ShadingContext> points;
  // animated: every instance marked so, so that every light is LightList::movable (what a refit visits).
  explicit SamplerScene(int count, bool animated = false) : scene(make_manylights_scene(std::max(1, count / 2), 7)) {
    for (Instance& instance : scene.instances) instance.animated = animated;
    lights = std::make_unique<LightList>(scene);
    Rng rng(5, 5);
    Bounds3 b = scene.bounds();
    for (int k = 0; k < 1024; ++k) {
      vec3 p = b.lo + (b.hi - b.lo) * vec3(rng.next_float(), rng.next_float() * 0.9f, rng.next_float());
      points.push_back({p, vec3(0.0f, 1.0f, 0.0f)});
    }
  }
};

constexpr int kTileEntries = LightTiles::kRegionTileSize;

template <class Sampler>
void register_sampler(const std::string& name, const SamplerScene& s, const BenchOptions& o) {
  auto sampler = std::make_shared<Sampler>(*s.lights);
  std::string n = std::to_string(s.lights->size());
  auto configure = [&](benchmark::internal::Benchmark* b) {
    b->MinTime(o.min_time)->Repetitions(o.repetitions)->UseRealTime()->Unit(benchmark::kNanosecond)->Threads(1);
  };
  configure(benchmark::RegisterBenchmark(("sample/" + name + "/" + n).c_str(), [sampler, &s](benchmark::State& state) {
    Rng rng(1, 2);
    size_t k = 0;
    for (auto _ : state) {
      SampledLight l = sampler->sample(s.points[k++ & 1023], vec2(rng.next_float(), rng.next_float()));
      benchmark::DoNotOptimize(l);
    }
  }));
  // A region light tile's draw (restir/light_tiles.h): 128 stratified lights for one region (a shading point's
  // sphere of radius 0.5, any orientation) in one sample_lights call; the summary divides its time by 128.
  configure(benchmark::RegisterBenchmark(("tile/" + name + "/" + n).c_str(), [sampler, &s](benchmark::State& state) {
    Rng rng(3, 4);
    std::vector<vec2> u(kTileEntries);
    std::vector<SampledLight> out(kTileEntries);
    size_t k = 0;
    for (auto _ : state) {
      for (int e = 0; e < kTileEntries; ++e)
        u[size_t(e)] = vec2(stratified_uniform(e, kTileEntries, rng.next_float()), rng.next_float());
      const ShadingContext region{s.points[k++ & 1023].position, vec3(0.0f), 0.5f};
      sample_lights(*sampler, region, u.data(), out.data(), kTileEntries);
      benchmark::DoNotOptimize(out.data());
    }
  }));
  configure(benchmark::RegisterBenchmark(("pmf/" + name + "/" + n).c_str(), [sampler, &s](benchmark::State& state) {
    size_t k = 0;
    uint32_t count = uint32_t(s.lights->size());
    for (auto _ : state) {
      float p = sampler->pmf(s.points[k & 1023], uint32_t((k * 2654435761u) % count));
      ++k;
      benchmark::DoNotOptimize(p);
    }
  }));
}

// The numbers one direct-light path draws (film, light choice, point on the light, BSDF direction: 2D;
// lobe: 1D) from a new stream per path, as path_trace makes them.
template <class MakeStream>
void register_stream(const std::string& name, const BenchOptions& o, MakeStream make) {
  benchmark::RegisterBenchmark(("stream/" + name).c_str(),
                               [make](benchmark::State& state) {
                                 uint32_t k = 0;
                                 for (auto _ : state) {
                                   auto stream = make(k++);
                                   vec2 sum = stream.next_2d() + stream.next_2d() + stream.next_2d() + stream.next_2d();
                                   sum.x += stream.next_float();
                                   benchmark::DoNotOptimize(sum);
                                 }
                               })
      ->MinTime(o.min_time)
      ->Repetitions(o.repetitions)
      ->UseRealTime()
      ->Unit(benchmark::kNanosecond);
}

}  // namespace

int run_sampler_bench(const BenchOptions& o) {
  std::vector<std::unique_ptr<SamplerScene>> keep;
  for (int count : {100, 1000, 10000, 100000, 1000000}) {
    keep.push_back(std::make_unique<SamplerScene>(count));
    const SamplerScene& s = *keep.back();
    register_sampler<UniformLightSampler>("uniform", s, o);
    register_sampler<PowerLightSampler>("power", s, o);
    register_sampler<LightTreeSampler>("tree", s, o);
  }
  // Build over the largest list; refit of a 100k-light tree where every light may move (a refit visits only
  // the paths above movable lights: a still light costs it nothing).
  const SamplerScene& big = *keep[keep.size() - 1];
  benchmark::RegisterBenchmark(("tree_build/" + std::to_string(big.lights->size())).c_str(),
                               [&big](benchmark::State& state) {
                                 for (auto _ : state)
                                   benchmark::DoNotOptimize(LightTreeSampler(*big.lights).node_count());
                               })
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime()
      ->Repetitions(o.repetitions)
      ->Iterations(1);
  const auto moving_scene = std::make_unique<SamplerScene>(100000, true);
  const SamplerScene& all_moving = *moving_scene;
  auto tree = std::make_shared<LightTreeSampler>(*all_moving.lights);
  benchmark::RegisterBenchmark(("tree_refit/" + std::to_string(all_moving.lights->size())).c_str(),
                               [tree, &all_moving](benchmark::State& state) {
                                 for (auto _ : state) tree->refit(*all_moving.lights);
                               })
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime()
      ->Repetitions(o.repetitions)
      ->MinTime(o.min_time);

  register_stream("independent", o, [](uint32_t k) { return Rng::for_key(1, k >> 4, k & 15u, 0); });
  register_stream("sobol", o, [](uint32_t k) { return SobolStream::for_pixel(1, k >> 4, 0, k & 15u); });
  register_stream("zsobol", o, [](uint32_t k) {
    return SobolStream::for_screen(1, 0, zsobol_index(k >> 4 & 511u, k >> 13, 4, k & 15u));
  });

  BenchResults r = run_registered_benchmarks(o);
  std::printf("\nSummary (medians of %d repetitions, ns per call; tile: per entry of a %d-entry region tile):\n%-10s",
              o.repetitions, kTileEntries, "lights");
  for (const char* k : {"uniform", "power", "tree"})
    std::printf(" %12s %12s %12s", (std::string(k) + " smp").c_str(), (std::string(k) + " pmf").c_str(),
                (std::string(k) + " tile").c_str());
  std::printf("\n");
  for (const auto& s : keep) {
    std::string n = std::to_string(s->lights->size());
    std::printf("%-10s", n.c_str());
    for (const char* k : {"uniform", "power", "tree"})
      std::printf(" %12.1f %12.1f %12.1f",
                  BenchResults::median(r.ns_per_iteration, std::string("sample/") + k + "/" + n),
                  BenchResults::median(r.ns_per_iteration, std::string("pmf/") + k + "/" + n),
                  BenchResults::median(r.ns_per_iteration, std::string("tile/") + k + "/" + n) / kTileEntries);
    std::printf("\n");
  }
  std::printf(
      "tree build over %zu lights: %.0f ms; refit of %zu lights that all move: %.2f ms\n", big.lights->size(),
      BenchResults::median(r.ns_per_iteration, "tree_build/" + std::to_string(big.lights->size())) * 1e-6,
      all_moving.lights->size(),
      BenchResults::median(r.ns_per_iteration, "tree_refit/" + std::to_string(all_moving.lights->size())) * 1e-6);
  std::printf(
      "random numbers of one direct-light path (4 x 2D + 1D, new stream): independent %.1f ns, sobol %.1f ns, "
      "zsobol %.1f ns\n",
      BenchResults::median(r.ns_per_iteration, "stream/independent"),
      BenchResults::median(r.ns_per_iteration, "stream/sobol"),
      BenchResults::median(r.ns_per_iteration, "stream/zsobol"));
  LightTreeSampler big_tree(*big.lights);
  std::printf("tree over %zu lights: %zu nodes of %d children in %d levels, %.1f bytes per light\n", big.lights->size(),
              big_tree.node_count(), kTreeWidth, big_tree.depth(),
              double(big_tree.memory_bytes()) / double(big.lights->size()));
  return 0;
}

}  // namespace candela
