#pragma once
// Presampled light tiles (Wyman & Panteleev 2021, "Rearchitecting Spatiotemporal Resampling for
// Production"; RTXDI ships them): once per frame, tiles of light samples are drawn, each entry holding
// everything a candidate needs (a DiLightCandidate: the light, the uniforms that place the point on it, the
// point, and the density it was drawn with). A pixel reads the tile of its screen block, so the candidate
// stage touches one contiguous tile instead of light records scattered over the whole light list (on `city`,
// 104k emitting triangles), and a light sampler that costs a tree descent per sample is paid per entry, not
// per candidate.
//
// Two kinds, by the light sampler:
// - shared tiles, from a sampler whose choice ignores the shading point (power, uniform): a few tiles serve
//   every block, in an order shuffled per frame;
// - region tiles, from one whose choice depends on it (tree, exhaustive): each screen block draws its own
//   tile for the region its pixels' points occupy, the sphere around their bounding box
//   (ShadingContext::radius), for which the sampler's importance stays positive wherever some point of
//   the region can receive a light (light_bounds.h, LightBounds::importance).
//
// Unbiasedness: entry e of a tile of n draws its light with the sampler's uniform confined to the e-th of n
// equal parts of [0, 1) (stratified_uniform), and a pixel picks entries uniformly, so the uniform behind each
// candidate is uniform on [0, 1) and the candidate is marginally distributed with exactly the density of a
// direct draw for the tile's context, p_light(x) = pmf(ctx, light) / area, which is positive wherever the pixel
// can receive light. RIS needs nothing more: the expectation of its estimate is the sum over candidates of
// E[f(x_i) / p(x_i)] / M, which involves each candidate's marginal alone; MIS with BSDF candidates asks
// the sampler for the same density (Tile::ctx). Candidates of one screen block are correlated (they share
// a tile), which costs variance, not bias; the strata make a tile cover the distribution evenly, which lowers
// that variance (docs/restir.md, "Stratified tile entries").
#include <algorithm>
#include <type_traits>
#include <vector>

#include "engine/gbuffer.h"
#include "engine/parallel.h"
#include "restir/di.h"
#include "samplers/simple_samplers.h"

namespace candela {

// The samplers whose choice does not depend on the shading point: tiles drawn once serve every pixel.
template <class S>
inline constexpr bool kContextFreeSampler =
    std::is_same_v<S, PowerLightSampler> || std::is_same_v<S, UniformLightSampler>;

// The uniform with which a tile's entry e (of `size`) chooses its light: x in [0, 1) moved into the e-th of `size`
// equal parts of [0, 1) (the stratification the header explains). A tile's uniforms thus come nearly sorted, the
// order in which the light tree's sample_many takes them fastest.
inline float stratified_uniform(int e, int size, float x) {
  return std::min(float((double(e) + double(x)) / double(size)), 0x1.fffffep-1f);
}

class LightTiles {
 public:
  static constexpr int kBlock = 16;  // pixels per side of the screen block that shares a tile
  // Entries per tile when DiParams::light_tile_size is 0: RTXDI's 1,024 for shared tiles; 128 for region
  // tiles, where a block's 256 pixels share their own (equal-time sweep in docs/restir.md, "Region light tiles").
  static constexpr int kSharedTileSize = 1024, kRegionTileSize = 128;

  // What a pixel reads: the tile's `size` entries and the context they were drawn for, with which the
  // sampler's pmf gives any light's density in this tile (for MIS with BSDF candidates).
  struct Tile {
    const DiLightCandidate* entries;
    int size;
    ShadingContext ctx;
    // The entry a uniform u in [0, 1) picks, each with probability 1 / size.
    const DiLightCandidate& entry(float u) const { return entries[std::min(int(u * float(size)), size - 1)]; }
  };

