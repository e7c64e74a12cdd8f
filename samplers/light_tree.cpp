#include "samplers/light_tree.h"

#include <algorithm>

#include "engine/check.h"

namespace candela {

namespace {

constexpr int kBuckets = 12;
constexpr int kMaxDepth = 63;  // the bit trail is a uint64_t
constexpr uint32_t kNoLeaf = 0xffffffffu;

// A 48-bit uniform from two 24-bit ones, so that many successive binary choices keep their precision.
double wide_uniform(vec2 u) { return double(u.x) + double(u.y) * 0x1p-24; }

// Bounds of many lights at once without pairwise cone unions (which need trigonometry): the cone axis is
// the power-weighted mean direction, the spread the widest member measured from it. Conservative.
struct BoundsAccumulator {
  Bounds3 bounds, centroids;
  vec3 axis_sum{0.0f};
  float phi = 0.0f, cos_theta_e = 1.0f;
  bool two_sided = false;
  size_t count = 0;
  void add(const LightBounds& b) {
    bounds.extend(b.bounds);
    centroids.extend(b.bounds.center());
    axis_sum += b.w * std::max(b.phi, 1e-20f);
    phi += b.phi;
    cos_theta_e = std::min(cos_theta_e, b.cos_theta_e);
    two_sided = two_sided || b.two_sided;
    ++count;
  }
  void add(const BoundsAccumulator& o) {
    if (!o.count) return;
    bounds.extend(o.bounds);
    centroids.extend(o.centroids);
    axis_sum += o.axis_sum;
    phi += o.phi;
    cos_theta_e = std::min(cos_theta_e, o.cos_theta_e);
    two_sided = two_sided || o.two_sided;
    count += o.count;
  }
  // For split costs only: the spread guessed from how well the members' axes agree (|mean axis|).
  LightBounds estimate() const {
    LightBounds lb;
    lb.bounds = bounds;
    lb.phi = phi;
    lb.cos_theta_o = std::clamp(2.0f * glm::length(axis_sum) / std::max(phi, 1e-20f) - 1.0f, -1.0f, 1.0f);
    lb.cos_theta_e = cos_theta_e;
    return lb;
  }
};

// Exact bounds of entries [first, last): the accumulator, then a second pass for the cone spread.
template <class Entry>
LightBounds bounds_of(const BoundsAccumulator& acc, const Entry* first, const Entry* last) {
  LightBounds out;
  out.bounds = acc.bounds;
  out.phi = acc.phi;
  out.cos_theta_e = acc.cos_theta_e;
  out.two_sided = acc.two_sided;
  float len = glm::length(acc.axis_sum);
  out.w = len > 1e-12f ? acc.axis_sum / len : vec3(0.0f, 0.0f, 1.0f);
  float cos_o = 1.0f;
  for (const Entry* e = first; e != last; ++e) {
    // cos(angle(w, b.w) + theta_b), or -1 once the sum reaches pi.
    const LightBounds& b = e->bounds;
    float c = std::clamp(glm::dot(out.w, b.w), -1.0f, 1.0f), s = std::sqrt(1.0f - c * c);
    float cb = std::clamp(b.cos_theta_o, -1.0f, 1.0f), sb = std::sqrt(1.0f - cb * cb);
    bool past_pi = std::acos(c) + std::acos(cb) >= kPi;
    cos_o = std::min(cos_o, past_pi ? -1.0f : c * cb - s * sb);
  }
  out.cos_theta_o = cos_o;
  return out;
}

// Cost of a cluster in the surface-area-orientation heuristic (Conty Estevez & Kulla 2018, eq. 2).
float saoh_cost(const LightBounds& b, float regularization) {
  vec3 e = b.bounds.extent();
  float area = 2.0f * (e.x * e.y + e.y * e.z + e.z * e.x);
  return b.phi * cone_measure(b.cos_theta_o, b.cos_theta_e) * std::max(area, 1e-12f) * regularization;
}

}  // namespace

LightTreeSampler::LightTreeSampler(const LightList& lights) {
  std::vector<Entry> entries;
  trail_.assign(lights.size(), 0);
  leaf_of_.assign(lights.size(), kNoLeaf);
  for (uint32_t i = 0; i < lights.size(); ++i) {
    if (is_infinite_light(lights, i)) { infinite_.push_back(i); continue; }
    LightBounds b = light_bounds(lights, i);
    if (b.phi > 0.0f) entries.push_back({i, b});
  }
  if (!entries.empty()) {
    nodes_.reserve(2 * entries.size());
    build(entries, 0, entries.size(), 0, 0);
  }
}

// Builds the subtree over entries [begin, end) in depth-first order (first child right after its
// parent); returns its node index. Below depth 32 it always halves by count, so depth stays < 63.
uint32_t LightTreeSampler::build(std::vector<Entry>& entries, size_t begin, size_t end, uint64_t trail, int depth) {
  uint32_t node = uint32_t(nodes_.size());
  nodes_.emplace_back();
  max_depth_ = std::max(max_depth_, depth);
  if (end - begin == 1) {
    nodes_[node].bounds = entries[begin].bounds;
    nodes_[node].index = entries[begin].light;
    nodes_[node].leaf = true;
    trail_[entries[begin].light] = trail;
    leaf_of_[entries[begin].light] = node;
    return node;
  }
  BoundsAccumulator all;
  for (size_t k = begin; k < end; ++k) all.add(entries[k].bounds);
  nodes_[node].bounds = bounds_of(all, &entries[begin], entries.data() + end);

  // Binned SAOH: the cheapest (axis, bucket boundary) over 12 buckets per axis of the centroid box.
  vec3 extent = all.centroids.extent();
  float best_cost = kInfinity;
  int best_axis = -1, best_split = 0;
  auto bucket_of = [&](const Entry& e, int axis) {
    float t = (e.bounds.bounds.center()[axis] - all.centroids.lo[axis]) / extent[axis];
    return std::clamp(int(t * kBuckets), 0, kBuckets - 1);
  };
  for (int axis = 0; axis < 3 && depth < 32; ++axis) {
    if (extent[axis] <= 0.0f) continue;
    BoundsAccumulator bucket[kBuckets];
    for (size_t k = begin; k < end; ++k) bucket[bucket_of(entries[k], axis)].add(entries[k].bounds);
    float regularization = max_component(all.bounds.extent()) / std::max(all.bounds.extent()[axis], 1e-12f);
    for (int split = 1; split < kBuckets; ++split) {
      BoundsAccumulator left, right;
      for (int b = 0; b < split; ++b) left.add(bucket[b]);
      for (int b = split; b < kBuckets; ++b) right.add(bucket[b]);
      if (!left.count || !right.count) continue;
      float cost = saoh_cost(left.estimate(), regularization) + saoh_cost(right.estimate(), regularization);
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
      return a.bounds.bounds.center()[axis] < b.bounds.bounds.center()[axis];
    });
  }
  CHECK(depth < kMaxDepth);
  build(entries, begin, mid, trail, depth + 1);
  uint32_t second = build(entries, mid, end, trail | (uint64_t(1) << depth), depth + 1);
  nodes_[node].index = second;
  return node;
}

