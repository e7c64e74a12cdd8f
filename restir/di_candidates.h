#pragma once
// ReSTIR DI's first stage: resampled importance sampling of each pixel's light and BSDF candidates into
// its reservoir (Bitterli et al. 2020, sec. 3 and Alg. 3), one tile row of pixels at a time so that the
// light candidates' targets are evaluated in SIMD lanes (target_lanes.h) between drawing them and
// resampling them.
#include <vector>

#include "engine/check.h"
#include "engine/prefetch.h"
#include "restir/bsdf_ray.h"
#include "restir/di.h"
#include "restir/light_tiles.h"
#include "restir/receiver_lanes.h"
#include "restir/resample_lanes.h"

namespace candela {

// One tile row's candidates in flight: per pixel (slot) its receivers, random stream and light-sampling
// context, and per light candidate k the drawn sample, its light-sampling density and resampling uniform,
// beside the lanes the evaluation reads and writes.
struct DiCandidateBatch {
  SurfaceLanes surfaces;             // the slots' packed surfaces, from which the lanes' receivers are built
  ExactSurfaceLanes exact_surfaces;  // and their G-buffer surfaces, for the exact BSDFs' terms (params.simd)
  ReceiverLanes lanes;
  std::vector<CandidateLanes> planes;  // one per light candidate
  struct Slot {
    bool hit = false;
    size_t pixel = 0;
    Rng rng;
    ReuseReceiver receiver;  // exact (densities of BSDF candidates that hit a light, visibility), built by exact()
                             // on first use where the lanes hold the exact BSDFs' terms
    ReuseReceiver target;    // packed (targets), built by target() on first use where the lanes evaluate the
                             // light candidates
    bool receiver_built = false, target_built = false;
    ShadingContext ctx;
    int light_candidates = 0;  // M_l of the slot: DiParams::light_candidates, or history_light_candidates
  } slot[kLaneSlots];
  alignas(64) float M_l[kLaneSlots];  // the slots' M_l, as the resampling lanes read it
  // The packed receiver of a slot, for the targets the lanes do not evaluate (BSDF candidates, punctual
  // lights).
  const ReuseReceiver& target(const ReuseDomain& domain, int s) {
    if (!slot[s].target_built) slot[s].target = reuse_receiver(domain, slot[s].pixel), slot[s].target_built = true;
    return slot[s].target;
  }
  // The exact receiver of a slot (G-buffer g, eye and lights of `domain`).
  const ReuseReceiver& exact(const GBuffer& g, const ReuseDomain& domain, int s) {
    if (!slot[s].receiver_built)
      slot[s].receiver = exact_receiver(g, domain.eye, domain.lights, slot[s].pixel), slot[s].receiver_built = true;
    return slot[s].receiver;
  }
  // Light candidate k of a slot, at [k * kLaneSlots + slot]: the chosen light and the uniforms that place
  // the point on it (which, for a triangle light, planes[k] holds); where p_light is 0, stale.
  std::vector<uint32_t> light;
  std::vector<vec2> uv;
  std::vector<float> p_light, u;  // light-sampling area density (0: no light chosen), resampling uniform
  // BSDF candidate k of each slot: its direction sample (pdf 0: none, no ray), resampling uniform and hit.
  struct BsdfCandidate {
    BsdfSample sample;
    float u = 0.0f;
    Hit hit;
    int64_t light = -1;        // the light the hit landed on (-1: none, or no hit)
    ReuseSample light_sample;  // where light >= 0: the sample at the hit's point
  };
  std::vector<BsdfCandidate> bsdf;              // [k * kLaneSlots + slot]
  std::vector<CandidateLanes> bsdf_hits;        // per BSDF candidate, its hits' points on lights (params.simd)
  std::vector<DirectionLanes> directions;       // per BSDF candidate, its directions' value and density (params.simd)
  std::vector<BsdfUniformLanes> bsdf_uniforms;  // per BSDF candidate, its directions' uniforms (params.simd)
  // The light choices while they are drawn, at [slot * M_l + k]: the uniforms of the choice, the choices.
  std::vector<vec2> light_u;
  std::vector<SampledLight> chosen;
  // The slots' random streams while the light candidates' uniforms are drawn, and those uniforms
  // ([n * kLaneSlots + slot]); afterwards each slot's stream goes on in Slot::rng.
  RngRow<kLaneSlots> streams;
  std::vector<float> uniforms;
  void resize(int light_candidates, int bsdf_candidates);
  // Whether slot s drew a punctual light among its light_candidates (whose targets the lanes do not have).
  bool drew_punctual(const LightList& lights, int light_candidates, int s) const {
    for (int k = 0; k < light_candidates; ++k) {
      const size_t at = size_t(k) * kLaneSlots + size_t(s);
      if (p_light[at] > 0.0f && light[at] >= lights.triangle_count()) return true;
    }
    return false;
  }
  // Light candidate k of slot s as a sample, written into `out` field by field (returned whole, the sample was
  // copied out of a temporary through overlapping reloads that stalled on store forwarding).
  void candidate(const LightList& lights, int k, int s, ReuseSample& out) const {
    const size_t at = size_t(k) * kLaneSlots + size_t(s);
    out.light = light[at];
    out.uv = uv[at];
    out.point = light[at] < lights.triangle_count() ? planes[size_t(k)].point(s) : LightPoint{};
    out.age = 0;
  }
};

// Stage "di_candidates", part 1 (per tile row): each pixel's receivers and its M_l light candidates, drawn
// from the sampler and placed on their lights (or read from the pixel's light tile, with `tiles`: one
// uniform entry each, with the density of the tile's context), into the batch's slots and lanes; with `history`
// (the row's find_history_pixels answers) a pixel with history draws its first history_light_candidates only, and its
// other candidates stay empty (the uniforms are drawn either way, so every candidate keeps its numbers). In three
// passes over the row, so that the cache misses of the sampler's tables and of the chosen lights' records
// (with 1e5 lights, several per candidate) overlap across pixels instead of stalling each candidate in turn:
// the uniforms (and the sampler's prefetch), the choices (and the lights' records prefetched), the points.
template <LightSampler S>
void draw_light_candidates(const SceneView& view, const S& sampler, const GBuffer& g, const ReuseDomain& domain,
                           const DiParams& params, int frame, size_t row, int x0, int y, int slots,
                           const LightTiles* tiles, const int32_t* history, DiCandidateBatch& batch) {
  const int K = params.light_candidates;
  for (int s = 0; s < slots; ++s) {
    DiCandidateBatch::Slot& b = batch.slot[s];
    const size_t i = row + size_t(s);
    b.hit = g.hit(i);
    b.pixel = i;
    b.light_candidates = history && history[s] >= 0 ? std::min(K, params.history_light_candidates) : K;
    batch.M_l[s] = float(b.light_candidates);
    b.receiver_built = b.target_built = false;
    for (int k = 0; k < K; ++k) batch.planes[size_t(k)].clear(s);
  }
  // The row's packed surfaces, and with params.simd its exact ones (the exact BSDFs' terms are built in lanes).
  batch.surfaces.set_row(domain.surfaces.data() + row, slots);
  if (params.simd) batch.exact_surfaces.set_row(g, row, slots);
  batch.streams.key(slots, params.seed, row, uint64_t(frame), 0xd1);  // Rng::for_key(seed, pixel, frame, 0xd1)
  // The candidates' uniforms, in the order one candidate at a time would draw them: per candidate, a tile
  // entry and the resampling uniform, or the light choice (2), the point (2) and the resampling uniform.
  const int per_candidate = tiles ? 2 : 5;
  batch.uniforms.resize(size_t(K * per_candidate) * kLaneSlots);
  batch.streams.fill(K * per_candidate, slots, batch.uniforms.data());
  // With tiles: the row's tiles, one per screen block it crosses (looked up per pixel, each lookup was a call and
  // a copy that stalled on store forwarding), and the entries the row's candidates will read (uniform 2k of
  // candidate k) prefetched first: the tiles are 7 MB at 640x360, written a stage before, and each entry loaded
  // in turn stalled on its miss.
  constexpr int kBlock = LightTiles::kBlock;
  LightTiles::Tile row_tiles[kLaneSlots / kBlock + 1];
  const int first_block = x0 / kBlock;
  for (int block = first_block; tiles && block <= (x0 + slots - 1) / kBlock; ++block)
    row_tiles[block - first_block] = tiles->tile(block * kBlock, y, frame);
  auto tile_of = [&](int s) -> const LightTiles::Tile& { return row_tiles[(x0 + s) / kBlock - first_block]; };
  for (int s = 0; tiles && s < slots; ++s) {
    if (!batch.slot[s].hit) continue;
    for (int k = 0; k < batch.slot[s].light_candidates; ++k)
      prefetch_object(tile_of(s).entry(batch.uniforms[size_t(2 * k) * kLaneSlots + size_t(s)]));
  }
  for (int s = 0; s < slots; ++s) {
    DiCandidateBatch::Slot& b = batch.slot[s];
    if (!b.hit) continue;
    const size_t i = row + size_t(s);
    b.rng = batch.streams.stream(s);
    const float* uniform = batch.uniforms.data() + s;  // number n at uniform[n * kLaneSlots]
    auto next = [&uniform] {
      const float x = *uniform;
      uniform += kLaneSlots;
      return x;
    };
    b.ctx = tiles ? tile_of(s).ctx : ShadingContext{g.position[i], g.shading_normal[i]};  // what the density is for
    if (!params.simd) {  // the scalar reference evaluates and samples everything on the two receivers
      batch.exact(g, domain, s);
      batch.target(domain, s);
    }
    for (int k = 0; k < K; ++k) {
      const size_t at = size_t(k) * kLaneSlots + size_t(s);
      if (k >= b.light_candidates) {  // not drawn: its numbers are skipped
        batch.p_light[at] = 0.0f;
        uniform += per_candidate * kLaneSlots;
        continue;
      }
      if (tiles) {  // the candidate is a tile entry, whole
        const DiLightCandidate& c = tile_of(s).entry(next());
        batch.u[at] = next();
        batch.p_light[at] = c.p_light;
        batch.light[at] = c.sample.light, batch.uv[at] = c.sample.uv;
        if (c.p_light > 0.0f && c.sample.light < view.lights.triangle_count())
          batch.planes[size_t(k)].set(s, c.sample.point);
        continue;
      }
      // y before x: the numbers as the scalar vec2(rng.next_float(), rng.next_float()) took them (GCC
      // evaluates a constructor's arguments right to left), so images stay those of earlier versions.
      const float uy = next(), ux = next();
      batch.light_u[size_t(s * K + k)] = vec2(ux, uy);
      const float vy = next(), vx = next();
      batch.uv[at] = vec2(vx, vy);
      batch.u[at] = next();
    }
    if (!tiles) prefetch_lights(sampler, b.ctx, &batch.light_u[size_t(s * K)], b.light_candidates);
  }
  if (tiles) return;
  // The M_l lights of a pixel in one call (the light tree shares its upper levels between them).
  for (int s = 0; s < slots; ++s) {
    if (!batch.slot[s].hit) continue;
    SampledLight* chosen = &batch.chosen[size_t(s * K)];
    const int count = batch.slot[s].light_candidates;
    sample_lights(sampler, batch.slot[s].ctx, &batch.light_u[size_t(s * K)], chosen, count);
    for (int k = 0; k < count; ++k) view.lights.prefetch(chosen[k].index);
  }
  // Each candidate's light and density into the batch and its point straight into the lanes (a whole
  // ReuseSample assembled and copied per candidate stalled on store forwarding in the profile).
  for (int s = 0; s < slots; ++s) {
    if (!batch.slot[s].hit) continue;
    for (int k = 0; k < batch.slot[s].light_candidates; ++k) {
      const size_t at = size_t(k) * kLaneSlots + size_t(s);
      const SampledLight chosen = batch.chosen[size_t(s * K + k)];
      batch.p_light[at] = di_light_pdf(view.lights, chosen);
      if (batch.p_light[at] <= 0.0f) continue;
      batch.light[at] = chosen.index;
      if (chosen.index < view.lights.triangle_count())
        batch.planes[size_t(k)].set(s, view.lights.triangle_point(view.scene, chosen.index, batch.uv[at]));
    }
  }
}

// Area density with which BSDF sampling at the receiver reaches a light sample (0 for delta lights, and
// without BSDF candidates).
inline float di_bsdf_area_pdf(const ReuseReceiver& receiver, const SampleContribution& c, int bsdf_candidates) {
  if (bsdf_candidates == 0 || c.light.is_delta) return 0.0f;
  float d = c.light.distance;
  return receiver.bsdf.pdf(receiver.wo, c.light.wi) * std::abs(glm::dot(c.light.normal, c.light.wi)) / (d * d);
}

// Part 2, the scalar reference of evaluate_candidate_lanes: p_hat and BSDF area density of the active
// candidates of `slots` slots, one at a time through sample_contribution.
void evaluate_candidates_scalar(const DiParams& params, int slots, DiCandidateBatch& batch);

// Part 3 (per pixel): M_b BSDF directions sampled at the exact receiver (their rays are traced together
// next, in packets). With params.simd only their uniforms: the directions, values and densities come from the
// lanes (part 3b).
inline void draw_bsdf_candidates(const DiParams& params, int slot, DiCandidateBatch& batch) {
  DiCandidateBatch::Slot& b = batch.slot[slot];
  for (int k = 0; k < params.bsdf_candidates; ++k) {
    DiCandidateBatch::BsdfCandidate& c = batch.bsdf[size_t(k) * kLaneSlots + size_t(slot)];
    DirectionLanes* lanes = params.simd ? &batch.directions[size_t(k)] : nullptr;
    c.sample.pdf = 0.0f;
    if (lanes) lanes->active[slot] = lanes->x[slot] = lanes->y[slot] = lanes->z[slot] = 0.0f;
    if (!b.hit) continue;
    vec2 ub(b.rng.next_float(), b.rng.next_float());
    float lobe = b.rng.next_float();
    c.u = b.rng.next_float();
    // Drawn with probability params.bsdf_probability (the coin only below 1, so that the default keeps its
    // numbers): otherwise the candidate stays empty (pdf 0: no ray).
    if (params.bsdf_probability < 1.0f && !(b.rng.next_float() < params.bsdf_probability)) continue;
    if (lanes) {  // the direction is drawn in lanes (part 3b)
      BsdfUniformLanes& uniforms = batch.bsdf_uniforms[size_t(k)];
      uniforms.u[0][slot] = ub.x, uniforms.u[1][slot] = ub.y, uniforms.lobe[slot] = lobe;
      lanes->active[slot] = 1.0f;
      continue;
    }
    if (!b.receiver.bsdf.sample(b.receiver.wo, ub, lobe, c.sample) ||
        glm::dot(c.sample.wi, b.receiver.geometric_normal) <= 0.0f)
      c.sample.pdf = 0.0f;
  }
}

// Part 3b (params.simd): the BSDF candidates' directions at the exact receivers (their shading normal, alpha,
// lobe probability and wo: the same as the packed receivers', both seen from the G-buffer's position), kept
// where they leave the geometric surface, then their values and densities (Bsdf::eval and Bsdf::pdf), all in
// lanes; a direction of density 0 gets no ray, as Bsdf::sample refuses it.
inline void evaluate_bsdf_candidates(const GBuffer& g, const DiParams& params, int slots, DiCandidateBatch& batch) {
  const ReceiverLanes& r = batch.lanes;
  for (int k = 0; k < params.bsdf_candidates; ++k) {
    DirectionLanes& lanes = batch.directions[size_t(k)];
    sample_bsdf_lanes(r.exact, r.wox, r.woy, r.woz, batch.bsdf_uniforms[size_t(k)], slots, lanes);
    for (int s = 0; s < slots; ++s)
      if (lanes.active[s] != 0.0f &&
          !(glm::dot(vec3(lanes.x[s], lanes.y[s], lanes.z[s]), g.geometric_normal[batch.slot[s].pixel]) > 0.0f))
        lanes.active[s] = 0.0f;
    evaluate_bsdf_lanes(r.exact, r.wox, r.woy, r.woz, slots, false, lanes);
    for (int s = 0; s < slots; ++s) {
      if (lanes.active[s] == 0.0f) continue;
      BsdfSample& sample = batch.bsdf[size_t(k) * kLaneSlots + size_t(s)].sample;
      sample.wi = vec3(lanes.x[s], lanes.y[s], lanes.z[s]);
      sample.f = vec3(lanes.f[0][s], lanes.f[1][s], lanes.f[2][s]);
      sample.pdf = lanes.pdf[s] > 0.0f ? lanes.pdf[s] : 0.0f;
    }
  }
}

// Part 4: the BSDF candidates' rays of `slots` slots, 16 at a time (rtcIntersect16). Returns the rays traced.
uint64_t trace_bsdf_candidates(const SceneView& view, const GBuffer& g, const DiParams& params, int slots,
                               DiCandidateBatch& batch);

// Part 4b: the lights the BSDF candidates of `slots` slots hit, as samples (the point the hit's barycentrics place on
// the light), and with params.simd their targets and BSDF area densities evaluated in lanes (the light candidates'
// kernel, into bsdf_hits). Cost per hit: a light lookup and a point, ~100 flops in lanes.
void locate_bsdf_hits(const SceneView& view, const DiParams& params, int slots, DiCandidateBatch& batch);

// Part 5 (per pixel): the light candidates resampled with their evaluated targets, then the BSDF
// candidates with their hits, combined by the balance heuristic in area measure: each candidate x gets
// w = p_hat(x) / (M_l p_light(x) + M_b p_bsdf(x)) (Talbot et al. 2005; Bitterli et al. 2020, sec. 3).
// With params.bsdf_probability q < 1, a BSDF candidate is present with probability q: its slot samples x
// with the defective density q p_bsdf(x), so M_b counts q M_b (the balance heuristic over the slots' densities
// stays a partition of unity: unbiased), and so does the reservoir's confidence M.
// The light candidates' stream comes from `lanes` (resample_light_candidates_lanes, or null) unless the
// pixel drew a punctual light, whose target the lanes do not have. Light no light technique can sample
// (the environment, emitters below the light list's threshold) reaches the pixel only through the BSDF
// candidates: their plain estimate of it goes to `unsampled`. With candidate_visibility, one shadow ray to
// the kept sample. Writes `r` and `unsampled` whole (also where the pixel has no hit). Returns the rays traced.
template <LightSampler S>
uint64_t resample_candidates(const SceneView& view, const S& sampler, const GBuffer& g, const ReuseDomain& domain,
                             const DiParams& params, int slot, const StreamLanes* lanes, DiCandidateBatch& batch,
                             ReuseReservoir& r, vec3& unsampled) {
  r = ReuseReservoir{};
  unsampled = vec3(0.0f);
  DiCandidateBatch::Slot& b = batch.slot[slot];
  if (!b.hit) return 0;
  const float M_l = batch.M_l[slot], M_b = params.effective_bsdf_candidates();
  if (lanes && !batch.drew_punctual(view.lights, params.light_candidates, slot)) {
    r.w_sum = lanes->w_sum[slot];
    if (const int k = int(lanes->chosen[slot]); k >= 0) batch.candidate(view.lights, k, slot, r.y);
    r.p_hat_y = lanes->p_hat[slot];
  } else {
    for (int k = 0; k < params.light_candidates; ++k) {
      const size_t at = size_t(k) * kLaneSlots + size_t(slot);
      if (batch.p_light[at] <= 0.0f) continue;
      ReuseSample s;
      batch.candidate(view.lights, k, slot, s);
      float p_hat = batch.planes[size_t(k)].p_hat[slot], p_bsdf = batch.planes[size_t(k)].bsdf_area_pdf[slot];
      if (s.light >= view.lights.triangle_count()) {  // punctual: not in the lanes
        p_hat = sample_target(sample_contribution(batch.target(domain, slot), s));
        p_bsdf = 0.0f;
      }
      if (p_hat <= 0.0f) continue;
      r.update(s, p_hat / (M_l * batch.p_light[at] + M_b * p_bsdf), p_hat, batch.u[at]);
    }
  }
  for (int k = 0; k < params.bsdf_candidates; ++k) {
    const DiCandidateBatch::BsdfCandidate& candidate = batch.bsdf[size_t(k) * kLaneSlots + size_t(slot)];
    const BsdfSample& bs = candidate.sample;
    if (bs.pdf <= 0.0f) continue;
    const Hit& hit = candidate.hit;
    const int64_t light = candidate.light;
    if (light < 0) {
      vec3 L = !hit.valid() ? view.lights.environment()
               : view.scene.material_of(hit.instance).emissive()
                   ? surface_at(view.scene, hit.instance, hit.prim, hit.barycentric, -bs.wi).emission
                   : vec3(0.0f);
      unsampled += bs.f * (std::abs(glm::dot(bs.wi, g.shading_normal[b.pixel])) / bs.pdf) * L / M_b;
      continue;
    }
    const ReuseSample& s = candidate.light_sample;
    float p_hat, p_bsdf;
    if (params.simd && batch.bsdf_hits[size_t(k)].active[slot] > 0.0f) {  // evaluated by locate_bsdf_hits
      p_hat = batch.bsdf_hits[size_t(k)].p_hat[slot];
      p_bsdf = batch.bsdf_hits[size_t(k)].bsdf_area_pdf[slot];
    } else {
      const SampleContribution c = sample_contribution(batch.target(domain, slot), s);
      p_hat = sample_target(c);
      p_bsdf = di_bsdf_area_pdf(batch.exact(g, domain, slot), c, params.bsdf_candidates);
    }
    if (p_hat <= 0.0f) continue;
    float p_light = sampler.pmf(b.ctx, uint32_t(light)) * di_area_pdf(view.lights, uint32_t(light));
    r.update(s, p_hat / (M_l * p_light + M_b * p_bsdf), p_hat, candidate.u);
  }
  r.M = M_l + M_b;
  r.finalize();
  if (!params.candidate_visibility || r.W <= 0.0f) return 0;
  const ReuseReceiver& receiver = batch.exact(g, domain, slot);
  if (view.tracer.occluded(shadow_ray(view.tracer, receiver.position, receiver.geometric_normal,
                                      sample_contribution(receiver, r.y).light)))
    r.W = 0.0f;
  return 1;
}

// Part 4c (with `bsdf_rays`, per row): each slot's first BSDF candidate (direction, density, hit) into its pixel's
// BsdfRay, for ReSTIR GI's first ray; pdf 0 where the slot traced none.
inline void keep_bsdf_rays(int slots, size_t row, const DiCandidateBatch& batch, std::vector<BsdfRay>& bsdf_rays) {
  for (int s = 0; s < slots; ++s) {
    const DiCandidateBatch::BsdfCandidate& c = batch.bsdf[size_t(s)];
    bsdf_rays[row + size_t(s)] = BsdfRay{c.sample.wi, c.sample.pdf, c.hit};
  }
}

// Stage "di_candidates": reads the G-buffer (BSDF sampling and densities: the exact surface) and the
// packed surfaces (targets), writes one reservoir per pixel and the light only BSDF candidates reach
// (`unsampled`; zero without them), and with `bsdf_rays` every pixel's first BSDF candidate (which needs one BSDF
// candidate drawn with certainty: bsdf_candidates >= 1, bsdf_probability 1). Cost per pixel: M_l light samples (or
// tile reads, with `tiles`) and target evaluations (in lanes with params.simd), M_b BSDF samples, evaluations (in
// lanes with params.simd) and rays (in packets), plus one shadow ray with candidate_visibility.
template <LightSampler S>
void di_initial_candidates(const SceneView& view, const S& sampler, const GBuffer& g, const ReuseDomain& domain,
                           const DiParams& params, int frame, std::vector<ReuseReservoir>& out,
                           std::vector<vec3>& unsampled, RayCounter& rays, const LightTiles* tiles = nullptr,
                           const std::vector<int32_t>* history = nullptr, std::vector<BsdfRay>* bsdf_rays = nullptr) {
  CHECK(!bsdf_rays || (params.bsdf_candidates >= 1 && params.bsdf_probability == 1.0f));
  // Sized only: resample_candidates writes every pixel (in parallel, where a fill here ran on one thread).
  out.resize(g.size());
  unsampled.resize(g.size());
  if (bsdf_rays) bsdf_rays->resize(g.size());
  for_each_tile(g.width, g.height, [&](const Tile& tile) {
    thread_local DiCandidateBatch batch;
    batch.resize(params.light_candidates, params.bsdf_candidates);
    const int slots = tile.x1 - tile.x0;
    uint64_t traced = 0;
    for (int y = tile.y0; y < tile.y1; ++y) {
      const size_t row = size_t(y) * size_t(g.width) + size_t(tile.x0);
      draw_light_candidates(view, sampler, g, domain, params, frame, row, tile.x0, y, slots, tiles,
                            history ? history->data() + row : nullptr, batch);
      int row_candidates = 0;  // the planes that hold a candidate of some slot
      for (int s = 0; s < slots; ++s) row_candidates = std::max(row_candidates, batch.slot[s].light_candidates);
      if (params.simd) {
        build_receiver_lanes(batch.surfaces, domain.eye, slots, batch.lanes);
        build_exact_receiver_lanes(batch.exact_surfaces, domain.eye, slots, batch.lanes.exact);
        evaluate_candidate_lanes(batch.lanes, batch.planes.data(), row_candidates, slots, params.bsdf_candidates > 0);
      } else {
        evaluate_candidates_scalar(params, slots, batch);
      }
      for (int s = 0; s < slots; ++s) draw_bsdf_candidates(params, s, batch);
      if (params.simd) evaluate_bsdf_candidates(g, params, slots, batch);
      traced += trace_bsdf_candidates(view, g, params, slots, batch);
      if (bsdf_rays) keep_bsdf_rays(slots, row, batch, *bsdf_rays);
      locate_bsdf_hits(view, params, slots, batch);
      thread_local StreamLanes streams;
      if (params.simd)
        resample_light_candidates_lanes(batch.planes.data(), batch.p_light.data(), batch.u.data(), row_candidates,
                                        batch.M_l, params.effective_bsdf_candidates(), slots, streams);
      for (int s = 0; s < slots; ++s)
        traced += resample_candidates(view, sampler, g, domain, params, s, params.simd ? &streams : nullptr, batch,
                                      out[row + s], unsampled[row + s]);
    }
    rays.add(traced);
  });
}

}  // namespace candela
