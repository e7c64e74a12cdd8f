#pragma once
// SVGF's stages (Schied et al. 2017) as functions over named intermediate buffers; the Svgf class
// (svgf.h) runs them in order and owns the history they read and write.
#include <vector>

#include "denoise/guides.h"
#include "denoise/params.h"
#include "denoise/planes.h"
#include "engine/gbuffer.h"

namespace candela {

// What the a-trous iterations read and write: illumination, its luminance and its variance.
struct AtrousPlanes {
  ColorPlanes color;
  std::vector<float> luminance, variance;
  void resize(int w, int h);
};

// Temporally integrated luminance moments and how many frames each pixel has accumulated.
struct SvgfMoments {
  std::vector<float> moment1, moment2, length;
  void resize(size_t n);
};

// What the previous frame left for reprojection: the first a-trous iteration's colour (sec. 4.1), the
// integrated moments and which pixels were filtered (their colour is illumination; at the other hits it
// is radiance); `valid` is false before the first frame and after a reset.
struct SvgfHistory {
  ColorPlanes color;
  SvgfMoments moments;
  std::vector<int32_t> filtered;  // 32 bits per pixel: the temporal kernel gathers it
  bool valid = false;
};

// Stage "svgf_temporal" (sec. 4.1-4.2): reads the current and previous G-buffers (motion, jitter, depth,
// normal, instance), the guides (depth slope), this frame's illumination and the history; writes
// `integrated` (colour and luminance; not its variance) and `moments`. Per pixel: the pixel centre is
// reprojected with its motion vector and the 2x2 bilinear taps that pass the consistency tests (same
// instance, normal cosine, depth within the slope times the distance between the jittered samples plus
// a relative tolerance) are blended; if none does, the consistent pixels of the 3x3 block around the
// sample's previous position; if none, the history restarts. Colour and moments are then blended with
// alpha = max(alpha, 1 / length). Hits that are not filtered (emitter borders) accumulate their radiance
// the same way, from history that was not filtered either. O(pixels), up to 13 history reads per pixel.
void svgf_temporal(const GBuffer& current, const GBuffer& previous, const Guides& guides,
                   const ColorPlanes& illumination, const SvgfHistory& history, const SvgfParams& params,
                   AtrousPlanes& integrated, SvgfMoments& moments);

// Stage "svgf_variance" (sec. 4.2): reads the guides and the integrated moments; writes `variance` =
// mu2 - mu1^2 where the history holds at least params.spatial_variance_below frames, else the same from
// moments averaged over a 7x7 neighbourhood with the depth and normal weights. O(pixels), 49 taps per
// short-history pixel (chunks of 8 pixels without one are not filtered).
void svgf_variance(const Guides& guides, const SvgfMoments& moments, const SvgfParams& params,
                   std::vector<float>& variance);

// Stage "svgf_atrous", one iteration (sec. 4.3): reads the guides and `in`; writes `out`, filtered with
// the 5x5 B3-spline kernel at taps `step` pixels apart, weights w_z w_n w_l with
// w_l = exp(-|l_p - l_q| / (sigma_l sqrt(g3x3(Var(l_p))) + eps)) (eq. 5) and the variance filtered
// with the squared weights (eq. 2). `scale` is scratch for 1 / (sigma_l sqrt(g3x3 Var) + eps).
// O(pixels): 9 + 25 taps per filtered pixel.
void svgf_atrous_iteration(const Guides& guides, const SvgfParams& params, int step, const AtrousPlanes& in,
                           std::vector<float>& scale, AtrousPlanes& out);

}  // namespace candela
