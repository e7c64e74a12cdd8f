#pragma once
// Parameters of the denoisers, each with its default and what it trades.
#include <cstdint>

namespace candela {

enum class DenoiserKind { None, Bilateral, Svgf };

// Edge-stopping on geometry, shared by both filters (Schied et al. 2017, eq. 3 and 4):
//   w_z = exp(-|z_p - z_q| / (sigma_z * s_p * d(p, q) + eps_p)),  w_n = max(0, n_p . n_q)^128
// where s_p = |dz/dx| + |dz/dy| at p and d(p, q) the Chebyshev pixel distance plus one pixel of jitter
// slack, so s_p * d(p, q) bounds the paper's |grad z . (p - q)| for the jittered sample positions (the
// paper's form vanishes along iso-depth directions, where jittered depths still differ);
// eps_p = depth_epsilon * z_p. sigma_n is fixed at the paper's 128 (seven squarings).
struct EdgeStoppingParams {
  float sigma_depth = 1.0f;     // sigma_z: larger blurs across depth steps more readily
  float depth_epsilon = 1e-3f;  // relative to the pixel's depth; keeps w_z finite on planes facing the camera
};

// Cross-bilateral filter: one frame, weights from the G-buffer only (no colour range term), applied as
// a horizontal then a vertical pass (separable approximation, Pham & van Vliet 2005, "Separable bilateral
// filtering for fast video preprocessing"): 2 * (2r + 1) taps per pixel instead of (2r + 1)^2.
struct BilateralParams {
  int radius = 3;              // taps per side per pass (2 sigma); cost is linear in it
  float sigma_spatial = 1.5f;  // pixels; larger removes more noise and blurs lighting gradients more (on
                               // 1-spp direct light of cornell at 128x72, sigma 3 (r 8) had 2.3x the error)
  float sigma_albedo = 0.1f;   // L1 albedo difference scale; smaller keeps texture edges apart more strictly
  EdgeStoppingParams edges;
};

// SVGF (Schied et al. 2017, "Spatiotemporal Variance-Guided Filtering").
struct SvgfParams {
  float alpha_color = 0.2f;         // temporal blend of the new frame's colour (sec. 4.1); smaller: smoother, more lag
  float alpha_moments = 0.2f;       // the same for the luminance moments (sec. 4.2)
  float max_history = 32.0f;        // history length cap (frames); alpha is max(alpha, 1 / history), so the first
                                    // frames after a disocclusion average uniformly
  int spatial_variance_below = 4;   // history length under which variance is estimated spatially (7x7, sec. 4.2)
  int atrous_iterations = 5;        // steps 1, 2, 4, 8, 16 (sec. 4.3)
  int atrous_radius = 1;            // taps per side: 1 = 3x3 binomial (1, 2, 1) / 4 (9 taps), 2 = the paper's 5x5
                                    // B3 spline (25 taps, reaches twice as far). 3x3 measured better and faster
                                    // (docs/denoising.md, "The a-trous kernel"): the wider kernel blurs lighting
                                    // more than it removes noise after temporal accumulation
  float sigma_luminance = 4.0f;     // sigma_l of the luminance edge-stopping (eq. 5)
  float luminance_epsilon = 1e-4f;  // keeps w_l finite where the variance is zero
  float depth_tolerance = 0.05f;    // reprojection: relative depth difference accepted beyond the expected slope
  float normal_tolerance = 0.9f;    // reprojection: least cosine between the current and previous normal
  EdgeStoppingParams edges;
  bool simd = true;  // the temporal stage in SIMD lanes (svgf_temporal_lanes.h); false: the scalar code alone, the
                     // reference the lanes are tested against (not a setting)
};

struct DenoiserParams {
  DenoiserKind kind = DenoiserKind::None;
  BilateralParams bilateral;
  SvgfParams svgf;
};

}  // namespace candela