float LightTreeSampler::infinite_probability() const {
  if (infinite_.empty()) return 0.0f;
  return nodes_.empty() ? 1.0f : float(infinite_.size()) / float(infinite_.size() + 1);
}

// A node's bounds are looser than its children's, so both children may have zero importance where the
// parent had some: then the choice follows power, so that no path is a dead end and pmf sums to 1.
float LightTreeSampler::first_child_probability(const Node& node, const ShadingContext& ctx) const {
  const LightBounds& first = (&node + 1)->bounds;
  const LightBounds& second = nodes_[node.index].bounds;
  float i0 = first.importance(ctx.position, ctx.normal), i1 = second.importance(ctx.position, ctx.normal);
  if (i0 + i1 > 0.0f) return i0 / (i0 + i1);
  return first.phi / (first.phi + second.phi);
}

// Stochastic descent: at each interior node, a child with probability proportional to its importance;
// the 48-bit uniform is rescaled into the chosen interval so that it serves the next level too.
SampledLight LightTreeSampler::sample(const ShadingContext& ctx, vec2 u2) const {
  double u = wide_uniform(u2);
  float p_inf = infinite_probability();
  if (u < p_inf) {
    size_t k = std::min(size_t(u / p_inf * infinite_.size()), infinite_.size() - 1);
    return {infinite_[k], p_inf / float(infinite_.size())};
  }
  if (nodes_.empty() || nodes_[0].bounds.importance(ctx.position, ctx.normal) <= 0.0f) return {};
  u = std::min((u - p_inf) / (1.0 - p_inf), 1.0 - 0x1p-53);
  float pmf = 1.0f - p_inf;
  const Node* node = &nodes_[0];
  while (!node->leaf) {
    float p0 = first_child_probability(*node, ctx);
    if (u < p0) {
      u /= p0;
      pmf *= p0;
      node = node + 1;
    } else {
      u = std::min((u - p0) / (1.0 - p0), 1.0 - 0x1p-53);
      pmf *= 1.0f - p0;
      node = &nodes_[node->index];
    }
  }
  return {node->index, pmf};
}

