#include "restir/di_surface.h"

#include "engine/tiles.h"

namespace candela {

static uint32_t unorm8(float v) { return uint32_t(round_nearest(std::clamp(v, 0.0f, 1.0f) * 255.0f)); }
static float from_unorm8(uint32_t v) { return float(v & 255) * (1.0f / 255.0f); }

Bsdf DiSurface::bsdf(const vec3& n) const {
  vec3 sqrt_albedo(from_unorm8(albedo), from_unorm8(albedo >> 8), from_unorm8(albedo >> 16));
  float sqrt_f0 = from_unorm8(material >> 24);
  return Bsdf(n, sqrt_albedo * sqrt_albedo, from_unorm8(material >> 8), from_unorm8(material),
              from_unorm8(material >> 16), vec3(sqrt_f0 * sqrt_f0));
}

void pack_di_surfaces(const GBuffer& g, std::vector<DiSurface>& out) {
  out.resize(g.size());
  for_each_pixel(g.width, g.height, [&](size_t i, int, int) {
    DiSurface& s = out[i];
    if (!g.hit(i)) {
      s = DiSurface{};
      return;
    }
    vec3 a = glm::sqrt(glm::clamp(g.albedo[i], 0.0f, 1.0f));
    const vec3& m = g.material[i];
    float f0 = std::sqrt(max_component(g.specular_f0[i]));
    s = {g.position[i],
         g.depth[i],
         oct_encode(g.shading_normal[i]),
         oct_encode(g.geometric_normal[i]),
         unorm8(a.x) | unorm8(a.y) << 8 | unorm8(a.z) << 16,
         unorm8(m.x) | unorm8(m.y) << 8 | unorm8(m.z) << 16 | unorm8(f0) << 24};
  });
}

}  // namespace candela
