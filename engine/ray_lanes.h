#pragma once
// Rays of a batch in structure-of-arrays planes, one per slot: what the SIMD kernels that build Tracer::spawn_ray_to's
// rays write (restir/target_lanes.h shadow_ray_lanes, engine/path_lanes.h weigh_light_samples_lanes) for the
// caller to queue.
#include "engine/bsdf_lanes.h"
#include "engine/tracer.h"

namespace candela {

struct RayLanes {
  alignas(64) float ox[kLaneSlots], oy[kLaneSlots], oz[kLaneSlots];
  alignas(64) float dx[kLaneSlots], dy[kLaneSlots], dz[kLaneSlots];
  alignas(64) float tmax[kLaneSlots];
  Ray ray(int slot) const {
    return {vec3(ox[slot], oy[slot], oz[slot]), vec3(dx[slot], dy[slot], dz[slot]), 0.0f, tmax[slot]};
  }
};

}  // namespace candela
