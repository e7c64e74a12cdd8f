#include "restir/sample.h"

namespace candela {

SampleContribution sample_contribution(const ReuseReceiver& r, const ReuseSample& s) {
  SampleContribution c;
  c.light = light_sample_of(*r.lights, r.position, s);
  const LightSample& ls = c.light;
  if (max_component(ls.radiance) <= 0.0f || glm::dot(ls.wi, r.geometric_normal) <= 0.0f) return c;
  vec3 f = r.bsdf.eval(r.wo, ls.wi) * std::abs(glm::dot(ls.wi, r.shading_normal));
  if (ls.is_delta) {
    c.value = f * ls.radiance;
    return c;
  }
  // Solid angle to area: dw = |cos_l| / d^2 dA.
  float geometry = std::abs(glm::dot(ls.normal, ls.wi)) / (ls.distance * ls.distance);
  c.value = f * ls.radiance * geometry;
  return c;
}

}  // namespace candela
