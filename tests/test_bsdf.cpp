// BSDF proofs: sampling matches pdf (chi-square), Lambert integrates to its albedo, white materials pass
// the furnace test (no energy lost or created), the albedo table is right, and f is reciprocal.
#include <gtest/gtest.h>

#include <vector>

#include "engine/bsdf.h"
#include "engine/rng.h"
#include "tests/test_util.h"

namespace candela {
namespace {

struct BsdfCase {
  float roughness, metallic, cos_theta_o;
};

vec3 direction(float cos_theta, float phi) {
  float s = std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta));
  return {s * std::cos(phi), s * std::sin(phi), cos_theta};
}

// Monte Carlo estimate of the directional albedo  int f(wo, wi) |cos wi| dwi  with uniform hemisphere
// sampling; returns mean and standard error.
std::pair<double, double> albedo(const Bsdf& bsdf, const vec3& wo, int n, uint64_t seed) {
  Rng rng(seed, 1);
  double sum = 0.0, sum2 = 0.0;
  for (int i = 0; i < n; ++i) {
    vec3 wi = direction(rng.next_float(), 2.0f * kPi * rng.next_float());
    double v = luminance(bsdf.eval(wo, wi)) * wi.z * 2.0 * kPi;
    sum += v;
    sum2 += v * v;
  }
  double mean = sum / n;
  return {mean, std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n)};
}

class BsdfSampling : public ::testing::TestWithParam<BsdfCase> {};

// Chi-square goodness of fit of sample() against pdf() on a 20 x 40 (cos theta, phi) grid; bins expecting
// fewer than 5 samples are pooled, and failed samples are compared with the pdf mass below the horizon.
// Each case is tested at significance 1e-3 with a fixed seed.
TEST_P(BsdfSampling, SampleFrequenciesMatchPdf) {
  const BsdfCase c = GetParam();
  Bsdf bsdf(vec3(0, 0, 1), vec3(0.8f, 0.6f, 0.4f), c.metallic, c.roughness);
  vec3 wo = direction(c.cos_theta_o, 0.3f);
  const int n_cos = 20, n_phi = 40, n = 400000, sub = 12;
  std::vector<double> observed(n_cos * n_phi, 0.0), expected(n_cos * n_phi, 0.0);
  Rng rng(42, uint64_t(c.roughness * 1000 + c.metallic * 10 + c.cos_theta_o * 100000));
  int failed = 0;
  for (int i = 0; i < n; ++i) {
    BsdfSample s;
    if (!bsdf.sample(wo, vec2(rng.next_float(), rng.next_float()), rng.next_float(), s)) {
      ++failed;
      continue;
    }
    ASSERT_NEAR(s.pdf, bsdf.pdf(wo, s.wi), 1e-4f * s.pdf);
    float phi = std::atan2(s.wi.y, s.wi.x);
    if (phi < 0.0f) phi += 2.0f * kPi;
    int bc = std::min(int(s.wi.z * n_cos), n_cos - 1), bp = std::min(int(phi / (2.0f * kPi) * n_phi), n_phi - 1);
    observed[bc * n_phi + bp] += 1.0;
  }
  // dw = d(cos theta) d(phi): integrate the pdf over each bin with a sub x sub midpoint rule.
  double total_mass = 0.0;
  for (int bc = 0; bc < n_cos; ++bc)
    for (int bp = 0; bp < n_phi; ++bp) {
      double mass = 0.0;
      for (int i = 0; i < sub; ++i)
        for (int j = 0; j < sub; ++j) {
          float ct = (bc + (i + 0.5f) / sub) / n_cos, phi = (bp + (j + 0.5f) / sub) / n_phi * 2.0f * kPi;
          mass += bsdf.pdf(wo, direction(ct, phi));
        }
      mass *= (1.0 / n_cos) * (2.0 * kPi / n_phi) / (sub * sub);
      expected[bc * n_phi + bp] = mass * n;
      total_mass += mass;
    }
  observed.push_back(failed);
  expected.push_back(std::max(0.0, 1.0 - total_mass) * n);
  double chi2 = 0.0, pooled_obs = 0.0, pooled_exp = 0.0;
  int bins = 0;
  for (size_t k = 0; k < observed.size(); ++k) {
    if (expected[k] < 5.0) {
      pooled_obs += observed[k];
      pooled_exp += expected[k];
      continue;
    }
    chi2 += (observed[k] - expected[k]) * (observed[k] - expected[k]) / expected[k];
    ++bins;
  }
  if (pooled_exp >= 5.0) {
    chi2 += (pooled_obs - pooled_exp) * (pooled_obs - pooled_exp) / pooled_exp;
    ++bins;
  }
  double p = testing::chi_square_p_value(chi2, bins - 1);
  EXPECT_GT(p, 1e-3) << "chi2 " << chi2 << " over " << bins << " bins";
}

