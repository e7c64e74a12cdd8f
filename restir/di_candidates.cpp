#include "restir/di_candidates.h"

namespace candela {

void DiCandidateBatch::resize(int light_candidates, int bsdf_candidates) {
  const size_t k = size_t(std::max(light_candidates, 0));
  planes.resize(k);
  light.resize(k * kLaneSlots);
  uv.resize(k * kLaneSlots);
  p_light.resize(k * kLaneSlots);
  u.resize(k * kLaneSlots);
  light_u.resize(k * kLaneSlots);
  chosen.resize(k * kLaneSlots);
  bsdf.resize(size_t(std::max(bsdf_candidates, 0)) * kLaneSlots);
  directions.resize(size_t(std::max(bsdf_candidates, 0)));
  bsdf_uniforms.resize(size_t(std::max(bsdf_candidates, 0)));
  bsdf_hits.resize(size_t(std::max(bsdf_candidates, 0)));
}

uint64_t trace_bsdf_candidates(const SceneView& view, const GBuffer& g, const DiParams& params, int slots,
                               DiCandidateBatch& batch) {
  using Candidate = DiCandidateBatch::BsdfCandidate;
  auto answer = [&](Candidate* c, const RayPacket16& packet, int lane) {
    c->hit = view.tracer.packet_hit(packet, lane);
  };
  auto queue = ray_queue16<Candidate*>(view.tracer, RayQuery::Intersect, answer);
  for (int k = 0; k < params.bsdf_candidates; ++k)
    for (int s = 0; s < slots; ++s) {
      Candidate& c = batch.bsdf[size_t(k) * kLaneSlots + size_t(s)];
      if (c.sample.pdf <= 0.0f) continue;
      const size_t i = batch.slot[s].pixel;  // the exact receiver's point and normal
      queue.add(view.tracer.spawn_ray(g.position[i], g.geometric_normal[i], c.sample.wi), &c);
    }
  queue.finish();
  return queue.traced();
}

void locate_bsdf_hits(const SceneView& view, const DiParams& params, int slots, DiCandidateBatch& batch) {
  for (int k = 0; k < params.bsdf_candidates; ++k) {
    CandidateLanes* plane = params.simd ? &batch.bsdf_hits[size_t(k)] : nullptr;
    for (int s = 0; s < slots; ++s) {
      DiCandidateBatch::BsdfCandidate& c = batch.bsdf[size_t(k) * kLaneSlots + size_t(s)];
      const Hit& hit = c.hit;
      c.light = c.sample.pdf > 0.0f && hit.valid() ? view.lights.light_index(hit.instance, hit.prim) : -1;
      if (c.light >= 0) di_sample_at(view.scene, view.lights, uint32_t(c.light), hit.barycentric, c.light_sample);
      if (!plane) continue;
      if (c.light >= 0 && c.light_sample.light < view.lights.triangle_count())
        plane->set(s, c.light_sample.point);
      else
        plane->clear(s);
    }
    if (plane) evaluate_candidate_lanes(batch.lanes, plane, 1, slots, true);
  }
}

void evaluate_candidates_scalar(const DiParams& params, int slots, DiCandidateBatch& batch) {
  for (int k = 0; k < params.light_candidates; ++k) {
    CandidateLanes& plane = batch.planes[size_t(k)];
    for (int s = 0; s < slots; ++s) {
      if (plane.active[s] == 0.0f) continue;
      const DiCandidateBatch::Slot& b = batch.slot[s];
      ReuseSample sample;
      batch.candidate(*b.target.lights, k, s, sample);
      SampleContribution c = sample_contribution(b.target, sample);
      plane.p_hat[s] = sample_target(c);
      plane.bsdf_area_pdf[s] = di_bsdf_area_pdf(b.receiver, c, params.bsdf_candidates);
    }
  }
}

}  // namespace candela