  // Stage "di_light_tiles": `count` shared tiles (context-free samplers) or one tile per screen block of
  // `g` (the others), of `size` entries each (0: kSharedTileSize or kRegionTileSize), keyed on (seed,
  // frame, tile, entry) so that they do not depend on the thread count. Cost: tiles x size light samples (the tree
  // shares the upper levels of a tile's descents, sample_lights), plus one pass over the G-buffer's points for region
  // tiles.
  template <LightSampler S>
  void build(const SceneView& view, const S& sampler, const GBuffer& g, int count, int size, uint64_t seed, int frame) {
    size_ = size > 0 ? size : kContextFreeSampler<S> ? kSharedTileSize : kRegionTileSize;
    if constexpr (kContextFreeSampler<S>) {
      blocks_x_ = 0;
      contexts_.assign(size_t(count), ShadingContext{});
    } else {
      blocks_x_ = (g.width + kBlock - 1) / kBlock;
      contexts_.resize(size_t(blocks_x_) * size_t((g.height + kBlock - 1) / kBlock));
      parallel_for(0, int(contexts_.size()), [&](int b) { contexts_[size_t(b)] = block_region(g, b); });
    }
    entries_.resize(contexts_.size() * size_t(size_));
    parallel_for(0, int(contexts_.size()), [&](int t) { draw_tile(view, sampler, t, seed, frame); });
  }

  // The tile the pixel (x, y) reads in frame `frame`: its block's own (region tiles) or one of the shared
  // tiles, taken by the blocks in an order shuffled per frame so that one block's candidates differ from
  // frame to frame.
  Tile tile(int x, int y, int frame) const {
    size_t t;
    if (blocks_x_ > 0) {
      t = size_t(y / kBlock) * size_t(blocks_x_) + size_t(x / kBlock);
    } else {
      const uint64_t block = uint64_t(y / kBlock) * 4096u + uint64_t(x / kBlock);
      t = size_t(mix64(block ^ mix64(uint64_t(frame) + 1)) % uint64_t(contexts_.size()));
    }
    return {&entries_[t * size_t(size_)], size_, contexts_[t]};
  }

 private:
  // The region of screen block b: the sphere around the bounding box of its pixels' points (slightly
  // enlarged against rounding), any orientation. A block without hits gets radius -1: no pixel reads its
  // tile, which is not drawn.
  ShadingContext block_region(const GBuffer& g, int b) const {
    const int x0 = (b % blocks_x_) * kBlock, y0 = (b / blocks_x_) * kBlock;
    Bounds3 box;
    for (int y = y0; y < std::min(y0 + kBlock, g.height); ++y)
      for (int x = x0; x < std::min(x0 + kBlock, g.width); ++x) {
        const size_t i = size_t(y) * size_t(g.width) + size_t(x);
        if (g.hit(i)) box.extend(g.position[i]);
      }
    if (box.lo.x > box.hi.x) return {vec3(0.0f), vec3(0.0f), -1.0f};
    const float radius = 0.5f * box.diagonal();
    return {box.center(), vec3(0.0f), radius * 1.0001f + 1e-6f * max_component(glm::abs(box.center())) + 1e-6f};
  }

  // Draws tile t's entries for its context: uniforms per entry as keyed (stratified), then the lights in one call.
  template <LightSampler S>
  void draw_tile(const SceneView& view, const S& sampler, int t, uint64_t seed, int frame) {
    if (contexts_[size_t(t)].radius < 0.0f) return;
    thread_local std::vector<vec2> u, uv;
    thread_local std::vector<SampledLight> chosen;
    u.resize(size_t(size_)), uv.resize(size_t(size_)), chosen.resize(size_t(size_));
    for (int e = 0; e < size_; ++e) {
      Rng rng = Rng::for_key(seed, uint64_t(t) * uint64_t(size_) + uint64_t(e), uint64_t(frame), 0x7e);
      u[size_t(e)] = vec2(stratified_uniform(e, size_, rng.next_float()), rng.next_float());
      uv[size_t(e)] = vec2(rng.next_float(), rng.next_float());
    }
    sample_lights(sampler, contexts_[size_t(t)], u.data(), chosen.data(), size_);
    for (int e = 0; e < size_; ++e) view.lights.prefetch(chosen[size_t(e)].index);  // random records: misses
    DiLightCandidate* out = &entries_[size_t(t) * size_t(size_)];
    for (int e = 0; e < size_; ++e)
      di_light_candidate(view.scene, view.lights, chosen[size_t(e)], uv[size_t(e)], out[e]);
  }

  int size_ = 0;
  int blocks_x_ = 0;                       // region tiles: blocks per row; 0: shared tiles
  std::vector<ShadingContext> contexts_;   // per tile: what its entries were drawn for
  std::vector<DiLightCandidate> entries_;  // tile t: [t * size, (t + 1) * size)
};

}  // namespace candela
