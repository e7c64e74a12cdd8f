#include "denoise/bilateral.h"

#include <cmath>

#include "denoise/demodulate.h"
#include "denoise/edge_stopping.h"
#include "engine/check.h"

namespace candela {

namespace {

// Filters colour planes with the geometric weights times an albedo range term
// exp(-|a_p - a_q|_1 / sigma_albedo).
struct AlbedoKernel {
  const float *ar, *ag, *ab;  // albedo
  const float *r, *g, *b;     // input illumination
  const ColorPlanes& in;
  ColorPlanes& out;
  const uint8_t* filtered;
  float inv_sigma_albedo;

  AlbedoKernel(const Guides& guides, const ColorPlanes& in, ColorPlanes& out, float inv_sigma_albedo)
      : ar(guides.albedo.r.data()),
        ag(guides.albedo.g.data()),
        ab(guides.albedo.b.data()),
        r(in.r.data()),
        g(in.g.data()),
        b(in.b.data()),
        in(in),
        out(out),
        filtered(guides.filtered.data()),
        inv_sigma_albedo(inv_sigma_albedo) {}

  struct Chunk {
    float ar[kLanes], ag[kLanes], ab[kLanes];
    float sw[kLanes] = {}, sr[kLanes] = {}, sg[kLanes] = {}, sb[kLanes] = {};
  };
  bool begin(Chunk& c, size_t i0, int lanes) const {
    if (!any_filtered(filtered, i0, lanes)) {
      for (int k = 0; k < lanes; ++k) out.set(i0 + k, in.at(i0 + k));
      return false;
    }
    for (int k = 0; k < kLanes; ++k) {
      size_t i = i0 + size_t(std::min(k, lanes - 1));
      c.ar[k] = ar[i];
      c.ag[k] = ag[i];
      c.ab[k] = ab[i];
    }
    return true;
  }
  float range(const Chunk& c, int k, size_t q) const {
    return (std::abs(c.ar[k] - ar[q]) + std::abs(c.ag[k] - ag[q]) + std::abs(c.ab[k] - ab[q])) * inv_sigma_albedo;
  }
  void gather(Chunk& c, int k, size_t q, float w) const {
    c.sw[k] += w;
    c.sr[k] += w * r[q];
    c.sg[k] += w * g[q];
    c.sb[k] += w * b[q];
  }
  void store(const Chunk& c, size_t i0, int lanes) const {
    if (lanes == kLanes) {  // a chunk inside the image: whole vectors
      store_means(filtered_lanes(filtered + i0), load_lanes(c.sw), c.sr, c.sg, c.sb, in, out, i0);
      return;
    }
    for (int k = 0; k < lanes; ++k) {
      size_t i = i0 + size_t(k);
      // A filtered pixel's own tap has weight h(0) > 0, so sw > 0 there.
      out.set(i, filtered[i] ? vec3(c.sr[k], c.sg[k], c.sb[k]) / c.sw[k] : in.at(i));
    }
  }
};

}  // namespace

void cross_bilateral(const Guides& guides, const BilateralParams& params, const ColorPlanes& in, ColorPlanes& scratch,
                     ColorPlanes& out) {
  CHECK(params.radius >= 0 && params.sigma_spatial > 0.0f && params.sigma_albedo > 0.0f);
  CHECK(in.width == guides.width && in.height == guides.height);
  for (ColorPlanes* p : {&scratch, &out})
    if (p->width != in.width || p->height != in.height) p->resize(in.width, in.height);
  float inv_sigma_albedo = 1.0f / params.sigma_albedo;
  // One separable pass each way: offsets -r..r, Gaussian spatial weights.
  auto gaussian = [&](int tx, int ty) {
    return std::exp(-float(tx * tx + ty * ty) / (2.0f * params.sigma_spatial * params.sigma_spatial));
  };
  Stencil horizontal(params.radius, 0, 1, gaussian), vertical(0, params.radius, 1, gaussian);
  AlbedoKernel first(guides, in, scratch, inv_sigma_albedo);
  filter_image(guides, params.edges, horizontal, first);
  AlbedoKernel second(guides, scratch, out, inv_sigma_albedo);
  filter_image(guides, params.edges, vertical, second);
}

void BilateralDenoiser::denoise(const GBuffer& current, const GBuffer&, const Image& noisy, FrameStats& stats,
                                Image& out) {
  prepare_frame(current, noisy, true, guides_, illumination_, stats);
  {
    StageTimer timer(stats, "bilateral");
    cross_bilateral(guides_, params_, illumination_, scratch_, filtered_);
  }
  StageTimer timer(stats, "denoise_remodulate");
  remodulate(filtered_, current, guides_, noisy, out);
}

}  // namespace candela