// Retraces the path to the light's leaf with its bit trail, multiplying the same probabilities.
float LightTreeSampler::pmf(const ShadingContext& ctx, uint32_t index) const {
  float p_inf = infinite_probability();
  if (leaf_of_[index] == kNoLeaf) {
    bool infinite = std::find(infinite_.begin(), infinite_.end(), index) != infinite_.end();
    return infinite ? p_inf / float(infinite_.size()) : 0.0f;
  }
  if (nodes_[0].bounds.importance(ctx.position, ctx.normal) <= 0.0f) return 0.0f;
  float pmf = 1.0f - p_inf;
  const Node* node = &nodes_[0];
  uint64_t trail = trail_[index];
  for (int depth = 0; !node->leaf; ++depth) {
    float p0 = first_child_probability(*node, ctx);
    if (trail & (uint64_t(1) << depth)) {
      pmf *= 1.0f - p0;
      node = &nodes_[node->index];
    } else {
      pmf *= p0;
      node = node + 1;
    }
  }
  return pmf;
}

// Leaves take their lights' new bounds; interior nodes (which precede their children) are merged
// from the back of the array to the front.
void LightTreeSampler::refit(const LightList& lights) {
  for (size_t n = nodes_.size(); n-- > 0;) {
    Node& node = nodes_[n];
    node.bounds = node.leaf ? light_bounds(lights, node.index) : merge(nodes_[n + 1].bounds, nodes_[node.index].bounds);
  }
}

ExhaustiveLightSampler::ExhaustiveLightSampler(const LightList& lights) {
  bounds_.resize(lights.size());
  is_infinite_.assign(lights.size(), 0);
  for (uint32_t i = 0; i < lights.size(); ++i) {
    if (is_infinite_light(lights, i)) { infinite_.push_back(i); is_infinite_[i] = 1; continue; }
    bounds_[i] = light_bounds(lights, i);
  }
}

float ExhaustiveLightSampler::infinite_probability() const {
  if (infinite_.empty()) return 0.0f;
  return float(infinite_.size()) / float(infinite_.size() + 1);
}

SampledLight ExhaustiveLightSampler::sample(const ShadingContext& ctx, vec2 u2) const {
  double u = wide_uniform(u2);
  float p_inf = infinite_probability();
  if (u < p_inf) {
    size_t k = std::min(size_t(u / p_inf * infinite_.size()), infinite_.size() - 1);
    return {infinite_[k], p_inf / float(infinite_.size())};
  }
  u = (u - p_inf) / (1.0 - p_inf);
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
  float p_inf = infinite_probability();
  if (is_infinite_[index]) return p_inf / float(infinite_.size());
  double total = 0.0;
  for (const LightBounds& b : bounds_) total += b.importance(ctx.position, ctx.normal);
  if (total <= 0.0) return 0.0f;
  return float((1.0 - p_inf) * bounds_[index].importance(ctx.position, ctx.normal) / total);
}

}  // namespace candela
