#pragma once
// Bsdf (engine/bsdf.h) for up to a tile row of surfaces at once, in SIMD lanes: the constructor and
// Bsdf::wo_terms, then Bsdf::eval and Bsdf::pdf at one direction per surface, laid out as
// structure-of-arrays planes so that one vector holds the same term of 8 (AVX2) or 16 (AVX-512) surfaces.
// The kernels (Google Highway, runtime dispatch) repeat the scalar code's operations in its order, without
// fused multiply-adds, so they give its bits: ReSTIR's receivers (restir/receiver_lanes.h) and the path
// vertices of engine/path_batch.h use them, and the scalar Bsdf stays the reference
// (tests/test_target_lanes.cpp; PathBatch.GivesTracePathBits in tests/test_path_tracer.cpp).
#include <cstdint>

#include "engine/bsdf.h"
#include "engine/tiles.h"

namespace candela {

inline constexpr int kLaneSlots = kTileWidth;  // surfaces per batch: one tile row

// BsdfWoTerms, one plane per component (slot s: one surface).
struct BsdfLanes {
  alignas(64) float nx[kLaneSlots], ny[kLaneSlots], nz[kLaneSlots];
  alignas(64) float cos_o[kLaneSlots], alpha[kLaneSlots], s_o[kLaneSlots];
  alignas(64) float f0[3][kLaneSlots], f90[kLaneSlots], ms[3][kLaneSlots], ms_o[kLaneSlots];
  alignas(64) float base_o[3][kLaneSlots], d_f0[3][kLaneSlots], d_ms[3][kLaneSlots], d_f90[kLaneSlots];
  alignas(64) int32_t albedo_row[kLaneSlots];
  alignas(64) float albedo_weight[kLaneSlots], g1_o[kLaneSlots], p_specular[kLaneSlots];
  void set(int slot, const BsdfWoTerms& t);
};

// What the Bsdf constructor reads (shading normal and material), one plane per component.
struct BsdfMaterialLanes {
  alignas(64) float nx[kLaneSlots], ny[kLaneSlots], nz[kLaneSlots];  // shading normal
  alignas(64) float base[3][kLaneSlots], specular_f0[3][kLaneSlots];
  alignas(64) float roughness[kLaneSlots], metallic[kLaneSlots], specular[kLaneSlots];
  void set(int slot, const vec3& shading_normal, const vec3& base_color, float metallic_, float roughness_,
           float specular_, const vec3& specular_f0_) {
    nx[slot] = shading_normal.x, ny[slot] = shading_normal.y, nz[slot] = shading_normal.z;
    for (int c = 0; c < 3; ++c) base[c][slot] = base_color[c], specular_f0[c][slot] = specular_f0_[c];
    roughness[slot] = roughness_, metallic[slot] = metallic_, specular[slot] = specular_;
  }
};

// One direction per surface of a batch (with wo, the direction it is seen from): where `active` is 1,
// evaluate_bsdf_lanes writes the BSDF's value and sampling density there.
struct DirectionLanes {
  alignas(64) float x[kLaneSlots], y[kLaneSlots], z[kLaneSlots];
  alignas(64) float active[kLaneSlots];
  alignas(64) float f[3][kLaneSlots], pdf[kLaneSlots];
};

// The uniforms of one BSDF sample per surface of a batch: the direction's two (u[0] = u.x, u[1] = u.y) and the
// lobe's.
struct BsdfUniformLanes {
  alignas(64) float u[2][kLaneSlots], lobe[kLaneSlots];
};

// The path vertices of a batch: their BSDFs' parameters and the direction wo each is seen from.
struct BsdfVertexLanes {
  BsdfMaterialLanes material;
  alignas(64) float wox[kLaneSlots], woy[kLaneSlots], woz[kLaneSlots];
};

// Slots [0, slots) of `out`: Bsdf(...).wo_terms(wo) of each vertex, all terms (also g1_o and p_specular,
// which sampling and pdf read). Cost per vertex: ~250 flops and 6 table gathers, in lanes.
void build_bsdf_lanes(const BsdfVertexLanes& vertices, int slots, BsdfLanes& out);

// Slots [0, slots) of `directions`: Bsdf::eval (times |cos| at the shading normal with times_cosine, as the
// path tracer weighs a light sample) and Bsdf::pdf at each active direction, for the BSDFs `bsdf` seen along
// the planes (wox, woy, woz); inactive slots get 0. Cost per direction: ~60 flops and 4 table gathers, in lanes.
void evaluate_bsdf_lanes(const BsdfLanes& bsdf, const float* wox, const float* woy, const float* woz, int slots,
                         bool times_cosine, DirectionLanes& directions);

// Slots [0, slots) of `directions` that are active on entry: the direction Bsdf::sample draws for the slot's BSDF
// of `bsdf` (its normal, alpha and lobe probability) seen along the planes (wox, woy, woz) with the slot's
// uniforms (sample_bsdf_direction's arithmetic, sin_cos included: its bits); a slot stays active where one was
// drawn and becomes inactive (direction 0) where none was. Its value and density: evaluate_bsdf_lanes. Cost per
// direction: ~120 flops, two square roots per lobe and 5 divisions, in lanes (both lobes are computed).
void sample_bsdf_lanes(const BsdfLanes& bsdf, const float* wox, const float* woy, const float* woz,
                       const BsdfUniformLanes& uniforms, int slots, DirectionLanes& directions);

}  // namespace candela
