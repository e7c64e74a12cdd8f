#include "engine/image.h"

#include <OpenImageIO/imageio.h>

#include <bit>
#include <cstdio>
#include <filesystem>

#include "engine/atomic_files.h"
#include "engine/check.h"

namespace candela {

vec3 Image::mean() const {
  glm::dvec3 sum(0.0);
  for (const vec3& p : pixels) sum += glm::dvec3(p);
  return pixels.empty() ? vec3(0.0f) : vec3(sum / double(pixels.size()));
}

static float srgb_oetf(float x) { return x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1.0f / 2.4f) - 0.055f; }

// The filmic curve alone, into [0, 1].
static vec3 filmic(const vec3& linear, float exposure) {
  vec3 x = glm::max(linear * exposure * 0.6f, vec3(0.0f));
  return glm::clamp((x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f), 0.0f, 1.0f);
}

vec3 tonemap_srgb(const vec3& linear, float exposure) {
  vec3 mapped = filmic(linear, exposure);
  return {srgb_oetf(mapped.x), srgb_oetf(mapped.y), srgb_oetf(mapped.z)};
}

namespace {

// lround(255 * srgb_oetf(m)) for m in [0, 1] without the power: boundary[v] is the smallest float whose code
// is at least v, found once by bisection over the floats' bit patterns (the code never falls as m grows; a
// test compares every float around each boundary with the formula), and start[j] is the code of j / 1024, so a
// lookup steps up from its 1/1024 of [0, 1] through at most 4 boundaries (near 0, where the OETF is
// steepest). Cost to build: 255 x 30 powers, once.
struct SrgbCodes {
  float boundary[257];
  uint8_t start[1025];
  static int formula(float m) { return int(std::lround(srgb_oetf(m) * 255.0f)); }
  SrgbCodes() {
    boundary[0] = 0.0f;
    for (int v = 1; v <= 255; ++v) {
      uint32_t lo = 0, hi = std::bit_cast<uint32_t>(1.0f);  // formula(hi) = 255 >= v
      while (lo < hi) {
        const uint32_t mid = lo + (hi - lo) / 2;
        if (formula(std::bit_cast<float>(mid)) >= v)
          hi = mid;
        else
          lo = mid + 1;
      }
      boundary[v] = std::bit_cast<float>(lo);
    }
    boundary[256] = kInfinity;
    for (int j = 0; j <= 1024; ++j) start[j] = uint8_t(formula(float(j) / 1024.0f));
  }
  uint8_t code(float m) const {
    m = m > 0.0f ? std::min(m, 1.0f) : 0.0f;  // NaN gives 0, the byte lround's result for NaN gave on x86
    int v = start[int(m * 1024.0f)];
    while (m >= boundary[v + 1]) ++v;
    return uint8_t(v);
  }
};

// Built on first use (one initialisation check per call: tonemap_srgb8 makes one for its three channels).
const SrgbCodes& srgb_codes() {
  static const SrgbCodes codes;
  return codes;
}

}  // namespace

uint8_t srgb8(float m) { return srgb_codes().code(m); }

std::array<uint8_t, 3> tonemap_srgb8(const vec3& linear, float exposure) {
  const vec3 mapped = filmic(linear, exposure);
  const SrgbCodes& codes = srgb_codes();
  return {codes.code(mapped.x), codes.code(mapped.y), codes.code(mapped.z)};
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
  std::filesystem::path tmp = hidden_beside(target, target.stem().string() + ".tmp" + target.extension().string());
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
    const std::array<uint8_t, 3> c = tonemap_srgb8(image.pixels[i], exposure);
    for (int k = 0; k < 3; ++k) srgb[3 * i + k] = c[k];
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
