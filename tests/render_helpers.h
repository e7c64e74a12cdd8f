#pragma once
// Rendering for the statistical tests, which must fail when a stage dropped a NaN or infinite value (a
// mean would otherwise hide it): render_paths (the reference path tracer alone) and render_checked (a
// Renderer's frame).
#include <gtest/gtest.h>

#include "apps/renderer.h"
#include "engine/path_batch.h"
#include "samplers/simple_samplers.h"

namespace candela::testing {

// Fails the current test for every stage of `stats` that dropped non-finite values.
inline void expect_all_finite(const FrameStats& stats) {
  for (const StageStats& s : stats.stages)
    EXPECT_EQ(s.non_finite, 0u) << "frame " << stats.frame << ": stage " << s.name << " dropped non-finite values";
}

// Renderer::render_frame, then expect_all_finite on its stats.
inline FrameStats render_checked(Renderer& renderer, int frame, float time, const CameraDesc& camera) {
  FrameStats stats = renderer.render_frame(frame, time, camera);
  expect_all_finite(stats);
  return stats;
}

// Per-pixel means of `spp` reference paths; fails the test if a path's radiance was not finite.

template <class Sampler = PowerLightSampler>
Image render_paths(const Scene& scene, const LightList& lights, int w, int h, int spp, int max_depth, uint64_t seed,
                   SampleSequence sequence = SampleSequence::Independent) {
  Tracer tracer(scene);
  Sampler sampler(lights);
  Camera camera(scene.default_camera(), w, h);
  SceneView view{scene, tracer, lights, camera};
  PathTracerParams params;
  params.spp = spp;
  params.max_depth = max_depth;
  params.seed = seed;
  params.sequence = sequence;
  Image sum(w, h);
  RayCounter rays;
  Counter non_finite;
  path_trace(view, sampler, params, 0, sum, rays, non_finite);
  EXPECT_EQ(non_finite.count.load(), 0u) << "path_trace dropped non-finite samples";
  for (vec3& p : sum.pixels) p /= float(spp);
  return sum;
}

template <class Sampler = PowerLightSampler>
Image render_paths(const Scene& scene, int w, int h, int spp, int max_depth, uint64_t seed,
                   SampleSequence sequence = SampleSequence::Independent) {
  return render_paths<Sampler>(scene, LightList(scene), w, h, spp, max_depth, seed, sequence);
}

}  // namespace candela::testing