INSTANTIATE_TEST_SUITE_P(Lobes, BsdfSampling,
                         ::testing::Values(BsdfCase{1.0f, 0.0f, 0.8f}, BsdfCase{0.5f, 0.0f, 0.5f},
                                           BsdfCase{0.3f, 1.0f, 0.9f}, BsdfCase{0.5f, 1.0f, 0.2f},
                                           BsdfCase{0.7f, 0.5f, 0.6f}));

// A Lambert lobe of albedo 1 (specular factor 0) reflects all energy at every angle, within 4 standard errors.
// The sampling's sin_cos (engine/math.h) against double-precision sin and cos on 2^21 + 1 points of [-8, 8] (the
// angles direction sampling takes lie in [-pi/4, 2 pi]): bound 2 ulp of 1 (2^-22, ~2.4e-7) in absolute error. A
// polynomial coefficient cut to 4 digits, or the reduction with pi/2 in one part, fails it.
TEST(Bsdf, SinCosIsWithinTwoUlpOfOne) {
  double worst_sin = 0.0, worst_cos = 0.0;
  const int n = 1 << 21;
  for (int k = 0; k <= n; ++k) {
    const float x = -8.0f + 16.0f * float(k) / float(n);
    float s, c;
    sin_cos(x, s, c);
    worst_sin = std::max(worst_sin, std::abs(double(s) - std::sin(double(x))));
    worst_cos = std::max(worst_cos, std::abs(double(c) - std::cos(double(x))));
  }
  std::printf("  largest error: sin %.3g, cos %.3g (bound %.3g)\n", worst_sin, worst_cos, std::ldexp(1.0, -22));
  EXPECT_LE(worst_sin, std::ldexp(1.0, -22));
  EXPECT_LE(worst_cos, std::ldexp(1.0, -22));
}

TEST(Bsdf, LambertFurnaceIntegratesToOne) {
  Bsdf lambert(vec3(0, 0, 1), vec3(1.0f), 0.0f, 1.0f, 0.0f);
  for (float ct : {0.1f, 0.5f, 1.0f}) {
    auto [mean, err] = albedo(lambert, direction(ct, 1.0f), 200000, 3);
    EXPECT_NEAR(mean, 1.0, 4.0 * err + 1e-4) << "cos theta " << ct;
  }
}

// Importance-sampled directional albedo: mean of f cos / pdf over sample(); returns mean and standard error.
std::pair<double, double> sampled_albedo(const Bsdf& bsdf, const vec3& wo, int n, uint64_t seed) {
  Rng rng(seed, 2);
  double sum = 0.0, sum2 = 0.0;
  for (int i = 0; i < n; ++i) {
    BsdfSample s;
    if (!bsdf.sample(wo, vec2(rng.next_float(), rng.next_float()), rng.next_float(), s)) continue;
    double v = luminance(s.f) * s.wi.z / s.pdf;
    sum += v;
    sum2 += v * v;
  }
  double mean = sum / n;
  return {mean, std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n)};
}

