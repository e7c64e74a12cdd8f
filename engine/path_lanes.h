#pragma once
// A batch of path vertices' next-event estimation and continuation in SIMD lanes (engine/path_batch.h's
// bounce_paths). Next-event estimation for the light samples on triangle lights without an emission texture:
// LightList::sample's point, direction, distance and solid-angle density with place_light_sample's tests
// (sample_triangle_lights_lanes), then, once the BSDF has been evaluated towards them, weigh_light_sample's
// MIS-weighted contributions and shadow rays (weigh_light_samples_lanes); samples of punctual and textured lights stay
// with the scalar code. Continuation: continue_path's test, throughput factor and next ray (continue_paths_lanes).
// The kernels (Google Highway, runtime dispatch) repeat the scalar code's operations in its order without fused
// multiply-adds, so every path keeps trace_path's bits (PathBatch.GivesTracePathBits).
#include "engine/bsdf_lanes.h"
#include "engine/lights.h"
#include "engine/ray_lanes.h"

namespace candela {

// Slot s: one path vertex's position and geometric normal.
struct VertexLanes {
  alignas(64) float px[kLaneSlots], py[kLaneSlots], pz[kLaneSlots];
  alignas(64) float gx[kLaneSlots], gy[kLaneSlots], gz[kLaneSlots];
  void set(int s, const vec3& p, const vec3& ng) {
    px[s] = p.x, py[s] = p.y, pz[s] = p.z;
    gx[s] = ng.x, gy[s] = ng.y, gz[s] = ng.z;
  }
};

// Slot s: one vertex's light sample. Where `active` is 1 the caller fills the chosen triangle light's record, the
// point's uniforms and the light's selection probability (set_light); the kernels write the rest.
struct NeeLanes {
  alignas(64) float corner[3][kLaneSlots], edge1[3][kLaneSlots], edge2[3][kLaneSlots];  // TriangleLight p0, e1, e2
  alignas(64) float nx[kLaneSlots], ny[kLaneSlots], nz[kLaneSlots];                     // its normal
  alignas(64) float area[kLaneSlots], emitted[3][kLaneSlots], two_sided[kLaneSlots];    // average_radiance
  // (a valid sample sends its light's `emitted` radiance to the vertex)
  alignas(64) float u[2][kLaneSlots], pmf[kLaneSlots];
  alignas(64) float active[kLaneSlots];
  // sample_triangle_lights_lanes: the point on the light and the density.
  alignas(64) float qx[kLaneSlots], qy[kLaneSlots], qz[kLaneSlots];
  alignas(64) float pdf[kLaneSlots];
  // weigh_light_samples_lanes: where a shadow ray is pending (1), its contribution if unoccluded, and the ray.
  alignas(64) float pending[kLaneSlots], contribution[3][kLaneSlots];
  RayLanes shadow;

  void set_light(int s, const TriangleLight& l, vec2 uniforms, float probability) {
    for (int c = 0; c < 3; ++c)
      corner[c][s] = l.p0[c], edge1[c][s] = l.e1[c], edge2[c][s] = l.e2[c], emitted[c][s] = l.average_radiance[c];
    nx[s] = l.normal.x, ny[s] = l.normal.y, nz[s] = l.normal.z;
    area[s] = l.area, two_sided[s] = l.two_sided ? 1.0f : 0.0f;
    u[0][s] = uniforms.x, u[1][s] = uniforms.y, pmf[s] = probability;
    active[s] = 1.0f;
  }
};

// Slots [0, slots) of `nee` that are active, at the vertices `v`: LightList::sample (triangle_point,
// light_sample_towards, the density) and place_light_sample's tests; `light` gets the direction to the point and active
// = 1 where the sample can contribute, 0 where not (its other slots are left as they are). Cost per sample: ~40 flops,
// two square roots and 4 divisions, in lanes.
void sample_triangle_lights_lanes(const VertexLanes& v, NeeLanes& nee, int slots, DirectionLanes& light);

// Slots [0, slots) of `nee` that are active, after evaluate_bsdf_lanes (times the cosine) filled `light`'s values and
// densities: weigh_light_sample's result (pending where the BSDF's value is positive), its contribution and
// its shadow ray (Tracer::spawn_ray_to; epsilon: Tracer::offset_epsilon()). Cost per sample: ~80 flops, a square root
// and 5 divisions, in lanes.
void weigh_light_samples_lanes(const VertexLanes& v, const DirectionLanes& light, float epsilon, int slots,
                               NeeLanes& nee);

// Slot s: whether the path goes on from its vertex (1) and, where it does, the factor its throughput is multiplied
// by and its next ray's origin (the direction is the BSDF sample's; the ray is unbounded).
struct ContinueLanes {
  alignas(64) float go[kLaneSlots], factor[3][kLaneSlots];
  alignas(64) float ox[kLaneSlots], oy[kLaneSlots], oz[kLaneSlots];
};

// Slots [0, slots): continue_path's geometry for the BSDF samples `next` (those active with a positive density) drawn
// at the vertices `v` with shading normals (nx, ny, nz): the direction above the geometric surface, the throughput
// factor f |cos| / pdf at the shading normal and Tracer::spawn_ray's origin. Russian roulette and the bookkeeping stay
// with the caller (survive_bounce). Cost per vertex: ~30 flops and a division, in lanes.
void continue_paths_lanes(const VertexLanes& v, const float* nx, const float* ny, const float* nz,
                          const DirectionLanes& next, float epsilon, int slots, ContinueLanes& out);

}  // namespace candela
