#pragma once
// The denoiser a frame pipeline holds: one of none, cross-bilateral, SVGF, chosen by DenoiserKind
// (parameter structs in denoise/params.h), dispatched statically (std::variant, once per frame).
//
//   Denoiser denoiser(DenoiserParams{DenoiserKind::Svgf});
//   Image clean = denoiser.denoise(gbuffer, prev_gbuffer, noisy, stats);  // each frame
//   denoiser.reset();                                                   // on a camera cut
#include <variant>

#include "denoise/bilateral.h"
#include "denoise/params.h"
#include "denoise/svgf.h"

namespace candela {

// DenoiserKind::None: the noisy image, unchanged.
struct NoDenoiser {
  Image denoise(const GBuffer&, const GBuffer&, const Image& noisy, FrameStats&) { return noisy; }
  void reset() {}
};

class Denoiser {
 public:
  explicit Denoiser(const DenoiserParams& params);
  // `current` and `noisy` describe this frame (same size); `previous` is the G-buffer of the previous
  // call's frame (used by SVGF's reprojection; empty on the first frame). Stage times go into `stats`.
  Image denoise(const GBuffer& current, const GBuffer& previous, const Image& noisy, FrameStats& stats);
  void reset();

 private:
  std::variant<NoDenoiser, BilateralDenoiser, Svgf> impl_;
};

}  // namespace candela
