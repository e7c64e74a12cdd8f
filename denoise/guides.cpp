#include "denoise/guides.h"

#include "engine/check.h"

namespace candela {

// Depth change per pixel along one axis at pixel i: the central difference when both neighbours lie on
// the same instance, else the one-sided difference to the one that does, else 0 (an isolated pixel).
// `a` and `b` are the neighbours' indices, or i itself at the image border.
static float axis_slope(const GBuffer& g, size_t i, size_t a, size_t b) {
  bool use_a = a != i && g.instance[a] == g.instance[i];
  bool use_b = b != i && g.instance[b] == g.instance[i];
  if (use_a && use_b) return 0.5f * std::abs(g.depth[b] - g.depth[a]);
  if (use_a) return std::abs(g.depth[i] - g.depth[a]);
  if (use_b) return std::abs(g.depth[b] - g.depth[i]);
  return 0.0f;
}

// Whether a hit pixel of the 3x3 block around (x, y) emits differently from it (luminances apart by
// more than 10% of the larger).
static bool emission_edge(const GBuffer& g, int x, int y) {
  float le = luminance(g.emission[size_t(y) * g.width + x]);
  for (int qy = std::max(y - 1, 0); qy <= std::min(y + 1, g.height - 1); ++qy)
    for (int qx = std::max(x - 1, 0); qx <= std::min(x + 1, g.width - 1); ++qx) {
      size_t q = size_t(qy) * g.width + qx;
      float lq = luminance(g.emission[q]);
      if (g.hit(q) && std::abs(lq - le) > 0.1f * std::max(lq, le)) return true;
    }
  return false;
}

void compute_guides(const GBuffer& g, bool with_albedo, Guides& out) {
  CHECK(g.width > 0 && g.height > 0);
  if (out.width != g.width || out.height != g.height) {
    out.width = g.width;
    out.height = g.height;
    size_t n = out.size();
    for (std::vector<float>* p : {&out.depth, &out.depth_slope, &out.nx, &out.ny, &out.nz}) p->assign(n, 0.0f);
    out.filtered.assign(n, 0);
  }
  if (with_albedo && out.albedo.size() != out.size()) out.albedo.resize(g.width, g.height);
  const int w = g.width, h = g.height;
  for_each_row(h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      size_t i = size_t(y) * w + x;
      bool hit = g.hit(i), filtered = hit && !emission_edge(g, x, y);
      out.filtered[i] = filtered;
      out.depth[i] = hit ? g.depth[i] : kInfinity;
      vec3 n = filtered ? g.shading_normal[i] : vec3(0.0f);
      out.nx[i] = n.x;
      out.ny[i] = n.y;
      out.nz[i] = n.z;
      if (with_albedo) out.albedo.set(i, g.albedo[i]);
      out.depth_slope[i] = hit ? axis_slope(g, i, x > 0 ? i - 1 : i, x + 1 < w ? i + 1 : i) +
                                     axis_slope(g, i, y > 0 ? i - w : i, y + 1 < h ? i + w : i)
                               : 0.0f;
    }
  });
}

}  // namespace candela
