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

void Denoiser::denoise(const GBuffer& current, const GBuffer& previous, const Image& noisy, FrameStats& stats,
                       Image& out) {
  CHECK(noisy.width == current.width && noisy.height == current.height);
  std::visit([&](auto& d) { d.denoise(current, previous, noisy, stats, out); }, impl_);
}

void Denoiser::reset() {
  std::visit([](auto& d) { d.reset(); }, impl_);
}

}  // namespace candela
