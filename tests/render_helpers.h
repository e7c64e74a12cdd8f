#pragma once
// Renders a small image with the reference path tracer for tests: per-pixel means of `spp` paths.
#include "engine/path_tracer.h"
#include "samplers/simple_samplers.h"

namespace candela::testing {

template <class Sampler = PowerLightSampler>
Image render_paths(const Scene& scene, const LightList& lights, int w, int h, int spp, int max_depth, uint64_t seed) {
  Tracer tracer(scene);
  Sampler sampler(lights);
  Camera camera(scene.default_camera(), w, h);
  SceneView view{scene, tracer, lights, camera};
  PathTracerParams params;
  params.spp = spp;
  params.max_depth = max_depth;
  params.seed = seed;
  Image sum(w, h);
  RayCounter rays;
  path_trace(view, sampler, params, 0, sum, rays);
  for (vec3& p : sum.pixels) p /= float(spp);
  return sum;
}

template <class Sampler = PowerLightSampler>
Image render_paths(const Scene& scene, int w, int h, int spp, int max_depth, uint64_t seed) {
  return render_paths<Sampler>(scene, LightList(scene), w, h, spp, max_depth, seed);
}

}  // namespace candela::testing
