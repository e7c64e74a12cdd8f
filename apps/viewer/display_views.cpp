#include "apps/viewer/display_views.h"

#include <algorithm>

#include "engine/parallel.h"

namespace candela {

const char* display_view_name(DisplayView view) {
  switch (view) {
    case DisplayView::Radiance: return "radiance";
    case DisplayView::Albedo: return "albedo";
    case DisplayView::Normal: return "normal";
    case DisplayView::Depth: return "depth";
    case DisplayView::Motion: return "motion";
    case DisplayView::ReservoirM: return "reservoir M";
    case DisplayView::ReservoirW: return "reservoir W";
  }
  return "?";
}

const char* display_view_option(DisplayView view) {
  switch (view) {
    case DisplayView::ReservoirM: return "reservoir-m";
    case DisplayView::ReservoirW: return "reservoir-w";
    default: return display_view_name(view);
  }
}

bool display_view_available(DisplayView view, const Renderer& renderer) {
  bool reservoir = view == DisplayView::ReservoirM || view == DisplayView::ReservoirW;
  return !reservoir || renderer.di_reservoirs().size() == renderer.gbuffer().size();
}

bool display_view_tonemapped(DisplayView view) {
  return view == DisplayView::Radiance || view == DisplayView::ReservoirW;
}

Image display_view_image(const Renderer& renderer, DisplayView view) {
  const GBuffer& g = renderer.gbuffer();
  if (view == DisplayView::Radiance || g.size() == 0) return renderer.image();
  if (view == DisplayView::ReservoirM || view == DisplayView::ReservoirW) {
    if (!display_view_available(view, renderer)) return Image(g.width, g.height);
    Image image =
        di_reservoir_image(g, renderer.di_reservoirs(), view == DisplayView::ReservoirM ? DiAov::M : DiAov::W);
    if (view == DisplayView::ReservoirM) {
      float max_m = 0.0f;
      for (const vec3& p : image.pixels) max_m = std::max(max_m, p.x);
      if (max_m > 0.0f)
        for (vec3& p : image.pixels) p /= max_m;
    }
    return image;
  }
  Image image(g.width, g.height);
  float max_depth = 0.0f;
  for (size_t i = 0; i < g.size(); ++i)
    if (g.hit(i)) max_depth = std::max(max_depth, g.depth[i]);
  for (size_t i = 0; i < g.size(); ++i) {
    if (!g.hit(i)) continue;
    switch (view) {
      case DisplayView::Albedo: image.pixels[i] = g.albedo[i]; break;
      case DisplayView::Normal: image.pixels[i] = g.shading_normal[i] * 0.5f + 0.5f; break;
      case DisplayView::Depth: image.pixels[i] = vec3(max_depth > 0.0f ? g.depth[i] / max_depth : 0.0f); break;
      case DisplayView::Motion: image.pixels[i] = vec3(0.5f + g.motion[i] / 16.0f, 0.0f); break;
      default: break;
    }
  }
  return image;
}

Rgba8Image to_display_pixels(const Image& image, bool tonemap, float exposure) {
  Rgba8Image out{image.width, image.height, std::vector<uint8_t>(image.pixels.size() * 4)};
  parallel_for(0, image.height, [&](int y) {
    for (int x = 0; x < image.width; ++x) {
      size_t i = size_t(y) * image.width + x;
      vec3 c = tonemap ? tonemap_srgb(image.pixels[i], exposure) : glm::clamp(image.pixels[i], 0.0f, 1.0f);
      for (int k = 0; k < 3; ++k) out.pixels[4 * i + k] = uint8_t(std::lround(c[k] * 255.0f));
      out.pixels[4 * i + 3] = 255;
    }
  });
  return out;
}

}  // namespace candela
