#pragma once
// Linear RGB images, tonemapping and atomic image files (EXR keeps linear radiance, PNG is tonemapped sRGB).
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/math.h"

namespace candela {

struct Image {
  int width = 0, height = 0;
  std::vector<vec3> pixels;  // row-major, row 0 at the top

  Image() = default;
  Image(int w, int h) : width(w), height(h), pixels(size_t(w) * h, vec3(0.0f)) {}
  vec3& at(int x, int y) { return pixels[size_t(y) * width + x]; }
  const vec3& at(int x, int y) const { return pixels[size_t(y) * width + x]; }
  vec3 mean() const;
};

// ACES filmic curve fitted by Narkowicz 2015 ("ACES Filmic Tone Mapping Curve"), then the sRGB OETF.
vec3 tonemap_srgb(const vec3& linear, float exposure = 1.0f);
// Its 8-bit codes, lround(255 * tonemap_srgb(linear, exposure)) per channel, bit for bit (PNG files and the
// viewer's display pass).
std::array<uint8_t, 3> tonemap_srgb8(const vec3& linear, float exposure = 1.0f);
// The sRGB OETF's 8-bit code of a display value m in [0, 1] (clamped; NaN gives 0): lround(255 * OETF(m)),
// found among the 255 codes' boundaries instead of by a power.
uint8_t srgb8(float m);

// Writes .exr (float, linear) or .png (8-bit tonemapped sRGB) chosen by extension. The file appears
// atomically (written beside it under a temporary name, then renamed). Throws InputError on failure.
void write_image(const std::string& path, const Image& image, float exposure = 1.0f);
// Writes 8-bit RGBA pixels (row 0 at the top, already display-encoded) as a PNG, atomically like
// write_image. Throws InputError on failure.
void write_png_rgba8(const std::string& path, int width, int height, const uint8_t* rgba);
// Reads an EXR (or any OIIO format) as linear RGB. Throws InputError naming the file on failure.
Image read_image(const std::string& path);

}  // namespace candela
