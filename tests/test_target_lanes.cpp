// ReSTIR's SIMD lanes (restir/target_lanes.h, receiver_lanes.h, reuse_targets.h, neighbour_lanes.h, and the BSDF
// directions of engine/bsdf_lanes.h) against the scalar
// reference (sample_contribution, Bsdf::eval, Bsdf::pdf, Tracer::spawn_ray_to): the kernel repeats the scalar
// operations in the same order without fused multiply-adds, so the bound is exact equality (0 ulp), for p_hat and the
// BSDF's area density alike (where p_hat > 0, the only place it is read); a kernel that fused a multiply-add or
// reordered a sum fails here.
#include <gtest/gtest.h>

#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "apps/renderer.h"
#include "engine/builtin_scenes.h"
#include "engine/simd_targets.h"
#include "restir/di_candidates.h"
#include "restir/gi.h"
#include "restir/neighbour_lanes.h"
#include "restir/receiver_lanes.h"
#include "samplers/simple_samplers.h"
#include "tests/render_helpers.h"
#include "tests/test_util.h"
#include "tests/settings_builder.h"

namespace candela {
namespace {

using testing::same_bits;

vec3 random_unit(Rng& rng) {
  vec3 v;
  do v = vec3(rng.next_float(), rng.next_float(), rng.next_float()) * 2.0f - 1.0f;
  while (glm::dot(v, v) > 1.0f || glm::dot(v, v) < 1e-4f);
  return glm::normalize(v);
}

using Terms = std::vector<std::pair<std::string, std::pair<float, float>>>;

// Expects each (lanes, scalar) pair of `terms`, and the albedo table rows, to hold the same bits. Returns how
// many terms it compared.
int expect_same_bits(const Terms& terms, int32_t row_lanes, int32_t row_scalar, const char* target, int batch, int s) {
  for (const auto& [name, values] : terms)
    EXPECT_TRUE(same_bits(values.first, values.second))
        << target << ", " << name << ", batch " << batch << " slot " << s << ": lanes " << values.first << ", scalar "
        << values.second;
  EXPECT_EQ(row_lanes, row_scalar) << target << ", albedo row, batch " << batch << " slot " << s;
  return int(terms.size());
}

// Every term of slot s of two BSDF plane sets, named: (lanes, scalar) pairs for same_bits. with_sampling adds the
// two terms only BSDF sampling reads (G1 and the lobe probability), which the packed receivers leave 0.
Terms bsdf_terms(const BsdfLanes& a, const BsdfLanes& b, int s, bool with_sampling) {
  Terms terms = {{"nx", {a.nx[s], b.nx[s]}},          {"ny", {a.ny[s], b.ny[s]}},
                 {"nz", {a.nz[s], b.nz[s]}},          {"cos_o", {a.cos_o[s], b.cos_o[s]}},
                 {"alpha", {a.alpha[s], b.alpha[s]}}, {"s_o", {a.s_o[s], b.s_o[s]}},
                 {"f90", {a.f90[s], b.f90[s]}},       {"ms_o", {a.ms_o[s], b.ms_o[s]}},
                 {"d_f90", {a.d_f90[s], b.d_f90[s]}}, {"albedo_weight", {a.albedo_weight[s], b.albedo_weight[s]}}};
  const char* rgb = "rgb";
  for (int c = 0; c < 3; ++c) {
    const std::string channel = std::string(".") + rgb[c];
    terms.push_back({"f0" + channel, {a.f0[c][s], b.f0[c][s]}});
    terms.push_back({"ms" + channel, {a.ms[c][s], b.ms[c][s]}});
    terms.push_back({"base_o" + channel, {a.base_o[c][s], b.base_o[c][s]}});
    terms.push_back({"d_f0" + channel, {a.d_f0[c][s], b.d_f0[c][s]}});
    terms.push_back({"d_ms" + channel, {a.d_ms[c][s], b.d_ms[c][s]}});
  }
  if (with_sampling) {
    terms.push_back({"g1_o", {a.g1_o[s], b.g1_o[s]}});
    terms.push_back({"p_specular", {a.p_specular[s], b.p_specular[s]}});
  }
  return terms;
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
    // Odd batches give every slot one roughness: the albedo lookups read their table rows from registers then
    // (albedo_corners), else they gather.
    const float batch_roughness = rng.next_float();
    for (int s = 0; s < kLaneSlots; ++s) {
      DiCandidateBatch::Slot& b = lanes->slot[s];
      b.hit = true;
      const vec3 p = (vec3(rng.next_float(), rng.next_float(), rng.next_float()) - 0.5f) * 4.0f;
      const vec3 n = random_unit(rng), ng = glm::normalize(n + 0.3f * random_unit(rng));
      vec3 wo = random_unit(rng);
      if (rng.next_float() < 0.8f && glm::dot(wo, n) < 0.0f) wo = -wo;  // mostly lit from the eye's side
      const vec3 base(rng.next_float(), rng.next_float(), rng.next_float());
      const float metallic = rng.next_float() < 0.3f ? 1.0f : rng.next_float();
      const float roughness = batches % 2 ? batch_roughness : rng.next_float() < 0.2f ? 0.0f : rng.next_float();
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
        lanes->light[at] = 0, lanes->uv[at] = vec2(0.0f);
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
          EXPECT_TRUE(same_bits(a.p_hat[s], b.p_hat[s]))
              << target << ", p_hat, batch " << batches << " candidate " << k << " slot " << s << ": lanes "
              << a.p_hat[s] << ", scalar " << b.p_hat[s];
          if (b.p_hat[s] <= 0.0f)
            continue;  // the density is read only where the target is positive (scalar:
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

// Receivers built in lanes from random packed surfaces (normals all over the octahedron, every material
// byte including the extremes, the eye on either side) against reuse_receiver and Bsdf::wo_terms: every plane
// the target evaluation reads holds the scalar bits (bound: 0 ulp), and so do packed_points_lanes's points and
// normals (the shading's shadow rays start there).
TEST(TargetLanes, ReceiversGiveTheScalarBitsOnRandomSurfaces) {
  const Scene scene = make_cornell_scene();
  const LightList lights(scene);
  Rng rng(777, 3);
  auto byte = [&] {
    const float u = rng.next_float();
    return u < 0.1f ? 0u : u < 0.2f ? 255u : uint32_t(rng.next_float() * 256.0f) & 255u;
  };
  std::vector<PackedSurface> surfaces(kLaneSlots);
  auto lanes = std::make_unique<ReceiverLanes>(), scalar = std::make_unique<ReceiverLanes>();
  auto points = std::make_unique<ReceiverLanes>();  // packed_points_lanes's
  auto packed = std::make_unique<SurfaceLanes>();
  int compared = 0, lit = 0;
  std::string targets;
  for (int batch = 0; batch < 100; ++batch) {
    const vec3 eye = (vec3(rng.next_float(), rng.next_float(), rng.next_float()) - 0.5f) * 6.0f;
    const uint32_t batch_roughness = byte();  // every slot's in odd batches (albedo_corners' in-register path)
    for (int s = 0; s < kLaneSlots; ++s) {
      PackedSurface& surface = surfaces[size_t(s)];
      surface.position = (vec3(rng.next_float(), rng.next_float(), rng.next_float()) - 0.5f) * 4.0f;
      surface.depth = 1.0f;
      surface.shading_normal = oct_encode(random_unit(rng));
      surface.geometric_normal = oct_encode(random_unit(rng));
      surface.albedo = byte() | byte() << 8 | byte() << 16;
      surface.material = byte() | byte() << 8 | byte() << 16 | byte() << 24;
      if (batch % 2) surface.material = (surface.material & ~0xffu) | batch_roughness;
      packed->set(s, surface);
    }
    const ReuseDomain domain{surfaces, kLaneSlots, 1, eye, lights};
    for (int s = 0; s < kLaneSlots; ++s) {
      const ReuseReceiver r = reuse_receiver(domain, size_t(s));
      const BsdfWoTerms t = r.bsdf.wo_terms(r.wo);
      scalar->set(s, r.position, r.geometric_normal, r.wo, t, t);
      lit += t.cos_o > 0.0f;
    }
    for_each_simd_target([&](const char* target) {
      if (batch == 0) targets += std::string(targets.empty() ? "" : ", ") + target;
      build_receiver_lanes(*packed, eye, kLaneSlots, *lanes);
      packed_points_lanes(*packed, kLaneSlots, *points);
      for (int s = 0; s < kLaneSlots; ++s) {
        const BsdfLanes &a = lanes->target, &b = scalar->target;
        Terms terms = {{"px", {lanes->px[s], scalar->px[s]}},         {"py", {lanes->py[s], scalar->py[s]}},
                       {"pz", {lanes->pz[s], scalar->pz[s]}},         {"gx", {lanes->gx[s], scalar->gx[s]}},
                       {"gy", {lanes->gy[s], scalar->gy[s]}},         {"gz", {lanes->gz[s], scalar->gz[s]}},
                       {"wox", {lanes->wox[s], scalar->wox[s]}},      {"woy", {lanes->woy[s], scalar->woy[s]}},
                       {"woz", {lanes->woz[s], scalar->woz[s]}},      {"points px", {points->px[s], scalar->px[s]}},
                       {"points py", {points->py[s], scalar->py[s]}}, {"points pz", {points->pz[s], scalar->pz[s]}},
                       {"points gx", {points->gx[s], scalar->gx[s]}}, {"points gy", {points->gy[s], scalar->gy[s]}},
                       {"points gz", {points->gz[s], scalar->gz[s]}}};
        for (auto& term : bsdf_terms(a, b, s, false)) terms.push_back(term);
        compared += expect_same_bits(terms, a.albedo_row[s], b.albedo_row[s], target, batch, s);
      }
    });
    if (::testing::Test::HasFailure()) break;
  }
  std::printf("  %d receiver terms compared (%d receivers lit from the eye's side) on %s\n", compared, lit,
              targets.c_str());
  EXPECT_GT(lit, 100 * kLaneSlots / 4) << "too few receivers facing the eye to test the wo terms";
}

// build_receiver_lanes with `wanted` (reuse's planes of inputs few slots have): a vector holding a wanted slot is
// built as without it (the wanted slot's planes hold the full build's bits), and the vectors of no wanted slot keep
// what they held. Slot 37 alone is wanted: slots 0-31 and 48-63 share no vector with it at 4, 8 or 16 lanes.
TEST(TargetLanes, ReceiversSkipTheVectorsNobodyWants) {
  Rng rng(778, 3);
  auto packed = std::make_unique<SurfaceLanes>();
  for (int s = 0; s < kLaneSlots; ++s) {
    PackedSurface surface;
    surface.position = (vec3(rng.next_float(), rng.next_float(), rng.next_float()) - 0.5f) * 4.0f;
    surface.depth = 1.0f;
    surface.shading_normal = oct_encode(random_unit(rng));
    surface.geometric_normal = oct_encode(random_unit(rng));
    surface.albedo = 0x80c0e0u;
    surface.material = uint32_t(rng.next_u32());
    packed->set(s, surface);
  }
  const vec3 eye(0.5f, 3.0f, -2.0f);
  alignas(64) float wanted[kLaneSlots] = {};
  wanted[37] = 1.0f;
  constexpr float kUntouched = -12345.0f;
  auto full = std::make_unique<ReceiverLanes>(), some = std::make_unique<ReceiverLanes>();
  for_each_simd_target([&](const char* target) {
    build_receiver_lanes(*packed, eye, kLaneSlots, *full);
    std::fill(std::begin(some->px), std::end(some->px), kUntouched);
    std::fill(std::begin(some->target.cos_o), std::end(some->target.cos_o), kUntouched);
    build_receiver_lanes(*packed, eye, kLaneSlots, *some, wanted);
    EXPECT_TRUE(same_bits(some->px[37], full->px[37]) && same_bits(some->target.cos_o[37], full->target.cos_o[37]))
        << target;
    for (int s = 0; s < kLaneSlots; ++s) {
      if (s < 32 || s >= 48) {
        EXPECT_TRUE(some->px[s] == kUntouched && some->target.cos_o[s] == kUntouched) << target << " slot " << s;
      }
    }
  });
}

// The exact receivers' BSDF terms built in lanes from G-buffer surfaces (random positions, normals, colours,
// roughness, metallic and specular factors with their extremes, coloured dielectric F0s, the eye on either
// side) against exact_receiver and Bsdf::wo_terms, including the two terms only BSDF sampling reads (G1 and
// the lobe probability), and the whole receivers of the final shading (build_exact_receivers) with their
// contributions at random light points (evaluate_exact_contribution_lanes against sample_contribution): every
// plane and value holds the scalar bits (bound: 0 ulp).
TEST(TargetLanes, ExactReceiversGiveTheScalarBitsOnRandomSurfaces) {
  const Scene scene = make_cornell_scene();
  const LightList lights(scene);
  Rng rng(778, 5);
  auto factor = [&] {
    const float u = rng.next_float();
    return u < 0.1f ? 0.0f : u < 0.2f ? 1.0f : rng.next_float();
  };
  GBuffer g;
  g.resize(kLaneSlots, 1);
  auto lanes = std::make_unique<ReceiverLanes>(), scalar = std::make_unique<ReceiverLanes>();
  auto shading = std::make_unique<ReceiverLanes>();
  auto surfaces = std::make_unique<ExactSurfaceLanes>();
  auto points = std::make_unique<CandidateLanes>();
  auto contributions = std::make_unique<ContributionLanes>();
  std::vector<ReuseReceiver> receivers(kLaneSlots);
  int compared = 0, lit = 0, contributing = 0;
  for (int batch = 0; batch < 100; ++batch) {
    const vec3 eye = (vec3(rng.next_float(), rng.next_float(), rng.next_float()) - 0.5f) * 6.0f;
    const float batch_roughness = factor();  // every slot's in odd batches (albedo_corners' in-register path)
    for (int s = 0; s < kLaneSlots; ++s) {
      g.position[size_t(s)] = (vec3(rng.next_float(), rng.next_float(), rng.next_float()) - 0.5f) * 4.0f;
      g.shading_normal[size_t(s)] = random_unit(rng);
      g.geometric_normal[size_t(s)] = random_unit(rng);
      g.albedo[size_t(s)] = vec3(factor(), factor(), factor());
      g.material[size_t(s)] = vec3(factor(), factor(), factor());
      if (batch % 2) g.material[size_t(s)].x = batch_roughness;  // x: the roughness
      g.specular_f0[size_t(s)] = vec3(factor(), factor(), factor());
      g.instance[size_t(s)] = 0;
      const ReuseReceiver& r = receivers[size_t(s)] = exact_receiver(g, eye, lights, size_t(s));
      scalar->exact.set(s, r.bsdf.wo_terms(r.wo));
      lit += scalar->exact.cos_o[s] > 0.0f;
      // A light point mostly in front of the surface (one- or two-sided); some inactive.
      const vec3 ng = g.geometric_normal[size_t(s)];
      LightPoint point{g.position[size_t(s)] + (random_unit(rng) + ng) * (0.1f + 2.0f * rng.next_float()),
                       random_unit(rng), vec3(rng.next_float(), rng.next_float(), rng.next_float()) * 5.0f,
                       rng.next_float() < 0.5f};
      if (rng.next_float() < 0.1f)
        points->clear(s);
      else
        points->set(s, point);
    }
    surfaces->set_row(g, 0, kLaneSlots);
    for_each_simd_target([&](const char* target) {
      build_exact_receiver_lanes(*surfaces, eye, kLaneSlots, lanes->exact);
      build_exact_receivers(*surfaces, eye, kLaneSlots, *shading);
      evaluate_exact_contribution_lanes(*shading, *points, kLaneSlots, *contributions);
      const BsdfLanes &a = lanes->exact, &b = scalar->exact;
      for (int s = 0; s < kLaneSlots; ++s) {
        compared += expect_same_bits(bsdf_terms(a, b, s, true), a.albedo_row[s], b.albedo_row[s], target, batch, s);
        const ReuseReceiver& r = receivers[size_t(s)];
        Terms terms = bsdf_terms(shading->exact, b, s, true);
        const vec3 value = points->active[s] > 0.0f
                               ? sample_contribution(r, ReuseSample{0, vec2(0.0f), points->point(s), 0}).value
                               : vec3(0.0f);
        contributing += max_component(value) > 0.0f;
        const float* position[3] = {shading->px, shading->py, shading->pz};
        const float* normal[3] = {shading->gx, shading->gy, shading->gz};
        const float* wo[3] = {shading->wox, shading->woy, shading->woz};
        for (int c = 0; c < 3; ++c) {
          terms.push_back({"position", {position[c][s], r.position[c]}});
          terms.push_back({"geometric normal", {normal[c][s], r.geometric_normal[c]}});
          terms.push_back({"wo", {wo[c][s], r.wo[c]}});
          terms.push_back({"contribution", {contributions->value[c][s], value[c]}});
        }
        compared += expect_same_bits(terms, shading->exact.albedo_row[s], b.albedo_row[s], target, batch, s);
      }
    });
    if (::testing::Test::HasFailure()) break;
  }
  std::printf("  %d exact receiver terms compared (%d receivers lit from the eye's side, %d contributions > 0)\n",
              compared, lit, contributing);
  EXPECT_GT(lit, 100 * kLaneSlots / 4) << "too few receivers facing the eye to test the wo terms";
  EXPECT_GT(contributing, 100 * kLaneSlots / 8) << "too few lit light points to test the contributions";
}

// BSDF directions drawn in lanes (sample_bsdf_lanes) against sample_bsdf_direction, on random normals, wo on
// either side, GGX alphas from 0.03^2 to 1, lobe probabilities from 0 to 1 and uniforms including 0 and the square's
// centre (where the concentric map divides 0 by 0): whether a direction is drawn, and its bits (bound: 0 ulp), on
// every instruction set.
TEST(TargetLanes, BsdfDirectionsGiveTheScalarBits) {
  Rng rng(99, 5);
  auto bsdf = std::make_unique<BsdfLanes>();
  auto uniforms = std::make_unique<BsdfUniformLanes>();
  auto lanes = std::make_unique<DirectionLanes>();
  alignas(64) float wox[kLaneSlots], woy[kLaneSlots], woz[kLaneSlots];
  auto uniform = [&] {
    const float u = rng.next_float();
    return u < 0.05f ? 0.0f : u < 0.1f ? 0.5f : rng.next_float();
  };
  int compared = 0, drawn = 0, specular = 0;
  std::string targets;
  for (int batch = 0; batch < 200; ++batch) {
    struct Expected {
      bool drawn;
      vec3 wi;
    } expected[kLaneSlots];
    for (int s = 0; s < kLaneSlots; ++s) {
      const vec3 n = random_unit(rng), wo = random_unit(rng);
      const float roughness = std::max(0.03f, rng.next_float());
      bsdf->nx[s] = n.x, bsdf->ny[s] = n.y, bsdf->nz[s] = n.z;
      bsdf->alpha[s] = roughness * roughness;
      bsdf->p_specular[s] = rng.next_float() < 0.2f ? 1.0f : rng.next_float();
      wox[s] = wo.x, woy[s] = wo.y, woz[s] = wo.z;
      uniforms->u[0][s] = uniform(), uniforms->u[1][s] = uniform(), uniforms->lobe[s] = rng.next_float();
      expected[s].drawn =
          sample_bsdf_direction(Frame::from_normal(n), bsdf->alpha[s], wo, vec2(uniforms->u[0][s], uniforms->u[1][s]),
                                uniforms->lobe[s], bsdf->p_specular[s], expected[s].wi);
      drawn += expected[s].drawn;
      specular += expected[s].drawn && uniforms->lobe[s] < bsdf->p_specular[s];
    }
    for_each_simd_target([&](const char* target) {
      if (batch == 0) targets += std::string(targets.empty() ? "" : ", ") + target;
      for (int s = 0; s < kLaneSlots; ++s) lanes->active[s] = 1.0f;
      sample_bsdf_lanes(*bsdf, wox, woy, woz, *uniforms, kLaneSlots, *lanes);
      for (int s = 0; s < kLaneSlots; ++s) {
        ASSERT_EQ(lanes->active[s] > 0.0f, expected[s].drawn) << target << ", batch " << batch << " slot " << s;
        if (!expected[s].drawn) continue;
        ++compared;
        EXPECT_TRUE(same_bits(lanes->x[s], expected[s].wi.x) && same_bits(lanes->y[s], expected[s].wi.y) &&
                    same_bits(lanes->z[s], expected[s].wi.z))
            << target << ", batch " << batch << " slot " << s << ": lanes (" << lanes->x[s] << ", " << lanes->y[s]
            << ", " << lanes->z[s] << "), scalar (" << expected[s].wi.x << ", " << expected[s].wi.y << ", "
            << expected[s].wi.z << ")";
      }
    });
    if (::testing::Test::HasFailure()) break;
  }
  std::printf("  %d directions compared (%d drawn per target, %d of them specular) on %s\n", compared, drawn, specular,
              targets.c_str());
  EXPECT_GT(specular, drawn / 4) << "too few specular directions";
  EXPECT_GT(drawn - specular, drawn / 4) << "too few diffuse directions";
}

// Which neighbours are similar, in lanes (similar_neighbour_lanes) against similar_surfaces, on random pixels
// with up to 31 neighbours each: depths within and beyond the tolerance (and exactly at it), no surface, and
// shading normals tilted to around the cosine tolerance (the quantised normals put many pairs within a few
// ulps of it). The bound is the same answer for every pair.
TEST(TargetLanes, NeighbourSimilarityGivesTheScalarAnswers) {
  Rng rng(4242, 7);
  ReuseParams params;
  auto lanes = std::make_unique<NeighbourLanes>();
  std::vector<PackedSurface> pixels(kLaneSlots), neighbours(size_t(kMaxNeighbours) * kLaneSlots);
  int pairs = 0, similar = 0, depth_edges = 0;
  std::string targets;
  for (int batch = 0; batch < 40; ++batch) {
    const int count = 1 + batch % kMaxNeighbours, slots = batch % 3 == 0 ? kLaneSlots - 5 : kLaneSlots;
    for (int s = 0; s < kLaneSlots; ++s) {
      PackedSurface& a = pixels[size_t(s)];
      const vec3 n = random_unit(rng);
      a.depth = 0.5f + 4.0f * rng.next_float();
      a.shading_normal = oct_encode(n);
      lanes->set(s, a);
      for (int k = 0; k < count; ++k) {
        PackedSurface& b = neighbours[size_t(k) * kLaneSlots + size_t(s)];
        const float u = rng.next_float();
        b.depth = u < 0.1f    ? kInfinity
                  : u < 0.2f  ? a.depth + params.depth_tolerance * a.depth
                  : u < 0.25f ? a.depth - params.depth_tolerance * a.depth
                              : a.depth * (0.8f + 0.4f * rng.next_float());
        depth_edges += u >= 0.1f && u < 0.25f;
        // A tilt whose cosine is spread around the tolerance's (0.9: about 0.45 rad).
        b.shading_normal = oct_encode(glm::normalize(n + random_unit(rng) * (0.3f + 0.4f * rng.next_float())));
        lanes->set_neighbour(k, s, b);
      }
    }
    for_each_simd_target([&](const char* target) {
      if (batch == 0) targets += std::string(targets.empty() ? "" : ", ") + target;
      similar_neighbour_lanes(*lanes, count, slots, params.depth_tolerance, params.normal_tolerance);
      for (int s = 0; s < slots; ++s) {
        const PackedSurface& a = pixels[size_t(s)];
        for (int k = 0; k < count; ++k) {
          const bool scalar =
              similar_surfaces(a, a.shading_n(), neighbours[size_t(k) * kLaneSlots + size_t(s)], params);
          ASSERT_EQ(lanes->similar[k][s] != 0, scalar)
              << target << ", batch " << batch << " slot " << s << " neighbour " << k;
          ++pairs, similar += scalar;
        }
      }
    });
  }
  std::printf("  %d pairs compared (%d similar, %d neighbours at the depth tolerance) on %s\n", pairs, similar,
              depth_edges, targets.c_str());
  EXPECT_GT(similar, pairs / 5) << "too few similar pairs to test the normal's cosine";
  EXPECT_LT(similar, pairs * 4 / 5) << "too few pairs rejected";
}

// Shadow rays built in lanes (shadow_ray_lanes: reuse's visibility rays, shading's) against Tracer::spawn_ray_to: the
// same bits for every ray, on receivers and points at the scales of a scene whose offset epsilon is the city's, with
// ends close together, far apart and on either side of each other's normals.
TEST(TargetLanes, ShadowRaysGiveTheScalarBits) {
  const Scene scene = make_builtin_scene("city");
  const Tracer tracer(scene);
  Rng rng(977, 3);
  auto from = std::make_unique<ReceiverLanes>();
  auto to = std::make_unique<CandidateLanes>();
  auto rays = std::make_unique<RayLanes>();
  std::vector<Ray> scalar(kLaneSlots);
  int compared = 0;
  std::string targets;
  for (int batch = 0; batch < 60; ++batch) {
    const float scale = batch % 3 == 0 ? 0.01f : batch % 3 == 1 ? 1.0f : 300.0f;
    for (int s = 0; s < kLaneSlots; ++s) {
      const vec3 p = (vec3(rng.next_float(), rng.next_float(), rng.next_float()) - 0.5f) * scale;
      const vec3 q = p + random_unit(rng) * scale * (rng.next_float() < 0.2f ? 1e-3f : rng.next_float());
      const vec3 ng = random_unit(rng), nq = random_unit(rng);
      from->px[s] = p.x, from->py[s] = p.y, from->pz[s] = p.z;
      from->gx[s] = ng.x, from->gy[s] = ng.y, from->gz[s] = ng.z;
      to->set(s, LightPoint{q, nq, vec3(1.0f), false});
      scalar[size_t(s)] = tracer.spawn_ray_to(p, ng, q, nq);
    }
    for_each_simd_target([&](const char* target) {
      if (batch == 0) targets += std::string(targets.empty() ? "" : ", ") + target;
      shadow_ray_lanes(*from, *to, tracer.offset_epsilon(), kLaneSlots, *rays);
      for (int s = 0; s < kLaneSlots; ++s) {
        const Ray lanes = rays->ray(s), &ref = scalar[size_t(s)];
        for (int c = 0; c < 3; ++c) {
          ASSERT_TRUE(same_bits(lanes.origin[c], ref.origin[c])) << target << ", batch " << batch << " slot " << s;
          ASSERT_TRUE(same_bits(lanes.direction[c], ref.direction[c]))
              << target << ", batch " << batch << " slot " << s;
        }
        ASSERT_TRUE(same_bits(lanes.tmax, ref.tmax)) << target << ", batch " << batch << " slot " << s;
        ++compared;
      }
    });
  }
  std::printf("  %d rays compared on %s\n", compared, targets.c_str());
}

// The whole chain on rendered frames: the reservoirs after 3 frames of candidates and reuse are the same
// bits with the lanes (candidates, and the targets of temporal and spatial reuse) as with the scalar path,
// on manylights, the Cornell box and city (whose lights and camera move: history placed by other lights), for ReSTIR DI
// alone and with ReSTIR GI (whose reuse shares the code), with pairwise and basic MIS, with 3 shaded samples
// (the further samples' weights come from the lanes; the images hold their shading), with 31 neighbours (on the
// Cornell box, dozens of rows hold a pixel with all 32 inputs: every bit of the rows' masks, counted once by hand), and
// with fused spatiotemporal reuse (city's moving lights: last frame's neighbours placed anew).
// The further samples' picks in lanes (systematic_picks_lanes) against systematic_picks on random combinations: up to
// 32 inputs with zero, tiny, ordinary, huge and infinite weights (an overflowed m p_hat W; zero from each slot's count
// on, as combine_pairwise_lanes leaves them), the kept input drawn among those with weight, uniforms up to the largest
// float below 1, and 2 to 8 samples. Bound: the same picks.
TEST(TargetLanes, SystematicPicksGiveTheScalarPicks) {
  auto lanes = std::make_unique<CombineLanes>();
  Rng rng(4242, 9);
  alignas(64) float v[kLaneSlots];
  int compared = 0, apart = 0;  // picks compared, and those that differ from the kept input
  std::string targets;
  for (int batch = 0; batch < 400; ++batch) {
    const int n = 2 + batch % (kMaxShadedSamples - 1);
    int max_count = 0;
    for (int s = 0; s < kLaneSlots; ++s) {
      const int count = 1 + int(rng.next_u32() % kMaxReuseInputs);
      lanes->count[s] = float(count);
      max_count = std::max(max_count, count);
      float sum = 0.0f;
      for (int k = 0; k < kMaxReuseInputs; ++k) {
        const float u = rng.next_float();
        float& w = lanes->w[k][s];
        w = k >= count || u < 0.3f ? 0.0f
            : u < 0.31f            ? std::numeric_limits<float>::infinity()
            : u < 0.35f            ? 1e-30f
            : u < 0.4f             ? 1e30f
                                   : rng.next_float();
        sum += w;
      }
      // An input with weight, drawn in proportion to it, or where the point lies beyond every interval (an infinite
      // sum) the last one (-1 without weights: the kernel's picks are not read).
      int chosen = -1;
      const float point = rng.next_float() * sum;
      float end = 0.0f;
      for (int k = 0; sum > 0.0f && chosen < 0 && k < count; ++k) {
        end += lanes->w[k][s];
        if (lanes->w[k][s] > 0.0f && point < end) chosen = k;
      }
      for (int k = count - 1; sum > 0.0f && chosen < 0 && k >= 0; --k)
        if (lanes->w[k][s] > 0.0f) chosen = k;
      lanes->result.chosen[s] = float(chosen);
      v[s] = rng.next_float() < 0.05f ? 0x1.fffffep-1f : rng.next_float();
    }
    for_each_simd_target([&](const char* target) {
      if (batch == 0) targets += std::string(targets.empty() ? "" : ", ") + target;
      systematic_picks_lanes(*lanes, v, n, kLaneSlots, max_count);
      for (int s = 0; s < kLaneSlots; ++s) {
        const int chosen = int(lanes->result.chosen[s]);
        if (chosen < 0) continue;
        float w[kMaxReuseInputs];
        for (int k = 0; k < kMaxReuseInputs; ++k) w[k] = lanes->w[k][s];
        int picks[kMaxShadedSamples];
        systematic_picks(w, int(lanes->count[s]), chosen, v[s], n, picks);
        for (int j = 1; j < n; ++j) {
          ++compared;
          apart += picks[j] != chosen;
          EXPECT_EQ(int(lanes->picks[j][s]), picks[j])
              << target << ", batch " << batch << " slot " << s << " pick " << j;
        }
      }
    });
    if (::testing::Test::HasFailure()) break;
  }
  std::printf("  %d picks compared (%d apart from the kept input) on %s\n", compared, apart, targets.c_str());
  EXPECT_GT(apart, compared / 4) << "too few picks that leave the kept input to test anything";
}

TEST(TargetLanes, ReservoirsEqualTheScalarPath) {
  struct Case {
    const char* scene;
    const char* method;
    const char* bias;
    int shaded_samples = 1;
    int neighbours = 3;
    bool fused = false;  // DI's and GI's fused spatiotemporal reuse
  };
  for (const Case& c : {Case{"manylights", "restir-di", "pairwise"}, Case{"cornell", "restir-di", "pairwise"},
                        Case{"city", "restir-di", "pairwise"}, Case{"manylights", "restir-di", "basic"},
                        Case{"cornell", "restir", "pairwise"}, Case{"manylights", "restir", "pairwise", 3},
                        Case{"cornell", "restir-di", "pairwise", 1, 31}, Case{"city", "restir-di", "pairwise", 2},
                        Case{"city", "restir", "pairwise", 2, 3, true}}) {
    std::vector<ReuseReservoir> result[2], gi[2];
    Image image[2];
    for (int simd = 0; simd < 2; ++simd) {
      RenderSettings settings = testing::settings({{"width", 96},
                                                   {"height", 64},
                                                   {"method", c.method},
                                                   {"di_bias", c.bias},
                                                   {"di_shaded_samples", c.shaded_samples},
                                                   {"gi_shaded_samples", c.shaded_samples},
                                                   {"di_neighbours", c.neighbours},
                                                   {"di_fused", c.fused},
                                                   {"gi_fused", c.fused}});
      settings.di.simd = settings.di_reuse.simd = settings.gi_reuse.simd = simd == 1;  // not a setting: the oracle
      Scene scene = make_builtin_scene(c.scene);
      const CameraDesc camera = scene.default_camera();
      Renderer renderer(std::move(scene), settings);
      for (int frame = 0; frame < 3; ++frame) {
        const FrameStats stats = testing::render_checked(renderer, frame, 0.1f * float(frame), camera);
        if (frame > 0) {
          ASSERT_EQ(stats.stage_ms("di_fused") > 0.0, c.fused) << c.scene << " frame " << frame;
        }
      }
      result[simd] = renderer.di_reservoirs();
      gi[simd] = renderer.gi_reservoirs();
      image[simd] = renderer.image();
    }
    // The images too: the BSDF candidates' values and densities (in lanes) reach them through the light that
    // only BSDF sampling finds (city's sky).
    for (size_t i = 0; i < image[0].pixels.size(); ++i)
      ASSERT_TRUE(same_bits(image[0].pixels[i].x, image[1].pixels[i].x) &&
                  same_bits(image[0].pixels[i].y, image[1].pixels[i].y) &&
                  same_bits(image[0].pixels[i].z, image[1].pixels[i].z))
          << c.scene << " pixel " << i;
    for (auto* r : {result, gi}) {
      ASSERT_EQ(r[0].size(), r[1].size());
      int with_sample = 0;
      for (size_t i = 0; i < r[0].size(); ++i) {
        const ReuseReservoir &a = r[0][i], &b = r[1][i];
        with_sample += a.W > 0.0f;
        ASSERT_TRUE(a.y.light == b.y.light && a.y.uv == b.y.uv && same_bits(a.W, b.W) &&
                    same_bits(a.p_hat_y, b.p_hat_y) && same_bits(a.M, b.M))
            << c.scene << (r == gi ? " GI" : " DI") << " pixel " << i << ": W " << a.W << " / " << b.W << ", light "
            << a.y.light << " / " << b.y.light;
      }
      if (r == result || std::string(c.method) == "restir") {
        EXPECT_GT(with_sample, int(r[0].size()) / 4) << c.scene;
      }
    }
  }
}

// ReSTIR GI's initial samples (gi_initial_samples: the first rays' BSDF terms and densities, the paths' BSDF work
// and the samples' targets in lanes) against the scalar code they stand for, written out here: exact_receiver
// and Bsdf::sample for the first ray, trace_path (one ray at a time, scalar BSDFs) for the path, sample_contribution
// at the packed receiver for the target. The bound is exact equality of every reservoir.
TEST(TargetLanes, GiSamplesEqualTheScalarPath) {
  for (const char* name : {"manylights", "city"}) {
    const Scene scene = make_builtin_scene(name);
    const Tracer tracer(scene);
    const LightList lights(scene);
    const PowerLightSampler sampler(lights);
    const int w = 96, h = 64, frame = 2;
    const Camera camera(scene.default_camera(), w, h);
    const SceneView view{scene, tracer, lights, camera};
    GBuffer g;
    RayCounter rays;
    trace_gbuffer(scene, tracer, camera, camera, GBufferParams{3, frame, true, true, true}, g, rays);
    const ReuseDomain domain{g.packed, w, h, camera.position(), lights};
    GiParams params;
    params.seed = 11;
    std::vector<ReuseReservoir> lanes;
    Counter non_finite;
    gi_initial_samples(view, sampler, g, domain, params, frame, lanes, rays, non_finite);
    ASSERT_EQ(lanes.size(), g.size());
    PathTracerParams path;
    path.max_depth = params.max_depth;
    path.rr_start_depth = params.rr_start_depth;
    int with_sample = 0;
    for (size_t i = 0; i < g.size(); ++i) {
      ReuseReservoir r;
      if (g.hit(i)) {
        r.M = 1.0f;
        Rng rng = Rng::for_key(params.seed, i, uint64_t(frame), 0x61);
        const ReuseReceiver receiver = exact_receiver(g, domain.eye, lights, i);
        vec2 ub(rng.next_float(), rng.next_float()), tag(rng.next_float(), rng.next_float());
        float lobe = rng.next_float(), u = rng.next_float();
        BsdfSample bs;
        if (receiver.bsdf.sample(receiver.wo, ub, lobe, bs) && glm::dot(bs.wi, receiver.geometric_normal) > 0.0f) {
          const PathStart start{tracer.spawn_ray(receiver.position, receiver.geometric_normal, bs.wi), 1, bs.pdf,
                                ShadingContext{receiver.position, receiver.shading_normal}, false};
          std::optional<SurfacePoint> x_s;
          uint64_t traced = 0;
          const vec3 L = trace_path(view, sampler, path, start, rng, traced, &x_s);
          if (x_s && is_finite(L) && max_component(L) > 0.0f) {
            const vec3 d = x_s->position - receiver.position;
            const float d2 = glm::dot(d, d), cos_s = std::abs(glm::dot(x_s->geometric_normal, d)) / std::sqrt(d2);
            const float p_area = bs.pdf * cos_s / d2;
            ReuseSample s{kSurfacePointSample, tag, LightPoint{x_s->position, x_s->geometric_normal, L, false}, 0};
            const float p_hat = sample_target(sample_contribution(reuse_receiver(domain, i), s));
            if (p_area > 0.0f && p_hat > 0.0f) {
              r.update(s, p_hat / p_area, p_hat, u);
              r.finalize();
            }
          }
        }
      }
      const ReuseReservoir& a = lanes[i];
      ASSERT_TRUE(a.y.light == r.y.light && a.y.uv == r.y.uv && same_bits(a.W, r.W) && same_bits(a.w_sum, r.w_sum) &&
                  same_bits(a.p_hat_y, r.p_hat_y) && same_bits(a.M, r.M) &&
                  same_bits(a.y.point.radiance.x, r.y.point.radiance.x) &&
                  same_bits(a.y.point.position.y, r.y.point.position.y))
          << name << " pixel " << i << ": W " << a.W << " / " << r.W << ", p_hat " << a.p_hat_y << " / " << r.p_hat_y;
      with_sample += r.W > 0.0f;
    }
    EXPECT_GT(with_sample, int(g.size()) / 4) << name << ": too few pixels with a GI sample to compare";
  }
}

}  // namespace
}  // namespace candela
