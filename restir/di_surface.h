#pragma once
// The surface of a G-buffer pixel as ReSTIR DI's target function sees it, packed into 32 bytes: reuse
// reads the surfaces of random neighbours, and one cache line per neighbour instead of one per G-buffer
// plane (seven) is what made the reuse stages fast. Resampling only needs a target function that every
// stage evaluates the same way, so targets use this approximate surface everywhere; sampling
// densities and the final shading use the exact G-buffer.
#include <vector>

#include "engine/gbuffer.h"
#include "engine/octahedral.h"

namespace candela {

struct DiSurface {
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

// Stage "di_surfaces": reads the G-buffer, writes one packed surface per pixel. Cost: one streaming pass.
void pack_di_surfaces(const GBuffer& g, std::vector<DiSurface>& out);

}  // namespace candela
