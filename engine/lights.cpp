#include "engine/lights.h"

#include "engine/check.h"
#include "engine/parallel.h"
#include "engine/surface.h"

namespace candela {

// Average emission over a triangle: stratified barycentric samples (centroids of a k x k subdivision),
// with k growing with the triangle's footprint in texels so that small texture features are not missed.
vec3 integrate_triangle_emission(const Scene& scene, const Mesh& mesh, uint32_t prim) {
  const Material& m = scene.materials[mesh.material];
  if (!m.emissive()) return vec3(0.0f);
  if (!m.emissive_tex.valid()) return m.emission;
  const uvec3& tri = mesh.triangles[prim];
  const Texture& tex = scene.textures[m.emissive_tex.texture];
  const std::vector<vec2>& uvs = m.emissive_tex.texcoord == 1 && !mesh.uv1.empty() ? mesh.uv1 : mesh.uv0;
  if (uvs.empty()) return material_emission(scene, m, vec2(0.0f), vec2(0.0f));
  vec2 a = m.emissive_tex.apply(uvs[tri.x]), b = m.emissive_tex.apply(uvs[tri.y]), c = m.emissive_tex.apply(uvs[tri.z]);
  vec2 e1 = (b - a) * vec2(tex.width, tex.height), e2 = (c - a) * vec2(tex.width, tex.height);
  float texels = 0.5f * std::abs(e1.x * e2.y - e1.y * e2.x);
  int k = std::clamp(int(std::ceil(std::sqrt(texels))), 2, 32);
  vec3 sum(0.0f);
  int count = 0;
  // Sub-triangles of the k x k grid: "upright" ones at (i, j) and "inverted" ones between them.
  for (int i = 0; i < k; ++i) {
    for (int j = 0; i + j < k; ++j) {
      vec2 up((i + 1.0f / 3.0f) / k, (j + 1.0f / 3.0f) / k);
      sum += vec3(tex.sample(a + (b - a) * up.x + (c - a) * up.y));
      ++count;
      if (i + j + 1 < k) {
        vec2 down((i + 2.0f / 3.0f) / k, (j + 2.0f / 3.0f) / k);
        sum += vec3(tex.sample(a + (b - a) * down.x + (c - a) * down.y));
        ++count;
      }
    }
  }
  return m.emission * sum / float(count);
}

// Emission analysis of one mesh: which triangles emit more than the threshold, and their averages.
static MeshEmission analyse_mesh(const Scene& scene, const Mesh& mesh) {
  MeshEmission me;
  if (!scene.materials[mesh.material].emissive()) return me;
  std::vector<vec3> avg(mesh.triangles.size());
  parallel_for(size_t(0), mesh.triangles.size(),
               [&](size_t i) { avg[i] = integrate_triangle_emission(scene, mesh, uint32_t(i)); });
  me.light_of_prim.assign(mesh.triangles.size(), -1);
  for (size_t i = 0; i < avg.size(); ++i) {
    if (max_component(avg[i]) <= kEmissionThreshold) continue;
    me.light_of_prim[i] = int32_t(me.prims.size());
    me.prims.push_back(uint32_t(i));
    me.average_radiance.push_back(avg[i]);
  }
  return me;
}

LightList::LightList(const Scene& scene)
    : environment_(scene.environment), scene_radius_(0.5f * scene.bounds().diagonal()) {
  mesh_emission_.reserve(scene.meshes.size());
  for (const Mesh& mesh : scene.meshes) mesh_emission_.push_back(analyse_mesh(scene, mesh));
  // Each emitting instance's lights follow the previous one's; the slots are allocated once, then the
  // instances place their lights in parallel (1e6 lights: one world-space triangle each).
  instance_first_light_.assign(scene.instances.size(), -1);
  size_t total = 0;
  for (uint32_t i = 0; i < scene.instances.size(); ++i) {
    instance_mesh_.push_back(uint32_t(scene.instances[i].mesh));
    const MeshEmission& me = mesh_emission_[scene.instances[i].mesh];
    if (me.prims.empty()) continue;
    instance_first_light_[i] = int64_t(total);
    total += me.prims.size();
    if (scene.instances[i].animated) animated_emitters_.push_back(i);
  }
  triangles_.resize(total);
  parallel_for(uint32_t(0), uint32_t(scene.instances.size()), [&](uint32_t i) {
    if (instance_first_light_[i] >= 0) place_instance(scene, i);
  });
  mark_changing(scene);
  for (const PunctualLight& l : scene.punctual_lights) punctual_.push_back(to_world(scene, l));
}

// The lights that are not fixed(): those of animated instances (update() re-places them) and those whose
// material's emission a power animation scales (every frame's list is rebuilt then, the others' records alike).
void LightList::mark_changing(const Scene& scene) {
  changing_.assign((triangles_.size() + 63) / 64, 0);
  std::vector<bool> animated_material(scene.materials.size(), false);
  for (const PowerAnimation& a : scene.power_animations)
    if (a.target == PowerAnimation::Target::Material) animated_material[size_t(a.index)] = true;
  for (uint32_t i = 0; i < scene.instances.size(); ++i) {
    if (instance_first_light_[i] < 0) continue;
    if (!scene.instances[i].animated && !animated_material[scene.meshes[instance_mesh_[i]].material]) continue;
    const size_t first = size_t(instance_first_light_[i]);
    for (size_t k = first; k < first + mesh_emission_[instance_mesh_[i]].prims.size(); ++k)
      changing_[k >> 6] |= uint64_t(1) << (k & 63);
  }
}

// Writes the world-space triangle lights of one instance into their slots.
void LightList::place_instance(const Scene& scene, uint32_t instance) {
  const Mesh& mesh = scene.meshes[scene.instances[instance].mesh];
  const MeshEmission& me = mesh_emission_[scene.instances[instance].mesh];
  const Material& material = scene.materials[mesh.material];
  for (size_t k = 0; k < me.prims.size(); ++k) {
    WorldTriangle t = world_triangle(scene, instance, me.prims[k]);
    TriangleLight& l = triangles_[size_t(instance_first_light_[instance]) + k];
    l.p0 = t.p0;
    l.e1 = t.p1 - t.p0;
    l.e2 = t.p2 - t.p0;
    vec3 n = t.normal();
    float len = glm::length(n);
    l.area = 0.5f * len;
    l.normal = len > 0.0f ? n / len : vec3(0.0f, 0.0f, 1.0f);
    l.average_radiance = me.average_radiance[k];
    l.instance = instance;
    l.prim = me.prims[k];
    l.two_sided = material.double_sided;
    l.textured = material.emissive_tex.valid();
  }
}

PunctualLight LightList::to_world(const Scene& scene, const PunctualLight& light) {
  if (light.instance < 0) return light;
  const mat4& m = scene.instances[light.instance].transform;
  PunctualLight w = light;
  w.position = transform_point(m, light.position);
  w.direction = glm::normalize(transform_vector(m, light.direction));
  return w;
}

void LightList::update(const Scene& scene) {
  for (uint32_t i : animated_emitters_) place_instance(scene, i);
  for (size_t i = 0; i < punctual_.size(); ++i)
    if (punctual_[i].instance >= 0) punctual_[i] = to_world(scene, scene.punctual_lights[i]);
}

std::vector<std::pair<size_t, size_t>> LightList::movable() const {
  std::vector<std::pair<size_t, size_t>> ranges;
  for (uint32_t i : animated_emitters_) {
    const size_t first = size_t(instance_first_light_[i]);
    ranges.emplace_back(first, first + mesh_emission_[instance_mesh_[i]].prims.size());
  }
  for (size_t i = 0; i < punctual_.size(); ++i)
    if (punctual_[i].instance >= 0) ranges.emplace_back(triangles_.size() + i, triangles_.size() + i + 1);
  return ranges;
}

float LightList::power(size_t index) const {
  if (index < triangles_.size()) return triangles_[index].power();
  const PunctualLight& l = punctual_[index - triangles_.size()];
  float I = luminance(l.intensity);
  switch (l.type) {
    case PunctualType::Point: return 4.0f * kPi * I;
    case PunctualType::Spot: return 2.0f * kPi * (1.0f - std::cos(0.5f * (l.inner_cone + l.outer_cone))) * I;
    // Irradiance times the area of the scene's bounding disk (pbrt-v4 does the same).
    case PunctualType::Directional:
    default: return kPi * scene_radius_ * scene_radius_ * I;
  }
}

int64_t LightList::light_index(uint32_t instance, uint32_t prim) const {
  int64_t first = instance_first_light_[instance];
  if (first < 0) return -1;
  int32_t local = mesh_emission_[instance_mesh_[instance]].light_of_prim[prim];
  return local < 0 ? -1 : first + local;
}

// Smooth spot falloff of KHR_lights_punctual: squared linear ramp in cos between the outer and inner cone.
static float spot_falloff(const PunctualLight& l, float cos_angle) {
  float cos_outer = std::cos(l.outer_cone), cos_inner = std::cos(l.inner_cone);
  float t = std::clamp((cos_angle - cos_outer) / std::max(cos_inner - cos_outer, 1e-4f), 0.0f, 1.0f);
  return t * t;
}

// Triangle lights: uniform point on the area (density 1/A), converted to solid angle at p.
// Punctual lights: the light's position or direction, a delta density reported as pdf 1.
LightSample LightList::sample(const Scene& scene, size_t index, const vec3& p, vec2 u) const {
  if (index >= triangles_.size()) return sample_punctual(index, p);
  const TriangleLight& l = triangles_[index];
  LightSample s = light_sample_towards(triangle_point(scene, index, u), p);
  if (max_component(s.radiance) > 0.0f && l.area > 0.0f)
    s.pdf = s.distance * s.distance / (std::abs(glm::dot(l.normal, s.wi)) * l.area);
  else
    s.radiance = vec3(0.0f);
  return s;
}

void LightList::triangle_point(const Scene& scene, size_t index, vec2 u, LightPoint& out) const {
  const TriangleLight& l = triangles_[index];
  float su = std::sqrt(u.x);
  vec2 bary(su * (1.0f - u.y), su * u.y);
  out.position = l.p0 + l.e1 * bary.x + l.e2 * bary.y;
  out.normal = l.normal;
  out.radiance = l.textured ? emission_at(scene, l.instance, l.prim, bary) : l.average_radiance;
  out.two_sided = l.two_sided;
}

LightSample LightList::sample_punctual(size_t index, const vec3& p) const {
  const PunctualLight& l = punctual_[index - triangles_.size()];
  LightSample s;
  s.is_delta = true;
  s.pdf = 1.0f;
  if (l.type == PunctualType::Directional) {
    s.wi = -l.direction;
    s.distance = kInfinity;
    s.radiance = l.intensity;
    return s;
  }
  vec3 d = l.position - p;
  float dist2 = glm::dot(d, d);
  if (dist2 <= 0.0f) return s;
  s.position = l.position;
  s.distance = std::sqrt(dist2);
  s.wi = d / s.distance;
  float falloff = l.type == PunctualType::Spot ? spot_falloff(l, glm::dot(-s.wi, l.direction)) : 1.0f;
  s.radiance = l.intensity * (falloff / dist2);
  return s;
}

float LightList::pdf_solid_angle(size_t index, const vec3& p, const vec3& y) const {
  if (index >= triangles_.size()) return 0.0f;
  const TriangleLight& l = triangles_[index];
  vec3 d = y - p;
  float dist2 = glm::dot(d, d);
  if (dist2 <= 0.0f) return 0.0f;
  float cos_l = std::abs(glm::dot(l.normal, d)) / std::sqrt(dist2);
  if (cos_l <= 1e-7f || l.area <= 0.0f) return 0.0f;
  return dist2 / (cos_l * l.area);
}

}  // namespace candela
