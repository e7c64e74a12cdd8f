#include "denoise/edge_stopping.h"
#include "denoise/svgf_stages.h"
#include "engine/check.h"

namespace candela {

namespace {

// Averages the moments over the 7x7 taps with the geometric weights where the history is short; keeps
// the temporal estimate elsewhere.
struct MomentsKernel {
  const float *m1, *m2;
  const SvgfMoments& moments;
  const std::vector<uint8_t>& filtered;
  float short_history;
  std::vector<float>& variance;

  struct Chunk {
    float sw[kLanes] = {}, s1[kLanes] = {}, s2[kLanes] = {};
  };
  float temporal_variance(size_t i) const {
    return std::max(0.0f, moments.moment2[i] - moments.moment1[i] * moments.moment1[i]);
  }
  bool is_short(size_t i) const { return filtered[i] && moments.length[i] < short_history; }
  bool begin(Chunk&, size_t i0, int lanes) const {
    bool any_short = false;
    for (int k = 0; k < lanes; ++k) any_short = any_short || is_short(i0 + k);
    if (!any_short)
      for (int k = 0; k < lanes; ++k) variance[i0 + k] = temporal_variance(i0 + k);
    return any_short;
  }
  float range(const Chunk&, int, size_t) const { return 0.0f; }
  void gather(Chunk& c, int k, size_t q, float w) const {
    c.sw[k] += w;
    c.s1[k] += w * m1[q];
    c.s2[k] += w * m2[q];
  }
  void store(const Chunk& c, size_t i0, int lanes) const {
    for (int k = 0; k < lanes; ++k) {
      size_t i = i0 + size_t(k);
      if (!is_short(i)) {
        variance[i] = temporal_variance(i);
        continue;
      }
      float m1 = c.s1[k] / c.sw[k];
      variance[i] = std::max(0.0f, c.s2[k] / c.sw[k] - m1 * m1);
    }
  }
};

}  // namespace

void svgf_variance(const Guides& guides, const SvgfMoments& moments, const SvgfParams& params,
                   std::vector<float>& variance) {
  CHECK(moments.length.size() == guides.size() && variance.size() == guides.size());
  static const Stencil stencil(3, 3, 1, [](int, int) { return 1.0f; });
  MomentsKernel kernel{moments.moment1.data(),
                       moments.moment2.data(),
                       moments,
                       guides.filtered,
                       float(params.spatial_variance_below),
                       variance};
  filter_image(guides, params.edges, stencil, kernel);
}

}  // namespace candela
