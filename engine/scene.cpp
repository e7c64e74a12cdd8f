#include "engine/scene.h"

#include <glm/gtc/matrix_transform.hpp>

namespace candela {

Bounds3 Mesh::bounds() const {
  Bounds3 b;
  for (const vec3& p : positions) b.extend(p);
  return b;
}

Bounds3 Scene::bounds() const {
  Bounds3 b;
  for (const Instance& inst : instances) {
    Bounds3 mb = meshes[inst.mesh].bounds();
    if (mb.empty()) continue;
    for (int corner = 0; corner < 8; ++corner) {
      vec3 p((corner & 1) ? mb.hi.x : mb.lo.x, (corner & 2) ? mb.hi.y : mb.lo.y, (corner & 4) ? mb.hi.z : mb.lo.z);
      b.extend(transform_point(inst.transform, p));
    }
  }
  return b;
}

size_t Scene::triangle_count() const {
  size_t n = 0;
  for (const Instance& inst : instances) n += meshes[inst.mesh].triangles.size();
  return n;
}

void Scene::set_time(float t) {
  for (Instance& inst : instances) inst.prev_transform = inst.transform;
  for (const InstanceMotion& m : motions) {
    float speed = glm::length(m.velocity);
    vec3 offset(0.0f);
    if (speed > 0.0f) offset = m.velocity / speed * std::fmod(speed * t + m.phase, m.wrap_distance);
    instances[m.instance].transform = glm::translate(mat4(1.0f), offset) * m.start;
  }
  for (const InstanceAnimation& a : instance_animations) instances[a.instance].transform = a.transform_at(t);
  for (const PowerAnimation& a : power_animations) {
    vec3 value = a.base * a.scale.at(t);
    if (a.target == PowerAnimation::Target::Punctual)
      punctual_lights[a.index].intensity = value;
    else
      materials[a.index].emission = value;
  }
  time = t;
}

CameraDesc Scene::default_camera() const {
  if (camera) return *camera;
  Bounds3 b = bounds();
  CameraDesc cam;
  if (b.empty()) return cam;
  vec3 c = b.center();
  float radius = 0.5f * b.diagonal();
  float distance = radius / std::tan(glm::radians(0.5f * cam.vfov_degrees)) * 1.1f;
  cam.target = c;
  cam.position = c + glm::normalize(vec3(0.0f, 0.25f, 1.0f)) * distance;
  return cam;
}

}  // namespace candela
