#pragma once
// The receivers of ReSTIR DI and GI built in SIMD lanes: the receiver of a packed surface (reuse_receiver: decoded
// normals, direction to the eye and the BSDF of the packed material) with the wo terms of its BSDF, for up to a tile
// row of surfaces at once. Reuse evaluates each neighbour's receiver against one or two samples only, so building it
// costs as much as evaluating it: in lanes, both are cheap. The kernel repeats the scalar code's operations in order
// (oct_decode, glm::normalize, PackedSurface::bsdf, the Bsdf constructor and Bsdf::wo_terms), so it gives their bits
// (tests/test_target_lanes.cpp).
#include "engine/gbuffer.h"
#include "engine/packed_surface.h"
#include "restir/target_lanes.h"

namespace candela {

// Packed surfaces gathered into one plane per field (slot s: one surface; set() transposes).
struct SurfaceLanes {
  alignas(64) float px[kLaneSlots], py[kLaneSlots], pz[kLaneSlots];
  alignas(64) uint32_t shading_normal[kLaneSlots], geometric_normal[kLaneSlots];
  alignas(64) uint32_t albedo[kLaneSlots], material[kLaneSlots];
  void set(int slot, const PackedSurface& s) {
    px[slot] = s.position.x, py[slot] = s.position.y, pz[slot] = s.position.z;
    shading_normal[slot] = s.shading_normal, geometric_normal[slot] = s.geometric_normal;
    albedo[slot] = s.albedo, material[slot] = s.material;
  }
  // Slots [0, count) from the consecutive surfaces at `from` (a tile row's), as set() of each: one loop that
  // only transposes, which the compiler vectorises (set() inside a loop doing more stays one scalar store per field).
  void set_row(const PackedSurface* __restrict from, int count) {
    for (int s = 0; s < count; ++s) set(s, from[s]);
  }
};

// Slots [0, slots) of `out`: position, geometric normal, wo and the `target` BSDF planes of the receivers
// of `surfaces` seen from `eye`, except the two terms only Bsdf::pdf reads (g1_o and p_specular are left 0):
// evaluate_candidate_lanes may read these receivers without with_bsdf_pdf. A slot holding an empty surface
// (no hit) gets a receiver too: callers leave its candidates inactive. With `wanted`, a vector of slots none of
// which has wanted[s] > 0 is left as it was (a plane of inputs that few pixels of the row have). Cost per receiver:
// ~150 flops and 4 table gathers, in lanes.
void build_receiver_lanes(const SurfaceLanes& surfaces, const vec3& eye, int slots, ReceiverLanes& out,
                          const float* wanted = nullptr);

// Slots [0, slots) of `out`: the positions and geometric normals of `surfaces` as build_receiver_lanes gives them
// (reuse_receiver's), nothing else: where the shading's shadow rays start (shadow_ray_lanes reads no more), so that
// they are reuse's rays. Cost per slot: an octahedral decode, in lanes.
void packed_points_lanes(const SurfaceLanes& surfaces, int slots, ReceiverLanes& out);

// Exact G-buffer surfaces gathered into one plane per field (slot s: one pixel; set_row() transposes).
struct ExactSurfaceLanes {
  alignas(64) float px[kLaneSlots], py[kLaneSlots], pz[kLaneSlots];
  alignas(64) float gx[kLaneSlots], gy[kLaneSlots], gz[kLaneSlots];  // geometric normal
  BsdfMaterialLanes material;                                        // shading normal and material
  // Slots [0, count) from the consecutive pixels [first, first + count) (a tile row): one transposing loop over
  // plane pointers the compiler knows apart from the lanes, which it vectorises.
  void set_row(const GBuffer& g, size_t first, int count) {
    const vec3* __restrict p = g.position.data() + first;
    const vec3* __restrict ng = g.geometric_normal.data() + first;
    const vec3* __restrict ns = g.shading_normal.data() + first;
    const vec3* __restrict base = g.albedo.data() + first;
    const vec3* __restrict m = g.material.data() + first;
    const vec3* __restrict f0 = g.specular_f0.data() + first;
    for (int s = 0; s < count; ++s) {
      px[s] = p[s].x, py[s] = p[s].y, pz[s] = p[s].z;
      gx[s] = ng[s].x, gy[s] = ng[s].y, gz[s] = ng[s].z;
      material.set(s, ns[s], base[s], m[s].y, m[s].x, m[s].z, f0[s]);
    }
  }
};

// Slots [0, slots) of `exact`: the wo terms of the exact receivers' BSDFs (exact_receiver's
// GBuffer::bsdf and Bsdf::wo_terms, all of them: also g1_o and p_specular, which BSDF sampling reads) for
// `surfaces` seen from `eye`. Slots whose surface is empty (no hit) get terms nobody may read. Cost per
// receiver: ~250 flops and 6 table gathers, in lanes.
void build_exact_receiver_lanes(const ExactSurfaceLanes& surfaces, const vec3& eye, int slots, BsdfLanes& exact);

// Slots [0, slots) of `out`: the whole exact receivers of `surfaces` seen from `eye` (exact_receiver):
// position, geometric normal and wo, and the exact BSDF planes as build_exact_receiver_lanes builds them; the
// target planes are left alone. The final shading's receivers. Cost: build_exact_receiver_lanes's and 9 stores.
void build_exact_receivers(const ExactSurfaceLanes& surfaces, const vec3& eye, int slots, ReceiverLanes& out);

}  // namespace candela
