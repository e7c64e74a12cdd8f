#pragma once
// The light tree's inner loop: the importance (light_bounds.h, LightBounds::importance) of a node's 8
// children for one shading point, in SIMD lanes (Highway, dispatched at run time; engine/simd_targets.h).
// The lanes repeat the scalar arithmetic in the same order without fused multiply-adds, so each equals
// LightBounds::importance bit for bit on every instruction set (tests/test_samplers.cpp).
#include "samplers/light_bounds.h"

namespace candela {

constexpr int kTreeWidth = 8;
constexpr float kFixedPointUnit = 1.0f / 32767.0f;  // of WideBounds' 16-bit fields

// The bounds of up to 8 siblings side by side (structure of arrays), compact so that a tree node with its
// children's references fills 4 cache lines (256 bytes; 6 with every field in float). Centres and powers stay
// in float: the importance's first operations wait on them. The rest is quantised conservatively, so that
// each slot bounds at least the lights its LightBounds did:
// - the radius in half precision, in units of a power-of-two scale that the owner chooses (radius_scale_for),
//   rounded up;
// - the cone axis as three 16-bit integers (its length is divided out by the importance), and the cone
//   widened by the angle between the true and the rounded axis;
// - cos theta_o and cos theta_e in 16-bit fixed point (x / 32767), rounded down (wider cones).
// An empty slot has phi 0 and so importance 0.
struct alignas(32) WideBounds {
  float cx[kTreeWidth], cy[kTreeWidth], cz[kTreeWidth];
  float phi[kTreeWidth];        // the power, negative for two-sided emitters
  uint16_t radius[kTreeWidth];  // IEEE half-precision bits, times the scale
  int16_t wx[kTreeWidth], wy[kTreeWidth], wz[kTreeWidth];
  int16_t cos_o[kTreeWidth], cos_e[kTreeWidth];

  WideBounds();  // every slot empty
  // Quantises b into `slot`. False (and the slot left empty) when its radius exceeds the half range at this
  // scale: the owner must choose a larger scale and set every slot again.
  [[nodiscard]] bool set(int slot, const LightBounds& b, float radius_scale);
  // The bounds the lanes evaluate for `slot` (w not unit length); LightBounds::importance of them equals
  // the slot's lane bit for bit.
  LightBounds get(int slot, float radius_scale) const;
};
static_assert(sizeof(WideBounds) == 224);

// The scale for a tree whose largest radius is max_radius: the smallest power of two at least max_radius / 16,
// so that radii may grow 4,000 times (refits) before they leave the half range, and a radius of 1e-5 of the
// largest keeps 11 bits.
float radius_scale_for(float max_radius);

// out[k] = LightBounds::importance(ctx) of get(k, radius_scale), for the 8 slots. Cost: ~80 flops, 5 square
// roots and 3 divisions per slot, in one AVX2 / AVX-512 vector or two SSE ones; the quantised fields are
// converted beside the distance's square root, off the chain from the node's load to the importances.
void wide_importance(const WideBounds& bounds, const ShadingContext& ctx, float radius_scale, float out[kTreeWidth]);

}  // namespace candela
