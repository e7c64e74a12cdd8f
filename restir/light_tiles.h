#pragma once
// Presampled light tiles (Wyman & Panteleev 2021, "Rearchitecting Spatiotemporal Resampling for
// Production"; RTXDI ships them): once per frame, a few tiles of light samples are drawn from a
// context-free light sampler (power or uniform), each entry holding everything a candidate needs (a
// DiLightCandidate: the light, the uniforms that place the point on it, the point, and the density it was
// drawn with). A pixel reads the tile of its screen block, so the candidate stage touches one contiguous
// tile instead of light records scattered over the whole light list (on `city`, 104k emitting triangles).
//
// Unbiasedness: every entry is drawn independently with density p_light(x) = pmf(light) / area (as a
// direct draw would be), and a pixel picks entries uniformly, so each candidate is marginally distributed
// with exactly that density. RIS needs nothing more: the expectation of its estimate is the sum over
// candidates of E[f(x_i) / p(x_i)] / M, which involves each candidate's marginal alone. Candidates of one
// screen block are correlated (they share a tile), which costs variance, not bias.
#include <type_traits>
#include <vector>

#include "engine/parallel.h"
#include "restir/di.h"
#include "samplers/simple_samplers.h"

namespace candela {

// The samplers whose choice does not depend on the shading point: tiles drawn once serve every pixel.
template <class S>
inline constexpr bool kContextFreeSampler =
    std::is_same_v<S, PowerLightSampler> || std::is_same_v<S, UniformLightSampler>;

class LightTiles {
 public:
  static constexpr int kBlock = 16;  // pixels per side of the screen block that shares a tile

  // Stage "di_light_tiles": draws `count` tiles of `size` entries from `sampler`, keyed on (seed, frame,
  // tile, entry) so that they do not depend on the thread count. Cost: count x size light samples.
  template <class S>
  void build(const SceneView& view, const S& sampler, int count, int size, uint64_t seed, int frame) {
    static_assert(kContextFreeSampler<S>, "light tiles need a sampler whose choice ignores the shading point");
    count_ = count;
    size_ = size;
    entries_.resize(size_t(count) * size_t(size));
    const ShadingContext anywhere{vec3(0.0f), vec3(0.0f, 0.0f, 1.0f)};
    parallel_for(0, count, [&](int t) {
      for (int e = 0; e < size; ++e) {
        Rng rng = Rng::for_key(seed, uint64_t(t) * uint64_t(size) + uint64_t(e), uint64_t(frame), 0x7e);
        SampledLight chosen = sampler.sample(anywhere, vec2(rng.next_float(), rng.next_float()));
        vec2 uv(rng.next_float(), rng.next_float());
        entries_[size_t(t) * size_t(size) + size_t(e)] = di_light_candidate(view.scene, view.lights, chosen, uv);
      }
    });
  }

  // The tile of the screen block holding pixel (x, y) in frame `frame` (blocks take tiles in an order
  // shuffled per frame, so that one block's candidates differ from frame to frame).
  const DiLightCandidate* tile(int x, int y, int frame) const {
    const uint64_t block = uint64_t(y / kBlock) * 4096u + uint64_t(x / kBlock);
    return &entries_[size_t(mix64(block ^ mix64(uint64_t(frame) + 1)) % uint64_t(count_)) * size_t(size_)];
  }

 private:
  int count_ = 0, size_ = 0;
  std::vector<DiLightCandidate> entries_;
};

}  // namespace candela
