#pragma once
// The inner loop shared by the cross-bilateral filter and the a-trous iterations: a row is processed in
// chunks of kLanes neighbouring pixels; for each tap of the kernel the chunk's lanes read kLanes
// consecutive floats of every plane, which the compiler turns into vector loads. The geometric weights
// (depth, normal; Schied et al. 2017, eq. 3-4, see EdgeStoppingParams) are computed here; a Kernel adds
// its own range term (albedo, luminance) to the exponent and accumulates what it filters.
#include <array>
#include <bit>
#include <cstdint>
#include <cstring>

#include "denoise/guides.h"
#include "denoise/params.h"
#include "engine/check.h"

namespace candela {

// 16: one AVX-512 vector of floats (two AVX2 ones). Measured against 8 on 2026-12-06: the a-trous stage 0.66x
// at 1280x720 (docs/performance.md, "Denoiser cost").
inline constexpr int kLanes = 16;

// exp(-x) for x >= 0 with relative error below 3e-4: exp(-x) = 2^-n 2^-f with u = x log2(e) = n + f,
// 2^-f by its degree-5 Taylor polynomial in f ln 2 (f in [0, 1)), 2^-n put into the exponent bits.
// Branch- and call-free (u >= 0, so truncation is the floor), so loops over it vectorise; arguments
// beyond 80 give exp(-80), which no weight sum notices.
inline float fast_exp_neg(float x) {
  float u = std::clamp(x, 0.0f, 80.0f) * 1.44269504f;
  int32_t n = int32_t(u);
  float f = (u - float(n)) * 0.693147181f;
  float p = 1.0f - f * (1.0f - f * (0.5f - f * (1.0f / 6.0f - f * (1.0f / 24.0f - f * (1.0f / 120.0f)))));
  return p * std::bit_cast<float>((127 - n) << 23);
}

// max(0, c)^128 by seven squarings.
inline float normal_power(float c) {
  float c2 = std::max(c, 0.0f) * std::max(c, 0.0f), c4 = c2 * c2, c8 = c4 * c4, c16 = c8 * c8, c32 = c16 * c16;
  return (c32 * c32) * (c32 * c32);
}

// A whole chunk as one vector (GCC's vector extensions), for the kernels' final stores: their loop over the
// lanes (a division and a select per lane) stayed scalar in every form GCC 12 was given, a quarter of the
// a-trous time.
using LaneVector = float __attribute__((vector_size(kLanes * sizeof(float))));
using LaneMask = int32_t __attribute__((vector_size(kLanes * sizeof(float))));
inline LaneVector load_lanes(const float* p) {
  LaneVector v;
  std::memcpy(&v, p, sizeof(v));
  return v;
}
inline void store_lanes(float* p, LaneVector v) { std::memcpy(p, &v, sizeof(v)); }
// All ones in the lanes whose pixel is filtered.
inline LaneMask filtered_lanes(const uint8_t* filtered) {
  LaneMask m;
  for (int k = 0; k < kLanes; ++k) m[k] = filtered[k] != 0 ? -1 : 0;
  return m;
}
// The weighted means sr / sw, sg / sw, sb / sw where `keep`, else the input colour, into out[0, kLanes).
// Returns the means (computed in every lane; only the kept ones are meaningful).
inline std::array<LaneVector, 3> store_means(LaneMask keep, LaneVector sw, const float* sr, const float* sg,
                                             const float* sb, const ColorPlanes& in, ColorPlanes& out, size_t i0) {
  const std::array<LaneVector, 3> mean = {load_lanes(sr) / sw, load_lanes(sg) / sw, load_lanes(sb) / sw};
  store_lanes(out.r.data() + i0, keep ? mean[0] : load_lanes(in.r.data() + i0));
  store_lanes(out.g.data() + i0, keep ? mean[1] : load_lanes(in.g.data() + i0));
  store_lanes(out.b.data() + i0, keep ? mean[2] : load_lanes(in.b.data() + i0));
  return mean;
}

// Without an early exit, so that with lanes = kLanes (a chunk inside the image) it is one vector test.
inline bool any_filtered(const uint8_t* filtered, size_t i0, int lanes) {
  uint8_t any = 0;
  for (int k = 0; k < lanes; ++k) any |= filtered[i0 + k];
  return any != 0;
}

struct Tap {
  int dx, dy;  // offset in pixels
  float h;     // kernel weight
  int ring;    // Chebyshev distance in units of the stencil's spacing
};

inline constexpr int kMaxRings = 16;

// The taps of a filter: the (2 rx + 1) x (2 ry + 1) grid of points `spacing` pixels apart, weighted by
// h(tx, ty) (grid units). The depth weight's distance is d(p, q) = ring * spacing + 1.
struct Stencil {
  std::vector<Tap> taps;
  int rings = 0, reach = 0;  // reach: largest |dx| in pixels
  float spacing = 1.0f;

