#pragma once
// The denoiser a frame pipeline holds: one of none, cross-bilateral, SVGF, chosen by DenoiserKind
// (parameter structs in denoise/params.h), dispatched statically (std::variant, once per frame).
//
//   Denoiser denoiser(DenoiserParams{DenoiserKind::Svgf});
//   denoiser.denoise(gbuffer, prev_gbuffer, noisy, stats, clean);  // each frame, into Image clean
//   denoiser.reset();                                             // on a camera cut
#include <variant>

#include "denoise/bilateral.h"
#include "denoise/params.h"
#include "denoise/svgf.h"

namespace candela {

// DenoiserKind::None: the noisy image, unchanged.
struct NoDenoiser {
  void denoise(const GBuffer&, const GBuffer&, const Image& noisy, FrameStats&, Image& out) { out = noisy; }
  void reset() {}
};

class Denoiser {
 public:
  explicit Denoiser(const DenoiserParams& params);
  // `current` and `noisy` describe this frame (same size); `previous` is the G-buffer of the previous
  // call's frame (used by SVGF's reprojection; empty on the first frame). Stage times go into `stats`. Writes
  // the filtered image into `out`, whose pixels are reused when it already has this size (a new 1280x720
  // image per frame cost SVGF ~2 ms in page faults).
  void denoise(const GBuffer& current, const GBuffer& previous, const Image& noisy, FrameStats& stats, Image& out);
  void reset();

 private:
  std::variant<NoDenoiser, BilateralDenoiser, Svgf> impl_;
};

}  // namespace candela
