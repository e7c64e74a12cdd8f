#include "denoise/edge_stopping.h"
#include "denoise/svgf_stages.h"
#include "engine/check.h"

namespace candela {

namespace {

// B3-spline weights (1, 4, 6, 4, 1) / 16 (Schied et al. 2017, sec. 4.3), and the 3x3 alternative's
// binomial (1, 2, 1) / 4.
constexpr float kB3[5] = {1.0f / 16.0f, 1.0f / 4.0f, 3.0f / 8.0f, 1.0f / 4.0f, 1.0f / 16.0f};
constexpr float kBinomial3[3] = {1.0f / 4.0f, 1.0f / 2.0f, 1.0f / 4.0f};

// scale = 1 / (sigma_l sqrt(g3x3(Var)) + eps): the variance prefiltered with the 3x3 Gaussian
// (1, 2, 1)^2 / 16 (sec. 4.3, "we prefilter the variance with a 3x3 Gaussian"), borders clamped; read at
// filtered pixels only, written everywhere so that the row's inner loop has no branch and vectorises (it
// was a scalar loop with clamped taps, 10% of SVGF's time). Cost: 9 loads and a square root per pixel.
void luminance_scale(const Guides& guides, const SvgfParams& params, const std::vector<float>& variance,
                     std::vector<float>& scale) {
  const int w = guides.width, h = guides.height;
  const float sigma = params.sigma_luminance * 0.25f, eps = params.luminance_epsilon;  // sqrt(sum / 16) = sqrt(sum) / 4
  for_each_row(h, [&](int y) {
    const float* up = variance.data() + size_t(std::max(y - 1, 0)) * w;
    const float* mid = variance.data() + size_t(y) * w;
    const float* down = variance.data() + size_t(std::min(y + 1, h - 1)) * w;
    float* out = scale.data() + size_t(y) * w;
    auto column = [&](int x) { return up[x] + 2.0f * mid[x] + down[x]; };
    auto at = [&](float sum) { return 1.0f / (sigma * std::sqrt(sum) + eps); };
    for (int x = 1; x + 1 < w; ++x) out[x] = at(column(x - 1) + 2.0f * column(x) + column(x + 1));
    out[0] = at(3.0f * column(0) + column(std::min(1, w - 1)));
    if (w > 1) out[w - 1] = at(column(w - 2) + 3.0f * column(w - 1));
  });
}

// Filters colour and variance with the luminance range term (eq. 5) and the squared weights for the
// variance (eq. 2).
struct AtrousKernel {
  const float *r, *g, *b, *l, *var;  // input colour, luminance, variance
  const float* scale;
  const uint8_t* filtered;
  const AtrousPlanes& in;
  AtrousPlanes& out;

  AtrousKernel(const Guides& guides, const AtrousPlanes& in, const std::vector<float>& scale, AtrousPlanes& out)
      : r(in.color.r.data()),
        g(in.color.g.data()),
        b(in.color.b.data()),
        l(in.luminance.data()),
        var(in.variance.data()),
        scale(scale.data()),
        filtered(guides.filtered.data()),
        in(in),
        out(out) {}

  struct Chunk {
    float l[kLanes], s[kLanes];
    float sw[kLanes] = {}, sr[kLanes] = {}, sg[kLanes] = {}, sb[kLanes] = {}, sv[kLanes] = {};
  };
  void copy(size_t i) const {
    out.color.set(i, in.color.at(i));
    out.luminance[i] = in.luminance[i];
    out.variance[i] = in.variance[i];
  }
  bool begin(Chunk& c, size_t i0, int lanes) const {
    if (!any_filtered(filtered, i0, lanes)) {
      for (int k = 0; k < lanes; ++k) copy(i0 + k);
      return false;
    }
    for (int k = 0; k < kLanes; ++k) {
      size_t i = i0 + size_t(std::min(k, lanes - 1));
      c.l[k] = l[i];
      c.s[k] = scale[i];
    }
    return true;
  }
  float range(const Chunk& c, int k, size_t q) const { return std::abs(c.l[k] - l[q]) * c.s[k]; }
  void gather(Chunk& c, int k, size_t q, float w) const {
    c.sw[k] += w;
    c.sr[k] += w * r[q];
    c.sg[k] += w * g[q];
    c.sb[k] += w * b[q];
    c.sv[k] += w * w * var[q];
  }
  // The lanes' results: filtered pixels take the weighted means, the others keep their input. The centre
  // tap's weight is h(0)^2 > 0, so sw > 0 at a filtered pixel; elsewhere the quotients are computed and
  // not used. A chunk inside the image does it on whole vectors (LaneVector).
  void store(const Chunk& c, size_t i0, int lanes) const {
    if (lanes == kLanes) return store_vector(c, i0);
    for (int k = 0; k < lanes; ++k) {
      size_t i = i0 + size_t(k);
      if (!filtered[i]) {
        copy(i);
        continue;
      }
      vec3 color = vec3(c.sr[k], c.sg[k], c.sb[k]) / c.sw[k];
      out.color.set(i, color);
      out.luminance[i] = luminance(color);
      out.variance[i] = c.sv[k] / (c.sw[k] * c.sw[k]);
    }
  }
  void store_vector(const Chunk& c, size_t i0) const {
    const LaneMask keep = filtered_lanes(filtered + i0);
    const LaneVector sw = load_lanes(c.sw);
    const auto mean = store_means(keep, sw, c.sr, c.sg, c.sb, in.color, out.color, i0);
    store_lanes(out.luminance.data() + i0, keep ? luminance(mean[0], mean[1], mean[2]) : load_lanes(l + i0));
    store_lanes(out.variance.data() + i0, keep ? load_lanes(c.sv) / (sw * sw) : load_lanes(var + i0));
  }
};

}  // namespace

void svgf_atrous_iteration(const Guides& guides, const SvgfParams& params, int step, const AtrousPlanes& in,
                           std::vector<float>& scale, AtrousPlanes& out) {
  CHECK(step >= 1 && in.color.width == guides.width && in.color.height == guides.height);
  if (out.color.width != guides.width || out.color.height != guides.height) out.resize(guides.width, guides.height);
  scale.resize(guides.size());
  luminance_scale(guides, params, in.variance, scale);
  CHECK(params.atrous_radius == 1 || params.atrous_radius == 2);
  const int r = params.atrous_radius;
  const float* h = r == 2 ? kB3 : kBinomial3;
  Stencil stencil(r, r, step, [h, r](int tx, int ty) { return h[tx + r] * h[ty + r]; });
  AtrousKernel kernel(guides, in, scale, out);
  filter_image(guides, params.edges, stencil, kernel);
}

}  // namespace candela
