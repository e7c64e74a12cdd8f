#pragma once
// Low-discrepancy sample streams: Owen-scrambled Sobol points, padded dimension pair by dimension pair
// (Burley 2020, "Practical Hash-based Owen Scrambling", JCGT 9(4)).
//
// Every decision of a path (film position, light choice, point on the light, BSDF direction, lobe,
// Russian roulette) draws from its own dimension. A 2D decision reads the first two Sobol dimensions,
// which form a (0,2)-sequence: any aligned run of 2^k indices is a (0,k,2)-net, so the first 16 samples
// of a pixel stratify each 2D decision into 16 cells of every elementary shape. A 1D decision reads the
// first dimension alone (van der Corput). Decisions are decorrelated by shuffling the index per
// dimension (a nested scramble of the index, which keeps every aligned run of 2^k indices aligned, so the
// stratification holds at every power of two) and by scrambling the values per dimension. Each point is
// uniform on its square, so an estimator that is unbiased with independent numbers stays unbiased.
//
// The scrambles are keyed on (seed, pixel, epoch, dimension) and the index is the sample's number within
// its accumulation, so images do not depend on thread count or tile order.
#include <array>
#include <cstdint>

#include "engine/math.h"
#include "engine/rng.h"

namespace candela {

// Where an estimator's random numbers come from: independent PCG32 streams; Owen-scrambled Sobol points,
// stratified within each pixel's run of samples (Sobol); or one screen-wide Sobol sequence per frame
// ordered along the Morton curve (ZSobol), which also stratifies neighbouring pixels against each other.
enum class SampleSequence { Independent, Sobol, ZSobol };

// Bits of x in reverse order.
constexpr uint32_t reverse_bits(uint32_t x) {
  x = (x << 16) | (x >> 16);
  x = ((x & 0x00ff00ffu) << 8) | ((x & 0xff00ff00u) >> 8);
  x = ((x & 0x0f0f0f0fu) << 4) | ((x & 0xf0f0f0f0u) >> 4);
  x = ((x & 0x33333333u) << 2) | ((x & 0xccccccccu) >> 2);
  x = ((x & 0x55555555u) << 1) | ((x & 0xaaaaaaaau) >> 1);
  return x;
}

// Laine and Karras' permutation, with the constants Burley 2020 (section 3) found to mix best: each step
// changes a bit only as a function of the bits below it (additions and products with even constants
// carry upwards), so on bit-reversed numbers it is a nested uniform (Owen) scramble.
inline uint32_t laine_karras(uint32_t x, uint32_t seed) {
  x += seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return x;
}

// Nested uniform (Owen) scramble of a 32-bit fixed-point number: bit p flips by a hash of the bits above
// it and of the seed.
inline uint32_t owen_scramble(uint32_t x, uint32_t seed) { return reverse_bits(laine_karras(reverse_bits(x), seed)); }

// The first two Sobol dimensions of index i as 32-bit fixed-point fractions: the first is van der Corput
// in base 2 (the bits of i reversed); the second has the primitive polynomial x + 1, direction numbers
// m_k = m_{k-1} XOR 2 m_{k-1}, m_1 = 1 (Pascal's triangle modulo 2). The second is a product of its 32x32
// generator matrix with the bits of i over GF(2), read as four byte tables (each entry the XOR of the
// columns its byte selects): four loads instead of a loop over 32 bits with unpredictable branches.
// `reversed` gives it bit-reversed, as the scramble wants it.
inline uint32_t sobol_dimension0(uint32_t i) { return reverse_bits(i); }
template <bool reversed = false>
inline uint32_t sobol_dimension1(uint32_t i) {
  using Tables = std::array<std::array<uint32_t, 256>, 4>;
  static constexpr Tables tables = [] {
    std::array<uint32_t, 32> columns{};
    uint32_t m = 1;
    for (int k = 0; k < 32; ++k) {
      columns[size_t(k)] = reversed ? reverse_bits(m << (31 - k)) : m << (31 - k);
      m ^= m << 1;
    }
    Tables t{};
    for (size_t byte = 0; byte < 4; ++byte)
      for (uint32_t v = 0; v < 256; ++v)
        for (size_t bit = 0; bit < 8; ++bit)
          if (v >> bit & 1u) t[byte][v] ^= columns[8 * byte + bit];
    return t;
  }();
  return tables[0][i & 0xffu] ^ tables[1][i >> 8 & 0xffu] ^ tables[2][i >> 16 & 0xffu] ^ tables[3][i >> 24];
}

// A 32-bit fixed-point fraction as a float in [0, 1) (the top 24 bits, so 1 is never reached).
inline float fraction_to_float(uint32_t x) { return float(x >> 8) * 0x1p-24f; }

// Bits of x (16 of them) spread to the even positions.
inline uint32_t spread_bits(uint32_t x) {
  x &= 0xffffu;
  x = (x | (x << 8)) & 0x00ff00ffu;
  x = (x | (x << 4)) & 0x0f0f0f0fu;
  x = (x | (x << 2)) & 0x33333333u;
  x = (x | (x << 1)) & 0x55555555u;
  return x;
}

// Where sample s (of 2^log2_samples per pixel) of pixel (x, y) sits in a screen-wide sequence ordered along
// the Morton curve, as pbrt-v4's ZSobolSampler orders it (Ahmed & Wonka 2020, "Screen-space blue-noise
// diffusion of Monte Carlo sampling error via hierarchical ordering of pixels"): the pixels of an aligned
// 2^j x 2^j block hold an aligned run of 4^j 2^log2_samples indices, so after the nested shuffle their
// samples together form a net: neighbours take complementary strata, and the error is spread to high
// frequencies, where a denoiser's spatial filter removes it. The per-dimension index shuffle of
// SobolStream (a nested scramble, where pbrt permutes base-4 digits) keeps that block structure.
// Indices wrap at 32 bits: images up to 2^(16 - log2_samples / 2) pixels on a side keep them distinct.
inline uint32_t zsobol_index(uint32_t x, uint32_t y, int log2_samples, uint32_t s) {
  return ((spread_bits(y) << 1 | spread_bits(x)) << log2_samples) | s;
}

// The sample stream of one sample of one pixel: successive calls draw successive dimensions.
class SobolStream {
 public:
  // `key`: the pixel's scramble key (seed, pixel, epoch); `index`: the sample's number in its pixel.
  SobolStream(uint64_t key, uint32_t index) : key_(key), reversed_index_(reverse_bits(index)) {}
  static SobolStream for_pixel(uint64_t seed, uint64_t pixel, uint64_t epoch, uint32_t index) {
    return SobolStream(mix64(seed ^ mix64(pixel + 0x9e3779b97f4a7c15ull * (epoch + 1))), index);
  }
  // Sample `index` of one screen-wide sequence (zsobol_index): scrambles shared by every pixel.
  static SobolStream for_screen(uint64_t seed, uint64_t epoch, uint32_t index) {
    return SobolStream(mix64(seed ^ mix64(0x5a50b01ull + 0x9e3779b97f4a7c15ull * (epoch + 1))), index);
  }

