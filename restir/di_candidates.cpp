#include "restir/di_candidates.h"

namespace candela {

void DiCandidateBatch::resize(int light_candidates, int bsdf_candidates) {
  const size_t k = size_t(std::max(light_candidates, 0));
  planes.resize(k);
  sample.resize(k * kLaneSlots);
  p_light.resize(k * kLaneSlots);
  u.resize(k * kLaneSlots);
  bsdf.resize(size_t(std::max(bsdf_candidates, 0)) * kLaneSlots);
}

uint64_t trace_bsdf_candidates(const SceneView& view, const DiParams& params, int slots, DiCandidateBatch& batch) {
  RayPacket16 packet;
  DiCandidateBatch::BsdfCandidate* lane[16];
  int lanes = 0;
  uint64_t traced = 0;
  auto flush = [&] {
    for (int k = lanes; k < 16; ++k) packet.set_inactive(k);
    view.tracer.intersect16(packet, false);
    for (int k = 0; k < lanes; ++k) lane[k]->hit = view.tracer.packet_hit(packet, k);
    traced += uint64_t(lanes);
    lanes = 0;
  };
  for (int k = 0; k < params.bsdf_candidates; ++k)
    for (int s = 0; s < slots; ++s) {
      DiCandidateBatch::BsdfCandidate& c = batch.bsdf[size_t(k) * kLaneSlots + size_t(s)];
      if (c.sample.pdf <= 0.0f) continue;
      const DiReceiver& r = batch.slot[s].receiver;
      packet.set(lanes, view.tracer.spawn_ray(r.position, r.geometric_normal, c.sample.wi));
      lane[lanes++] = &c;
      if (lanes == 16) flush();
    }
  if (lanes > 0) flush();
  return traced;
}

void evaluate_candidates_scalar(const DiParams& params, int slots, DiCandidateBatch& batch) {
  for (int k = 0; k < params.light_candidates; ++k) {
    CandidateLanes& plane = batch.planes[size_t(k)];
    for (int s = 0; s < slots; ++s) {
      if (plane.active[s] == 0.0f) continue;
      const DiCandidateBatch::Slot& b = batch.slot[s];
      DiContribution c = di_contribution(b.target, batch.sample[size_t(k) * kLaneSlots + size_t(s)]);
      plane.p_hat[s] = di_target(c);
      plane.bsdf_area_pdf[s] = di_bsdf_area_pdf(b.receiver, c, params.bsdf_candidates);
    }
  }
}

}  // namespace candela
