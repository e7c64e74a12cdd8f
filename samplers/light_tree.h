#pragma once
// Light BVH sampler (Conty Estevez & Kulla 2018; pbrt-v4's BVHLightSampler is a documented instance):
// a binary tree over the lights, each node holding the LightBounds of its subtree. Sampling descends
// from the root choosing a child with probability proportional to its importance for the shading point;
// pmf() retraces the same path with the light's bit trail. Lights at infinity (directional) are chosen
// uniformly with a separate probability. refit() follows lights that move or change power.
#include <algorithm>
#include <vector>

#include "engine/light_sampler.h"
#include "engine/lights.h"
#include "samplers/light_bounds.h"

namespace candela {

// Lights at infinity (directional) beside the finite ones: each is chosen with probability 1 / (n + 1)
// and the finite lights together with 1 / (n + 1) (as pbrt-v4 does); all of it when nothing is finite.
class InfiniteLightChoice {
 public:
  InfiniteLightChoice() = default;
  InfiniteLightChoice(std::vector<uint32_t> indices, bool has_finite);
  float probability() const { return probability_; }  // of choosing one of the infinite lights
  bool contains(uint32_t index) const { return std::binary_search(indices_.begin(), indices_.end(), index); }
  float pmf_each() const { return indices_.empty() ? 0.0f : probability_ / float(indices_.size()); }
  // Picks an infinite light if u (in [0,1)) falls on one; otherwise rescales u into [0,1) for the finite lights.
  bool choose(double& u, SampledLight& out) const;

 private:
  std::vector<uint32_t> indices_;  // sorted
  float probability_ = 0.0f;
};

class LightTreeSampler {
 public:
  // Builds with a binned surface-area-orientation heuristic (12 buckets per axis), subtrees in parallel.
  // O(n log n); the tree does not depend on the thread count.
  explicit LightTreeSampler(const LightList& lights);

  SampledLight sample(const ShadingContext& ctx, vec2 u) const;
  float pmf(const ShadingContext& ctx, uint32_t index) const;
  // Recomputes every node's bounds from the lights' current geometry and power (same topology), subtrees
  // in parallel. O(n). Lights without power when the tree was built stay out of it (pmf 0) until a rebuild.
  void refit(const LightList& lights);

  size_t node_count() const { return nodes_.size(); }
  int depth() const { return max_depth_; }

 private:
  struct Node {
    LightBounds bounds;
    uint32_t index = 0;  // leaf: light index; interior: the second child (the first is the next node)
    bool leaf = false;
  };
  struct Entry {
    uint32_t light;
    LightBounds bounds;
    Bounds3 box;
  };
  // Subtree over entries [begin, end) at nodes [node, node + 2 (end - begin) - 1); returns its depth.
  int build(std::vector<Entry>& entries, size_t begin, size_t end, uint32_t node, uint64_t trail, int depth);
  void refit(const LightList& lights, uint32_t node, uint32_t end);
  // Probabilities of stepping to the first and to the second child of interior node `node` (computed
  // separately, so that neither rounds to zero when the other is near one).
  struct ChildProbabilities {
    double first, second;
  };
  ChildProbabilities child_probabilities(const Node& node, const ShadingContext& ctx) const;

  std::vector<Node> nodes_;
  InfiniteLightChoice infinite_;
  std::vector<uint64_t> trail_;       // per light: the child taken at each level, bit d for depth d
  std::vector<uint32_t> leaf_of_;     // per light: its leaf node (none for infinite and powerless lights)
  int max_depth_ = 0;
};

// The oracle: importance of every light for the shading point, sampled by a linear scan. O(n) per call.
class ExhaustiveLightSampler {
 public:
  explicit ExhaustiveLightSampler(const LightList& lights);
  SampledLight sample(const ShadingContext& ctx, vec2 u) const;
  float pmf(const ShadingContext& ctx, uint32_t index) const;

 private:
  std::vector<LightBounds> bounds_;  // phi = 0 for infinite lights
  InfiniteLightChoice infinite_;
};

static_assert(LightSampler<LightTreeSampler>);
static_assert(LightSampler<ExhaustiveLightSampler>);

}  // namespace candela