  template <class H>
  Stencil(int rx, int ry, int spacing_pixels, H&& h) : spacing(float(spacing_pixels)) {
    for (int ty = -ry; ty <= ry; ++ty)
      for (int tx = -rx; tx <= rx; ++tx)
        taps.push_back(Tap{tx * spacing_pixels, ty * spacing_pixels, h(tx, ty), std::max(std::abs(tx), std::abs(ty))});
    rings = std::max(rx, ry) + 1;
    reach = rx * spacing_pixels;
    CHECK(rings <= kMaxRings);
  }
};

// Filters row y, pixels [x0, x0 + kLanes) (clipped to the image), over `taps`. kBorder: some tap may
// fall outside the image horizontally (those taps are skipped per lane; slower, not vectorised), or the
// chunk may be cut by the image's right edge; without it, lanes is the constant kLanes, so that the
// centre pixels' loads (here and in the kernel's begin) are vector loads instead of gathers.
// Kernel: struct Chunk (its per-lane state); bool begin(Chunk&, i0, lanes) loads the centre pixels and
// returns whether any lane needs filtering (if not, it has written the chunk's output itself);
// float range(const Chunk&, k, q) is its term of the weight's exponent; gather(Chunk&, k, q, weight)
// accumulates tap q into lane k; store(const Chunk&, i0, lanes) writes the result.
template <bool kBorder, class Kernel>
void filter_chunk(const Guides& g, const EdgeStoppingParams& e, const Stencil& stencil, int y, int x0, Kernel& kernel) {
  const int w = g.width, h = g.height;
  const size_t i0 = size_t(y) * size_t(w) + size_t(x0);
  const int lanes = kBorder ? std::min(kLanes, w - x0) : kLanes;
  typename Kernel::Chunk c;
  if (!kernel.begin(c, i0, lanes)) return;
  // Centre guides; inv_d[r] = 1 / (sigma_z s_p d + eps_p) for the taps of ring r.
  float cz[kLanes], cnx[kLanes], cny[kLanes], cnz[kLanes], inv_d[kMaxRings][kLanes];
  for (int k = 0; k < kLanes; ++k) {
    size_t i = i0 + size_t(std::min(k, lanes - 1));
    cz[k] = g.depth[i];
    cnx[k] = g.nx[i];
    cny[k] = g.ny[i];
    cnz[k] = g.nz[i];
  }
  for (int r = 0; r < stencil.rings; ++r)
    for (int k = 0; k < kLanes; ++k) {
      size_t i = i0 + size_t(std::min(k, lanes - 1));
      inv_d[r][k] =
          1.0f / (e.sigma_depth * g.depth_slope[i] * (float(r) * stencil.spacing + 1.0f) + e.depth_epsilon * cz[k]);
    }
  const float* depth = g.depth.data();
  const float *nx = g.nx.data(), *ny = g.ny.data(), *nz = g.nz.data();
  for (const Tap& t : stencil.taps) {
    if (t.dx == 0 && t.dy == 0) {
      // The centre tap: its depth and range terms are exp(0) = 1 and its normal term (n . n)^128 is 1 for the
      // unit normal of a filtered pixel (the only lanes whose sums are read), so its weight is the kernel's h.
      // Skipping the weight's arithmetic saves one tap in nine of the 3x3 kernel.
      for (int k = 0; k < kLanes; ++k) kernel.gather(c, k, i0 + size_t(std::min(k, lanes - 1)), t.h);
      continue;
    }
    const float* inv = inv_d[t.ring];
    int qy = y + t.dy;
    if (qy < 0 || qy >= h) continue;
    const size_t row = size_t(qy) * size_t(w);
    for (int k = 0; k < kLanes; ++k) {
      int qx = x0 + k + t.dx;
      if constexpr (kBorder) {
        if (qx < 0 || qx >= w) continue;
      }
      size_t q = row + size_t(qx);
      float ez = std::abs(cz[k] - depth[q]) * inv[k];
      float wn = normal_power(cnx[k] * nx[q] + cny[k] * ny[q] + cnz[k] * nz[q]);
      kernel.gather(c, k, q, t.h * wn * fast_exp_neg(ez + kernel.range(c, k, q)));
    }
  }
  kernel.store(c, i0, lanes);
}

// Runs the kernel over the whole image, rows in parallel; chunks whose taps all stay inside the image
// take the vectorised path.
template <class Kernel>
void filter_image(const Guides& g, const EdgeStoppingParams& e, const Stencil& stencil, Kernel& kernel) {
  const int reach = stencil.reach;
  for_each_row(g.height, [&](int y) {
    for (int x0 = 0; x0 < g.width; x0 += kLanes) {
      if (x0 >= reach && x0 + kLanes + reach <= g.width)
        filter_chunk<false>(g, e, stencil, y, x0, kernel);
      else
        filter_chunk<true>(g, e, stencil, y, x0, kernel);
    }
  });
}

}  // namespace candela
