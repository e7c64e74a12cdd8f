#include "restir/reuse.h"

#include "engine/check.h"
#include "engine/parallel.h"
#include "engine/prefetch.h"
#include "restir/di.h"
#include "restir/neighbour_lanes.h"
#include "restir/resample_lanes.h"
#include "restir/reuse_targets.h"

namespace candela {

namespace {

// The random streams of a tile row's pixels (slot s: pixel first + s), each where its combination starts.
using ReuseStreams = RngRow<kLaneSlots>;

// Spatial reuse's neighbour offsets in the unit disk: the R2 sequence (Roberts 2018, "The Unreasonable
// Effectiveness of Quasirandom Sequences": frac(0.5 + n (1/g, 1/g^2)), g the plastic number) over the square,
// kept where it falls in the disk. A pixel reads consecutive entries from a random start (the neighbour
// offset buffer of RTXDI's spatial resampling): every entry is uniform in the disk and consecutive ones are
// spread apart. Measured against independent rejection-sampled points, 8 seeds of frame 16 (docs/restir.md,
// "Neighbour offsets"): relMSE no worse on manylights, city and occluded_room, spatial reuse ~0.85x the time.
constexpr uint32_t kOffsetCount = 1024;
const std::vector<vec2>& neighbour_offsets() {
  static const std::vector<vec2> offsets = [] {
    std::vector<vec2> t;
    const double g = 1.32471795724474602596, a1 = 1.0 / g, a2 = 1.0 / (g * g);
    for (int n = 0; t.size() < kOffsetCount; ++n) {
      const vec2 u(float(std::fmod(0.5 + a1 * n, 1.0)) * 2.0f - 1.0f,
                   float(std::fmod(0.5 + a2 * n, 1.0)) * 2.0f - 1.0f);
      if (glm::dot(u, u) <= 1.0f) t.push_back(u);
    }
    return t;
  }();
  return offsets;
}

// A sample of input k as seen by the receiver of input z: samples hold their point as placed in their
// own frame; it is re-placed only where z's frame's lights do not place it alike (placed_alike: moving lights,
// temporal reuse).
struct PlacedSample {
  const ReuseSample& own;  // as stored by its input
  const LightList* own_lights;
  const ReuseSample& here;  // placed for the combining pixel (input 0)
  const LightList* here_lights;
  const ReuseSample& at(const LightList* lights, const Scene& scene, ReuseSample& scratch) const {
    if (lights == here_lights) return here;
    if (placed_alike(*own_lights, *lights, own)) return own;
    di_resolve(scene, *lights, own.light, own.uv, scratch);
    return scratch;
  }
};

float target_at(const SceneView& view, const ReuseReceiver& receiver, const PlacedSample& y) {
  ReuseSample scratch;
  return sample_target(sample_contribution(receiver, y.at(receiver.lights, view.scene, scratch)));
}

// Whether input z's surface does not see the sample (one shadow ray, against this frame's geometry).
bool occluded_from(const SceneView& view, const ReuseInput& z, const PlacedSample& y) {
  ReuseSample scratch;
  const ReuseSample& placed = y.at(&z.domain->lights, view.scene, scratch);
  return view.tracer.occluded(sample_shadow_ray(view.tracer, z.domain->surfaces[z.pixel], z.domain->lights, placed));
}

// A slot of a row (ReuseRow) whose targets evaluate_reuse_targets evaluated beforehand.
struct SlotTargets {
  const ReuseRow& row;
  int slot;
};

// The inputs' target functions as the weights and the combination read them: p_z(y) for the sample y of
// input `source`, from the values evaluate_reuse_targets found in lanes where the stage has them, else
// evaluated here on the inputs' receivers, each built on first use (pairwise MIS needs a neighbour's
// receiver only when the combining pixel has a sample of its own). Receiver storage is per thread:
// constructing an array of 32 receivers per pixel cost more than using them.
class InputTargets {
 public:
  InputTargets(const ReuseInput* inputs, int count, const SlotTargets* lanes) : inputs_(inputs), lanes_(lanes) {
    thread_local std::vector<ReuseReceiver> storage(kMaxReuseInputs);
    receivers_ = storage.data();
    std::fill(built_, built_ + count, false);
  }
  const ReuseReceiver& receiver(int z) {
    if (!built_[z]) receivers_[z] = reuse_receiver(*inputs_[z].domain, inputs_[z].pixel), built_[z] = true;
    return receivers_[z];
  }
  float at(const SceneView& view, int z, int source, const PlacedSample& y) {
    if (lanes_ && z == 0 && (lanes_->row.known_at[lanes_->slot] >> source & 1u))
      return lanes_->row.at_combiner[source][lanes_->slot];
    if (lanes_ && source == 0 && (lanes_->row.known_of[lanes_->slot] >> z & 1u))
      return lanes_->row.of_combiner[z][lanes_->slot];
    return target_at(view, receiver(z), y);
  }
  // Whether the combining pixel's sample is visible from input z, where it was traced beforehand (-1: it
  // was not).
  int combiner_visible_from(int z) const {
    if (!lanes_ || !(lanes_->row.known_visible[lanes_->slot] >> z & 1u)) return -1;
    return int(lanes_->row.visible[lanes_->slot] >> z & 1u);
  }

