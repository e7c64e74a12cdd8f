#include "engine/surface.h"

namespace candela {

WorldTriangle world_triangle(const Scene& scene, uint32_t instance, uint32_t prim) {
  const Instance& inst = scene.instances[instance];
  const Mesh& mesh = scene.meshes[inst.mesh];
  const uvec3& tri = mesh.triangles[prim];
  return {transform_point(inst.transform, mesh.positions[tri.x]),
          transform_point(inst.transform, mesh.positions[tri.y]),
          transform_point(inst.transform, mesh.positions[tri.z]), glm::determinant(mat3(inst.transform)) < 0.0f};
}

template <class T>
static T interpolate(const std::vector<T>& attr, const uvec3& tri, vec2 b) {
  return attr[tri.x] * (1.0f - b.x - b.y) + attr[tri.y] * b.x + attr[tri.z] * b.y;
}

static vec4 lookup(const Scene& scene, const TextureRef& ref, vec2 uv0, vec2 uv1) {
  return scene.textures[ref.texture].sample(ref.apply(ref.texcoord == 1 ? uv1 : uv0));
}

vec3 material_emission(const Scene& scene, const Material& m, vec2 uv0, vec2 uv1) {
  if (!m.emissive()) return vec3(0.0f);
  if (!m.emissive_tex.valid()) return m.emission;
  return m.emission * vec3(lookup(scene, m.emissive_tex, uv0, uv1));
}

mat3 normal_matrix(const mat4& m) {
  mat3 a(m);
  return mat3(glm::cross(a[1], a[2]), glm::cross(a[2], a[0]), glm::cross(a[0], a[1]));
}

vec3 emission_at(const Scene& scene, uint32_t instance, uint32_t prim, vec2 b) {
  const Mesh& mesh = scene.meshes[scene.instances[instance].mesh];
  const Material& m = scene.materials[mesh.material];
  if (!m.emissive()) return vec3(0.0f);
  if (!m.emissive_tex.valid()) return m.emission;
  const uvec3& tri = mesh.triangles[prim];
  vec2 uv0 = mesh.uv0.empty() ? vec2(0.0f) : interpolate(mesh.uv0, tri, b);
  vec2 uv1 = mesh.uv1.empty() ? uv0 : interpolate(mesh.uv1, tri, b);
  return material_emission(scene, m, uv0, uv1);
}

// Tangent frame of the triangle from its UV parametrisation, for meshes without TANGENT.
static vec3 uv_tangent(const WorldTriangle& t, const std::vector<vec2>& uv, const uvec3& tri) {
  vec2 d1 = uv[tri.y] - uv[tri.x], d2 = uv[tri.z] - uv[tri.x];
  float det = d1.x * d2.y - d1.y * d2.x;
  if (std::abs(det) < 1e-20f) return vec3(0.0f);
  return ((t.p1 - t.p0) * d2.y - (t.p2 - t.p0) * d1.y) / det;
}

SurfacePoint surface_at(const Scene& scene, uint32_t instance, uint32_t prim, vec2 b, const vec3& wo) {
  const Instance& inst = scene.instances[instance];
  const Mesh& mesh = scene.meshes[inst.mesh];
  const Material& m = scene.materials[mesh.material];
  const uvec3& tri = mesh.triangles[prim];
  WorldTriangle t = world_triangle(scene, instance, prim);

  SurfacePoint sp;
  sp.instance = instance;
  sp.prim = prim;
  sp.position = t.p0 * (1.0f - b.x - b.y) + t.p1 * b.x + t.p2 * b.y;
  vec3 n_front = glm::normalize(t.normal());
  sp.front_face = glm::dot(n_front, wo) >= 0.0f;
  vec3 ng = sp.front_face ? n_front : -n_front;
  sp.geometric_normal = ng;

  vec2 uv0 = mesh.uv0.empty() ? vec2(0.0f) : interpolate(mesh.uv0, tri, b);
  vec2 uv1 = mesh.uv1.empty() ? uv0 : interpolate(mesh.uv1, tri, b);

  // Material parameters, resolved through textures.
  vec4 base = m.base_color;
  if (m.base_color_tex.valid()) base *= lookup(scene, m.base_color_tex, uv0, uv1);
  sp.base_color = vec3(base);
  sp.metallic = m.metallic;
  sp.roughness = m.roughness;
  sp.specular = m.specular;
  if (m.specular_tex.valid()) sp.specular *= lookup(scene, m.specular_tex, uv0, uv1).a;
  vec3 specular_color = m.specular_color;
  if (m.specular_color_tex.valid()) specular_color *= vec3(lookup(scene, m.specular_color_tex, uv0, uv1));
  sp.specular_f0 = dielectric_f0(m.ior, specular_color);
  if (m.metallic_roughness_tex.valid()) {
    vec4 mr = lookup(scene, m.metallic_roughness_tex, uv0, uv1);
    sp.roughness *= mr.y;
    sp.metallic *= mr.z;
  }
  if (m.emissive() && (sp.front_face || m.double_sided)) sp.emission = material_emission(scene, m, uv0, uv1);

  // Shading normal on the front side: interpolated vertex normal, then the normal map in the tangent
  // frame; turned to the viewer's side afterwards, so that back faces see the same bumps mirrored.
  mat3 nm = normal_matrix(inst.transform);
  vec3 ns = mesh.normals.empty() ? n_front : glm::normalize(nm * interpolate(mesh.normals, tri, b));
  if (!is_finite(ns)) ns = n_front;
  if (glm::dot(ns, n_front) < 0.0f) ns = -ns;
  if (m.normal_tex.valid()) {
    const std::vector<vec2>& uv = m.normal_tex.texcoord == 1 && !mesh.uv1.empty() ? mesh.uv1 : mesh.uv0;
    vec3 tangent(0.0f);
    float handedness = 1.0f;
    if (!mesh.tangents.empty()) {
      vec4 tg = interpolate(mesh.tangents, tri, b);
      tangent = mat3(inst.transform) * vec3(tg);
      handedness = tg.w < 0.0f ? -1.0f : 1.0f;
    } else if (!uv.empty()) {
      tangent = uv_tangent(t, uv, tri);
    }
    tangent -= ns * glm::dot(ns, tangent);
    if (glm::dot(tangent, tangent) > 1e-20f) {
      tangent = glm::normalize(tangent);
      vec3 bitangent = glm::cross(ns, tangent) * handedness;
      vec3 c = vec3(lookup(scene, m.normal_tex, uv0, uv1)) * 2.0f - vec3(1.0f);
      c.x *= m.normal_scale;
      c.y *= m.normal_scale;
      vec3 mapped = tangent * c.x + bitangent * c.y + ns * c.z;
      if (glm::dot(mapped, mapped) > 1e-12f) ns = glm::normalize(mapped);
    }
  }
  if (!sp.front_face) ns = -ns;
  // A shading normal facing away from the viewer would give a BSDF with no valid wo: fall back.
  if (glm::dot(ns, wo) <= 1e-4f) ns = ng;
  sp.shading_normal = ns;
  return sp;
}

}  // namespace candela
