#include "samplers/light_tree.h"


#include <algorithm>

#include "engine/check.h"
#include "engine/parallel.h"

namespace candela {

namespace {

constexpr int kBuckets = 12;
constexpr int kMaxDepth = 63;  // the bit trail is a uint64_t
constexpr uint32_t kNoLeaf = 0xffffffffu;
constexpr size_t kParallelGrain = 4096;  // subtrees smaller than this are built / refitted serially

// A 48-bit uniform from two 24-bit ones, so that many successive binary choices keep their precision.
double wide_uniform(vec2 u) { return double(u.x) + double(u.y) * 0x1p-24; }

// Bounds of many lights at once: their box, and a cone around the power-weighted mean axis. The cone's
// spread needs a second pass over the members (bounds_of); split costs only estimate it.
struct BoundsAccumulator {
  Bounds3 box, centroids;
  vec3 axis_sum{0.0f};
  float phi = 0.0f, cos_theta_e = 1.0f;
  uint32_t two_sided = 0;
  size_t count = 0;
  // Adds a light; `with_centroid` = false skips the centroid box (buckets do not need it).
  void add(const LightBounds& b, const Bounds3& b_box, bool with_centroid = true) {
    box.extend(b_box);
    if (with_centroid) centroids.extend(b_box.center());
    axis_sum += b.w * b.phi;
    phi += b.phi;
    cos_theta_e = std::min(cos_theta_e, b.cos_theta_e);
    two_sided |= b.two_sided;
    ++count;
  }
  void add(const BoundsAccumulator& o) {
    if (!o.count) return;
    box.extend(o.box);
    centroids.extend(o.centroids);
    axis_sum += o.axis_sum;
    phi += o.phi;
    cos_theta_e = std::min(cos_theta_e, o.cos_theta_e);
    two_sided |= o.two_sided;
    count += o.count;
  }
  // Cone spread guessed from how well the members' axes agree (|mean axis|), for split costs only.
  float estimated_cos_theta_o() const { return std::clamp(2.0f * glm::length(axis_sum) / std::max(phi, 1e-20f) - 1.0f, -1.0f, 1.0f); }
};

// Exact bounds of entries [first, last): sphere around their box, and the cone spread measured from the
// mean axis over every member.
template <class Entry>
LightBounds bounds_of(const BoundsAccumulator& acc, const Entry* first, const Entry* last) {
  LightBounds out;
  out.center = acc.box.center();
  out.radius = 0.5f * acc.box.diagonal();
  out.phi = acc.phi;
  out.cos_theta_e = acc.cos_theta_e;
  out.two_sided = acc.two_sided;
  float len = glm::length(acc.axis_sum);
  out.w = len > 1e-12f * acc.phi ? acc.axis_sum / len : first->bounds.w;
  float cos_o = 1.0f;
  for (const Entry* e = first; e != last; ++e)
    cos_o = std::min(cos_o, cos_of_sum(glm::dot(out.w, e->bounds.w), e->bounds.cos_theta_o, e->bounds.sin_theta_o));
  out.set_cos_theta_o(cos_o);
  return out;
}

// Cost of a cluster in the surface-area-orientation heuristic (Conty Estevez & Kulla 2018, eq. 2).
float saoh_cost(const BoundsAccumulator& a, float regularization) {
  vec3 e = a.box.extent();
  float area = 2.0f * (e.x * e.y + e.y * e.z + e.z * e.x);
  return a.phi * cone_measure(a.estimated_cos_theta_o(), a.cos_theta_e) * std::max(area, 1e-12f) * regularization;
}

}  // namespace

InfiniteLightChoice::InfiniteLightChoice(std::vector<uint32_t> indices, bool has_finite) : indices_(std::move(indices)) {
  std::sort(indices_.begin(), indices_.end());
  if (!indices_.empty()) probability_ = has_finite ? float(indices_.size()) / float(indices_.size() + 1) : 1.0f;
}

bool InfiniteLightChoice::choose(double& u, SampledLight& out) const {
  if (u < probability_) {
    size_t k = std::min(size_t(u / probability_ * double(indices_.size())), indices_.size() - 1);
    out = {indices_[k], pmf_each()};
    return true;
  }
  u = std::min((u - probability_) / (1.0 - probability_), 1.0 - 0x1p-53);
  return false;
}

LightTreeSampler::LightTreeSampler(const LightList& lights) {
  std::vector<Entry> entries;
  std::vector<uint32_t> infinite;
  trail_.assign(lights.size(), 0);
  leaf_of_.assign(lights.size(), kNoLeaf);
  for (uint32_t i = 0; i < lights.size(); ++i) {
    if (is_infinite_light(lights, i)) { infinite.push_back(i); continue; }
    Bounds3 box;
    LightBounds b = light_bounds(lights, i, &box);
    if (b.phi > 0.0f) entries.push_back({i, b, box});
  }
  infinite_ = InfiniteLightChoice(std::move(infinite), !entries.empty());
  if (!entries.empty()) {
    nodes_.resize(2 * entries.size() - 1);
    max_depth_ = build(entries, 0, entries.size(), 0, 0, 0);
  }
}

// Builds the subtree over entries [begin, end) in depth-first order: the first child right after its
// parent, the second after the first child's 2m - 1 nodes (m lights), which fixes every index in advance
// so that subtrees build in parallel. Below depth 32 it always halves by count, so depth stays < 63.
int LightTreeSampler::build(std::vector<Entry>& entries, size_t begin, size_t end, uint32_t node, uint64_t trail, int depth) {
  if (end - begin == 1) {
    nodes_[node].bounds = entries[begin].bounds;
    nodes_[node].index = entries[begin].light;
    nodes_[node].leaf = true;
    trail_[entries[begin].light] = trail;
    leaf_of_[entries[begin].light] = node;
    return depth;
  }
  BoundsAccumulator all;
  for (size_t k = begin; k < end; ++k) all.add(entries[k].bounds, entries[k].box);
  nodes_[node].bounds = bounds_of(all, &entries[begin], entries.data() + end);

  // Binned SAOH: the cheapest (axis, bucket boundary) over up to 12 buckets per axis of the centroid
  // box (no more buckets than lights: a small node has few distinct splits).
  vec3 extent = all.centroids.extent();
  const int buckets = int(std::min<size_t>(kBuckets, end - begin));
  float best_cost = kInfinity;
  int best_axis = -1, best_split = 0;
  auto bucket_of = [&](const Entry& e, int axis) {
    float t = (e.box.center()[axis] - all.centroids.lo[axis]) / extent[axis];
    return std::clamp(int(t * buckets), 0, buckets - 1);
  };
  // One pass over the entries fills the buckets of all three axes.
  BoundsAccumulator buckets_of_axis[3][kBuckets];
  if (depth < 32)
    for (size_t k = begin; k < end; ++k)
      for (int axis = 0; axis < 3; ++axis)
        if (extent[axis] > 0.0f) buckets_of_axis[axis][bucket_of(entries[k], axis)].add(entries[k].bounds, entries[k].box, false);
  for (int axis = 0; axis < 3 && depth < 32; ++axis) {
    if (extent[axis] <= 0.0f) continue;
    const BoundsAccumulator* bucket = buckets_of_axis[axis];
    float regularization = max_component(all.box.extent()) / std::max(all.box.extent()[axis], 1e-12f);
    for (int split = 1; split < buckets; ++split) {
      BoundsAccumulator left, right;
      for (int b = 0; b < split; ++b) left.add(bucket[b]);
      for (int b = split; b < buckets; ++b) right.add(bucket[b]);
      if (!left.count || !right.count) continue;
      float cost = saoh_cost(left, regularization) + saoh_cost(right, regularization);
      if (cost < best_cost) { best_cost = cost; best_axis = axis; best_split = split; }
    }
  }
  size_t mid = begin;
  if (best_axis >= 0) {
    auto it = std::partition(entries.begin() + begin, entries.begin() + end,
                             [&](const Entry& e) { return bucket_of(e, best_axis) < best_split; });
    mid = size_t(it - entries.begin());
  }
  if (mid == begin || mid == end) {
    // No useful split (coincident centroids, or deep): halve by count along the widest axis.
    mid = begin + (end - begin) / 2;
    int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
    std::nth_element(entries.begin() + begin, entries.begin() + mid, entries.begin() + end, [&](const Entry& a, const Entry& b) {
      return a.box.center()[axis] < b.box.center()[axis];
    });
  }
  CHECK(depth < kMaxDepth);
  uint32_t second = node + 2 * uint32_t(mid - begin);
  nodes_[node].index = second;
  int depth_first = 0, depth_second = 0;
  auto first = [&] { depth_first = build(entries, begin, mid, node + 1, trail, depth + 1); };
  auto other = [&] { depth_second = build(entries, mid, end, second, trail | (uint64_t(1) << depth), depth + 1); };
  if (end - begin > kParallelGrain) parallel_invoke(first, other);
  else { first(); other(); }
  return std::max(depth_first, depth_second);
}

// A node's bounds are looser than its children's, so both children may have zero importance where the
// parent had some: then the choice follows power (or is even), so that no path is a dead end and pmf
// sums to 1.
LightTreeSampler::ChildProbabilities LightTreeSampler::child_probabilities(const Node& node, const ShadingContext& ctx) const {
  const Node& a = *(&node + 1);
  const Node& b = nodes_[node.index];
  // The next level reads one of these children's far child: fetch both while this level computes.
  if (!a.leaf) __builtin_prefetch(&nodes_[a.index]);
  if (!b.leaf) __builtin_prefetch(&nodes_[b.index]);
  const LightBounds& first = a.bounds;
  const LightBounds& second = b.bounds;
  double i0 = first.importance(ctx.position, ctx.normal), i1 = second.importance(ctx.position, ctx.normal);
  if (!(i0 + i1 > 0.0) || !std::isfinite(i0 + i1)) {
    i0 = first.phi;
    i1 = second.phi;
    if (!(i0 + i1 > 0.0)) i0 = i1 = 1.0;
  }
  return {i0 / (i0 + i1), i1 / (i0 + i1)};
}

// Stochastic descent: at each interior node, a child with probability proportional to its importance;
// the 48-bit uniform is rescaled into the chosen interval so that it serves the next level too.
SampledLight LightTreeSampler::sample(const ShadingContext& ctx, vec2 u2) const {
  double u = wide_uniform(u2);
  SampledLight chosen;
  if (infinite_.choose(u, chosen)) return chosen;
  if (nodes_.empty() || nodes_[0].bounds.importance(ctx.position, ctx.normal) <= 0.0f) return {};
  float pmf = 1.0f - infinite_.probability();
  const Node* node = &nodes_[0];
  while (!node->leaf) {
    ChildProbabilities p = child_probabilities(*node, ctx);
    if (u < p.first) {
      u /= p.first;
      pmf *= float(p.first);
      node = node + 1;
    } else {
      u = std::min((u - p.first) / p.second, 1.0 - 0x1p-53);
      pmf *= float(p.second);
      node = &nodes_[node->index];
    }
  }
  return {node->index, pmf};
}

// Retraces the path to the light's leaf with its bit trail, multiplying the same probabilities.
float LightTreeSampler::pmf(const ShadingContext& ctx, uint32_t index) const {
  if (leaf_of_[index] == kNoLeaf) return infinite_.contains(index) ? infinite_.pmf_each() : 0.0f;
  if (nodes_[0].bounds.importance(ctx.position, ctx.normal) <= 0.0f) return 0.0f;
  float pmf = 1.0f - infinite_.probability();
  const Node* node = &nodes_[0];
  uint64_t trail = trail_[index];
  for (int depth = 0; !node->leaf; ++depth) {
    ChildProbabilities p = child_probabilities(*node, ctx);
    if (trail & (uint64_t(1) << depth)) {
      pmf *= float(p.second);
      node = &nodes_[node->index];
    } else {
      pmf *= float(p.first);
      node = node + 1;
    }
  }
  return pmf;
}

void LightTreeSampler::refit(const LightList& lights) {
  if (!nodes_.empty()) refit(lights, 0, uint32_t(nodes_.size()));
}

// Leaves take their lights' new bounds, interior nodes the merge of their children's; the subtree of
// `node` occupies nodes [node, end).
void LightTreeSampler::refit(const LightList& lights, uint32_t node, uint32_t end) {
  Node& n = nodes_[node];
  if (n.leaf) {
    n.bounds = light_bounds(lights, n.index);
    return;
  }
  auto first = [&] { refit(lights, node + 1, n.index); };
  auto other = [&] { refit(lights, n.index, end); };
  if (end - node > kParallelGrain) parallel_invoke(first, other);
  else { first(); other(); }
  n.bounds = merge(nodes_[node + 1].bounds, nodes_[n.index].bounds);
}

ExhaustiveLightSampler::ExhaustiveLightSampler(const LightList& lights) {
  bounds_.resize(lights.size());
  std::vector<uint32_t> infinite;
  bool has_finite = false;
  for (uint32_t i = 0; i < lights.size(); ++i) {
    if (is_infinite_light(lights, i)) { infinite.push_back(i); continue; }
    bounds_[i] = light_bounds(lights, i);
    has_finite = has_finite || bounds_[i].phi > 0.0f;
  }
  infinite_ = InfiniteLightChoice(std::move(infinite), has_finite);
}

SampledLight ExhaustiveLightSampler::sample(const ShadingContext& ctx, vec2 u2) const {
  double u = wide_uniform(u2);
  SampledLight chosen;
  if (infinite_.choose(u, chosen)) return chosen;
  double total = 0.0;
  for (const LightBounds& b : bounds_) total += b.importance(ctx.position, ctx.normal);
  if (total <= 0.0) return {};
  double target = u * total, running = 0.0;
  uint32_t last = 0;
  for (uint32_t i = 0; i < bounds_.size(); ++i) {
    float imp = bounds_[i].importance(ctx.position, ctx.normal);
    if (imp <= 0.0f) continue;
    last = i;
    running += imp;
    if (running > target) break;
  }
  return {last, pmf(ctx, last)};
}

float ExhaustiveLightSampler::pmf(const ShadingContext& ctx, uint32_t index) const {
  if (infinite_.contains(index)) return infinite_.pmf_each();
  double total = 0.0;
  for (const LightBounds& b : bounds_) total += b.importance(ctx.position, ctx.normal);
  if (total <= 0.0) return 0.0f;
  return float((1.0 - infinite_.probability()) * bounds_[index].importance(ctx.position, ctx.normal) / total);
}

}  // namespace candela
