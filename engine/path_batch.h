#pragma once
// Many paths traced together, bounce by bounce ("wavefront" order): each bounce traces the closest hits of
// every live path in packets of 16, runs path_bounce on each path, then traces the bounce's shadow rays in
// packets. Each path keeps its own random stream and path_bounce is trace_path's own step, so every path
// gets trace_path's bits (test PathBatch.GivesTracePathBits); what changes is the cost: packets instead of
// single rays, and one path's memory waits overlapping the next path's arithmetic.
#include <vector>

#include "engine/gbuffer_lanes.h"
#include "engine/path_tracer.h"

namespace candela {

// Traces paths[k] with stream rngs[k] to its end (paths[k].radiance() is then trace_path's result);
// first_hits, if not null, receives per path the surface its start's ray hits. With `instances` (the scene's,
// GBufferInstances), each bounce's hits on plain materials get their surfaces in SIMD lanes
// (surface_points_lanes), the others surface_at. Returns the rays traced.
// Cost: trace_path's per path; rays in packets of 16 in slot order (slots of neighbouring pixels keep
// the first bounces' packets coherent).
template <LightSampler S, class Stream>
uint64_t trace_paths(const SceneView& view, const S& sampler, const PathTracerParams& params,
                     std::vector<PathState>& paths, std::vector<Stream>& rngs,
                     std::vector<std::optional<SurfacePoint>>* first_hits,
                     const GBufferInstances* instances = nullptr) {
  const Tracer& tracer = view.tracer;
  std::vector<uint32_t> live(paths.size());
  for (uint32_t k = 0; k < live.size(); ++k) live[k] = k;
  std::vector<Hit> hits(paths.size());
  std::vector<SurfacePoint> surfaces(instances ? paths.size() : 0);
  uint64_t traced = 0;
  while (!live.empty()) {
    // Closest hits of the live paths' rays.
    auto bounce = ray_queue16<uint32_t>(tracer, RayQuery::Intersect, [&](uint32_t k, const RayPacket16& p, int lane) {
      hits[k] = tracer.packet_hit(p, lane);
    });
    for (uint32_t k : live) bounce.add(paths[k].ray, k);
    bounce.finish();
    // The surfaces of the hits on plain materials, a tile row's worth of live paths at a time.
    for (size_t first = 0; instances && first < live.size(); first += kTileWidth) {
      const int count = int(std::min<size_t>(kTileWidth, live.size() - first));
      PrimaryHitLanes row;
      for (int j = 0; j < count; ++j) {
        const Hit& hit = hits[live[first + size_t(j)]];
        const vec3& dir = paths[live[first + size_t(j)]].ray.direction;
        row.instance[j] = hit.instance, row.prim[j] = hit.prim;
        row.u[j] = hit.barycentric.x, row.v[j] = hit.barycentric.y;
        row.dir[0][j] = dir.x, row.dir[1][j] = dir.y, row.dir[2][j] = dir.z;
      }
      surface_points_lanes(*instances, row, count, &surfaces[first]);
    }
    // The bounce of each path: emission, its next-event estimate's shadow ray, its next ray.
    for (size_t j = 0; j < live.size(); ++j) {
      const uint32_t k = live[j];
      const bool lanes = instances && instances->in_lanes(hits[k].instance);
      path_bounce(view, sampler, params, paths[k], hits[k], rngs[k], first_hits ? &(*first_hits)[k] : nullptr,
                  lanes ? &surfaces[j] : nullptr);
    }
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
