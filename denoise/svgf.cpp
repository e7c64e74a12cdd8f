#include "denoise/svgf.h"

#include "denoise/demodulate.h"
#include "engine/check.h"

namespace candela {

Svgf::Svgf(const SvgfParams& params) : params_(params) {
  CHECK(params.atrous_iterations >= 1 && params.alpha_color > 0.0f && params.alpha_moments > 0.0f);
  CHECK(params.max_history >= 1.0f && params.sigma_luminance > 0.0f);
}

// The next frame's history: the colour `color` and this frame's filtered mask, copied a row block per worker
// (a plain copy ran on one thread: ~11 MB at 1280x720).
void Svgf::keep_history(const ColorPlanes& color) {
  if (history_.color.width != color.width || history_.color.height != color.height)
    history_.color.resize(color.width, color.height);
  history_.filtered.resize(guides_.filtered.size());
  const size_t w = size_t(color.width);
  for_each_row(color.height, [&](int y) {
    const size_t first = size_t(y) * w;
    std::copy_n(color.r.begin() + first, w, history_.color.r.begin() + first);
    std::copy_n(color.g.begin() + first, w, history_.color.g.begin() + first);
    std::copy_n(color.b.begin() + first, w, history_.color.b.begin() + first);
    std::copy_n(guides_.filtered.begin() + first, w, history_.filtered.begin() + first);
  });
}

void Svgf::denoise(const GBuffer& current, const GBuffer& previous, const Image& noisy, FrameStats& stats, Image& out) {
  prepare_frame(current, noisy, false, guides_, illumination_, stats);
  {
    StageTimer timer(stats, "svgf_temporal");
    svgf_temporal(current, previous, guides_, illumination_, history_, params_, atrous_[0], moments_);
  }
  {
    StageTimer timer(stats, "svgf_variance");
    svgf_variance(guides_, moments_, params_, atrous_[0].variance);
    std::swap(history_.moments, moments_);
  }
  int last = 0;
  {
    StageTimer timer(stats, "svgf_atrous");
    for (int k = 0; k < params_.atrous_iterations; ++k) {
      svgf_atrous_iteration(guides_, params_, 1 << k, atrous_[last], scale_, atrous_[1 - last]);
      last = 1 - last;
      // The first iteration's output is the next frame's colour history (sec. 4.1).
      if (k == 0) keep_history(atrous_[last].color);
    }
  }
  history_.valid = true;
  StageTimer timer(stats, "denoise_remodulate");
  remodulate(atrous_[last].color, current, guides_, noisy, out);
}

}  // namespace candela
