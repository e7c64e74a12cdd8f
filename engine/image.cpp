#include "engine/image.h"

#include <OpenImageIO/imageio.h>

#include <cstdio>
#include <filesystem>

#include "engine/check.h"

namespace candela {

vec3 Image::mean() const {
  glm::dvec3 sum(0.0);
  for (const vec3& p : pixels) sum += glm::dvec3(p);
  return pixels.empty() ? vec3(0.0f) : vec3(sum / double(pixels.size()));
}

static float srgb_oetf(float x) { return x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1.0f / 2.4f) - 0.055f; }

vec3 tonemap_srgb(const vec3& linear, float exposure) {
  vec3 x = glm::max(linear * exposure * 0.6f, vec3(0.0f));
  vec3 mapped = glm::clamp((x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f), 0.0f, 1.0f);
  return {srgb_oetf(mapped.x), srgb_oetf(mapped.y), srgb_oetf(mapped.z)};
}

static bool has_extension(const std::string& path, const char* ext) {
  std::string e = std::filesystem::path(path).extension().string();
  for (char& c : e) c = char(std::tolower(c));
  return e == ext;
}

// Writes `data` (laid out as `spec` says) to `path` through a temporary file beside it, then renames it
// into place, so the file appears whole or not at all. Throws InputError naming the file.
static void write_atomically(const std::string& path, const OIIO::ImageSpec& spec, const void* data) {
  std::filesystem::path target(path);
  std::filesystem::path tmp =
      target.parent_path() / ("." + target.stem().string() + ".tmp" + target.extension().string());
  auto out = OIIO::ImageOutput::create(tmp.string());
  bool ok = out && out->open(tmp.string(), spec) && out->write_image(spec.format, data) && out->close();
  std::error_code ec;
  if (!ok) {
    std::string why = out ? out->geterror() : OIIO::geterror();
    std::filesystem::remove(tmp, ec);
    throw InputError(path + ": cannot write image: " + why);
  }
  std::filesystem::rename(tmp, target, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw InputError(path + ": cannot write image: " + ec.message());
  }
}

void write_image(const std::string& path, const Image& image, float exposure) {
  bool exr = has_extension(path, ".exr");
  if (!exr && !has_extension(path, ".png")) throw InputError(path + ": output must end in .exr or .png");
  OIIO::ImageSpec spec(image.width, image.height, 3, exr ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
  if (exr) {
    write_atomically(path, spec, image.pixels.data());
    return;
  }
  std::vector<uint8_t> srgb(image.pixels.size() * 3);
  for (size_t i = 0; i < image.pixels.size(); ++i) {
    vec3 c = tonemap_srgb(image.pixels[i], exposure);
    for (int k = 0; k < 3; ++k) srgb[3 * i + k] = uint8_t(std::lround(c[k] * 255.0f));
  }
  write_atomically(path, spec, srgb.data());
}

void write_png_rgba8(const std::string& path, int width, int height, const uint8_t* rgba) {
  if (!has_extension(path, ".png")) throw InputError(path + ": must end in .png");
  write_atomically(path, OIIO::ImageSpec(width, height, 4, OIIO::TypeDesc::UINT8), rgba);
}

Image read_image(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) throw InputError(path + ": cannot read image: " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.nchannels < 3) throw InputError(path + ": expected an RGB image");
  Image image(spec.width, spec.height);
  std::vector<float> data(size_t(spec.width) * spec.height * spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, data.data()))
    throw InputError(path + ": cannot read image: " + in->geterror());
  for (size_t i = 0; i < image.pixels.size(); ++i)
    image.pixels[i] = vec3(data[i * spec.nchannels], data[i * spec.nchannels + 1], data[i * spec.nchannels + 2]);
  return image;
}

}  // namespace candela