 private:
  const ReuseInput* inputs_;
  const SlotTargets* lanes_;
  ReuseReceiver* receivers_;
  bool built_[kMaxReuseInputs];
};

// p_z(y): input z's target at sample y of input `source`, as the MIS weights use it. The combining
// pixel's value (z = 0) is known already, and so is the source's own: the one its reservoir stored.
float input_target(const SceneView& view, const ReuseInput* inputs, InputTargets& targets, int z, int source,
                   const PlacedSample& y, float p_hat_here) {
  if (z == 0) return p_hat_here;
  if (z == source) return inputs[source].reservoir->p_hat_y;
  return targets.at(view, z, source, y);
}

// Whether y is visible from input z's surface: the spatial pass's answer for a source's own sample when
// it has one, or the row's for the combining pixel's sample, otherwise one shadow ray (counted in `rays`).
bool input_sees(const SceneView& view, const ReuseInput* inputs, InputTargets& targets, int z, int source,
                const PlacedSample& y, uint64_t& rays) {
  if (z == source && inputs[z].own_visible >= 0) return inputs[z].own_visible == 1;
  if (const int known = source == 0 ? targets.combiner_visible_from(z) : -1; known >= 0) return known == 1;
  ++rays;
  return !occluded_from(view, inputs[z], y);
}

// Generalized balance heuristic: m_k(y) = M_k p_k(y) / sum_z M_z p_z(y), for input k = `role` and y the
// sample of input `source`. Evaluates every input's target, with `visibility` times the visibility of y
// from each input's surface (Bitterli et al. 2020, sec. 4.3: unbiased also when reservoirs were
// visibility-tested), tracing up to `count` rays.
float basic_weight(const SceneView& view, const ReuseInput* inputs, InputTargets& targets, int count, int source,
                   int role, const PlacedSample& y, float p_hat_here, bool visibility, uint64_t& rays) {
  float numerator = 0.0f, denominator = 0.0f;
  for (int z = 0; z < count; ++z) {
    float p = input_target(view, inputs, targets, z, source, y, p_hat_here);
    if (visibility && p > 0.0f && !input_sees(view, inputs, targets, z, source, y, rays)) p = 0.0f;
    float term = inputs[z].M * p;
    denominator += term;
    if (z == role) numerator = term;
  }
  return denominator > 0.0f ? numerator / denominator : 0.0f;
}

// Pairwise MIS (Bitterli 2022, "Correlations and Reuse for Fast and Accurate Physically Based Light
// Transport", ch. 9; Lin et al. 2022): the canonical input c = 0 is paired with each of the n others,
// each pair splits a 1/n share by a two-technique balance heuristic in which the canonical counts M_c / n:
//   m_i(y) = (1/n) M_i p_i(y) / (M_i p_i(y) + (M_c/n) p_c(y))                       (i > 0)
//   m_c(y) = (1/n) sum_i (M_c/n) p_c(y) / (M_i p_i(y) + (M_c/n) p_c(y))
// (here for input `role` and the sample y of input `source`). The weights sum to one wherever p_c > 0,
// which covers every y the canonical pixel's integrand is non-zero at, so the combination stays unbiased,
// at O(n) target evaluations instead of O(n^2). With `visibility`, every neighbour's p_i(y) counts only if
// y is visible from its surface, in both formulas alike (up to 2n shadow rays; the spatial pass answers
// the own-sample half once per pixel beforehand): inputs whose samples are visible by construction
// (ReSTIR GI's, or visibility-tested candidates) rarely produce an occluded y, and weighting them as if
// they did darkened the image; using V_i in one formula only made the weights of a sample sum to more
// than one, which temporal reuse amplified without bound (measured). p_c needs no visibility: where y is
// occluded from the canonical pixel, it shades to zero whatever its weight.
float pairwise_weight(const SceneView& view, const ReuseInput* inputs, InputTargets& targets, int count, int source,
                      int role, const PlacedSample& y, float p_hat_here, bool visibility, uint64_t& rays) {
  const int n = count - 1;
  if (n == 0) return 1.0f;
  const float canonical = inputs[0].M / float(n) * p_hat_here;
  auto term = [&](int i) {
    float t = inputs[i].M * input_target(view, inputs, targets, i, source, y, p_hat_here);
    return visibility && t > 0.0f && !input_sees(view, inputs, targets, i, source, y, rays) ? 0.0f : t;
  };
  if (role > 0) {
    const float t = term(role);
    return t + canonical > 0.0f ? t / (t + canonical) / float(n) : 0.0f;
  }
  float m = 0.0f;
  for (int i = 1; i < count; ++i) {
    const float t = term(i);
    if (t + canonical > 0.0f) m += canonical / (t + canonical);
  }
  return m / float(n);
}

// The weight m_role(y) of params.bias for the sample y of input `source`, placed for input 0 (where
// input 0's target is p_hat_here).
float mis_weight(const SceneView& view, const ReuseInput* inputs, InputTargets& targets, int count, int source,
                 int role, const PlacedSample& y, float p_hat_here, const ReuseParams& params, uint64_t& rays) {
  switch (params.bias) {
    case BiasCorrection::None: {
      float M_total = 0.0f;
      for (int z = 0; z < count; ++z) M_total += inputs[z].M;
      return inputs[role].M / M_total;
    }
    case BiasCorrection::Basic:
      return basic_weight(view, inputs, targets, count, source, role, y, p_hat_here, params.mis_visibility, rays);
    case BiasCorrection::Pairwise:
      return pairwise_weight(view, inputs, targets, count, source, role, y, p_hat_here, params.mis_visibility, rays);
  }
  return 0.0f;
}

// Input k's sample as placed for the combining pixel (input 0), into `here`, aged by the input's age_step: re-placed
// only where input 0's frame's lights do not place it alike (placed_alike: moving lights, temporal reuse). (Written
// in place: returned by value, the copy stalled on store forwarding in the profile.)
void place_for_combiner(const SceneView& view, const ReuseInput& in, const LightList* here_lights, ReuseSample& here) {
  const ReuseSample& own = in.reservoir->y;
  if (placed_alike(in.domain->lights, *here_lights, own))
    here = own;
  else
    di_resolve(view.scene, *here_lights, own.light, own.uv, here);
  here.age = aged_by(own.age, in.age_step);
}

// |J| of moving a surface-point sample's reconnection from `own` to `here` (Ouyang et al. 2021, eq. 11):
// (|cos| at the sample point / d^2) seen from here over the same seen from own.
float reconnection_jacobian(const LightPoint& sample, const vec3& here, const vec3& own) {
  auto solid_angle_per_area = [&](const vec3& x) {
    vec3 d = x - sample.position;
    float d2 = glm::dot(d, d);
    return d2 > 0.0f ? std::abs(glm::dot(sample.normal, d)) / (d2 * std::sqrt(d2)) : kInfinity;
  };
  float from_own = solid_angle_per_area(own);
  return from_own > 0.0f ? solid_angle_per_area(here) / from_own : kInfinity;
}

// What a combination resampled: each input's resampling weight (0 where it was skipped) and target at the
// combining pixel, and which input it kept (-1: none).
struct Resampled {
  float w[kMaxReuseInputs], p_hat[kMaxReuseInputs];
  int chosen = -1;
};

// Combines the inputs into one reservoir for the pixel of inputs[0] (the receiver's own reservoir); the
// result's sample is placed in input 0's frame. The canonical input's target at its own sample is the one
// its reservoir stored; `lanes` (or null) holds targets evaluated beforehand. `resampled` (or null) receives
// the weights it streamed.
ReuseReservoir combine(const SceneView& view, const ReuseInput* inputs, int count, const ReuseParams& params,
                       const SlotTargets* lanes, Rng& rng, uint64_t& rays, Resampled* resampled = nullptr) {
  ReuseReservoir out;
  if (resampled) std::fill(resampled->w, resampled->w + count, 0.0f);
  InputTargets targets(inputs, count, lanes);
  const LightList* here_lights = &inputs[0].domain->lights;
  const vec3& here_position = inputs[0].domain->surfaces[inputs[0].pixel].position;
  for (int k = 0; k < count; ++k) {
    const ReuseInput& in = inputs[k];
    float u = rng.next_float();
    out.M += in.M;
    if (in.reservoir->W <= 0.0f) continue;
    const ReuseSample& own = in.reservoir->y;
    if (k > 0 && own.light == kSurfacePointSample && params.max_jacobian > 0.0f &&
        reconnection_jacobian(own.point, here_position, in.domain->surfaces[in.pixel].position) > params.max_jacobian)
      continue;
    ReuseSample here;
    place_for_combiner(view, in, here_lights, here);
    const PlacedSample y{own, &in.domain->lights, here, here_lights};
    float p_hat_here = k == 0 ? in.reservoir->p_hat_y : targets.at(view, 0, k, y);
    float m = mis_weight(view, inputs, targets, count, k, k, y, p_hat_here, params, rays);
    const float w = m * p_hat_here * in.reservoir->W;
    const bool kept = out.update(here, w, p_hat_here, u);
    if (resampled) {
      resampled->w[k] = w, resampled->p_hat[k] = p_hat_here;
      if (kept) resampled->chosen = k;
    }
  }
  out.finalize();
  return out;
}

// Whether slot s of a row can combine in lanes: every target its pairwise weights read was evaluated
// beforehand (not so for punctual lights' samples), and with `visibility` every visibility they read was
// traced beforehand (a neighbour's own sample: the spatial pass's rays; the combining pixel's sample from a
// neighbour: evaluate_reuse_targets's), where the weight's term is positive. Bit tests on the row's masks, and
// with visibility a pass over the slot's inputs.
bool targets_known(const ReuseRow& row, int s, bool visibility) {
  const uint32_t others = uint32_t((uint64_t(1) << row.count[s]) - 1u) & ~1u;  // inputs 1 .. count - 1
  const uint32_t sampled = row.sampled[s] & others;
  const bool own_sampled = row.sampled[s] & 1u;
  if ((sampled & ~row.known_at[s]) || (own_sampled && (others & ~row.known_of[s]))) return false;
  for (int k = 1; visibility && k < row.count[s]; ++k) {
    const ReuseInput& in = row.inputs[k][s];
    if ((sampled >> k & 1u) && in.M * row.own[k][s] > 0.0f && in.own_visible < 0) return false;
    if (own_sampled && in.M * row.of_combiner[k][s] > 0.0f && !(row.known_visible[s] >> k & 1u)) return false;
  }
  return true;
}

// The slots of a row that can combine in lanes (targets_known: in_lanes[s] receives whether slot s can) into the
// combination lanes (the others get count 0): their confidences, and with `visibility` the visibilities the weights
// read; the uniforms of every slot's inputs, in combine's order, drawn in lanes from a copy of the streams (slots
// that do not combine in lanes ignore theirs); the lanes read the row's reservoir and target planes where
// evaluate_reuse_targets left them. Returns the largest count.
int gather_combinations(const ReuseRow& row, int slots, bool visibility, const ReuseStreams& streams, bool* in_lanes,
                        CombineLanes& lanes) {
  int max_count = 0;
  for (int s = 0; s < slots; ++s) {
    in_lanes[s] = row.count[s] > 0 && targets_known(row, s, visibility);
    const int count = in_lanes[s] ? row.count[s] : 0;
    lanes.count[s] = float(count);
    max_count = std::max(max_count, count);
    for (int k = 0; k < count; ++k) lanes.M[k][s] = row.inputs[k][s].M;
    for (int k = 0; visibility && k < count; ++k) {
      lanes.own_visible[k][s] = row.inputs[k][s].own_visible == 1 ? 1.0f : 0.0f;
      lanes.of_visible[k][s] = float(row.visible[s] >> k & 1u);
    }
  }
  ReuseStreams uniforms = streams;
  uniforms.fill(max_count, slots, &lanes.u[0][0]);  // lanes.u[k][s]: number k of slot s
  lanes.W = row.W;
  lanes.own = row.own;
  lanes.at = row.at_combiner;
  lanes.of = row.of_combiner;
  return max_count;
}

// Further samples of a tile row's combinations (ReuseParams::shaded_samples): (*out)[j][first + slot] receives
// slot's sample j + 2, drawn with the uniform v[slot].
struct FurtherSamples {
  std::vector<std::vector<ReuseReservoir>>* out;
  const float* v;
};

// The further samples of slot s's combination `r` into further.out at pixel i: sample j (1 <= j < n) is input
// picks[j]'s, drawn by systematic resampling over the combination's weights (systematic_picks, reservoir.h, or
// systematic_picks_lanes), and p_hat[j] its target at the combining pixel. Each is kept as the combination keeps its
// one and gets its contribution weight w_sum / p_0(y), so every reservoir is the combination's estimator, and the
// samples are stratified over the weights. Without picks (the slot kept no sample: nothing combined, or no weight) `r`
// is copied into each.
void write_further(const SceneView& view, const ReuseRow& row, int s, const int* picks, const float* p_hat,
                   const ReuseReservoir& r, size_t i, const FurtherSamples& further) {
  for (int j = 1; j <= int(further.out->size()); ++j) {
    ReuseReservoir& out = (*further.out)[size_t(j - 1)][i];
    if (!picks) {
      out = r;
      continue;
    }
    out.w_sum = r.w_sum, out.M = r.M;  // the sample's fields are written once, below
    place_for_combiner(view, row.inputs[picks[j]][s], &row.inputs[0][s].domain->lights, out.y);
    out.p_hat_y = p_hat[j];
    out.finalize();
  }
}

// Combines every slot of a tile row (ReuseRow) into out[first + slot], with the targets evaluated in lanes
// first where params.simd, and with pairwise MIS the combinations too (resample_lanes.h; slots whose targets
// or visibilities are not all known combine one at a time); `streams` gives each slot's random numbers. A
// slot without inputs keeps its reservoir of `in`. `kept` (or null) receives per slot the input whose sample the
// result holds (0 also for a slot without inputs, which keeps its own; -1: none). Returns the rays traced.
uint64_t combine_row(const SceneView& view, const ReuseParams& params, int slots, ReuseRow& row,
                     const ReuseStreams& streams, size_t first, const std::vector<ReuseReservoir>& in,
                     std::vector<ReuseReservoir>& out, const FurtherSamples* further = nullptr, int* kept = nullptr) {
  const bool weights = params.bias != BiasCorrection::None;
  uint64_t traced =
      params.simd ? evaluate_reuse_targets(view, slots, weights, weights && params.mis_visibility, row) : 0;
  const int n = further ? int(further->out->size()) + 1 : 1;  // samples per slot
  CHECK(n <= kMaxShadedSamples);
  thread_local CombineLanes lanes;
  bool in_lanes[kLaneSlots] = {};
  if (params.simd && params.bias == BiasCorrection::Pairwise && params.max_jacobian <= 0.0f) {
    if (const int max_count = gather_combinations(row, slots, params.mis_visibility, streams, in_lanes, lanes);
        max_count > 0) {
      combine_pairwise_lanes(lanes, slots, max_count, params.mis_visibility);
      if (n > 1) systematic_picks_lanes(lanes, further->v, n, slots, max_count);
    }
  }
  ReuseInput inputs[kMaxReuseInputs];  // a slot's inputs, for combining it one at a time
  Resampled resampled;
  int picks[kMaxShadedSamples];  // a slot's further samples' inputs (picks[0]: the kept one) and targets
  float p_hat[kMaxShadedSamples];
  for (int s = 0; s < slots; ++s) {
    const size_t i = first + size_t(s);
    ReuseReservoir& r = out[i];
    bool picked = false;  // picks and p_hat hold the slot's further samples
    int chosen = 0;       // the input whose sample r holds (-1: none)
    if (row.count[s] == 0) {
      r = in[i];
    } else if (!in_lanes[s]) {
      for (int k = 0; k < row.count[s]; ++k) inputs[k] = row.inputs[k][s];
      const SlotTargets targets{row, s};
      Rng rng = streams.stream(s);
      resampled.chosen = -1;
      r = combine(view, inputs, row.count[s], params, params.simd ? &targets : nullptr, rng, traced,
                  further || kept ? &resampled : nullptr);
      chosen = resampled.chosen;
      if ((picked = n > 1 && resampled.chosen >= 0 && r.W > 0.0f)) {
        systematic_picks(resampled.w, row.count[s], resampled.chosen, further->v[s], n, picks);
        for (int j = 1; j < n; ++j) p_hat[j] = resampled.p_hat[picks[j]];
      }
    } else {
      // The kept input's sample, placed for the combining pixel, with the lanes' sums.
      static const ReuseSample kNone{};
      chosen = int(lanes.result.chosen[s]);
      if (chosen >= 0)
        place_for_combiner(view, row.inputs[chosen][s], &row.inputs[0][s].domain->lights, r.y);
      else
        r.y = kNone;
      r.p_hat_y = lanes.result.p_hat[s], r.w_sum = lanes.result.w_sum[s], r.M = lanes.M_sum[s], r.W = lanes.W_out[s];
      if ((picked = n > 1 && chosen >= 0 && r.W > 0.0f))
        for (int j = 1; j < n; ++j) {
          picks[j] = int(lanes.picks[j][s]);
          p_hat[j] = picks[j] == 0 ? lanes.own[0][s] : row.at_combiner[picks[j]][s];
        }
    }
    if (further) write_further(view, row, s, picked ? picks : nullptr, p_hat, r, i, *further);
    if (kept) kept[s] = chosen;
  }
  return traced;
}

// Last frame's reservoir r (pixel j of `domain`, last frame's) as an input of this frame's combination whose own
// reservoir has confidence M, into `input` (own_visible left unknown), as temporal and fused reuse take it: its sample
// a frame older, its confidence capped at params.history_cap times M. False where the sample would then be older than
// params.max_sample_age (the input is dropped).
bool history_input(const ReuseReservoir& r, const ReuseDomain& domain, size_t j, float M, const ReuseParams& params,
                   ReuseInput& input) {
  constexpr uint8_t kAgeStep = 1;
  if (params.max_sample_age > 0 && aged_by(r.y.age, kAgeStep) > params.max_sample_age) return false;
  input = {&r, &domain, j, std::min(r.M, params.history_cap * M)};
  input.age_step = kAgeStep;
  return true;
}

// Last frame's pixel under pixel (x, y) = i's surface point (find_history_pixels), or -1; whether its surface is
// similar is tested apart.
int64_t reprojected_pixel(const GBuffer& g, const ReuseDomain& current, const ReuseParams& params, int frame, size_t i,
                          int x, int y) {
  if (!g.hit(i) || current.surfaces[i].roughness() < params.min_roughness) return -1;
  vec2 p = vec2(x, y) + g.jitter[i] + g.motion[i];
  if (!(p.x >= 0.0f && p.y >= 0.0f && p.x < float(g.width) && p.y < float(g.height))) return -1;
  int px = int(p.x), py = int(p.y);
  if (params.permutation_sampling) {
    uint64_t pattern = mix64(params.seed ^ uint64_t(frame));
    px ^= int(pattern & 1);
    py ^= int((pattern >> 1) & 1);
  }
  if (px < 0 || py < 0 || px >= g.width || py >= g.height) return -1;
  return int64_t(py) * g.width + px;
}

}  // namespace

bool similar_surfaces(const PackedSurface& a, const vec3& a_n, const PackedSurface& b, const ReuseParams& p) {
  if (!b.hit() || std::abs(a.depth - b.depth) > p.depth_tolerance * a.depth) return false;
  return glm::dot(a_n, b.shading_n()) >= p.normal_tolerance;
}

void reuse_mis_weights(const SceneView& view, const ReuseInput* inputs, int count, int source,
                       const ReuseParams& params, float* weights) {
  InputTargets targets(inputs, count, nullptr);
  const LightList* here_lights = &inputs[0].domain->lights;
  ReuseSample here;
  place_for_combiner(view, inputs[source], here_lights, here);
  const PlacedSample y{inputs[source].reservoir->y, &inputs[source].domain->lights, here, here_lights};
  const float p_hat_here = source == 0 ? inputs[0].reservoir->p_hat_y : targets.at(view, 0, source, y);
  uint64_t rays = 0;
  for (int role = 0; role < count; ++role)
    weights[role] = mis_weight(view, inputs, targets, count, source, role, y, p_hat_here, params, rays);
}

bool history_follows(const ReuseParams& first, const ReuseParams& second) {
  return first.temporal && second.temporal && first.min_roughness <= second.min_roughness &&
         first.depth_tolerance == second.depth_tolerance && first.normal_tolerance == second.normal_tolerance &&
         first.simd == second.simd && !first.permutation_sampling && !second.permutation_sampling;
}

void find_history_pixels(const GBuffer& g, const ReuseDomain& current, const ReuseDomain& previous,
                         const ReuseParams& params, int frame, std::vector<int32_t>& history_pixel,
                         const SecondHistory* second) {
  if (previous.surfaces.size() != g.size()) {  // no surfaces last frame: nothing to reuse
    history_pixel.assign(g.size(), -1);
    if (second) second->history_pixel->assign(g.size(), -1);
    return;
  }
  history_pixel.resize(g.size());  // every pixel is written by its tile row below
  if (second) second->history_pixel->resize(g.size());
  for_each_tile(g.width, g.height, [&](const Tile& tile) {
    thread_local NeighbourLanes lanes;  // params.simd: whether the reprojected pixel's surface is similar
    const int slots = tile.x1 - tile.x0;
    for (int y = tile.y0; y < tile.y1; ++y) {
      const size_t first = size_t(y) * size_t(g.width) + size_t(tile.x0);
      int32_t* found = history_pixel.data() + first;
      // The tile's next row's surfaces prefetched, and last frame's under them (where a still or slowly moving
      // camera finds their history): their first touch in this loop was most of its time.
      for (int s = 0; y + 1 < tile.y1 && s < slots; s += std::max(1, int(64 / sizeof(PackedSurface)))) {
        const size_t next = first + size_t(g.width) + size_t(s);
        prefetch_object(current.surfaces[next]);
        prefetch_object(previous.surfaces[next]);
      }
      for (int s = 0; s < slots; ++s)
        found[s] = int32_t(reprojected_pixel(g, current, params, frame, first + size_t(s), tile.x0 + s, y));
      if (params.simd) {
        for (int s = 0; s < slots; ++s) {
          lanes.set(s, current.surfaces[first + size_t(s)]);
          if (found[s] >= 0)
            lanes.set_neighbour(0, s, previous.surfaces[size_t(found[s])]);
          else
            lanes.clear_neighbour(0, s);
        }
        similar_neighbour_lanes(lanes, 1, slots, params.depth_tolerance, params.normal_tolerance);
      }
      for (int s = 0; s < slots; ++s) {
        const size_t i = first + size_t(s);
        if (found[s] >= 0 && !(params.simd ? lanes.similar[0][s] != 0
                                           : similar_surfaces(current.surfaces[i], current.surfaces[i].shading_n(),
                                                              previous.surfaces[size_t(found[s])], params)))
          found[s] = -1;
        // reprojected_pixel's first test with the second chain's roughness bound; the others are this chain's.
        if (second)
          (*second->history_pixel)[i] = current.surfaces[i].roughness() < second->min_roughness ? -1 : found[s];
      }
    }
  });
}

void temporal_reuse(const SceneView& view, const GBuffer& g, const ReuseDomain& current, const ReuseDomain& previous,
                    const std::vector<ReuseReservoir>& reservoirs, const std::vector<ReuseReservoir>& history,
                    const ReuseParams& params, int frame, std::vector<ReuseReservoir>& out,
                    std::vector<int32_t>& history_pixel, RayCounter& rays,
                    const std::vector<SampleVisibility>* history_verdicts) {
  if (history.size() != g.size() || previous.surfaces.size() != g.size()) {
    history_pixel.assign(g.size(), -1);
    out = reservoirs;
    return;
  }
  CHECK(history_pixel.size() == g.size());  // find_history_pixels's
  out.resize(reservoirs.size());            // every pixel is written by its tile row below
  // With visibility in the pairwise weights, whether each history sample is visible from its own surface
  // (against this frame's geometry; the weight of a positive term reads it), into the input: last frame's verdict
  // where its shading traced this very ray (history_verdicts: a verdict of its own, not one reused from an earlier
  // frame, on the same sample), else traced, 16 at a time in slot order instead of one ray at a time inside the
  // combinations. Returns the rays traced.
  const bool own_visibility = params.mis_visibility && params.bias == BiasCorrection::Pairwise;
  auto verdict_on = [&](const ReuseInput& in) {
    if (!history_verdicts) return -1;
    const SampleVisibility& v = (*history_verdicts)[in.pixel];
    return v.on(in.reservoir->y) && v.age == 0 ? int(v.visible) : -1;
  };
  auto trace_own_visibility = [&](int slots, ReuseRow& row) {
    auto answer = [&](int s, const RayPacket16& packet, int lane) {
      row.inputs[1][s].own_visible = Tracer::occluded_lane(packet, lane) ? 0 : 1;
    };
    auto queue = ray_queue16<int>(view.tracer, RayQuery::Occluded, answer);
    for (int s = 0; s < slots; ++s) {
      ReuseInput& in = row.inputs[1][s];
      if (row.count[s] < 2 || in.reservoir->W <= 0.0f || !(in.M * in.reservoir->p_hat_y > 0.0f)) continue;
      if (const int verdict = verdict_on(in); verdict >= 0) {
        in.own_visible = int8_t(verdict);
        continue;
      }
      queue.add(sample_shadow_ray(view.tracer, previous.surfaces[in.pixel], previous.lights, in.reservoir->y), s);
    }
    queue.finish();
    return queue.traced();
  };
  // Per tile row: each pixel's pair of inputs (its reservoir and its history, whose sample ages by a frame), then the
  // row's combinations.
  for_each_tile(g.width, g.height, [&](const Tile& tile) {
    struct Batch {
      ReuseRow row;
      ReuseStreams streams;
    };
    thread_local Batch batch;
    const int slots = tile.x1 - tile.x0;
    uint64_t traced = 0;
    for (int y = tile.y0; y < tile.y1; ++y) {
      const size_t first = size_t(y) * size_t(g.width) + size_t(tile.x0);
      batch.streams.key(slots, params.seed, first, uint64_t(frame), 0xd2);  // Rng::for_key(seed, pixel, frame, 0xd2)
      // The tile's next row's reservoirs, history and last frame's surfaces prefetched: their first touch, in the
      // copies below, was most of this loop's time. And its outputs for writing: the combinations' stores then find
      // their lines owned (di_temporal 0.95x).
      for (int s = 0; y + 1 < tile.y1 && s < slots; ++s) {
        const size_t next = first + size_t(g.width) + size_t(s);
        prefetch_object(reservoirs[next]);
        prefetch_to_write(&out[next]);
        if (const int32_t j = history_pixel[next]; j >= 0) {
          prefetch_object(history[size_t(j)]);
          prefetch_object(previous.surfaces[size_t(j)]);
        }
      }
      for (int s = 0; s < slots; ++s) {
        const size_t i = first + size_t(s);
        batch.row.count[s] = 0;
        const int32_t j = history_pixel[i];
        history_pixel[i] = -1;
        if (j < 0) continue;
        ReuseInput old;
        if (!history_input(history[size_t(j)], previous, size_t(j), reservoirs[i].M, params, old)) continue;
        batch.row.set_input(0, s, {&reservoirs[i], &current, i, reservoirs[i].M});
        batch.row.set_input(1, s, old);
        batch.row.count[s] = 2;
        history_pixel[i] = int32_t(j);
      }
      if (own_visibility) traced += trace_own_visibility(slots, batch.row);
      traced += combine_row(view, params, slots, batch.row, batch.streams, first, reservoirs, out);
    }
    rays.add(traced);
  });
}

void spatial_reuse(const SceneView& view, const ReuseDomain& current, const std::vector<ReuseReservoir>& in,
                   const ReuseParams& params, int frame, int pass, const std::vector<int32_t>* history_pixel,
                   std::vector<ReuseReservoir>& out, RayCounter& rays,
                   std::vector<std::vector<ReuseReservoir>>* further, std::vector<int8_t>* kept_visible,
                   const PreviousFrame* previous) {
  CHECK(!previous ||
        (pass == 0 && previous->reservoirs.size() == in.size() && previous->domain.surfaces.size() == in.size()));
  const std::span<const PackedSurface> surfaces = current.surfaces;
  // Where the neighbours come from: `in`, around each pixel, or last frame's reservoirs around its reprojection.
  const ReuseDomain& source = previous ? previous->domain : current;
  const std::vector<ReuseReservoir>& from = previous ? previous->reservoirs : in;
  const std::span<const PackedSurface> source_surfaces = source.surfaces;
  if (further && further->empty()) further = nullptr;
  if (further)
    for (std::vector<ReuseReservoir>& samples : *further) samples.resize(in.size());
  const int width = current.width, height = current.height;
  out.resize(in.size());  // every pixel is written by its tile row below, and so is kept_visible
  if (kept_visible) kept_visible->resize(in.size());
  const bool boost = pass == 0 && history_pixel && history_pixel->size() == in.size();
  // Pairwise MIS with visibility asks every neighbour whether its own sample is visible from it: asked
  // here once per pixel of the neighbours' frame (one shadow ray each, 16 at a time in pixel order, against this
  // frame's geometry) instead of once per pixel and neighbour.
  std::vector<int8_t> own_visible;
  if (params.mis_visibility && params.bias == BiasCorrection::Pairwise) {
    own_visible.assign(in.size(), -1);
    for_each_tile(width, height, [&](const Tile& tile) {
      auto answer = [&](size_t j, const RayPacket16& packet, int lane) {
        own_visible[j] = Tracer::occluded_lane(packet, lane) ? 0 : 1;
      };
      auto queue = ray_queue16<size_t>(view.tracer, RayQuery::Occluded, answer);
      for (int y = tile.y0; y < tile.y1; ++y)
        for (int x = tile.x0; x < tile.x1; ++x) {
          const size_t j = size_t(y) * size_t(width) + size_t(x);
          if (!source_surfaces[j].hit() || from[j].W <= 0.0f || from[j].p_hat_y <= 0.0f) continue;
          queue.add(sample_shadow_ray(view.tracer, source_surfaces[j], source.lights, from[j].y), j);
        }
      queue.finish();
      rays.add(queue.traced());
    });
  }
  // Neighbours: consecutive offsets of the table (scaled by the radius once per pass) from a start drawn with
  // the pixel's random stream (one number instead of ~2.5 per neighbour and no rejection loop), or shared by
  // the pixel's block of params.neighbour_block pixels on a side, and their surfaces and reservoirs
  // prefetched. A shared start makes neighbouring pixels read neighbouring pixels' data. With `previous`, the
  // offsets are taken around the pixel's reprojection, which is the first neighbour.
  struct Drawn {
    bool active = false;  // the pixel takes part in reuse (a surface, rough enough)
    int count = 0;
    size_t pixels[kMaxReuseInputs];
  };
  // The offset table in whole pixels at this radius, once per pass (8 KB) instead of per pixel and neighbour.
  const std::vector<vec2>& offsets = neighbour_offsets();
  std::vector<glm::ivec2> pixel_offsets(kOffsetCount);
  for (uint32_t k = 0; k < kOffsetCount; ++k)
    pixel_offsets[k] = {round_nearest(params.spatial_radius * offsets[k].x),
                        round_nearest(params.spatial_radius * offsets[k].y)};
  const int block = std::max(params.neighbour_block, 1);
  const int blocks_x = (width + block - 1) / block;
  auto block_start = [&](int x, int y) {
    const uint64_t b = uint64_t(y / block) * uint64_t(blocks_x) + uint64_t(x / block);
    return Rng::for_key(params.seed, b, uint64_t(frame), spatial_stream(kBlockStarts, pass)).next_u32();
  };
  // shared_start: the pixel's block's start (block > 1); streams: the row's, the pixel's in slot s.
  auto draw = [&](size_t i, int x, int y, uint32_t shared_start, ReuseStreams& streams, int s, Drawn& d) {
    d.count = 0;
    prefetch_to_write(&out[i]);  // the combination's outputs: their stores then find the lines owned (0.97x)
    for (int f = 0; further && f < int(further->size()); ++f) prefetch_to_write(&(*further)[size_t(f)][i]);
    d.active = surfaces[i].hit() && surfaces[i].roughness() >= params.min_roughness;
    if (!d.active) return;
    const int neighbours =
        boost && (*history_pixel)[i] < 0 ? params.disocclusion_neighbours : params.spatial_neighbours;
    const int centre_inputs = previous ? 1 : 0;  // the reprojection
    const int max_inputs = 1 + centre_inputs + std::clamp(neighbours, 0, kMaxReuseInputs - 1 - centre_inputs);
    const uint32_t own_start = streams.next_u32(s);  // drawn either way: the stream's later numbers stay the same
    const uint32_t start = block > 1 ? shared_start : own_start;
    auto add = [&](size_t j) {
      prefetch_object(source_surfaces[j]);
      prefetch_object(from[j]);
      d.pixels[d.count++] = j;
    };
    int cx = x, cy = y;  // the centre of the offsets
    if (previous) {
      const int64_t c = reprojected_pixel(previous->g, current, params, frame, i, x, y);
      if (c < 0) return;  // no reprojection: the pixel keeps its own reservoir
      cx = int(c % width), cy = int(c / width);
      add(size_t(c));
    }
    for (int k = 1 + centre_inputs; k < max_inputs; ++k) {
      const glm::ivec2 o = pixel_offsets[(start + uint32_t(k)) % kOffsetCount];
      const int nx = cx + o.x, ny = cy + o.y;
      if (nx < 0 || ny < 0 || nx >= width || ny >= height || (nx == cx && ny == cy)) continue;
      add(size_t(ny) * width + nx);
    }
  };
  // Which of a row's drawn neighbours are similar to their pixels, in lanes (params.simd).
  auto test_similar = [&](size_t first, int slots, const Drawn* drawn, NeighbourLanes& lanes) {
    int count = 0;
    for (int s = 0; s < slots; ++s) count = std::max(count, drawn[s].count);
    for (int s = 0; s < slots; ++s) {
      lanes.set(s, surfaces[first + size_t(s)]);
      for (int c = 0; c < count; ++c)
        if (c < drawn[s].count)
          lanes.set_neighbour(c, s, source_surfaces[drawn[s].pixels[c]]);
        else
          lanes.clear_neighbour(c, s);
    }
    similar_neighbour_lanes(lanes, count, slots, params.depth_tolerance, params.normal_tolerance);
  };
  // The pixel and its similar neighbours, as the inputs of its combination in slot s of `row` (none without a
  // surface); `lanes`: their similarity tested in slot s of a row, else null (tested here). Last frame's neighbours
  // (`previous`) enter as temporal reuse's history does (history_input).
  auto select = [&](size_t i, const Drawn& d, const NeighbourLanes* lanes, int s, ReuseRow& row) {
    int& count = row.count[s];
    count = 0;
    if (!d.active) return;
    row.set_input(count++, s, {&in[i], &current, i, in[i].M});
    const vec3 n = lanes ? vec3(0.0f) : surfaces[i].shading_n();
    for (int c = 0; c < d.count; ++c) {
      size_t j = d.pixels[c];
      if (!(lanes ? lanes->similar[c][s] != 0 : similar_surfaces(surfaces[i], n, source_surfaces[j], params))) continue;
      ReuseInput input{&from[j], &source, j, from[j].M};
      if (previous && !history_input(from[j], source, j, in[i].M, params, input)) continue;
      input.own_visible = own_visible.empty() ? int8_t(-1) : own_visible[j];
      row.set_input(count++, s, input);
    }
  };
  // Per tile row: every pixel's neighbours drawn first, a row ahead (so that the cache misses of their surfaces and
  // reservoirs, whose planes' rows within the radius exceed L2 at 640 pixels wide, overlap with the previous row's
  // combinations), then tested for similarity (in lanes with params.simd) and selected, then the row's combinations.
  struct RowDraws {
    Drawn drawn[kLaneSlots];
    ReuseStreams streams;             // the row's pixels' streams, after their neighbours' draws
    uint32_t start[kLaneSlots] = {};  // block > 1: each slot's block's start
  };
  // Row y's neighbours into `r`: the blocks' starts, one draw per block (a keyed stream costs about as much as the
  // pixel's own) or the row above's (`above`, or null) where it lies in the same blocks, then each pixel's.
  auto draw_row = [&](const Tile& tile, int y, const RowDraws* above, RowDraws& r) {
    const int slots = tile.x1 - tile.x0;
    const size_t first = size_t(y) * size_t(width) + size_t(tile.x0);
    if (block > 1 && above && (y - 1) / block == y / block) {
      std::copy(above->start, above->start + slots, r.start);
    } else {
      for (int s = 0; block > 1 && s < slots; ++s) {
        const int x = tile.x0 + s;
        r.start[s] = s > 0 && x % block != 0 ? r.start[s - 1] : block_start(x, y);
      }
    }
    r.streams.key(slots, params.seed, first, uint64_t(frame), spatial_stream(kPixelStreams, pass));  // Rng::for_key
    for (int s = 0; s < slots; ++s) draw(first + size_t(s), tile.x0 + s, y, r.start[s], r.streams, s, r.drawn[s]);
  };
  for_each_tile(width, height, [&](const Tile& tile) {
    struct Batch {
      ReuseRow row;
      RowDraws draws[2];             // row y's in draws[(y - tile.y0) % 2]
      ReuseStreams further_streams;  // further: the uniforms of the further samples
      alignas(64) float v[kLaneSlots];
      NeighbourLanes neighbours;  // params.simd
    };
    thread_local Batch batch;
    const int slots = tile.x1 - tile.x0;
    uint64_t traced = 0;
    draw_row(tile, tile.y0, nullptr, batch.draws[0]);
    for (int y = tile.y0; y < tile.y1; ++y) {
      const size_t first = size_t(y) * size_t(width) + size_t(tile.x0);
      RowDraws& now = batch.draws[(y - tile.y0) % 2];
      if (y + 1 < tile.y1) draw_row(tile, y + 1, &now, batch.draws[(y + 1 - tile.y0) % 2]);
      if (params.simd) test_similar(first, slots, now.drawn, batch.neighbours);
      for (int s = 0; s < slots; ++s)
        select(first + size_t(s), now.drawn[s], params.simd ? &batch.neighbours : nullptr, s, batch.row);
      if (further) {
        batch.further_streams.key(slots, params.seed, first, uint64_t(frame), spatial_stream(kFurtherPoints, pass));
        batch.further_streams.fill(1, slots, batch.v);
      }
      const FurtherSamples more{further, batch.v};
      int kept[kLaneSlots];
      traced += combine_row(view, params, slots, batch.row, now.streams, first, in, out, further ? &more : nullptr,
                            kept_visible ? kept : nullptr);
      // Where a pixel kept its own sample, the visibility traced for it above is its result's (not so with `previous`:
      // the rays were traced for last frame's samples).
      for (int s = 0; kept_visible && s < slots; ++s) {
        const size_t i = first + size_t(s);
        (*kept_visible)[i] = kept[s] == 0 && !own_visible.empty() && !previous ? own_visible[i] : int8_t(-1);
      }
    }
    rays.add(traced);
  });
}

void boiling_filter(const ReuseDomain& current, float threshold, std::vector<ReuseReservoir>& reservoirs) {
  constexpr int kBlock = 16;
  const int bw = (current.width + kBlock - 1) / kBlock, bh = (current.height + kBlock - 1) / kBlock;
  auto contribution = [&](size_t i) { return reservoirs[i].p_hat_y * reservoirs[i].W; };
  parallel_for(0, bw * bh, [&](int b) {
    const int x0 = (b % bw) * kBlock, y0 = (b / bw) * kBlock;
    const int x1 = std::min(x0 + kBlock, current.width), y1 = std::min(y0 + kBlock, current.height);
    double sum = 0.0;
    int count = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x)
        if (size_t i = size_t(y) * current.width + x; reservoirs[i].W > 0.0f) sum += contribution(i), ++count;
    if (count == 0) return;
    const float limit = threshold * float(sum / count);
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x)
        if (size_t i = size_t(y) * current.width + x; contribution(i) > limit)
          reservoirs[i].W = reservoirs[i].w_sum = 0.0f;
  });
}

}  // namespace candela
