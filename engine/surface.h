#pragma once
// What a ray hit: world-space position, normals (geometric and normal-mapped shading normal, both turned
// to face the viewer), texture-resolved material parameters and emitted radiance.
#include "engine/bsdf.h"
#include "engine/scene.h"
#include "engine/tracer.h"

namespace candela {

struct SurfacePoint {
  vec3 position{0.0f};
  vec3 geometric_normal{0.0f, 0.0f, 1.0f};  // faces wo
  vec3 shading_normal{0.0f, 0.0f, 1.0f};    // faces wo (normal map applied)
  vec3 base_color{0.0f};
  float metallic = 0.0f, roughness = 1.0f, specular = 1.0f;
  vec3 specular_f0{0.04f};  // the dielectric's F0 (ior, specular colour)
  vec3 emission{0.0f};      // radiance leaving towards wo
  uint32_t instance = kNoHit, prim = kNoHit;
  bool front_face = true;  // wo is on the side the triangle's winding faces
  Bsdf bsdf() const { return Bsdf(shading_normal, base_color, metallic, roughness, specular, specular_f0); }
};

// World-space corners of a triangle of an instance.
struct WorldTriangle {
  vec3 p0, p1, p2;
  bool mirrored = false;  // the instance transform flips handedness, which flips the front side (glTF 3.7.4)
  // Unnormalised normal of the front side (counter-clockwise winding in object space).
  vec3 normal() const {
    vec3 n = glm::cross(p1 - p0, p2 - p0);
    return mirrored ? -n : n;
  }
};
WorldTriangle world_triangle(const Scene& scene, uint32_t instance, uint32_t prim);
// Cofactor matrix of the linear part: transforms normals like the inverse transpose, up to a positive scale.
mat3 normal_matrix(const mat4& m);

// Full shading data of the point at barycentric (u, v) on (instance, prim), seen from direction wo.
SurfacePoint surface_at(const Scene& scene, uint32_t instance, uint32_t prim, vec2 barycentric, const vec3& wo);
// Emission of the point at barycentric (u, v), whatever the direction (the caller checks sidedness).
vec3 emission_at(const Scene& scene, uint32_t instance, uint32_t prim, vec2 barycentric);
// Emissive colour of a material at a UV point (factor * strength * texture), ignoring orientation.
vec3 material_emission(const Scene& scene, const Material& m, vec2 uv0, vec2 uv1);

}  // namespace candela
