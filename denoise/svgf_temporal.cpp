#include "denoise/svgf_stages.h"

#include "denoise/svgf_temporal_lanes.h"

#include "engine/check.h"

namespace candela {

void AtrousPlanes::resize(int w, int h) {
  color.resize(w, h);
  luminance.assign(color.size(), 0.0f);
  variance.assign(color.size(), 0.0f);
}

void SvgfMoments::resize(size_t n) {
  moment1.assign(n, 0.0f);
  moment2.assign(n, 0.0f);
  length.assign(n, 0.0f);
}

namespace {

// History gathered for one pixel: weighted sums of the consistent previous pixels.
struct Gathered {
  vec3 color{0.0f};
  float moment1 = 0.0f, moment2 = 0.0f, length = 0.0f, weight = 0.0f;
};

struct Reprojector {
  const GBuffer& current;
  const GBuffer& previous;
  const Guides& guides;
  const SvgfHistory& history;
  const SvgfParams& params;

  // Whether previous pixel (qx, qy) shows the surface of current pixel i, whose sample lay at film
  // position `sample` in the previous frame.
  bool consistent(size_t i, vec2 sample, int qx, int qy) const {
    if (qx < 0 || qy < 0 || qx >= previous.width || qy >= previous.height) return false;
    size_t q = size_t(qy) * previous.width + qx;
    if (previous.instance[q] != current.instance[i] || history.filtered[q] != guides.filtered[i]) return false;
    if (glm::dot(current.shading_normal[i], previous.shading_normal[q]) < params.normal_tolerance) return false;
    vec2 apart = glm::abs(vec2(qx, qy) + previous.jitter[q] - sample);
    float expected = guides.depth_slope[i] * std::max(apart.x, apart.y) + params.depth_tolerance * current.depth[i];
    return std::abs(current.depth[i] - previous.depth[q]) <= expected;
  }
  void add(Gathered& g, int qx, int qy, float w) const {
    size_t q = size_t(qy) * previous.width + qx;
    g.color += w * history.color.at(q);
    g.moment1 += w * history.moments.moment1[q];
    g.moment2 += w * history.moments.moment2[q];
    g.length += w * history.moments.length[q];
    g.weight += w;
  }
  // Bilinear taps around the reprojected pixel centre, else the 3x3 block around the sample.
  Gathered gather(size_t i, int x, int y) const {
    Gathered g;
    vec2 centre = vec2(x, y) + current.motion[i];  // (x + 0.5 + motion) - 0.5: in pixel-centre coordinates
    vec2 sample = vec2(x, y) + current.jitter[i] + current.motion[i];
    if (!(std::abs(centre.x) < 1e6f && std::abs(centre.y) < 1e6f)) return g;
    int x0 = int(std::floor(centre.x)), y0 = int(std::floor(centre.y));
    float fx = centre.x - float(x0), fy = centre.y - float(y0);
    for (int b = 0; b < 2; ++b)
      for (int a = 0; a < 2; ++a) {
        float w = (a ? fx : 1.0f - fx) * (b ? fy : 1.0f - fy);
        if (w > 0.0f && consistent(i, sample, x0 + a, y0 + b)) add(g, x0 + a, y0 + b, w);
      }
    if (g.weight > 1e-3f) return g;
    g = Gathered{};
    int sx = int(std::floor(sample.x)), sy = int(std::floor(sample.y));
    for (int qy = sy - 1; qy <= sy + 1; ++qy)
      for (int qx = sx - 1; qx <= sx + 1; ++qx)
        if (consistent(i, sample, qx, qy)) add(g, qx, qy, 1.0f);
    return g;
  }
};

}  // namespace

void svgf_temporal(const GBuffer& current, const GBuffer& previous, const Guides& guides,
                   const ColorPlanes& illumination, const SvgfHistory& history, const SvgfParams& params,
                   AtrousPlanes& integrated, SvgfMoments& moments) {
  const int w = current.width, h = current.height;
  CHECK(illumination.width == w && illumination.height == h && guides.width == w && guides.height == h);
  bool reproject = history.valid && previous.width == w && previous.height == h && history.color.width == w &&
                   history.color.height == h;
  if (integrated.color.width != w || integrated.color.height != h) integrated.resize(w, h);
  if (moments.length.size() != current.size()) moments.resize(current.size());
  Reprojector reprojector{current, previous, guides, history, params};
  // One pixel: its reprojected history (if any) blended with this frame's colour and moments.
  auto integrate = [&](size_t i, int x, int y) {
    vec3 c = illumination.at(i);
    float l = luminance(c);
    Gathered g = reproject && current.hit(i) ? reprojector.gather(i, x, y) : Gathered{};
    float length = 1.0f;
    if (g.weight > 0.0f) {
      float inv = 1.0f / g.weight;
      length = std::min(g.length * inv + 1.0f, params.max_history);
      float alpha_c = std::max(params.alpha_color, 1.0f / length);
      float alpha_m = std::max(params.alpha_moments, 1.0f / length);
      c = glm::mix(g.color * inv, c, alpha_c);
      moments.moment1[i] = glm::mix(g.moment1 * inv, l, alpha_m);
      moments.moment2[i] = glm::mix(g.moment2 * inv, l * l, alpha_m);
      l = luminance(c);
    } else {
      moments.moment1[i] = l;
      moments.moment2[i] = l * l;
    }
    moments.length[i] = current.hit(i) ? length : 0.0f;
    integrated.color.set(i, c);
    integrated.luminance[i] = l;
  };
  if (!params.simd) {
    for_each_row(h, [&](int y) {
      for (int x = 0; x < w; ++x) integrate(size_t(y) * w + x, x, y);
    });
    return;
  }
  // In lanes (svgf_temporal_lanes.h), which leave the pixels that need the 3x3 search to integrate().
  TemporalPlanes planes{.width = w,
                        .height = h,
                        .reproject = reproject,
                        .normal_tolerance = params.normal_tolerance,
                        .depth_tolerance = params.depth_tolerance,
                        .alpha_color = params.alpha_color,
                        .alpha_moments = params.alpha_moments,
                        .max_history = params.max_history,
                        .instance = current.instance.data(),
                        .normal = &current.shading_normal.data()->x,
                        .depth = current.depth.data(),
                        .motion = &current.motion.data()->x,
                        .jitter = &current.jitter.data()->x,
                        .filtered = guides.filtered.data(),
                        .depth_slope = guides.depth_slope.data(),
                        .r = illumination.r.data(),
                        .g = illumination.g.data(),
                        .b = illumination.b.data(),
                        .out_r = integrated.color.r.data(),
                        .out_g = integrated.color.g.data(),
                        .out_b = integrated.color.b.data(),
                        .out_luminance = integrated.luminance.data(),
                        .moment1 = moments.moment1.data(),
                        .moment2 = moments.moment2.data(),
                        .length = moments.length.data()};
  if (reproject) {
    planes.prev_instance = previous.instance.data();
    planes.prev_normal = &previous.shading_normal.data()->x;
    planes.prev_depth = previous.depth.data();
    planes.prev_jitter = &previous.jitter.data()->x;
    planes.prev_filtered = history.filtered.data();
    planes.history_r = history.color.r.data(), planes.history_g = history.color.g.data();
    planes.history_b = history.color.b.data();
    planes.history_m1 = history.moments.moment1.data(), planes.history_m2 = history.moments.moment2.data();
    planes.history_length = history.moments.length.data();
  }
  for_each_row(h, [&](int y) {
    thread_local std::vector<int> left;
    left.resize(size_t(w));
    const int count = svgf_temporal_row_lanes(planes, y, left.data());
    for (int k = 0; k < count; ++k) integrate(size_t(y) * w + left[size_t(k)], left[size_t(k)], y);
  });
}

}  // namespace candela