// White furnace over angles (cos 0.05 .. 1) and roughness (0.05 .. 1), 400,000 samples each (fixed seeds):
// a white dielectric reflects between 0.97 and 1 of the incident energy, a white metal too (its lost
// multiple scattering is returned), and none more than 1 + 3 standard errors + 0.002. The model conserves
// energy exactly up to its albedo table, so a bound of 1 + one standard error would fail about one case
// in six by chance; 3 standard errors make a false failure a 0.13% event per case, and 0.002 is the
// table's interpolation error (GgxAlbedo.TableMatchesIntegral; ~0.001 measured away from grazing angles).
// The uniformly sampled albedo agrees with the importance-sampled one within 4 combined standard errors (a
// check of sample() against eval() and pdf() that needs no chi-square binning).
TEST(Bsdf, WhiteFurnace) {
  constexpr double kTableTolerance = 0.002;
  for (float metallic : {0.0f, 1.0f})
    for (float roughness : {0.05f, 0.1f, 0.25f, 0.5f, 0.75f, 1.0f})
      for (float ct : {0.05f, 0.1f, 0.2f, 0.4f, 0.7f, 1.0f}) {
        Bsdf b(vec3(0, 0, 1), vec3(1.0f), metallic, roughness);
        vec3 wo = direction(ct, 0.0f);
        uint64_t seed = uint64_t(roughness * 1000 + ct * 10) + (metallic > 0.0f ? 100000 : 0);
        auto [mean, err] = sampled_albedo(b, wo, 400000, seed);
        SCOPED_TRACE(::testing::Message() << "metallic " << metallic << " roughness " << roughness << " cos " << ct
                                          << ": albedo " << mean << " +- " << err);
        EXPECT_GE(mean, 0.97);
        EXPECT_LE(mean, 1.0 + 3.0 * err + kTableTolerance);
        if (roughness >= 0.25f) {  // uniform sampling cannot resolve the peak of smoother lobes
          auto [uniform_mean, uniform_err] = albedo(b, wo, 400000, seed + 1);
          EXPECT_NEAR(mean, uniform_mean, 4.0 * std::hypot(err, uniform_err));
        }
      }
}

// The roughest white metal, the case the issue names: at least 0.95 at every angle.
TEST(Bsdf, RoughWhiteMetalKeepsItsEnergy) {
  Bsdf metal(vec3(0, 0, 1), vec3(1.0f), 1.0f, 1.0f);
  for (float ct : {0.05f, 0.3f, 1.0f}) {
    auto [mean, err] = sampled_albedo(metal, direction(ct, 0.0f), 400000, 21);
    EXPECT_GE(mean, 0.95) << "cos " << ct;
  }
}

// specularFactor 0 (KHR_materials_specular) leaves exactly Lambert: f = base / pi, pdf = cos / pi.
TEST(Bsdf, SpecularFactorZeroIsExactlyLambert) {
  Rng rng(5, 5);
  for (int i = 0; i < 1000; ++i) {
    vec3 base(rng.next_float(), rng.next_float(), rng.next_float());
    Bsdf b(vec3(0, 0, 1), base, 0.0f, rng.next_float(), 0.0f, vec3(rng.next_float()));
    vec3 wo = direction(rng.next_float(), 2.0f * kPi * rng.next_float());
    vec3 wi = direction(rng.next_float(), 2.0f * kPi * rng.next_float());
    EXPECT_EQ(b.eval(wo, wi), base * kInvPi);
    EXPECT_FLOAT_EQ(b.pdf(wo, wi), wi.z * kInvPi);
  }
}

// F0 from the ior and the specular colour (KHR_materials_ior, KHR_materials_specular).
TEST(Bsdf, DielectricF0FromIorAndSpecularColour) {
  EXPECT_NEAR(dielectric_f0(1.5f, vec3(1.0f)).x, 0.04f, 1e-7f);
  EXPECT_NEAR(dielectric_f0(1.33f, vec3(1.0f)).x, 0.0200593f, 1e-6f);
  EXPECT_EQ(dielectric_f0(0.0f, vec3(1.0f)), vec3(1.0f));        // ior 0: total reflection
  vec3 clamped = dielectric_f0(1.5f, vec3(0.0f, 1.0f, 100.0f));  // at most 1
  EXPECT_EQ(clamped.x, 0.0f);
  EXPECT_NEAR(clamped.y, 0.04f, 1e-7f);
  EXPECT_EQ(clamped.z, 1.0f);
}

