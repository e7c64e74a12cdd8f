#pragma once
// Vector types (GLM) and the small geometric helpers every stage shares.
#include <glm/glm.hpp>
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace candela {

using glm::mat3;
using glm::mat4;
using glm::uvec3;
using glm::vec2;
using glm::vec3;
using glm::vec4;

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kInvPi = 1.0f / kPi;
inline constexpr float kInfinity = 1e30f;

// Rec. 709 luminance of linear RGB, for any T that scales by a float and adds (float, compiler vectors of floats).
template <class T>
inline T luminance(const T& r, const T& g, const T& b) {
  return 0.2126f * r + 0.7152f * g + 0.0722f * b;
}
inline float luminance(const vec3& c) { return luminance(c.x, c.y, c.z); }
inline float max_component(const vec3& c) { return std::max(c.x, std::max(c.y, c.z)); }
// Nearest integer, halves rounded up. Inlines to a few instructions, where std::lround is a libm call
// (it showed as 1.7% of a ReSTIR DI frame).
inline int round_nearest(float v) { return int(std::floor(v + 0.5f)); }
// sin x and cos x for |x| <= 8 (the angles of direction sampling), with an error of at most 2 ulp of 1 (2^-22,
// ~2.4e-7; tests/test_bsdf.cpp): x reduced by the nearest multiple q of pi/2 (pi/2 in three parts, each product with q
// exact), then Cephes' single-precision polynomials on [-pi/4, pi/4] (S. L. Moshier, sinf.c: coefficients and
// the three-part constant), the quadrant q mod 4 swapping and negating the two. Written out, rather than
// std::sin and std::cos, so that the SIMD kernels (engine/lanes-inl.h sin_cos) repeat the same operations and
// get the same bits.
namespace sin_cos_constants {
inline constexpr float kTwoOverPi = 0.636619772367581343f;
inline constexpr float kPiOver2[3] = {2.0f * 0.78515625f, 2.0f * 2.4187564849853515625e-4f,
                                      2.0f * 3.77489497744594108e-8f};
inline constexpr float kSin[3] = {-1.9515295891e-4f, 8.3321608736e-3f, -1.6666654611e-1f};
inline constexpr float kCos[3] = {2.443315711809948e-5f, -1.388731625493765e-3f, 4.166664568298827e-2f};
}  // namespace sin_cos_constants
inline void sin_cos(float x, float& sine, float& cosine) {
  using namespace sin_cos_constants;
  const int q = round_nearest(x * kTwoOverPi);
  const float qf = float(q);
  const float r = ((x - qf * kPiOver2[0]) - qf * kPiOver2[1]) - qf * kPiOver2[2];
  const float z = r * r;
  const float s = ((kSin[0] * z + kSin[1]) * z + kSin[2]) * z * r + r;
  const float c = ((kCos[0] * z + kCos[1]) * z + kCos[2]) * z * z - 0.5f * z + 1.0f;
  sine = (q & 1) ? c : s;
  cosine = (q & 1) ? s : c;
  if (q & 2) sine = -sine;
  if ((q + 1) & 2) cosine = -cosine;
}
inline bool is_finite(const vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Orthonormal basis around unit n (Duff et al. 2017, "Building an Orthonormal Basis, Revisited").
struct Frame {
  vec3 t, b, n;
  static Frame from_normal(const vec3& n) {
    float sign = std::copysign(1.0f, n.z);
    float a = -1.0f / (sign + n.z);
    float b = n.x * n.y * a;
    return {vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x), vec3(b, sign + n.y * n.y * a, -n.y), n};
  }
  vec3 to_local(const vec3& v) const { return {glm::dot(v, t), glm::dot(v, b), glm::dot(v, n)}; }
  vec3 to_world(const vec3& v) const { return t * v.x + b * v.y + n * v.z; }
};

inline vec3 transform_point(const mat4& m, const vec3& p) { return vec3(m * vec4(p, 1.0f)); }
inline vec3 transform_vector(const mat4& m, const vec3& v) { return mat3(m) * v; }
// Normals transform by the inverse transpose of the linear part.
inline vec3 transform_normal(const mat3& inv_transpose, const vec3& n) { return glm::normalize(inv_transpose * n); }

// Axis-aligned box.
struct Bounds3 {
  vec3 lo{kInfinity}, hi{-kInfinity};
  void extend(const vec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  void extend(const Bounds3& b) {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
  }
  bool empty() const { return lo.x > hi.x; }
  vec3 center() const { return 0.5f * (lo + hi); }
  vec3 extent() const { return hi - lo; }
  float diagonal() const { return empty() ? 0.0f : glm::length(hi - lo); }
};

}  // namespace candela
