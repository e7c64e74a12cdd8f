#include "engine/packed_surface.h"

#include <algorithm>

namespace candela {

static uint32_t unorm8(float v) { return uint32_t(round_nearest(std::clamp(v, 0.0f, 1.0f) * 255.0f)); }
static float from_unorm8(uint32_t v) { return float(v & 255) * (1.0f / 255.0f); }

Bsdf PackedSurface::bsdf(const vec3& n) const {
  vec3 sqrt_albedo(from_unorm8(albedo), from_unorm8(albedo >> 8), from_unorm8(albedo >> 16));
  float sqrt_f0 = from_unorm8(material >> 24);
  return Bsdf(n, sqrt_albedo * sqrt_albedo, from_unorm8(material >> 8), from_unorm8(material),
              from_unorm8(material >> 16), vec3(sqrt_f0 * sqrt_f0));
}

PackedSurface pack_surface(const vec3& position, float depth, const vec3& shading_normal, const vec3& geometric_normal,
                           const vec3& albedo, const vec3& material, const vec3& specular_f0) {
  const vec3 a = glm::sqrt(glm::clamp(albedo, 0.0f, 1.0f));
  const float f0 = std::sqrt(max_component(specular_f0));
  return {position,
          depth,
          oct_encode(shading_normal),
          oct_encode(geometric_normal),
          unorm8(a.x) | unorm8(a.y) << 8 | unorm8(a.z) << 16,
          unorm8(material.x) | unorm8(material.y) << 8 | unorm8(material.z) << 16 | unorm8(f0) << 24};
}

}  // namespace candela
