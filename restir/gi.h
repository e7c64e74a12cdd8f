#pragma once
// ReSTIR GI (Ouyang et al. 2021, "ReSTIR GI: Path Resampling for Real-Time Path Tracing"): per pixel, one
// BSDF-sampled ray from the visible point x_v to a sample point x_s, whose outgoing radiance towards x_v is
// estimated by path tracing (NEE with the light sampler, Russian roulette; the emission of x_s itself is
// direct light, left to ReSTIR DI so nothing is counted twice). The sample is stored as a surface-point
// sample (DiSample with light = kSurfacePointSample: position, normal facing x_v, radiance), so ReSTIR
// DI's reuse stages, bias corrections, boiling filter, visibility reuse and shading apply unchanged. The
// target at a receiver is the luminance of f L_o |cos_v| |cos_s| / d^2, the sample's contribution in the
// area measure of x_s: moving a sample to another receiver changes that area factor exactly by the
// reconnection Jacobian (the paper's eq. 11), so the Jacobian is part of the target and of W. The
// paper's approximation stays: x_s is taken to send L_o to every receiver (exact for diffuse x_s).
#include "engine/path_batch.h"
#include "restir/di.h"

namespace candela {

struct GiParams {
  int max_depth = 8;       // bounces counted from the camera, as the path tracer's --max-depth (2: one
                           // indirect bounce); below 2 there is no indirect light
  int rr_start_depth = 3;  // Russian roulette from this bounce on
  uint64_t seed = 0;
};

// Stage "gi_samples": reads the G-buffer (exact surface: BSDF sampling) and packed surfaces (target);
// writes one reservoir per pixel holding its sample point, M = 1 and W = 1 / p_area(x_s) with p_area the
// BSDF's solid-angle density times |cos_s| / d^2; a path whose radiance is not finite leaves an empty
// reservoir and is counted in `non_finite`. Cost: one path per pixel (about 1 + 2 x bounces rays), a tile's
// paths traced together with their rays in packets (engine/path_batch.h).
template <LightSampler S>
void gi_initial_samples(const SceneView& view, const S& sampler, const GBuffer& g, const DiDomain& domain,
                        const GiParams& params, int frame, std::vector<DiReservoir>& out, RayCounter& rays,
                        Counter& non_finite) {
  if (params.max_depth < 2) {
    out.assign(g.size(), DiReservoir{});
    return;
  }
  out.resize(g.size());  // every pixel is written below (in parallel, where a fill here ran on one thread)
  PathTracerParams path;
  path.max_depth = params.max_depth;
  path.rr_start_depth = params.rr_start_depth;
  // What a path's reservoir needs of its start.
  struct Start {
    size_t pixel;
    vec3 position;  // x_v
    float pdf;      // the BSDF's solid-angle density of the first ray
    vec2 tag;
    float u;  // the reservoir's uniform
  };
  const GBufferInstances instances(view.scene);  // the path vertices' surfaces in lanes
  for_each_tile(g.width, g.height, [&](const Tile& tile) {
    std::vector<Start> starts;
    std::vector<PathState> paths;
    std::vector<Rng> rngs;
    // Per pixel: the first ray, drawn from the BSDF of the visible point x_v.
    for (int y = tile.y0; y < tile.y1; ++y)
      for (int x = tile.x0; x < tile.x1; ++x) {
        const size_t i = size_t(y) * size_t(g.width) + size_t(x);
        out[i] = DiReservoir{};
        if (!g.hit(i)) continue;
        // One attempt, M = 1, whatever comes of it: a ray that escapes or a path that brings no light is a
        // sample of zero contribution, and counting it keeps the reuse MIS weights consistent (with M = 0
        // there, the neighbours' samples were weighted as if this pixel could not have drawn theirs: +11%
        // indirect light with one neighbour, measured).
        out[i].M = 1.0f;
        Rng rng = Rng::for_key(params.seed, i, uint64_t(frame), 0x61);
        const DiReceiver receiver = di_exact_receiver(g, domain.eye, domain.lights, i);
        vec2 ub(rng.next_float(), rng.next_float()), tag(rng.next_float(), rng.next_float());
        float lobe = rng.next_float(), u = rng.next_float();
        BsdfSample bs;
        if (!receiver.bsdf.sample(receiver.wo, ub, lobe, bs) || glm::dot(bs.wi, receiver.geometric_normal) <= 0.0f)
          continue;
        starts.push_back(Start{i, receiver.position, bs.pdf, tag, u});
        paths.emplace_back(PathStart{view.tracer.spawn_ray(receiver.position, receiver.geometric_normal, bs.wi), 1,
                                     bs.pdf, ShadingContext{receiver.position, receiver.shading_normal}, false});
        rngs.push_back(rng);
      }
    // The tile's paths, to their ends; x_s is each path's first hit.
    std::vector<std::optional<SurfacePoint>> x_s(paths.size());
    rays.add(trace_paths(view, sampler, path, paths, rngs, &x_s, &instances));
    // Per path: its sample x_s, with the target at its own pixel and the area density of x_s.
    for (size_t k = 0; k < paths.size(); ++k) {
      const Start& start = starts[k];
      const vec3 L = paths[k].radiance();
      if (!is_finite(L)) non_finite.add(1);
      if (!x_s[k] || !is_finite(L) || max_component(L) <= 0.0f) continue;
      const vec3 d = x_s[k]->position - start.position;
      const float d2 = glm::dot(d, d), cos_s = std::abs(glm::dot(x_s[k]->geometric_normal, d)) / std::sqrt(d2);
      const float p_area = start.pdf * cos_s / d2;
      DiSample s{kSurfacePointSample, start.tag, LightPoint{x_s[k]->position, x_s[k]->geometric_normal, L, false}, 0};
      float p_hat = di_target(di_contribution(di_receiver(domain, start.pixel), s));
      if (!(p_area > 0.0f) || p_hat <= 0.0f) continue;
      DiReservoir& r = out[start.pixel];
      r.update(s, p_hat / p_area, p_hat, start.u);
      r.finalize();
    }
  });
}

}  // namespace candela
