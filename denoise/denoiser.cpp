#include "denoise/denoiser.h"

#include "engine/check.h"

namespace candela {

static std::variant<NoDenoiser, BilateralDenoiser, Svgf> make_denoiser(const DenoiserParams& p) {
  switch (p.kind) {
    case DenoiserKind::Bilateral: return BilateralDenoiser(p.bilateral);
    case DenoiserKind::Svgf: return Svgf(p.svgf);
    case DenoiserKind::None: break;
  }
  return NoDenoiser{};
}

Denoiser::Denoiser(const DenoiserParams& params) : impl_(make_denoiser(params)) {}

Image Denoiser::denoise(const GBuffer& current, const GBuffer& previous, const Image& noisy, FrameStats& stats) {
  CHECK(noisy.width == current.width && noisy.height == current.height);
  return std::visit([&](auto& d) { return d.denoise(current, previous, noisy, stats); }, impl_);
}

void Denoiser::reset() {
  std::visit([](auto& d) { d.reset(); }, impl_);
}

}  // namespace candela