  // Each dimension's point, in the bit-reversed domain where the scrambles are Laine-Karras permutations:
  // the shuffled index is reverse(LK(reverse(index))), its first coordinate reverse(shuffled index), whose
  // scramble is reverse(LK(shuffled index)); the second coordinate is tabulated reversed. Three reversals
  // per 2D point instead of seven.
  float next_float() {
    const uint64_t h = dimension_hash();
    return fraction_to_float(reverse_bits(laine_karras(shuffled(h), uint32_t(h >> 32))));
  }
  vec2 next_2d() {
    const uint64_t h = dimension_hash();
    const uint32_t i = shuffled(h);
    const uint32_t seed_y = uint32_t(mix64(h) >> 32);
    return vec2(fraction_to_float(reverse_bits(laine_karras(i, uint32_t(h >> 32)))),
                fraction_to_float(reverse_bits(laine_karras(sobol_dimension1<true>(i), seed_y))));
  }

 private:
  // 64 bits of hash per dimension: the low half shuffles the index, the high half scrambles x.
  uint64_t dimension_hash() { return mix64(key_ + 0x632be59bd9b4e019ull * uint64_t(++dimension_)); }
  uint32_t shuffled(uint64_t h) const { return reverse_bits(laine_karras(reversed_index_, uint32_t(h))); }

  uint64_t key_;
  uint32_t reversed_index_;
  uint32_t dimension_ = 0;
};

}  // namespace candela
