#pragma once
// Counter-based random streams: a sample's random numbers depend only on (seed, pixel, sample index,
// stream), never on which thread or in which order tiles run, so images are identical for any thread count.
#include <cstdint>

#include "engine/math.h"

namespace candela {

// 64-bit mix (SplitMix64 finaliser, Steele et al. 2014).
inline uint64_t mix64(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

// PCG32 (O'Neill 2014): 64-bit state, 32-bit output, one multiply-add per number.
class Rng {
 public:
  Rng() : Rng(0, 0) {}
  Rng(uint64_t seed, uint64_t stream) {
    state_ = 0;
    inc_ = (mix64(stream) << 1u) | 1u;
    next_u32();
    state_ += mix64(seed);
    next_u32();
  }
  // A stream keyed by several integers (seed, pixel, sample, pass...).
  static Rng for_key(uint64_t seed, uint64_t a, uint64_t b = 0, uint64_t c = 0) {
    return Rng(mix64(seed ^ mix64(a + 0x9e3779b97f4a7c15ull * (b + 1))), mix64(c + 0x632be59bd9b4e019ull * (a ^ b)));
  }
  uint32_t next_u32() {
    uint64_t old = state_;
    state_ = old * 6364136223846793005ull + inc_;
    uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
    uint32_t rot = uint32_t(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31));
  }
  // Uniform float in [0, 1).
  float next_float() { return float(next_u32() >> 8) * 0x1p-24f; }
  // Two of them, for a 2D decision (the interface engine/sobol.h's streams share).
  vec2 next_2d() { return vec2(next_float(), next_float()); }

 private:
  uint64_t state_, inc_;
};

}  // namespace candela
