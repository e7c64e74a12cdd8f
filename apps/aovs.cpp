#include "apps/aovs.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "engine/check.h"
#include "engine/parallel.h"

namespace candela {

const std::vector<AovInfo>& aov_table() {
  static const std::vector<AovInfo> table = {
      {Aov::Radiance, "radiance", "the frame's radiance (denoised when a denoiser is set)", "tonemapped", false, true},
      {Aov::Albedo, "albedo", "base colour", "as is", false, false},
      {Aov::Normal, "normal", "shading normal, world space", "n * 0.5 + 0.5", false, false},
      {Aov::Depth, "depth", "linear view depth", "over the farthest hit's depth", false, false},
      {Aov::Motion, "motion", "pixels to last frame's film position (R: x, G: y)", "0.5 + motion / 16", false, false},
      {Aov::ReservoirM, "reservoir-m", "ReSTIR DI reservoir confidence M", "over the frame's largest M", true, false},
      {Aov::ReservoirW, "reservoir-w", "ReSTIR DI contribution weight W", "tonemapped", true, true},
      {Aov::ReservoirLight, "reservoir-light", "ReSTIR DI's chosen light as a hashed colour (black: none)", "as is",
       true, false},
  };
  return table;
}

const AovInfo& aov_info(Aov aov) {
  for (const AovInfo& info : aov_table())
    if (info.aov == aov) return info;
  CHECK(false && "every Aov has a row");
  return aov_table().front();
}

const AovInfo* find_aov(const std::string& name) {
  for (const AovInfo& info : aov_table())
    if (name == info.name) return &info;
  return nullptr;
}

std::vector<std::string> aov_names() {
  std::vector<std::string> names;
  for (const AovInfo& info : aov_table()) names.push_back(info.name);
  return names;
}

bool aov_available(Aov aov, const Renderer& renderer) {
  return !aov_info(aov).restir || renderer.di_reservoirs().size() == renderer.gbuffer().size();
}

Image aov_image(const Renderer& renderer, Aov aov) {
  const GBuffer& g = renderer.gbuffer();
  if (aov == Aov::Radiance) return renderer.image();
  if (g.size() == 0 || !aov_available(aov, renderer))
    return Image(renderer.settings().width, renderer.settings().height);
  if (aov_info(aov).restir) {
    const DiAov kind = aov == Aov::ReservoirM ? DiAov::M : aov == Aov::ReservoirW ? DiAov::W : DiAov::Light;
    return di_reservoir_image(g, renderer.di_reservoirs(), kind);
  }
  Image image(g.width, g.height);
  for (size_t i = 0; i < g.size(); ++i) {
    if (!g.hit(i)) continue;
    switch (aov) {
      case Aov::Albedo: image.pixels[i] = g.albedo[i]; break;
      case Aov::Normal: image.pixels[i] = g.shading_normal[i]; break;
      case Aov::Depth: image.pixels[i] = vec3(g.depth[i]); break;
      case Aov::Motion: image.pixels[i] = vec3(g.motion[i], 0.0f); break;
      default: break;
    }
  }
  return image;
}

namespace {

// The plane's values mapped into [0, 1] for display (AovInfo::shown), for the planes not tonemapped;
// pixels without a surface stay black.
void map_for_display(Aov aov, const GBuffer& g, Image& image) {
  float largest = 0.0f;  // depth: the farthest hit; M: the largest M
  for (const vec3& p : image.pixels) largest = std::max(largest, p.x);
  for (size_t i = 0; i < image.pixels.size() && i < g.size(); ++i) {
    if (!g.hit(i)) continue;
    vec3& p = image.pixels[i];
    switch (aov) {
      case Aov::Normal: p = p * 0.5f + 0.5f; break;
      case Aov::Depth:
      case Aov::ReservoirM: p = largest > 0.0f ? p / largest : p; break;
      case Aov::Motion: p = vec3(0.5f + vec2(p) / 16.0f, 0.0f); break;
      default: break;
    }
  }
}

}  // namespace

Rgba8Image aov_display_pixels(const Renderer& renderer, Aov aov, float exposure) {
  Image image = aov_image(renderer, aov);
  const bool tonemap = aov_info(aov).tonemapped;
  if (!tonemap) map_for_display(aov, renderer.gbuffer(), image);
  Rgba8Image out{image.width, image.height, std::vector<uint8_t>(image.pixels.size() * 4)};
  parallel_for(0, image.height, [&](int y) {
    for (int x = 0; x < image.width; ++x) {
      size_t i = size_t(y) * image.width + x;
      if (tonemap) {
        const std::array<uint8_t, 3> c = tonemap_srgb8(image.pixels[i], exposure);
        for (int k = 0; k < 3; ++k) out.pixels[4 * i + k] = c[k];
      } else {
        const vec3 c = glm::clamp(image.pixels[i], 0.0f, 1.0f);
        for (int k = 0; k < 3; ++k) out.pixels[4 * i + k] = uint8_t(std::lround(c[k] * 255.0f));
      }
      out.pixels[4 * i + 3] = 255;
    }
  });
  return out;
}

void write_aov(const std::string& path, const Renderer& renderer, Aov aov, float exposure) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(c));
  if (ext == ".png" && aov != Aov::Radiance) {
    const Rgba8Image pixels = aov_display_pixels(renderer, aov, exposure);
    write_png_rgba8(path, pixels.width, pixels.height, pixels.pixels.data());
  } else {
    write_image(path, aov_image(renderer, aov), exposure);
  }
}

std::string aovs_markdown() {
  std::string out = "| name | values (EXR) | shown (viewer, PNG) | methods |\n|---|---|---|---|\n";
  for (const AovInfo& info : aov_table())
    out += std::string("| `") + info.name + "` | " + info.values + " | " + info.shown + " | " +
           (info.restir ? "restir-di, restir" : "all") + " |\n";
  return out;
}

}  // namespace candela
