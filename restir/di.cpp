#include "restir/di.h"

namespace candela {

Image di_reservoir_image(const GBuffer& g, const std::vector<ReuseReservoir>& reservoirs, DiAov aov) {
  Image img(g.width, g.height);
  for (size_t i = 0; i < img.pixels.size() && i < reservoirs.size(); ++i) {
    const ReuseReservoir& r = reservoirs[i];
    if (!g.hit(i)) continue;
    switch (aov) {
      case DiAov::M: img.pixels[i] = vec3(r.M); break;
      case DiAov::W: img.pixels[i] = vec3(r.W); break;
      case DiAov::Light: {
        if (r.W <= 0.0f) break;
        uint64_t h = mix64(r.y.light + 1);
        img.pixels[i] = vec3(float(h & 255), float((h >> 8) & 255), float((h >> 16) & 255)) / 255.0f;
        break;
      }
    }
  }
  return img;
}

}  // namespace candela
