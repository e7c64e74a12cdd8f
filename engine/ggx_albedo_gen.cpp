// Build-time generator of the GGX albedo table (ggx_albedo.h): prints a C++ source file that defines
// kGgxAlbedoEntries and kGgxAlbedoAverages, and their 64-bit pair copies. Run by CMake; its output is never edited or
// committed.
#include <bit>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "engine/ggx_albedo_data.h"
#include "engine/microfacet.h"

namespace candela {
namespace {

constexpr int kMu = kGgxAlbedoMuCount, kRough = kGgxAlbedoRoughnessCount;
// Samples per table entry along each axis of the visible-normal sampler's square.
constexpr int kStrata = 64;

struct Albedo {
  double a = 0.0, b = 0.0;
};

// The bits of (float(a), float(b)) as one 64-bit word, a in the low half (the float tables' pair, as a
// little-endian load of its 8 bytes reads it).
unsigned long long pair_bits(const Albedo& v) {
  return uint64_t(std::bit_cast<uint32_t>(float(v.b))) << 32 | std::bit_cast<uint32_t>(float(v.a));
}

// (a, b) for one (mu, roughness): the integral over the visible-normal sampler's square of its weight
// f1 cos / pdf = G2 / G1(wo) (Heitz 2018, eq. 19), by the midpoint rule on a kStrata x kStrata grid. The
// weight drops to 0 where the reflected direction goes below the horizon, which happens as the radial
// input u.x nears 1; u.x = 1 - (1 - t)^3 (Jacobian 3 (1 - t)^2) crowds the strata there, so the grid
// resolves that edge (uniform strata were 0.7% off at roughness 0.3).
Albedo integrate(float mu, float alpha) {
  mu = std::max(mu, 1e-4f);
  vec3 wo(std::sqrt(1.0f - mu * mu), 0.0f, mu);
  double lambda_o = ggx_lambda(mu, alpha);
  Albedo e;
  for (int i = 0; i < kStrata; ++i) {
    double t = (i + 0.5) / kStrata, s = 1.0 - t;
    float ux = float(1.0 - s * s * s);
    double jacobian = 3.0 * s * s;
    for (int j = 0; j < kStrata; ++j) {
      vec3 h = ggx_sample_visible_normal(wo, alpha, vec2(ux, (j + 0.5f) / kStrata));
      vec3 wi = glm::reflect(-wo, h);
      if (wi.z <= 0.0f) continue;
      double w = jacobian * (1.0 + lambda_o) / (1.0 + lambda_o + ggx_lambda(wi.z, alpha));
      double m = 1.0 - std::clamp(double(glm::dot(wo, h)), 0.0, 1.0);
      e.a += w;
      e.b += w * (m * m) * (m * m) * m;
    }
  }
  double n = double(kStrata) * kStrata;
  return {e.a / n, e.b / n};
}

// 2 int v(mu) mu dmu = 4 int v(x) x^3 dx of the interpolant, piecewise linear in x = sqrt(mu): on [x0, x1]
// the two hat functions integrate against x^3 to (x1 (x^4/4) - x^5/5) / h and (x^5/5 - x0 (x^4/4)) / h
// between the ends. So the averages are exact for the table as the reader interpolates it.
Albedo average(const std::vector<Albedo>& row) {
  const double h = 1.0 / (kMu - 1);
  auto p4 = [](double x) { return x * x * x * x / 4.0; };
  auto p5 = [](double x) { return x * x * x * x * x / 5.0; };
  Albedo avg;
  for (int j = 0; j + 1 < kMu; ++j) {
    double x0 = j * h, x1 = (j + 1) * h;
    double w0 = (x1 * (p4(x1) - p4(x0)) - (p5(x1) - p5(x0))) / h;
    double w1 = ((p5(x1) - p5(x0)) - x0 * (p4(x1) - p4(x0))) / h;
    avg.a += 4.0 * (w0 * float(row[size_t(j)].a) + w1 * float(row[size_t(j) + 1].a));
    avg.b += 4.0 * (w0 * float(row[size_t(j)].b) + w1 * float(row[size_t(j) + 1].b));
  }
  return avg;
}

}  // namespace
}  // namespace candela

int main() {
  using namespace candela;
  std::printf("// Generated at build time by ggx_albedo_gen (engine/ggx_albedo_gen.cpp). Do not edit.\n");
  std::printf("#include \"engine/ggx_albedo_data.h\"\n\nnamespace candela {\n\n");
  std::vector<Albedo> averages, entries;
  std::printf("const float kGgxAlbedoEntries[%d] = {\n", kRough * kMu * 2);
  for (int k = 0; k < kRough; ++k) {
    float alpha = ggx_alpha(float(k) / (kRough - 1));
    std::vector<Albedo> row;
    for (int j = 0; j < kMu; ++j) {
      double x = double(j) / (kMu - 1);
      row.push_back(integrate(float(x * x), alpha));
      entries.push_back(row.back());
      std::printf("%.9gf, %.9gf,%s", float(row.back().a), float(row.back().b), j % 4 == 3 ? "\n" : " ");
    }
    averages.push_back(average(row));
  }
  std::printf("};\n\nconst float kGgxAlbedoAverages[%d] = {\n", kRough * 2);
  for (const Albedo& avg : averages) std::printf("%.9gf, %.9gf,\n", float(avg.a), float(avg.b));
  std::printf("};\n\nconst uint64_t kGgxAlbedoEntryPairs[%d] = {\n", kRough * kMu);
  for (size_t e = 0; e < entries.size(); ++e)
    std::printf("0x%016llxull,%s", pair_bits(entries[e]), e % 4 == 3 ? "\n" : " ");
  std::printf("};\n\nconst uint64_t kGgxAlbedoAveragePairs[%d] = {\n", kRough);
  for (const Albedo& avg : averages) std::printf("0x%016llxull,\n", pair_bits(avg));
  std::printf("};\n\nalignas(64) const float kGgxAlbedoRowPlanes[%d] = {\n", kRough * kMu * 2);
  for (int k = 0; k < kRough; ++k) {
    for (int j = 0; j < kMu; ++j)
      std::printf("%.9gf,%s", float(entries[size_t(k * kMu + j)].a), j % 8 == 7 ? "\n" : " ");
    for (int j = 0; j < kMu; ++j)
      std::printf("%.9gf,%s", float(entries[size_t(k * kMu + j)].b), j % 8 == 7 ? "\n" : " ");
  }
  std::printf("};\n\n}  // namespace candela\n");
  return 0;
}
