#pragma once
// Cross-bilateral (joint bilateral) filter of one frame's demodulated illumination, guided by the
// G-buffer's depth, normal and albedo (see BilateralParams for the separable form).
#include "denoise/guides.h"
#include "denoise/params.h"
#include "denoise/planes.h"
#include "engine/frame_stats.h"
#include "engine/gbuffer.h"
#include "engine/image.h"

namespace candela {

// Stage "bilateral": reads the guides and `in`; writes `out` (`scratch` holds the horizontal pass).
// Each pixel: 2 (2r + 1) taps, each reading 7 guide floats and 3 colour floats. Pixels not filtered
// (Guides::filtered) keep their input.
void cross_bilateral(const Guides& guides, const BilateralParams& params, const ColorPlanes& in, ColorPlanes& scratch,
                     ColorPlanes& out);

// The whole frame: demodulate, filter, remodulate. Keeps its planes between frames (no history).
class BilateralDenoiser {
 public:
  explicit BilateralDenoiser(const BilateralParams& params) : params_(params) {}
  // `previous` is unused (single-frame filter); present so every denoiser is called alike.
  void denoise(const GBuffer& current, const GBuffer& previous, const Image& noisy, FrameStats& stats, Image& out);
  void reset() {}

 private:
  BilateralParams params_;
  Guides guides_;
  ColorPlanes illumination_, scratch_, filtered_;
};

}  // namespace candela
