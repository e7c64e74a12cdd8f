#pragma once
// Whether a light can illuminate a receiver at all, for tests that a sampler never gives such a light
// zero probability.
#include <gtest/gtest.h>

#include <vector>

#include "engine/light_sampler.h"
#include "engine/lights.h"

namespace candela::testing {

// Triangle lights: tested at corners, edge midpoints and the centroid (slightly inside the triangle).
// Point lights: above the receiver's horizon. Spot lights: also inside the outer cone.
inline bool light_can_reach(const LightList& lights, size_t index, const vec3& p, const vec3& n) {
  if (index < lights.triangle_count()) {
    const TriangleLight& l = lights.triangles()[index];
    for (vec2 b : {vec2(0.02f, 0.02f), vec2(0.96f, 0.02f), vec2(0.02f, 0.96f), vec2(0.49f, 0.02f), vec2(0.02f, 0.49f),
                   vec2(0.49f, 0.49f), vec2(1.0f / 3.0f)}) {
      vec3 y = l.p0 + l.e1 * b.x + l.e2 * b.y;
      bool emits_towards_p = l.two_sided || glm::dot(l.normal, p - y) > 0.0f;
      if (emits_towards_p && glm::dot(n, y - p) > 0.0f) return true;
    }
    return false;
  }
  const PunctualLight& l = lights.punctual()[index - lights.triangle_count()];
  if (l.type == PunctualType::Directional) return glm::dot(n, -l.direction) > 0.0f;
  if (glm::dot(n, l.position - p) <= 0.0f) return false;
  if (l.type == PunctualType::Point) return true;
  return glm::dot(l.direction, glm::normalize(p - l.position)) > std::cos(l.outer_cone);
}

// Every light that can reach one of `receivers` has non-zero pmf for `ctx` (the receivers' region, or the
// receiver itself); returns how many lights were checked.
template <class Sampler>
size_t expect_no_dropped_lights_in(const Sampler& sampler, const LightList& lights, const ShadingContext& ctx,
                                   const std::vector<ShadingContext>& receivers) {
  size_t checked = 0;
  for (uint32_t i = 0; i < lights.size(); ++i)
    for (size_t k = 0; k < receivers.size(); ++k) {
      if (!light_can_reach(lights, i, receivers[k].position, receivers[k].normal)) continue;
      ++checked;
      if (sampler.pmf(ctx, i) <= 0.0f) {
        ADD_FAILURE() << "light " << i << " can reach receiver " << k << " but has pmf 0";
        return checked;
      }
      break;
    }
  return checked;
}

// Every light that can reach a receiver has non-zero pmf there; returns how many pairs were checked.
template <class Sampler>
size_t expect_no_dropped_lights(const Sampler& sampler, const LightList& lights,
                                const std::vector<ShadingContext>& points) {
  size_t checked = 0;
  for (const ShadingContext& p : points) checked += expect_no_dropped_lights_in(sampler, lights, p, {p});
  return checked;
}

}  // namespace candela::testing
