#pragma once
// ReSTIR GI (Ouyang et al. 2021, "ReSTIR GI: Path Resampling for Real-Time Path Tracing"): per pixel, one
// BSDF-sampled ray from the visible point x_v to a sample point x_s, whose outgoing radiance towards x_v is
// estimated by path tracing (NEE with the light sampler, Russian roulette; the emission of x_s itself is
// direct light, left to ReSTIR DI so nothing is counted twice). The sample is stored as a surface-point
// sample (ReuseSample with light = kSurfacePointSample: position, normal facing x_v, radiance), so the reuse
// stages, bias corrections, boiling filter, visibility reuse and shading that ReSTIR DI uses apply unchanged. The
// target at a receiver is the luminance of f L_o |cos_v| |cos_s| / d^2, the sample's contribution in the
// area measure of x_s: moving a sample to another receiver changes that area factor exactly by the
// reconnection Jacobian (the paper's eq. 11), so the Jacobian is part of the target and of W. The
// paper's approximation stays: x_s is taken to send L_o to every receiver (exact for diffuse x_s).
#include "engine/path_batch.h"
#include "restir/bsdf_ray.h"
#include "restir/sample.h"

namespace candela {

struct GiParams {
  int max_depth = 8;       // bounces counted from the camera, as the path tracer's --max-depth (2: one
                           // indirect bounce); below 2 there is no indirect light
  int rr_start_depth = 3;  // Russian roulette from this bounce on
  // Where ReSTIR DI runs with a BSDF candidate per pixel, each path's first ray is that candidate's (BsdfRay): one
  // BSDF sample and ray per pixel instead of two.
  bool share_bsdf_ray = true;
  uint64_t seed = 0;
};

// Where a pixel's GI path starts: the pixel, its visible point x_v, the BSDF's solid-angle density of the first
// ray, the sample's tag and the reservoir's uniform.
struct GiStart {
  size_t pixel;
  vec3 position;
  float pdf;
  vec2 tag;
  float u;
};

// Stage "gi_samples", part 1 (per tile row): pixels [x0, x1) of row y. Each hit pixel's reservoir gets M = 1
// (the others an empty one) and its first ray, drawn from the BSDF of x_v (the exact G-buffer surface) with the
// BSDF's terms, value and density in lanes (engine/bsdf_lanes.h, restir/receiver_lanes.h; the scalar
// exact_receiver and Bsdf::sample give the same bits), or with `shared` the pixel's BsdfRay (drawn from the same
// BSDF and traced by ReSTIR DI, its hit appended to `hits`): a start, a path and its random stream per pixel
// whose ray leaves the surface are appended.
void gi_first_rays(const SceneView& view, const GBuffer& g, const ReuseDomain& domain, const GiParams& params,
                   int frame, int x0, int x1, int y, const std::vector<BsdfRay>* shared,
                   std::vector<ReuseReservoir>& out, std::vector<GiStart>& starts, std::vector<PathState>& paths,
                   std::vector<Rng>& rngs, std::vector<Hit>& hits);

// Part 3 (per tile): each traced path's sample x_s (its first hit, with the path's radiance) into its pixel's
// reservoir, with W = 1 / p_area(x_s), p_area the BSDF's solid-angle density times |cos_s| / d^2, and the target
// at the pixel's packed receiver evaluated in lanes (evaluate_candidate_lanes: sample_target's bits). A path
// whose radiance is not finite is counted in `non_finite` and leaves the reservoir empty.
void gi_sample_reservoirs(const ReuseDomain& domain, const std::vector<GiStart>& starts,
                          const std::vector<PathState>& paths, const std::vector<std::optional<SurfacePoint>>& x_s,
                          std::vector<ReuseReservoir>& out, Counter& non_finite);

// Stage "gi_samples": reads the G-buffer (exact surface: BSDF sampling) and packed surfaces (target), and
// `shared` (the pixels' BsdfRays, ReSTIR DI's) if given; writes one reservoir per pixel holding its sample point,
// M = 1 and W = 1 / p_area(x_s); a path whose radiance is not finite leaves an empty reservoir and is counted in
// `non_finite`. Cost: one path per pixel (about 1 + 2 x bounces rays, one fewer with `shared`), a tile's paths
// traced together with their rays in packets and their BSDF work in lanes (engine/path_batch.h).
template <LightSampler S>
void gi_initial_samples(const SceneView& view, const S& sampler, const GBuffer& g, const ReuseDomain& domain,
                        const GiParams& params, int frame, std::vector<ReuseReservoir>& out, RayCounter& rays,
                        Counter& non_finite, const std::vector<BsdfRay>* shared = nullptr) {
  CHECK(!shared || shared->size() == g.size());
  if (params.max_depth < 2) {
    out.assign(g.size(), ReuseReservoir{});
    return;
  }
  out.resize(g.size());  // every pixel is written below (in parallel, where a fill here ran on one thread)
  PathTracerParams path;
  path.max_depth = params.max_depth;
  path.rr_start_depth = params.rr_start_depth;
  const GBufferInstances instances(view.scene);  // the path vertices' surfaces in lanes
  for_each_tile(g.width, g.height, [&](const Tile& tile) {
    std::vector<GiStart> starts;
    std::vector<PathState> paths;
    std::vector<Rng> rngs;
    std::vector<Hit> hits;  // with `shared`: the paths' first hits
    const size_t pixels = size_t(tile.x1 - tile.x0) * size_t(tile.y1 - tile.y0);  // at most one path each
    starts.reserve(pixels), paths.reserve(pixels), rngs.reserve(pixels), hits.reserve(shared ? pixels : 0);
    for (int y = tile.y0; y < tile.y1; ++y)
      gi_first_rays(view, g, domain, params, frame, tile.x0, tile.x1, y, shared, out, starts, paths, rngs, hits);
    // The tile's paths, to their ends; x_s is each path's first hit.
    std::vector<std::optional<SurfacePoint>> x_s(paths.size());
    rays.add(trace_paths(view, sampler, path, paths, rngs, &x_s, &instances, shared ? &hits : nullptr));
    gi_sample_reservoirs(domain, starts, paths, x_s, out, non_finite);
  });
}

}  // namespace candela
