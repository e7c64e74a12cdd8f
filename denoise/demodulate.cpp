#include "denoise/demodulate.h"

#include "engine/check.h"

namespace candela {

static vec3 albedo_floor(const vec3& albedo) { return glm::max(albedo, vec3(kMinAlbedo)); }

void demodulate(const Image& noisy, const GBuffer& g, const Guides& guides, ColorPlanes& illumination,
                Counter& non_finite) {
  CHECK(noisy.width == g.width && noisy.height == g.height && guides.width == g.width && guides.height == g.height);
  if (illumination.width != g.width || illumination.height != g.height) illumination.resize(g.width, g.height);
  for_each_row(g.height, [&](int y) {
    for (size_t i = size_t(y) * g.width, end = i + g.width; i < end; ++i) {
      vec3 e = guides.filtered[i] ? (noisy.pixels[i] - g.emission[i]) / albedo_floor(g.albedo[i])
               : g.hit(i)         ? noisy.pixels[i]
                                  : vec3(0.0f);
      bool finite = is_finite(e);
      illumination.set(i, finite ? e : vec3(0.0f));
      if (!finite) non_finite.add(1);
    }
  });
}

void remodulate(const ColorPlanes& filtered, const GBuffer& g, const Guides& guides, const Image& noisy, Image& out) {
  CHECK(filtered.width == g.width && filtered.height == g.height && noisy.width == g.width && noisy.height == g.height);
  if (out.width != g.width || out.height != g.height) out = Image(g.width, g.height);
  for_each_row(g.height, [&](int y) {
    for (size_t i = size_t(y) * g.width, end = i + g.width; i < end; ++i)
      out.pixels[i] = guides.filtered[i] ? filtered.at(i) * albedo_floor(g.albedo[i]) + g.emission[i]
                      : g.hit(i)         ? filtered.at(i)
                                         : noisy.pixels[i];
  });
}

void prepare_frame(const GBuffer& g, const Image& noisy, bool with_albedo, Guides& guides, ColorPlanes& illumination,
                   FrameStats& stats) {
  {
    StageTimer timer(stats, "denoise_guides");
    compute_guides(g, with_albedo, guides);
  }
  StageTimer timer(stats, "denoise_demodulate");
  demodulate(noisy, g, guides, illumination, timer.non_finite());
}

}  // namespace candela
