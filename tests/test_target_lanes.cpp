// ReSTIR DI's light candidates in SIMD lanes (restir/target_lanes.h) against the scalar reference
// (di_contribution, Bsdf::eval, Bsdf::pdf): the kernel repeats the scalar operations in the same order
// without fused multiply-adds, so the bound is exact equality (0 ulp), for p_hat and the BSDF's area
// density alike (where p_hat > 0, the only place it is read); a kernel that fused a multiply-add or reordered a sum fails here.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "apps/renderer.h"
#include "engine/builtin_scenes.h"
#include "engine/simd_targets.h"
#include "restir/di_candidates.h"
#include "tests/render_helpers.h"
#include "tests/test_util.h"

namespace candela {
namespace {

using testing::same_bits;

vec3 random_unit(Rng& rng) {
  vec3 v;
  do v = vec3(rng.next_float(), rng.next_float(), rng.next_float()) * 2.0f - 1.0f;
  while (glm::dot(v, v) > 1.0f || glm::dot(v, v) < 1e-4f);
  return glm::normalize(v);
}

// Random receivers (any material: metallic, rough or smooth, specular factor, coloured F0; eye on either
// side) against random triangle-light points (one- and two-sided, black, behind, at the receiver itself),
// evaluated by both paths on the same batch.
TEST(TargetLanes, KernelGivesTheScalarBitsOnRandomInputs) {
  const Scene scene = make_cornell_scene();
  const LightList lights(scene);
  ASSERT_GT(lights.triangle_count(), 0u);
  constexpr int kCandidates = 8;
  auto lanes = std::make_unique<DiCandidateBatch>(), scalar = std::make_unique<DiCandidateBatch>();
  lanes->resize(kCandidates, 0);
  Rng rng(12345, 1);
  int compared = 0, positive = 0, batches = 0;
  std::string targets;
  for (; batches < 200; ++batches) {
    for (int s = 0; s < kLaneSlots; ++s) {
      DiCandidateBatch::Slot& b = lanes->slot[s];
      b.hit = true;
      const vec3 p = (vec3(rng.next_float(), rng.next_float(), rng.next_float()) - 0.5f) * 4.0f;
      const vec3 n = random_unit(rng), ng = glm::normalize(n + 0.3f * random_unit(rng));
      vec3 wo = random_unit(rng);
      if (rng.next_float() < 0.8f && glm::dot(wo, n) < 0.0f) wo = -wo;  // mostly lit from the eye's side
      const vec3 base(rng.next_float(), rng.next_float(), rng.next_float());
      const float metallic = rng.next_float() < 0.3f ? 1.0f : rng.next_float();
      const float roughness = rng.next_float() < 0.2f ? 0.0f : rng.next_float();
      const Bsdf bsdf(n, base, metallic, roughness, rng.next_float(), vec3(0.02f + 0.1f * rng.next_float()));
      const Bsdf exact(glm::normalize(n + 0.01f * random_unit(rng)), base, metallic, roughness);
      b.target = {p, ng, n, wo, bsdf, &lights};
      b.receiver = {p, ng, exact.normal(), wo, exact, &lights};
      lanes->lanes.set(s, p, ng, wo, bsdf.wo_terms(wo), exact.wo_terms(wo));
      for (int k = 0; k < kCandidates; ++k) {
        const size_t at = size_t(k) * kLaneSlots + size_t(s);
        LightPoint point{p + random_unit(rng) * (0.01f + 3.0f * rng.next_float()), random_unit(rng),
                         vec3(rng.next_float(), rng.next_float(), rng.next_float()) * 10.0f, rng.next_float() < 0.3f};
        if (k == 0 && s % 16 == 0) point.position = p;           // at the receiver: no direction
        if (k == 1 && s % 16 == 1) point.radiance = vec3(0.0f);  // black
        lanes->sample[at] = DiSample{0, vec2(0.0f), point, 0};
        lanes->p_light[at] = 1.0f;
        lanes->planes[size_t(k)].set(s, point);
      }
    }
    *scalar = *lanes;
    DiParams params;
    params.light_candidates = kCandidates;
    params.bsdf_candidates = 1;
    evaluate_candidates_scalar(params, kLaneSlots, *scalar);
    for_each_simd_target([&](const char* target) {
      if (batches == 0) targets += std::string(targets.empty() ? "" : ", ") + target;
      evaluate_candidate_lanes(lanes->lanes, lanes->planes.data(), kCandidates, kLaneSlots, true);
      for (int k = 0; k < kCandidates; ++k)
        for (int s = 0; s < kLaneSlots; ++s) {
          const CandidateLanes &a = lanes->planes[size_t(k)], &b = scalar->planes[size_t(k)];
          ++compared;
          positive += b.p_hat[s] > 0.0f;
          EXPECT_TRUE(same_bits(a.p_hat[s], b.p_hat[s])) << target << ", p_hat, batch " << batches << " candidate " << k
                                                         << " slot " << s << ": lanes " << a.p_hat[s] << ", scalar " << b.p_hat[s];
          if (b.p_hat[s] <= 0.0f) continue;  // the density is read only where the target is positive (scalar:
                                             // NaN for a point at the receiver; lanes: 0)
          EXPECT_TRUE(same_bits(a.bsdf_area_pdf[s], b.bsdf_area_pdf[s]))
              << target << ", BSDF area density, batch " << batches << " candidate " << k << " slot " << s << ": lanes "
              << a.bsdf_area_pdf[s] << ", scalar " << b.bsdf_area_pdf[s];
        }
    });
    if (::testing::Test::HasFailure()) break;
  }
  std::printf("  %d candidate evaluations compared (%d with p_hat > 0) on %s\n", compared, positive, targets.c_str());
  EXPECT_GT(positive, compared / 10) << "too few lit candidates to test anything";
}

// The whole stage on rendered frames: the reservoirs of a restir-di frame are the same bits with the
// kernel as with the scalar path, on manylights, the Cornell box and city, after 3 frames of reuse.
TEST(TargetLanes, ReservoirsEqualTheScalarPath) {
  for (const char* name : {"manylights", "cornell", "city"}) {
    std::vector<DiReservoir> result[2];
    for (int simd = 0; simd < 2; ++simd) {
      RenderSettings settings;
      settings.width = 96;
      settings.height = 64;
      settings.method = Method::RestirDi;
      settings.di.simd = simd == 1;
      Scene scene = make_builtin_scene(name);
      const CameraDesc camera = scene.default_camera();
      Renderer renderer(std::move(scene), settings);
      for (int frame = 0; frame < 3; ++frame) testing::render_checked(renderer, frame, 0.0f, camera);
      result[simd] = renderer.di_reservoirs();
    }
    ASSERT_EQ(result[0].size(), result[1].size());
    int with_sample = 0;
    for (size_t i = 0; i < result[0].size(); ++i) {
      const DiReservoir &a = result[0][i], &b = result[1][i];
      with_sample += a.W > 0.0f;
      ASSERT_TRUE(a.y.light == b.y.light && a.y.uv == b.y.uv && same_bits(a.W, b.W) && same_bits(a.p_hat_y, b.p_hat_y) &&
                  same_bits(a.M, b.M))
          << name << " pixel " << i << ": W " << a.W << " / " << b.W << ", light " << a.y.light << " / " << b.y.light;
    }
    EXPECT_GT(with_sample, int(result[0].size()) / 4) << name;
  }
}

}  // namespace
}  // namespace candela
