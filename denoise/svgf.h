#pragma once
// SVGF (Schied et al. 2017, "Spatiotemporal Variance-Guided Filtering: Real-Time Reconstruction for
// Path-Traced Global Illumination"): demodulate, temporal accumulation with reprojection, variance from
// luminance moments, a-trous wavelet filtering guided by that variance, remodulate. Owns the history.
#include "denoise/guides.h"
#include "denoise/params.h"
#include "denoise/svgf_stages.h"
#include "engine/frame_stats.h"
#include "engine/gbuffer.h"
#include "engine/image.h"

namespace candela {

class Svgf {
 public:
  explicit Svgf(const SvgfParams& params = {});
  // Denoises one frame of noisy radiance seen through `current`; `previous` is the G-buffer of the frame
  // denoised before (any size, e.g. empty, on the first frame: then there is no history). Stages:
  // denoise_guides, denoise_demodulate, svgf_temporal, svgf_variance, svgf_atrous, denoise_remodulate. Writes
  // `out` (see Denoiser::denoise).
  void denoise(const GBuffer& current, const GBuffer& previous, const Image& noisy, FrameStats& stats, Image& out);
  // Forgets the history (camera cut, scene change): the next frame starts afresh.
  void reset() { history_.valid = false; }

 private:
  void keep_history(const ColorPlanes& color);

  SvgfParams params_;
  Guides guides_;
  ColorPlanes illumination_;
  SvgfHistory history_;
  SvgfMoments moments_;       // this frame's integrated moments (become the history's)
  AtrousPlanes atrous_[2];    // ping-pong; atrous_[0] starts with the temporal output
  std::vector<float> scale_;  // a-trous scratch: luminance edge-stopping scale
};

}  // namespace candela
