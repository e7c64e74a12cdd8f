#pragma once
// Unit vectors in 32 bits: the octahedral map with 16 bits per coordinate (Cigolle et al. 2014, "A Survey
// of Efficient Representations for Independent Unit Vectors", sec. 3.1); worst-case angular error ~3e-5 rad.
#include <cstdint>

#include "engine/math.h"

namespace candela {

inline uint32_t oct_encode(const vec3& n) {
  float l1 = std::abs(n.x) + std::abs(n.y) + std::abs(n.z);
  vec2 p = vec2(n.x, n.y) / l1;
  if (n.z < 0.0f)
    p = vec2((1.0f - std::abs(p.y)) * std::copysign(1.0f, p.x), (1.0f - std::abs(p.x)) * std::copysign(1.0f, p.y));
  auto quantise = [](float v) {
    return uint32_t(round_nearest((std::clamp(v, -1.0f, 1.0f) * 0.5f + 0.5f) * 65535.0f));
  };
  return quantise(p.x) | (quantise(p.y) << 16);
}

inline vec3 oct_decode(uint32_t e) {
  vec2 p(float(e & 0xffff) * (2.0f / 65535.0f) - 1.0f, float(e >> 16) * (2.0f / 65535.0f) - 1.0f);
  vec3 n(p.x, p.y, 1.0f - std::abs(p.x) - std::abs(p.y));
  float t = std::max(-n.z, 0.0f);
  n.x += n.x >= 0.0f ? -t : t;
  n.y += n.y >= 0.0f ? -t : t;
  return glm::normalize(n);
}

}  // namespace candela
