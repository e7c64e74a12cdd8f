// The Sobol sample streams (engine/sobol.h): the points the path tracer reads are stratified as the
// theory promises (every aligned run of 2^k samples of a 2D decision is a (0,k,2)-net, after the index
// shuffle and the value scrambles), the scrambles are bijections that keep aligned runs aligned, and the
// decisions of one path are not copies of each other.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "engine/sobol.h"

namespace candela {
namespace {

// True when the 2^k points have exactly one point in every elementary interval of area 2^-k (each
// split of the square into 2^a x 2^(k-a) cells, a = 0..k): the definition of a (0,k,2)-net in base 2.
bool is_net(const std::vector<vec2>& points, int k) {
  const size_t n = size_t(1) << k;
  if (points.size() != n) return false;
  for (int a = 0; a <= k; ++a) {
    std::vector<int> cells(n, 0);
    for (const vec2& p : points) {
      const size_t x = size_t(p.x * float(1u << a)), y = size_t(p.y * float(1u << (k - a)));
      if (x >= (size_t(1) << a) || y >= (size_t(1) << (k - a))) return false;
      if (++cells[(y << a) | x] > 1) return false;
    }
  }
  return true;
}

TEST(Sobol, FirstTwoDimensionsAreNets) {
  for (int k = 0; k <= 12; ++k) {
    std::vector<vec2> points;
    for (uint32_t i = 0; i < (1u << k); ++i)
      points.push_back(vec2(fraction_to_float(sobol_dimension0(i)), fraction_to_float(sobol_dimension1(i))));
    EXPECT_TRUE(is_net(points, k)) << "k = " << k;
  }
  // The second dimension's generator columns: m_k = 1, 3, 5, 15, 17, 51 (the direction numbers of x + 1).
  const uint32_t m[] = {1, 3, 5, 15, 17, 51};
  for (int k = 0; k < 6; ++k) EXPECT_EQ(sobol_dimension1(1u << k), m[k] << (31 - k)) << k;
}

// A nested scramble permutes: on 16-bit values (seeds varied), every aligned block of 2^j values maps
// onto an aligned block of 2^j values, and no two values collide.
TEST(Sobol, OwenScrambleKeepsAlignedBlocks) {
  for (uint32_t seed : {0u, 1u, 0x9e3779b9u, 0xdeadbeefu}) {
    std::vector<uint32_t> image;
    for (uint32_t v = 0; v < (1u << 16); ++v) image.push_back(owen_scramble(v, seed));
    const uint32_t high = image[0] >> 16;  // the bits above 16 flip by the seed alone
    for (uint32_t x : image) ASSERT_EQ(x >> 16, high) << seed;
    for (int j = 1; j <= 16; j += 3)
      for (uint32_t start = 0; start < (1u << 16); start += 1u << j) {
        const uint32_t block = image[start] >> j;
        for (uint32_t v = start; v < start + (1u << j); ++v) ASSERT_EQ(image[v] >> j, block) << seed << " " << j;
      }
    std::sort(image.begin(), image.end());
    EXPECT_TRUE(std::adjacent_find(image.begin(), image.end()) == image.end()) << seed;
  }
}

// Each 2D decision of a pixel's first 2^k samples (k = 0..10, 8 decisions deep, many pixels) is a
// (0,k,2)-net, and so is every aligned later run (samples 2^k .. 2^(k+1) - 1): stratified at every power of
// two, as a progressive render needs.
TEST(Sobol, StreamsStratifyEveryDecision) {
  const int decisions = 8;
  for (uint64_t pixel = 0; pixel < 20; ++pixel)
    for (int k = 0; k <= 10; ++k)
      for (uint32_t first : {0u, 1u << k}) {
        std::vector<std::vector<vec2>> points(decisions);
        for (uint32_t i = first; i < first + (1u << k); ++i) {
          SobolStream stream = SobolStream::for_pixel(11, pixel, 3, i);
          for (int d = 0; d < decisions; ++d) points[size_t(d)].push_back(stream.next_2d());
        }
        for (int d = 0; d < decisions; ++d)
          ASSERT_TRUE(is_net(points[size_t(d)], k))
              << "pixel " << pixel << ", 2^" << k << " from " << first << ", decision " << d;
      }
}

// Decisions are decorrelated: over 4096 pixels' first samples, the correlation between any two of 6
// dimensions (x and y of three 2D decisions, or 1D ones) is within 4 standard errors of zero (1/64
// each, uniform pairs being independent under the per-dimension scrambles); and a pixel's decision in
// one epoch is not the same number in the next.
TEST(Sobol, DimensionsAndEpochsAreDecorrelated) {
  const int n = 4096, dims = 6;
  for (uint32_t index : {0u, 5u}) {
    std::vector<std::vector<double>> v(dims);
    for (int p = 0; p < n; ++p) {
      SobolStream s = SobolStream::for_pixel(1, uint64_t(p), 0, index);
      for (int d = 0; d < dims; d += 2) {
        vec2 u;
        if (d == 4) {
          u.x = s.next_float();
          u.y = s.next_float();
        } else {
          u = s.next_2d();
        }
        v[size_t(d)].push_back(u.x);
        v[size_t(d + 1)].push_back(u.y);
      }
    }
    for (int a = 0; a < dims; ++a)
      for (int b = a + 1; b < dims; ++b) {
        double sab = 0, sa = 0, sb = 0, saa = 0, sbb = 0;
        for (int i = 0; i < n; ++i) {
          const double x = v[size_t(a)][size_t(i)], y = v[size_t(b)][size_t(i)];
          sa += x;
          sb += y;
          sab += x * y;
          saa += x * x;
          sbb += y * y;
        }
        const double cov = sab / n - sa / n * sb / n;
        const double r = cov / std::sqrt((saa / n - sa / n * sa / n) * (sbb / n - sb / n * sb / n));
        EXPECT_LT(std::abs(r), 4.0 / std::sqrt(double(n))) << "index " << index << ", dimensions " << a << " and " << b;
      }
  }
  int same = 0;
  for (uint64_t p = 0; p < 1000; ++p)
    same += SobolStream::for_pixel(1, p, 0, 0).next_float() == SobolStream::for_pixel(1, p, 1, 0).next_float();
  EXPECT_LT(same, 5);
}

// ZSobol: the screen-wide sequence stratifies neighbours against each other. With 2^l samples per pixel,
// the samples of the pixels of every aligned 2^j x 2^j block (j = 0..3) together form a (0, 2j + l, 2)-net
// in every 2D decision, and so do a pixel's own samples: at one sample per pixel, the four pixels of a
// 2x2 block take the four quadrants.
TEST(Sobol, ScreenSequenceStratifiesNeighbouringPixels) {
  const int decisions = 4;
  for (int l : {0, 2}) {
    for (int j = 0; j <= 3; ++j)
      for (uint32_t bx : {0u, 8u, 40u})
        for (uint32_t by : {0u, 16u}) {
          std::vector<std::vector<vec2>> points(decisions);
          for (uint32_t y = by; y < by + (1u << j); ++y)
            for (uint32_t x = bx; x < bx + (1u << j); ++x)
              for (uint32_t s = 0; s < (1u << l); ++s) {
                SobolStream stream = SobolStream::for_screen(5, 9, zsobol_index(x, y, l, s));
                for (int d = 0; d < decisions; ++d) points[size_t(d)].push_back(stream.next_2d());
              }
          for (int d = 0; d < decisions; ++d)
            ASSERT_TRUE(is_net(points[size_t(d)], 2 * j + l))
                << "2^" << l << " spp, block " << (1 << j) << " at (" << bx << ", " << by << "), decision " << d;
        }
  }
  // Two pixels side by side hold neighbouring indices, and distinct pixels distinct ones.
  EXPECT_EQ(zsobol_index(1, 0, 0, 0), zsobol_index(0, 0, 0, 0) + 1);
  EXPECT_EQ(zsobol_index(0, 1, 0, 0), 2u);
  EXPECT_EQ(zsobol_index(3, 5, 2, 1), ((spread_bits(5) << 1 | spread_bits(3)) << 2) | 1u);
}

}  // namespace
}  // namespace candela
