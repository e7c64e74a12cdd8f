#include "samplers/light_tree.h"

#include <algorithm>

#include "engine/check.h"
#include "engine/parallel.h"

namespace candela {

namespace {

constexpr int kBuckets = 12;
constexpr int kMaxDepth = 64;  // levels of the binary tree, and so at most those of the wide one
constexpr uint32_t kNoSlot = 0xffffffffu;
constexpr size_t kParallelGrain = 4096;  // subtrees smaller than this are built / refitted serially
// Nodes of at most this many lights split at the median of the widest centroid axis instead of by the SAOH:
// the build over StainedGlassLamp gridded to 1.39M emitters took 4.7 -> 3.8-4.0 s of setup, with no change
// in the tree's equal-time error on manylights or StainedGlassLamp (docs/performance.md, "Light selection cost").
constexpr size_t kSaohMinLights = 256;

// A subtree of the binary tree: nodes [node, end).
struct Span {
  uint32_t node, end;
  uint32_t lights() const { return (end - node + 1) / 2; }
};

// A light as the build sees it.
struct Entry {
  uint32_t light;
  LightBounds bounds;
  Bounds3 box;
};

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
  float estimated_cos_theta_o() const {
    return std::clamp(2.0f * glm::length(axis_sum) / std::max(phi, 1e-20f) - 1.0f, -1.0f, 1.0f);
  }
};

// Exact bounds of entries [first, last): sphere around their box, and the cone spread measured from the
// mean axis over every member.
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

namespace light_tree_detail {
struct BinaryNode {
  LightBounds bounds;
  uint32_t index = 0;  // leaf: light index; interior: the second child (the first is the next node)
  bool leaf = false;
};
}  // namespace light_tree_detail

namespace {
using light_tree_detail::BinaryNode;

// Binned SAOH over entries [begin, end) (their accumulated bounds `all`): the cheapest (axis, bucket
// boundary) over 12 buckets per axis of the centroid box, one pass filling the buckets of all three axes;
// partitions the entries by it and returns where the second part starts (begin or end: no split found).
size_t saoh_partition(std::vector<Entry>& entries, size_t begin, size_t end, const BoundsAccumulator& all) {
  const vec3 extent = all.centroids.extent();
  auto bucket_of = [&](const Entry& e, int axis) {
    float t = (e.box.center()[axis] - all.centroids.lo[axis]) / extent[axis];
    return std::clamp(int(t * kBuckets), 0, kBuckets - 1);
  };
  // Neighbouring entries mostly fall into the same bucket (earlier splits sorted them by position), and
  // each add waits for the previous one's stores: alternate entries fill two sets of buckets, merged after.
  BoundsAccumulator buckets_of_axis[3][kBuckets], odd_buckets[3][kBuckets];
  for (size_t k = begin; k < end; ++k) {
    BoundsAccumulator(&buckets)[3][kBuckets] = (k - begin) % 2 ? odd_buckets : buckets_of_axis;
    for (int axis = 0; axis < 3; ++axis)
      if (extent[axis] > 0.0f) buckets[axis][bucket_of(entries[k], axis)].add(entries[k].bounds, entries[k].box, false);
  }
  for (int axis = 0; axis < 3; ++axis)
    for (int b = 0; b < kBuckets; ++b) buckets_of_axis[axis][b].add(odd_buckets[axis][b]);
  float best_cost = kInfinity;
  int best_axis = -1, best_split = 0;
  for (int axis = 0; axis < 3; ++axis) {
    if (extent[axis] <= 0.0f) continue;
    const BoundsAccumulator* bucket = buckets_of_axis[axis];
    float regularization = max_component(all.box.extent()) / std::max(all.box.extent()[axis], 1e-12f);
    for (int split = 1; split < kBuckets; ++split) {
      BoundsAccumulator left, right;
      for (int b = 0; b < split; ++b) left.add(bucket[b]);
      for (int b = split; b < kBuckets; ++b) right.add(bucket[b]);
      if (!left.count || !right.count) continue;
      float cost = saoh_cost(left, regularization) + saoh_cost(right, regularization);
      if (cost < best_cost) {
        best_cost = cost;
        best_axis = axis;
        best_split = split;
      }
    }
  }
  if (best_axis < 0) return begin;
  auto it = std::partition(entries.begin() + begin, entries.begin() + end,
                           [&](const Entry& e) { return bucket_of(e, best_axis) < best_split; });
  return size_t(it - entries.begin());
}

// Builds the subtree over entries [begin, end) in depth-first order: the first child right after its
// parent, the second after the first child's 2m - 1 nodes (m lights), which fixes every index in advance
// so that subtrees build in parallel. Deeper than level 32, and in nodes of kSaohMinLights lights or fewer, it
// halves by count, so depth stays < 64.
void build_binary(std::vector<BinaryNode>& nodes, std::vector<Entry>& entries, size_t begin, size_t end, uint32_t node,
                  int depth) {
  if (end - begin == 1) {
    nodes[node] = {entries[begin].bounds, entries[begin].light, true};
    return;
  }
  BoundsAccumulator all;
  for (size_t k = begin; k < end; ++k) all.add(entries[k].bounds, entries[k].box);
  nodes[node].bounds = bounds_of(all, &entries[begin], entries.data() + end);

  const vec3 extent = all.centroids.extent();
  size_t mid = begin;
  if (depth < 32 && end - begin > kSaohMinLights) mid = saoh_partition(entries, begin, end, all);
  if (mid == begin || mid == end) {
    // No SAOH split (a small or deep node, or coincident centroids): halve by count along the widest axis.
    mid = begin + (end - begin) / 2;
    int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
    std::nth_element(entries.begin() + begin, entries.begin() + mid, entries.begin() + end,
                     [&](const Entry& a, const Entry& b) { return a.box.center()[axis] < b.box.center()[axis]; });
  }
  CHECK(depth < kMaxDepth);
  uint32_t second = node + 2 * uint32_t(mid - begin);
  nodes[node].index = second;
  auto first = [&] { build_binary(nodes, entries, begin, mid, node + 1, depth + 1); };
  auto other = [&] { build_binary(nodes, entries, mid, end, second, depth + 1); };
  if (end - begin > kParallelGrain)
    parallel_invoke(first, other);
  else {
    first();
    other();
  }
}

// The children of the wide node over the binary subtree at `node` (binary nodes [node, end)): its two
// children, then, again and again, the child with the most lights opened into its two, until there are 8
// (the collapse of a binary BVH into a wide one, as in Wald, Benthin & Boulos 2008, "Getting rid of
// packets", here by light count so that the tree stays shallow, and stopping at children small enough to be
// one full node). Children keep the binary tree's order. Returns how many.
int open_slots(const std::vector<BinaryNode>& binary, uint32_t node, uint32_t end, Span slots[kTreeWidth]) {
  int count = 1;
  slots[0] = {node, end};
  auto open = [&](int k) {
    Span s = slots[k];
    for (int j = count; j > k + 1; --j) slots[j] = slots[j - 1];
    slots[k] = {s.node + 1, binary[s.node].index};
    slots[k + 1] = {binary[s.node].index, s.end};
    ++count;
  };
  if (!binary[node].leaf) open(0);
  while (count < kTreeWidth) {
    int largest = -1;
    for (int k = 0; k < count; ++k)
      if (!binary[slots[k].node].leaf && (largest < 0 || slots[k].lights() > slots[largest].lights())) largest = k;
    // A child of at most 8 lights stays whole (it becomes one node of leaves) unless this node can hold all of
    // its lights: opening it further would leave nodes of 2 or 3 children below.
    if (largest < 0 ||
        (slots[largest].lights() <= uint32_t(kTreeWidth) && Span{node, end}.lights() > uint32_t(kTreeWidth)))
      break;
    open(largest);
  }
  return count;
}

// How many wide nodes the binary subtree at `node` collapses into (so that the nodes are allocated once).
uint32_t count_wide_nodes(const std::vector<BinaryNode>& binary, uint32_t node, uint32_t end) {
  Span slots[kTreeWidth];
  const int count = open_slots(binary, node, end, slots);
  uint32_t total = 1;
  for (int k = 0; k < count; ++k)
    if (!binary[slots[k].node].leaf) total += count_wide_nodes(binary, slots[k].node, slots[k].end);
  return total;
}

}  // namespace

InfiniteLightChoice::InfiniteLightChoice(std::vector<uint32_t> indices, bool has_finite)
    : indices_(std::move(indices)) {
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
  CHECK(lights.size() < kEmpty - kLeaf);  // a child holds kLeaf | light index, never kEmpty
  std::vector<Entry> entries;
  entries.reserve(lights.size());
  std::vector<uint32_t> infinite;
  slot_of_.assign(lights.size(), kNoSlot);
  for (uint32_t i = 0; i < lights.size(); ++i) {
    if (is_infinite_light(lights, i)) {
      infinite.push_back(i);
      continue;
    }
    Bounds3 box;
    LightBounds b = light_bounds(lights, i, &box);
    if (b.phi > 0.0f) entries.push_back({i, b, box});
  }
  infinite_ = InfiniteLightChoice(std::move(infinite), !entries.empty());
  if (entries.empty()) return;
  std::vector<BinaryNode> binary(2 * entries.size() - 1);
  build_binary(binary, entries, 0, entries.size(), 0, 0);
  // Released before the wide nodes are allocated, so that they can take its memory: fresh pages are what
  // the build's time goes to on these VMs (engine/huge_pages.cpp).
  std::vector<Entry>().swap(entries);
  root_ = binary[0].bounds;
  radius_scale_ = radius_scale_for(root_.radius);  // no child's sphere is larger than the root's
  const uint32_t wide_nodes = count_wide_nodes(binary, 0, uint32_t(binary.size()));
  nodes_.reserve(wide_nodes);
  parent_.reserve(wide_nodes);
  subtree_lights_.reserve(wide_nodes);
  collapse(binary, 0, uint32_t(binary.size()), kNoSlot, 0);
  mark_moving(lights);
}

// Each movable light's path to the root, slot by slot; a path stops where an earlier one already went up.
void LightTreeSampler::mark_moving(const LightList& lights) {
  moving_slots_.assign(nodes_.size(), 0);
  for (const auto& [first, end] : lights.movable()) {
    for (size_t i = first; i < end; ++i) {
      for (uint32_t ref = slot_of_[i]; ref != kNoSlot; ref = parent_[ref / kTreeWidth]) {
        uint8_t& bits = moving_slots_[ref / kTreeWidth];
        const uint8_t bit = uint8_t(1u << (ref % kTreeWidth));
        if (bits & bit) break;
        bits |= bit;
      }
    }
  }
}

// The wide node over the binary subtree at `node` (open_slots), with its children's exact bounds from the
// binary tree; nodes are numbered depth first.
uint32_t LightTreeSampler::collapse(const std::vector<BinaryNode>& binary, uint32_t node, uint32_t end, uint32_t up,
                                    int depth) {
  Span slots[kTreeWidth];
  const int count = open_slots(binary, node, end, slots);
  CHECK(depth < kMaxDepth);
  max_depth_ = std::max(max_depth_, depth + 1);
  const uint32_t index = uint32_t(nodes_.size());
  CHECK(index < kNoSlot / kTreeWidth);  // slot references node * 8 + slot fit in 32 bits, below kNoSlot
  nodes_.emplace_back();
  parent_.push_back(up);
  subtree_lights_.push_back(Span{node, end}.lights());
  for (int k = 0; k < count; ++k) {
    const BinaryNode& b = binary[slots[k].node];
    CHECK(nodes_[index].bounds.set(k, b.bounds, radius_scale_));
    const uint32_t ref = index * kTreeWidth + uint32_t(k);
    uint32_t child = kLeaf | b.index;
    if (b.leaf)
      slot_of_[b.index] = ref;
    else
      child = collapse(binary, slots[k].node, slots[k].end, ref, depth + 1);
    nodes_[index].child[k] = child;
  }
  return index;
}

void LightTreeSampler::child_weights(const Node& node, const ShadingContext& ctx, ChildWeights& out,
                                     bool fetch_children) const {
  const int count = node.count();
  wide_importance(node.bounds, ctx, radius_scale_, out.weight);
  // A descent reads one of the interior children next: all 4 lines of each are fetched while this level's
  // importances compute. After the importance's loads, not before: issued first, the 32 prefetches delayed
  // them (1e3 lights: sample 170-175 -> 145-151 ns; 1e6: 411-428 -> 386-397; docs/performance.md).
  if (fetch_children)
    for (int k = 0; k < count; ++k)
      if (!(node.child[k] & kLeaf)) prefetch(nodes_[node.child[k]]);
  auto accumulate = [&] {
    double sum = 0.0;
    for (int k = 0; k < count; ++k) out.cumulative[k] = sum += out.weight[k];
    return sum;
  };
  out.sum = accumulate();
  if (!(out.sum > 0.0 && std::isfinite(out.sum))) {
    for (int k = 0; k < count; ++k) out.weight[k] = std::abs(node.bounds.phi[k]);
    out.sum = accumulate();
    if (!(out.sum > 0.0 && std::isfinite(out.sum))) {
      for (int k = 0; k < count; ++k) out.weight[k] = 1.0f;
      out.sum = accumulate();
    }
  }
  out.last = count - 1;
  while (out.weight[out.last] <= 0.0f) --out.last;
}

// One step of a descent: the child whose share of [0, sum) holds u * sum (child_weights' values), found without
// branches: k shares end at or before it. A child of weight 0 ends where the one before it does, so it is never
// chosen; the last child with weight takes what rounding leaves over. The 48-bit uniform is rescaled into the
// child's interval so that it serves the next level too. The child's probability is probability(w, k).
int LightTreeSampler::choose_child(const ChildWeights& w, double& u) {
  const double t = u * w.sum;
  int k = 0;
  for (int j = 0; j < w.last; ++j) k += t >= w.cumulative[j];
  u = rescaled(w, k, t);
  return k;
}

float LightTreeSampler::probability(const ChildWeights& w, int k) { return float(w.weight[k] / w.sum); }

double LightTreeSampler::rescaled(const ChildWeights& w, int k, double t) {
  return std::min((t - (k > 0 ? w.cumulative[k - 1] : 0.0)) / w.weight[k], 1.0 - 0x1p-53);
}

// A stochastic descent from the root: at each node, a child with probability weight / sum (choose_child); the
// 48-bit uniform starts as its share left after the infinite lights.
SampledLight LightTreeSampler::sample(const ShadingContext& ctx, vec2 u2) const {
  double u = wide_uniform(u2);
  SampledLight chosen;
  if (infinite_.choose(u, chosen)) return chosen;
  if (nodes_.empty() || root_.importance(ctx) <= 0.0f) return {};
  float pmf = 1.0f - infinite_.probability();
  ChildWeights w;
  for (uint32_t node = 0;;) {
    const Node& n = nodes_[node];
    child_weights(n, ctx, w, true);
    const int k = choose_child(w, u);
    pmf *= probability(w, k);
    if (n.child[k] & kLeaf) return {n.child[k] & ~kLeaf, pmf};
    node = n.child[k];
  }
}

// The descents share one shading point, so they go down together: the group of descents that reached a node
// takes one computation of its weights, each descent its step (as sample() takes it: the same results). Sorted
// by their uniforms, the descents that take each child are a contiguous run, in child order (t = u * sum, the
// child choose_child picks and the uniform it rescales are all non-decreasing in u), and the rescaled uniforms
// keep the order, so each run goes on down in place. The sort is an insertion sort: callers that draw many
// lights at once draw them stratified (restir/light_tiles.h), so their uniforms come nearly in order. Cost: the
// sort (n steps for uniforms in order) and one child_weights per node any descent visits.
void LightTreeSampler::sample_many(const ShadingContext& ctx, const vec2* u2, SampledLight* out, int n) const {
  thread_local std::vector<Descent> group;
  group.clear();
  const bool reachable = !nodes_.empty() && root_.importance(ctx) > 0.0f;
  for (int k = 0; k < n; ++k) {
    double u = wide_uniform(u2[k]);
    if (infinite_.choose(u, out[k])) continue;
    out[k] = {};
    if (!reachable) continue;
    group.push_back({u, 1.0f - infinite_.probability(), k});
    for (size_t d = group.size() - 1; d > 0 && group[d].u < group[d - 1].u; --d) std::swap(group[d], group[d - 1]);
  }
  if (!group.empty()) descend_together(ctx, group.data(), int(group.size()), out);
}

// Level by level: every run that enters a node of the next level prefetches that node (all 4 lines), and its
// weights are computed only once the whole level has been split, so the misses on a level's nodes (up to one per
// descent; city's tree is ~3 MB, beyond L2) overlap instead of each waiting in turn, as in a depth-first walk.
// Each descent takes the same steps in the same order as in sample(), so the results are the same bits.
void LightTreeSampler::descend_together(const ShadingContext& ctx, Descent* group, int count, SampledLight* out) const {
  struct Run {
    uint32_t node;
    int first, end;  // the descents [first, end) of group that reached the node
  };
  thread_local std::vector<Run> level, next;
  level.assign(1, Run{0, 0, count});
  while (!level.empty()) {
    next.clear();
    for (const Run& run : level) {
      const Node& n = nodes_[run.node];
      ChildWeights w;
      child_weights(n, ctx, w, false);
      for (int first = run.first; first < run.end;) {
        // The run of the first descent left: its child by choose_child, then the descents whose t stays below
        // that child's end (all of them for the last child with weight).
        const int k = choose_child(w, group[first].u);
        int end = first + 1;
        for (; end < run.end; ++end) {
          const double t = group[end].u * w.sum;
          if (k < w.last && !(t < w.cumulative[k])) break;
          group[end].u = rescaled(w, k, t);
        }
        const float p = probability(w, k);
        for (int d = first; d < end; ++d) group[d].pmf *= p;
        if (n.child[k] & kLeaf) {
          for (int d = first; d < end; ++d) out[group[d].index] = {n.child[k] & ~kLeaf, group[d].pmf};
        } else {
          prefetch(nodes_[n.child[k]]);
          next.push_back({n.child[k], first, end});
        }
        first = end;
      }
    }
    std::swap(level, next);
  }
}

// The same probabilities along the path from the root to the light's slot (found from the slot up).
float LightTreeSampler::pmf(const ShadingContext& ctx, uint32_t index) const {
  if (slot_of_[index] == kNoSlot) return infinite_.contains(index) ? infinite_.pmf_each() : 0.0f;
  if (root_.importance(ctx) <= 0.0f) return 0.0f;
  uint32_t path[kMaxDepth];
  int depth = 0;
  for (uint32_t ref = slot_of_[index];; ref = parent_[ref / kTreeWidth]) {
    path[depth++] = ref;
    prefetch(nodes_[ref / kTreeWidth]);  // the path is known: its nodes load together
    if (ref / kTreeWidth == 0) break;
  }
  float pmf = 1.0f - infinite_.probability();
  while (depth > 0) {
    const uint32_t ref = path[--depth];
    ChildWeights w;
    child_weights(nodes_[ref / kTreeWidth], ctx, w, false);
    pmf *= probability(w, int(ref % kTreeWidth));
  }
  return pmf;
}

void LightTreeSampler::refit(const LightList& lights) {
  if (nodes_.empty()) return;
  std::atomic<bool> fits = true;
  const bool whole = subtree_bounds_.empty();
  if (whole) subtree_bounds_.resize(nodes_.size());
  root_ = refit(lights, 0, whole, fits);
  // A light moved so far (or a cluster grew so much) that its radius no longer fits the nodes' scale.
  if (!fits) *this = LightTreeSampler(lights);
}

// A node's children take their lights' new bounds or their subtrees' merged ones (subtrees of more than
// kParallelGrain lights in parallel); a slot without moving lights keeps its bounds and lends its subtree's
// remembered merge. Returns the merge of all of them, in slot order as the first refit merged them.
LightBounds LightTreeSampler::refit(const LightList& lights, uint32_t node, bool whole, std::atomic<bool>& fits) {
  Node& n = nodes_[node];
  LightBounds slot[kTreeWidth];
  auto one = [&](uint32_t k) {
    const uint32_t child = n.child[k];
    const bool moves = whole || (moving_slots_[node] >> k & 1u);
    if (child & kLeaf)
      slot[k] = light_bounds(lights, child & ~kLeaf);
    else
      slot[k] = moves ? refit(lights, child, whole, fits) : subtree_bounds_[child];
    if (moves && !n.bounds.set(int(k), slot[k], radius_scale_)) fits = false;
  };
  const uint32_t count = uint32_t(n.count());
  if (subtree_lights_[node] > kParallelGrain)
    parallel_for(0u, count, one);
  else
    for (uint32_t k = 0; k < count; ++k) one(k);
  LightBounds all = slot[0];
  for (uint32_t k = 1; k < count; ++k) all = merge(all, slot[k]);
  subtree_bounds_[node] = all;
  return all;
}

ExhaustiveLightSampler::ExhaustiveLightSampler(const LightList& lights) {
  bounds_.resize(lights.size());
  std::vector<uint32_t> infinite;
  bool has_finite = false;
  for (uint32_t i = 0; i < lights.size(); ++i) {
    if (is_infinite_light(lights, i)) {
      infinite.push_back(i);
      continue;
    }
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
  for (const LightBounds& b : bounds_) total += b.importance(ctx);
  if (total <= 0.0) return {};
  double target = u * total, running = 0.0;
  uint32_t last = 0;
  for (uint32_t i = 0; i < bounds_.size(); ++i) {
    float imp = bounds_[i].importance(ctx);
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
  for (const LightBounds& b : bounds_) total += b.importance(ctx);
  if (total <= 0.0) return 0.0f;
  return float((1.0 - infinite_.probability()) * bounds_[index].importance(ctx) / total);
}

}  // namespace candela
