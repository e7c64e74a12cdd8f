#pragma once
// The one class that talks to Embree: one process-wide device, per-mesh BVHs built once, a top-level
// scene of instances re-committed each frame, closest-hit and occlusion queries for single rays and
// 16-wide packets, and ray spawning with offsets relative to the scene's scale.
#include <embree3/rtcore.h>

#include <cstdint>
#include <vector>

#include "engine/math.h"
#include "engine/scene.h"

namespace candela {

inline constexpr uint32_t kNoHit = 0xffffffffu;

struct Ray {
  vec3 origin;
  vec3 direction;
  float tmin = 0.0f;
  float tmax = kInfinity;
};

struct Hit {
  float t = kInfinity;
  uint32_t instance = kNoHit;
  uint32_t prim = kNoHit;
  vec2 barycentric{0.0f};  // Embree's (u, v): p = (1-u-v) p0 + u p1 + v p2
  bool valid() const { return instance != kNoHit; }
};

// 16 rays in Embree's SoA layout (64-byte aligned as rtcIntersect16 requires).
struct alignas(64) RayPacket16 {
  RTCRayHit16 rayhit;
  alignas(64) int valid[16];
  void set(int lane, const Ray& ray);
  void set_inactive(int lane) { valid[lane] = 0; }
  Hit hit(int lane) const;
};

// Sets flush-to-zero and denormals-are-zero for the calling thread (Embree's advice for speed).
void enable_ftz_daz();

class Tracer {
 public:
  explicit Tracer(const Scene& scene);
  ~Tracer();
  Tracer(const Tracer&) = delete;
  Tracer& operator=(const Tracer&) = delete;

  // Copies animated instance transforms from the scene and re-commits the top level (per frame; cheap).
  void update_instances(const Scene& scene);

  Hit intersect(const Ray& ray) const;
  bool occluded(const Ray& ray) const;
  // Coherent rays (primary rays of a tile, shadow rays of a tile) in packets of 16.
  void intersect16(RayPacket16& packet, bool coherent) const;
  void occluded16(RayPacket16& packet) const;  // afterwards tfar < 0 in a lane means occluded
  static bool occluded_lane(const RayPacket16& packet, int lane) { return packet.rayhit.ray.tfar[lane] < 0.0f; }

  // A ray leaving surface point p (geometric normal ng) in direction d, offset to avoid self-hits.
  Ray spawn_ray(const vec3& p, const vec3& ng, const vec3& d) const;
  // A shadow ray from p (normal ng) to q (normal nq); both ends offset, tmax stops short of q.
  Ray spawn_ray_to(const vec3& p, const vec3& ng, const vec3& q, const vec3& nq) const;
  float scene_radius() const { return scene_radius_; }

 private:
  vec3 offset_point(const vec3& p, const vec3& ng, const vec3& towards) const;

  RTCScene top_ = nullptr;
  std::vector<RTCScene> mesh_scenes_;
  std::vector<RTCGeometry> instance_geoms_;
  std::vector<uint32_t> animated_;  // indices of instances whose transform can change
  float scene_radius_ = 1.0f;
  float epsilon_ = 1e-5f;
};

}  // namespace candela
