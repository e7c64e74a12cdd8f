#pragma once
// 8-bit RGBA textures (decoded sRGB through a table at lookup) with glTF wrap modes and bilinear filtering,
// and the texture reference a material holds (texture, UV set and KHR_texture_transform).
#include <string>
#include <vector>

#include "engine/math.h"

namespace candela {

enum class Wrap : uint8_t { Repeat, Clamp, Mirror };

struct Texture {
  std::string name;
  int width = 0, height = 0;
  std::vector<uint8_t> rgba;  // width * height * 4, row 0 at the top (v = 0)
  Wrap wrap_s = Wrap::Repeat, wrap_t = Wrap::Repeat;
  bool srgb = false;  // colour data (base colour, emission) is sRGB-encoded; data maps are linear

  // Bilinear lookup at uv, linear values in [0, 1].
  vec4 sample(vec2 uv) const;
  // Nearest texel, for integrating over texel footprints.
  vec4 texel(int x, int y) const;
};

// Which texture a material slot reads and how its UVs are transformed (KHR_texture_transform:
// uv' = T * R * S * uv, rotation counter-clockwise in UV space).
struct TextureRef {
  int texture = -1;
  int texcoord = 0;  // 0 = TEXCOORD_0, 1 = TEXCOORD_1
  vec2 offset{0.0f}, scale{1.0f};
  float rotation = 0.0f;
  bool valid() const { return texture >= 0; }
  vec2 apply(vec2 uv) const {
    if (rotation == 0.0f) return uv * scale + offset;
    float c = std::cos(rotation), s = std::sin(rotation);
    vec2 p = uv * scale;
    return vec2(c * p.x + s * p.y, -s * p.x + c * p.y) + offset;
  }
};

}  // namespace candela
