#include "denoise/guides.h"

#include "engine/check.h"

namespace candela {

// The guides are computed a row at a time, in loops simple enough for GCC to vectorise (each a function
// whose planes are restrict-qualified parameters: through the G-buffer's and the guides' members every
// pointer was reloaded per pixel, since the mask's byte stores may alias anything, and the per-pixel code
// stayed scalar). Rows above and below are clamped to the image, and so are columns: a clamped neighbour
// repeats a pixel of the 3x3 block, which changes neither test.

// Whether the hit pixel q emits differently from luminance le (apart by more than 10% of the larger).
static inline bool emits_differently(float le, const float* lum, const uint32_t* instance, int q) {
  const float lq = lum[q];
  return (instance[q] != kNoHit) & (std::abs(lq - le) > 0.1f * std::max(lq, le));
}

// edge[x]: whether a hit pixel of x's 3x3 block emits differently from x. l* and i*: the emission's
// luminance and the instance of the rows above, at and below.
static inline bool emission_edge_at(int x, int xm, int xp, const float* lu, const float* lm, const float* ld,
                                    const uint32_t* iu, const uint32_t* im, const uint32_t* id) {
  const float le = lm[x];
  return emits_differently(le, lu, iu, xm) | emits_differently(le, lu, iu, x) | emits_differently(le, lu, iu, xp) |
         emits_differently(le, lm, im, xm) | emits_differently(le, lm, im, xp) | emits_differently(le, ld, id, xm) |
         emits_differently(le, ld, id, x) | emits_differently(le, ld, id, xp);
}
static void emission_edges(int w, const float* __restrict lu, const float* __restrict lm, const float* __restrict ld,
                           const uint32_t* __restrict iu, const uint32_t* __restrict im, const uint32_t* __restrict id,
                           uint8_t* __restrict edge) {
  edge[0] = emission_edge_at(0, 0, std::min(1, w - 1), lu, lm, ld, iu, im, id);
  for (int x = 1; x < w - 1; ++x) edge[x] = emission_edge_at(x, x - 1, x + 1, lu, lm, ld, iu, im, id);
  if (w > 1) edge[w - 1] = emission_edge_at(w - 1, w - 2, w - 1, lu, lm, ld, iu, im, id);
}

// Depth change per pixel along one axis: the central difference when both neighbours a and b lie on the
// pixel's instance, else the one-sided difference to the one that does, else 0 (an isolated pixel).
// has_a, has_b: whether the neighbours exist (not beyond the image border).
static inline float axis_slope(uint32_t instance, float depth, bool has_a, uint32_t instance_a, float depth_a,
                               bool has_b, uint32_t instance_b, float depth_b) {
  const bool use_a = has_a & (instance_a == instance), use_b = has_b & (instance_b == instance);
  const float both = 0.5f * std::abs(depth_b - depth_a), only_a = std::abs(depth - depth_a),
              only_b = std::abs(depth_b - depth);
  return use_a ? (use_b ? both : only_a) : (use_b ? only_b : 0.0f);
}

// A row's filtered mask, depth, normals and depth slope from its emission edges; d* and i*: the depth and
// instance of the rows above, at and below; has_up, has_down: whether those rows exist; `normal`: the row's
// shading normals, x, y, z per pixel.
static void guide_row(int w, const uint8_t* __restrict edge, const float* __restrict du, const float* __restrict dm,
                      const float* __restrict dd, const uint32_t* __restrict iu, const uint32_t* __restrict im,
                      const uint32_t* __restrict id, bool has_up, bool has_down, const float* __restrict normal,
                      uint8_t* __restrict filtered, float* __restrict depth, float* __restrict slope,
                      float* __restrict nx, float* __restrict ny, float* __restrict nz) {
  for (int x = 0; x < w; ++x) {
    const bool hit = im[x] != kNoHit, keep = hit & (edge[x] == 0);
    filtered[x] = keep;
    depth[x] = hit ? dm[x] : kInfinity;
    nx[x] = keep ? normal[3 * x] : 0.0f;
    ny[x] = keep ? normal[3 * x + 1] : 0.0f;
    nz[x] = keep ? normal[3 * x + 2] : 0.0f;
    const int xm = std::max(x - 1, 0), xp = std::min(x + 1, w - 1);
    const float s = axis_slope(im[x], dm[x], x > 0, im[xm], dm[xm], x + 1 < w, im[xp], dm[xp]) +
                    axis_slope(im[x], dm[x], has_up, iu[x], du[x], has_down, id[x], dd[x]);
    slope[x] = hit ? s : 0.0f;
  }
}

static_assert(sizeof(vec3) == 3 * sizeof(float), "the G-buffer's vec3 rows are read as x, y, z floats");

// A row of vec3 (x, y, z per pixel) into three planes.
static void split_row(int w, const float* __restrict xyz, float* __restrict x, float* __restrict y,
                      float* __restrict z) {
  for (int k = 0; k < w; ++k) x[k] = xyz[3 * k], y[k] = xyz[3 * k + 1], z[k] = xyz[3 * k + 2];
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
  out.emission_luminance.resize(out.size());
  const int w = g.width, h = g.height;
  // The emission's luminance, once per pixel (the mask reads each nine times).
  for_each_row(h, [&](int y) {
    for (size_t i = size_t(y) * w, end = i + w; i < end; ++i) out.emission_luminance[i] = luminance(g.emission[i]);
  });
  for_each_row(h, [&](int y) {
    const size_t up = size_t(std::max(y - 1, 0)) * w, row = size_t(y) * w, down = size_t(std::min(y + 1, h - 1)) * w;
    thread_local std::vector<uint8_t> edge;
    edge.resize(size_t(w));
    const float* lum = out.emission_luminance.data();
    const uint32_t* instance = g.instance.data();
    emission_edges(w, lum + up, lum + row, lum + down, instance + up, instance + row, instance + down, edge.data());
    const float* depth = g.depth.data();
    guide_row(w, edge.data(), depth + up, depth + row, depth + down, instance + up, instance + row, instance + down,
              y > 0, y + 1 < h, &g.shading_normal[row].x, out.filtered.data() + row, out.depth.data() + row,
              out.depth_slope.data() + row, out.nx.data() + row, out.ny.data() + row, out.nz.data() + row);
    if (with_albedo)
      split_row(w, &g.albedo[row].x, out.albedo.r.data() + row, out.albedo.g.data() + row, out.albedo.b.data() + row);
  });
}

}  // namespace candela
