#pragma once
// The images a frame can be looked at as: its radiance and one debug image per G-buffer or reservoir plane
// (AOVs), each under one name that `render --aov`, `view --show`, the viewer's HUD and shot scripts' "output"
// keys all use. One function produces each plane's values (aov_image, what EXR files hold) and one maps them
// for display (aov_display_pixels: the viewer, PNG files).
#include <cstdint>
#include <string>
#include <vector>

#include "apps/renderer.h"

namespace candela {

enum class Aov { Radiance, Albedo, Normal, Depth, Motion, ReservoirM, ReservoirW, ReservoirLight };

struct AovInfo {
  Aov aov;
  const char* name;    // "reservoir-m"
  const char* values;  // what the plane holds (its EXR values; background pixels are 0)
  const char* shown;   // how it is displayed (viewer, PNG)
  bool restir;         // needs ReSTIR DI's reservoirs (method restir-di or restir)
  bool tonemapped;     // displayed tonemapped like radiance; else its displayed values are clamped to [0, 1]
};

// Every AOV, radiance first.
const std::vector<AovInfo>& aov_table();
const AovInfo& aov_info(Aov aov);
const AovInfo* find_aov(const std::string& name);  // null: no such name
std::vector<std::string> aov_names();              // in table order
// Whether the renderer's last frame has the plane (the reservoir planes need ReSTIR DI's reservoirs).
bool aov_available(Aov aov, const Renderer& renderer);

// The plane's values for the renderer's last frame (radiance: Renderer::image()); black where not available.
// Cost: one pass over the plane.
Image aov_image(const Renderer& renderer, Aov aov);

// 8-bit sRGB RGBA pixels, row 0 at the top.
struct Rgba8Image {
  int width = 0, height = 0;
  std::vector<uint8_t> pixels;  // 4 bytes per pixel
};

// The plane as displayed: tonemapped (tonemap_srgb at `exposure`) where AovInfo::tonemapped, else mapped into
// [0, 1] as AovInfo::shown says and clamped; rounded to nearest as write_image does, so a radiance frame
// matches `candela render`'s PNG. Parallel over rows.
Rgba8Image aov_display_pixels(const Renderer& renderer, Aov aov, float exposure);

// Writes the plane: .exr holds aov_image's values, .png the displayed pixels. Atomic, as write_image.
void write_aov(const std::string& path, const Renderer& renderer, Aov aov, float exposure);

// docs/settings.md's table of AOVs (part of `candela render --help-markdown`).
std::string aovs_markdown();

}  // namespace candela
