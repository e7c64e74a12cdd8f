#pragma once
// The light tree's inner loop: the importance (light_bounds.h, LightBounds::importance) of a node's 8
// children for one shading point, in SIMD lanes (Highway, dispatched at run time; engine/simd_targets.h).
// The lanes repeat the scalar arithmetic in the same order without fused multiply-adds, so each equals
// LightBounds::importance bit for bit on every instruction set (tests/test_samplers.cpp).
#include "samplers/light_bounds.h"

namespace candela {

constexpr int kTreeWidth = 8;

// The bounds of up to 8 siblings side by side (structure of arrays, 352 bytes, so that a tree node with its
// children's references fills 6 cache lines); an empty slot has phi 0 and so importance 0.
struct alignas(32) WideBounds {
  float cx[kTreeWidth], cy[kTreeWidth], cz[kTreeWidth], radius[kTreeWidth];
  float wx[kTreeWidth], wy[kTreeWidth], wz[kTreeWidth];
  float phi[kTreeWidth];  // the power, negative for two-sided emitters
  float cos_o[kTreeWidth], sin_o[kTreeWidth], cos_e[kTreeWidth];

  WideBounds();  // every slot empty
  void set(int slot, const LightBounds& b);
};

// out[k] = LightBounds::importance(ctx) of slot k, for the 8 slots. Cost: ~70 flops, 4 square roots and 2
// divisions per slot, in one AVX2 / AVX-512 vector or two SSE ones; about 75 cycles from the node's load to
// the importances (one square root, one reciprocal and two sine-cosine steps in a row).
void wide_importance(const WideBounds& bounds, const ShadingContext& ctx, float out[kTreeWidth]);

}  // namespace candela
