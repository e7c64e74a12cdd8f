#pragma once
// Light BVH sampler (Conty Estevez & Kulla 2018; pbrt-v4's BVHLightSampler is a documented instance):
// a tree over the lights, each node holding the LightBounds of its children. Sampling descends from the
// root choosing a child with probability proportional to its importance for the shading point; pmf()
// retraces the path from the light's slot up to the root. Lights at infinity (directional) are chosen
// uniformly with a separate probability. refit() follows lights that move or change power.
//
// The tree is built binary (binned SAOH) and collapsed to 8 children per node, stored side by side
// (wide_importance.h) so that one SIMD pass gives a level's 8 importances: a third of the binary tree's
// levels (7 instead of about 24 over 1e6 lights of builtin:manylights), each one vector evaluation.
#include <algorithm>
#include <atomic>
#include <vector>

#include "engine/light_sampler.h"
#include "engine/lights.h"
#include "samplers/light_bounds.h"
#include "samplers/wide_importance.h"

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

namespace light_tree_detail {
struct BinaryNode;  // the binary tree the build starts from (light_tree.cpp)
}

class LightTreeSampler {
 public:
  // Builds a binary tree with a binned surface-area-orientation heuristic (12 buckets per axis; median
  // splits in nodes of at most 256 lights), subtrees in parallel, then collapses it to 8 children per node.
  // O(n log n); the tree does not depend on the thread count.
  explicit LightTreeSampler(const LightList& lights);

  SampledLight sample(const ShadingContext& ctx, vec2 u) const;
  // n samples for one shading point (out[k] = sample(ctx, u[k]) exactly), each node's weights computed once.
  void sample_many(const ShadingContext& ctx, const vec2* u, SampledLight* out, int n) const;
  float pmf(const ShadingContext& ctx, uint32_t index) const;
  // Recomputes the nodes' bounds from the lights' current placement (same topology; changed powers rebuild the
  // tree instead, Renderer::update_scene). The first refit visits every node (subtrees in parallel, O(n)); later ones
  // only the nodes above the lights LightList::movable() names, so they cost O(moving lights x depth). Lights without
  // power when the tree was built stay out of it (pmf 0) until a rebuild.
  void refit(const LightList& lights);

  size_t node_count() const { return nodes_.size(); }
  int depth() const { return max_depth_; }  // levels of wide nodes
  // Bytes the sampler holds (nodes; parent, subtree and slot references), for the bench's bytes per light.
  size_t memory_bytes() const {
    return nodes_.capacity() * sizeof(Node) +
           (parent_.capacity() + subtree_lights_.capacity() + slot_of_.capacity()) * sizeof(uint32_t) +
           subtree_bounds_.capacity() * sizeof(LightBounds) + moving_slots_.capacity();
  }

 private:
  // A node: its children's bounds side by side, and what each child is: kLeaf | light index, the index of
  // a node, or kEmpty in the slots [count, 8) (phi 0). 256 bytes: 4 cache lines.
  static constexpr uint32_t kLeaf = 0x80000000u, kEmpty = 0xffffffffu;
  struct alignas(64) Node {
    WideBounds bounds;
    uint32_t child[kTreeWidth] = {kEmpty, kEmpty, kEmpty, kEmpty, kEmpty, kEmpty, kEmpty, kEmpty};
    int count() const {  // children come first; counted without branches
      int n = 0;
      for (int k = 0; k < kTreeWidth; ++k) n += child[k] != kEmpty;
      return n;
    }
  };
  static_assert(sizeof(Node) == 256 && kTreeWidth == 8);
  // Builds the wide nodes from the binary tree's subtree at `node` (occupying binary nodes [node, end));
  // returns the new node's index. `up` is the parent's slot reference (node * 8 + slot).
  uint32_t collapse(const std::vector<light_tree_detail::BinaryNode>& binary, uint32_t node, uint32_t end, uint32_t up,
                    int depth);
  // Returns the merged bounds of the node's children, refitting every slot (`whole`) or the moving ones;
  // `fits` turns false if a radius left the half range.
  LightBounds refit(const LightList& lights, uint32_t node, bool whole, std::atomic<bool>& fits);
  // Marks the slots on the paths from the lights LightList::update() may move up to the root.
  void mark_moving(const LightList& lights);
  // The weights a level chooses a child by: the importances of the node's children for the shading point,
  // or, where all are zero (a node's bounds are looser than its children's), their powers, or 1 for each
  // child; so no path is a dead end and pmf sums to 1. Child k is taken with probability weight[k] / sum.
  struct ChildWeights {
    float weight[kTreeWidth];
    double cumulative[kTreeWidth];  // weight[0] + ... + weight[k], summed in this order
    double sum;
    int last;  // the last child with weight > 0
  };
  // With fetch_children, the node's interior children are prefetched (a descent; pmf() knows its path).
  void child_weights(const Node& node, const ShadingContext& ctx, ChildWeights& out, bool fetch_children) const;
  static void prefetch(const Node& node) {  // all 4 lines
    for (size_t line = 0; line < sizeof(Node); line += 64)
      __builtin_prefetch(reinterpret_cast<const char*>(&node) + line);
  }
  static int choose_child(const ChildWeights& w, double& u);
  // Child k's probability, float(weight / sum): what sampling multiplies into a pmf and pmf() multiplies again.
  static float probability(const ChildWeights& w, int k);
  // The uniform a descent that took child k at t = u * sum goes on with: its place in the child's share.
  static double rescaled(const ChildWeights& w, int k, double t);
  // A descent of sample_many: its uniform, its pmf so far and its place in the output.
  struct Descent {
    double u;
    float pmf;
    int index;
  };
  // The `count` descents of `group` (sorted by u), from the root down to their lights.
  void descend_together(const ShadingContext& ctx, Descent* group, int count, SampledLight* out) const;

  std::vector<Node> nodes_;
  LightBounds root_;           // bounds of all finite lights
  float radius_scale_ = 1.0f;  // of the nodes' radii (WideBounds)
  InfiniteLightChoice infinite_;
  std::vector<uint32_t> parent_;             // per node: the slot reference (node * 8 + slot) that points to it
  std::vector<uint32_t> subtree_lights_;     // per node: lights below it (refit's parallel split)
  std::vector<uint32_t> slot_of_;            // per light: its slot reference (none for infinite and powerless lights)
  std::vector<LightBounds> subtree_bounds_;  // per node: its children merged, as of the last refit (none before)
  std::vector<uint8_t> moving_slots_;        // per node: bit k set where child k holds a light that may move
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
