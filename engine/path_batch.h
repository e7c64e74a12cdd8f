#pragma once
// Many paths traced together, bounce by bounce ("wavefront" order): each bounce traces the closest hits of
// every live path in packets of 16, runs path_bounce on each path, then traces the bounce's shadow rays in
// packets. Each path keeps its own random stream and path_bounce is trace_path's own step, so every path
// gets trace_path's bits (test PathBatch.GivesTracePathBits); what changes is the cost: packets instead of
// single rays, and one path's memory waits overlapping the next path's arithmetic.
#include <vector>

#include "engine/path_tracer.h"

namespace candela {

// Traces paths[k] with stream rngs[k] to its end (paths[k].radiance() is then trace_path's result);
// first_hits, if not null, receives per path the surface its start's ray hits. Returns the rays traced.
// Cost: trace_path's per path; rays in packets of 16 in slot order (slots of neighbouring pixels keep
// the first bounces' packets coherent).
template <LightSampler S, class Stream>
uint64_t trace_paths(const SceneView& view, const S& sampler, const PathTracerParams& params,
                     std::vector<PathState>& paths, std::vector<Stream>& rngs,
                     std::vector<std::optional<SurfacePoint>>* first_hits) {
  const Tracer& tracer = view.tracer;
  std::vector<uint32_t> live(paths.size());
  for (uint32_t k = 0; k < live.size(); ++k) live[k] = k;
  std::vector<Hit> hits(paths.size());
  uint64_t traced = 0;
  while (!live.empty()) {
    // Closest hits of the live paths' rays.
    auto bounce = ray_queue16<uint32_t>(tracer, RayQuery::Intersect, [&](uint32_t k, const RayPacket16& p, int lane) {
      hits[k] = tracer.packet_hit(p, lane);
    });
    for (uint32_t k : live) bounce.add(paths[k].ray, k);
    bounce.finish();
    // The bounce of each path: emission, its next-event estimate's shadow ray, its next ray.
    for (uint32_t k : live)
      path_bounce(view, sampler, params, paths[k], hits[k], rngs[k], first_hits ? &(*first_hits)[k] : nullptr);
    // The shadow rays, then the paths that go on.
    auto shadows = ray_queue16<uint32_t>(tracer, RayQuery::Occluded, [&](uint32_t k, const RayPacket16& p, int lane) {
      finish_direct_light(paths[k], Tracer::occluded_lane(p, lane));
    });
    size_t kept = 0;
    for (uint32_t k : live) {
      if (paths[k].light_pending) shadows.add(paths[k].shadow, k);
      if (paths[k].alive) live[kept++] = k;
    }
    shadows.finish();
    live.resize(kept);
    traced += bounce.traced() + shadows.traced();
  }
  return traced;
}

}  // namespace candela
