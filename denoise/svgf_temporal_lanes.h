#pragma once
// SVGF's temporal stage (svgf_temporal in svgf_stages.h) in SIMD lanes, one row of pixels at a time: the
// reprojection's bilinear taps, their consistency tests and the blend of colour and moments for 8 (AVX2) or
// 16 (AVX-512) pixels per vector, history read with gathers. The kernel repeats the scalar code's
// operations in its order (both files are compiled without fused multiply-adds), so it writes the scalar
// code's bits (test Denoise.SvgfTemporalLanesGiveTheScalarBits). Pixels whose bilinear taps keep no weight
// (the scalar code then searches the 3x3 block) and a row's last pixels short of a vector are left to
// the scalar code.
#include <cstdint>

namespace candela {

// What the kernel reads and writes, as plain planes (width x height, row-major; vec2 and vec3 planes
// interleaved as the G-buffer stores them).
struct TemporalPlanes {
  int width = 0, height = 0;
  bool reproject = false;  // a valid history of this size exists
  float normal_tolerance = 0.0f, depth_tolerance = 0.0f;
  float alpha_color = 0.0f, alpha_moments = 0.0f, max_history = 0.0f;
  // This frame: G-buffer, guides, illumination.
  const uint32_t* instance = nullptr;
  const float *normal = nullptr, *depth = nullptr, *motion = nullptr, *jitter = nullptr;  // xyz, xy per pixel
  const uint8_t* filtered = nullptr;
  const float* depth_slope = nullptr;
  const float *r = nullptr, *g = nullptr, *b = nullptr;
  // Last frame: G-buffer and history (read only with `reproject`).
  const uint32_t* prev_instance = nullptr;
  const float *prev_normal = nullptr, *prev_depth = nullptr, *prev_jitter = nullptr;
  const int32_t* prev_filtered = nullptr;
  const float *history_r = nullptr, *history_g = nullptr, *history_b = nullptr;
  const float *history_m1 = nullptr, *history_m2 = nullptr, *history_length = nullptr;
  // Written: the integrated colour and luminance, the moments and history length.
  float *out_r = nullptr, *out_g = nullptr, *out_b = nullptr, *out_luminance = nullptr;
  float *moment1 = nullptr, *moment2 = nullptr, *length = nullptr;
};

// Row y: writes every pixel the kernel can finish and returns how many it left to the scalar code, their
// x in `left` (room for `width` entries). ~120 flops and up to 4 x 14 gathers per pixel, in lanes.
int svgf_temporal_row_lanes(const TemporalPlanes& planes, int y, int* left);

}  // namespace candela
