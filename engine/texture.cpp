#include "engine/texture.h"

#include <array>

namespace candela {

static const std::array<float, 256>& srgb_table() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) {
      float c = i / 255.0f;
      t[i] = c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
    }
    return t;
  }();
  return table;
}

static int wrap_index(int i, int n, Wrap mode) {
  switch (mode) {
    case Wrap::Clamp: return std::clamp(i, 0, n - 1);
    case Wrap::Mirror: {
      int period = 2 * n;
      int m = ((i % period) + period) % period;
      return m < n ? m : period - 1 - m;
    }
    case Wrap::Repeat:
    default: return ((i % n) + n) % n;
  }
}

vec4 Texture::texel(int x, int y) const {
  x = wrap_index(x, width, wrap_s);
  y = wrap_index(y, height, wrap_t);
  const uint8_t* p = &rgba[(size_t(y) * width + x) * 4];
  if (srgb) {
    const auto& t = srgb_table();
    return {t[p[0]], t[p[1]], t[p[2]], p[3] / 255.0f};
  }
  return vec4(p[0], p[1], p[2], p[3]) * (1.0f / 255.0f);
}

vec4 Texture::sample(vec2 uv) const {
  if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) uv = vec2(0.0f);
  // Keep coordinates in a range where the texel index fits an int.
  float limit = float(1 << 30) / float(std::max(width, height));
  uv = glm::clamp(uv, vec2(-limit), vec2(limit));
  float x = uv.x * width - 0.5f, y = uv.y * height - 0.5f;
  float fx = std::floor(x), fy = std::floor(y);
  int x0 = int(fx), y0 = int(fy);
  float tx = x - fx, ty = y - fy;
  vec4 a = glm::mix(texel(x0, y0), texel(x0 + 1, y0), tx);
  vec4 b = glm::mix(texel(x0, y0 + 1), texel(x0 + 1, y0 + 1), tx);
  return glm::mix(a, b, ty);
}

}  // namespace candela