// Normal incidence reflectance of the specular lobe follows F0: a smooth dielectric of ior 1.33 reflects
// about half of what one of ior 1.5 reflects (0.020 against 0.040) where the specular lobe dominates.
TEST(Bsdf, IorScalesTheSpecularLobe) {
  vec3 wo = direction(1.0f, 0.0f), wi = direction(0.999f, kPi);
  Bsdf glass(vec3(0, 0, 1), vec3(0.0f), 0.0f, 0.1f, 1.0f, dielectric_f0(1.5f, vec3(1.0f)));
  Bsdf water(vec3(0, 0, 1), vec3(0.0f), 0.0f, 0.1f, 1.0f, dielectric_f0(1.33f, vec3(1.0f)));
  EXPECT_NEAR(water.eval(wo, wi).x / glass.eval(wo, wi).x, 0.0200593 / 0.04, 0.01);
}

// The albedo table against an independent integral of the F = 1 lobe (uniform hemisphere sampling of
// D G2 / (4 cos_o cos_i) cos_i, 1,000,000 samples) between its grid points: within 4 standard errors plus
// the table's interpolation tolerance of 0.002.
TEST(GgxAlbedo, TableMatchesIntegral) {
  for (float roughness : {0.3f, 0.55f, 1.0f})
    for (float ct : {0.07f, 0.45f, 0.9f}) {
      float alpha = ggx_alpha(roughness);
      vec3 wo = direction(ct, 0.0f);
      Rng rng(17, uint64_t(roughness * 100 + ct * 10));
      const int n = 1000000;
      double sum = 0.0, sum2 = 0.0;
      for (int i = 0; i < n; ++i) {
        vec3 wi = direction(rng.next_float(), 2.0f * kPi * rng.next_float());
        vec3 h = glm::normalize(wo + wi);
        double g2 = 1.0 / (1.0 + ggx_lambda(ct, alpha) + ggx_lambda(wi.z, alpha));
        double v = ggx_d(h.z, alpha) * g2 / (4.0 * ct) * 2.0 * kPi;
        sum += v;
        sum2 += v * v;
      }
      double mean = sum / n, err = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n);
      EXPECT_NEAR(GgxAlbedoRow(roughness).at(ct).a, mean, 4.0 * err + 0.002)
          << "roughness " << roughness << " cos " << ct;
    }
}

TEST(Bsdf, Reciprocity) {
  Rng rng(9, 9);
  for (int i = 0; i < 2000; ++i) {
    Bsdf b(vec3(0, 0, 1), vec3(rng.next_float(), rng.next_float(), rng.next_float()), rng.next_float(),
           0.05f + rng.next_float());
    vec3 a = direction(rng.next_float(), 2.0f * kPi * rng.next_float());
    vec3 c = direction(rng.next_float(), 2.0f * kPi * rng.next_float());
    vec3 f1 = b.eval(a, c), f2 = b.eval(c, a);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(f1[k], f2[k], 1e-4f * std::max(1.0f, f1[k]));
  }
}

TEST(Bsdf, NothingBelowTheSurface) {
  Bsdf b(vec3(0, 0, 1), vec3(0.5f), 0.3f, 0.5f);
  EXPECT_EQ(b.eval(direction(0.5f, 0.0f), vec3(0, 0.6f, -0.8f)), vec3(0.0f));
  EXPECT_EQ(b.pdf(direction(0.5f, 0.0f), vec3(0, 0.6f, -0.8f)), 0.0f);
}

}  // namespace
}  // namespace candela
