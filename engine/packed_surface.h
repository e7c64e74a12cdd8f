#pragma once
// The surface of a G-buffer pixel packed into 32 bytes, written by the G-buffer pass beside its planes when
// a consumer asks for it (GBufferParams::packed). ReSTIR's reuse reads the surfaces of random neighbours:
// one cache line per neighbour instead of one per G-buffer plane (seven) is what made its stages fast.
// Resampling only needs a target function that every stage evaluates the same way, so ReSTIR's targets use
// this approximate surface everywhere; sampling densities and the final shading use the exact G-buffer.
#include <cstdint>

#include "engine/bsdf.h"
#include "engine/octahedral.h"

namespace candela {

struct PackedSurface {
  vec3 position{0.0f};
  float depth = kInfinity;        // linear view depth; kInfinity: no surface
  uint32_t shading_normal = 0;    // octahedral
  uint32_t geometric_normal = 0;  // octahedral
  uint32_t albedo = 0;            // sqrt-encoded RGB, 8 bits each
  uint32_t material = 0;          // roughness, metallic, specular factor, sqrt of the dielectric F0's
                                  // largest component (grey F0), 8 bits each

  bool hit() const { return depth < kInfinity; }
  vec3 shading_n() const { return oct_decode(shading_normal); }
  vec3 geometric_n() const { return oct_decode(geometric_normal); }
  Bsdf bsdf(const vec3& shading_n) const;  // with the decoded shading normal
  float roughness() const { return float(material & 255) * (1.0f / 255.0f); }
};

// A hit's surface packed: material holds roughness, metallic, specular factor (the G-buffer's material plane).
PackedSurface pack_surface(const vec3& position, float depth, const vec3& shading_normal, const vec3& geometric_normal,
                           const vec3& albedo, const vec3& material, const vec3& specular_f0);

}  // namespace candela
