#pragma once
// The one class that talks to Embree: one process-wide device, closest-hit and occlusion queries for
// single rays and 16-wide packets, and ray spawning with offsets relative to the scene's scale.
//
// BVH layout (two levels): static instances whose mesh is used once are flattened into world space and
// share one BVH (overlapping per-instance BVHs would make every ray visit each of them); meshes used by
// several instances, and animated instances, get a per-mesh BVH built once. The top level holds the
// static BVH as one instance plus the other instances, and is the only part re-committed per frame.
// Alpha-tested materials reject hits in an Embree filter function: glTF alphaMode MASK below its cutoff,
// BLEND with probability 1 - alpha (stochastic coverage, for camera, shadow and path rays alike). The
// Tracer reads the Scene's meshes for that: the Scene must outlive it.
#include <embree3/rtcore.h>

#include <cstdint>
#include <memory>
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
  // The fields Embree reads and never writes that no ray changes (time 0, every mask bit, each lane's own id, no
  // flags), set once per packet instead of per ray: the ray queues' packets serve many traces.
  RayPacket16() {
    RTCRay16& r = rayhit.ray;
    for (int lane = 0; lane < 16; ++lane) {
      r.time[lane] = 0.0f;
      r.mask[lane] = 0xffffffffu;
      r.id[lane] = unsigned(lane);
      r.flags[lane] = 0;
    }
  }
  RTCRayHit16 rayhit;
  alignas(64) int valid[16];
  // Inline: the ray queues call it once per ray. Out of line, `di_shade` took 1.04-1.09x its time (2026-12-06).
  void set(int lane, const Ray& ray) {
    start(lane, ray.origin, ray.tmin, ray.tmax);
    rayhit.ray.dir_x[lane] = ray.direction.x;
    rayhit.ray.dir_y[lane] = ray.direction.y;
    rayhit.ray.dir_z[lane] = ray.direction.z;
  }
  void set_inactive(int lane) { valid[lane] = 0; }
  // Lanes [4r, 4r + 4), row r of a 4x4 pixel block: rays from `origin` along (dx[k], dy[k], dz[k]) for k < n,
  // from tmin 0 to infinity; the other lanes of the row inactive.
  void set_row4(int r, const vec3& origin, const float* dx, const float* dy, const float* dz, int n);

 private:
  // Everything of an active lane but its direction and the constructor's fields: origin, [tmin, tmax], no hit yet.
  // The origin by value: no store into the packet can change it, so set_row4's loop keeps it in registers.
  void start(int lane, vec3 origin, float tmin, float tmax) {
    RTCRay16& r = rayhit.ray;
    r.org_x[lane] = origin.x;
    r.org_y[lane] = origin.y;
    r.org_z[lane] = origin.z;
    r.tnear[lane] = tmin;
    r.tfar[lane] = tmax;
    rayhit.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
    rayhit.hit.instID[0][lane] = RTC_INVALID_GEOMETRY_ID;
    valid[lane] = -1;
  }
};

// What a query asks for: whether anything blocks the ray, or its closest hit.
enum class RayQuery { Occluded, Intersect };

class RayLog;

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
  // The hit of one lane after intersect16, with the scene's instance index. Inline: returned from a call, the
  // Hit went through memory and its caller's copy waited on the stores (22% of trace_paths' own time).
  Hit packet_hit(const RayPacket16& packet, int lane) const {
    Hit h;
    h.instance = lane_instance(packet, lane);
    if (h.instance == kNoHit) return h;
    h.t = packet.rayhit.ray.tfar[lane];
    h.prim = packet.rayhit.hit.primID[lane];
    h.barycentric = vec2(packet.rayhit.hit.u[lane], packet.rayhit.hit.v[lane]);
    return h;
  }
  // packet_hit of the 4 lanes [4r, 4r + 4) into arrays: scene instance (kNoHit where none), prim, Embree's u, v.
  void packet_hits_row4(const RayPacket16& packet, int r, uint32_t* instance, uint32_t* prim, float* u, float* v) const;
  static bool occluded_lane(const RayPacket16& packet, int lane) { return packet.rayhit.ray.tfar[lane] < 0.0f; }

  // A ray leaving surface point p (geometric normal ng) in direction d, offset to avoid self-hits.
  Ray spawn_ray(const vec3& p, const vec3& ng, const vec3& d) const {
    return Ray{offset_point(p, ng, d), d, 0.0f, kInfinity};
  }
  // A shadow ray from p (normal ng) to q (normal nq); both ends offset, tmax stops short of q.
  Ray spawn_ray_to(const vec3& p, const vec3& ng, const vec3& q, const vec3& nq) const {
    vec3 o = offset_point(p, ng, q - p);
    vec3 e = offset_point(q, nq, o - q);
    vec3 d = e - o;
    float len = glm::length(d);
    return Ray{o, d / std::max(len, 1e-30f), 0.0f, len * (1.0f - 1e-4f)};
  }
  float scene_radius() const { return scene_radius_; }
  // The scene-scale part of offset_point's offset (kernels that build spawn_ray_to's rays in lanes read it).
  float offset_epsilon() const { return epsilon_; }
  // With a log, every query is recorded into it before it is traced (the benchmark's replay of a frame's rays,
  // engine/ray_log.h); null: none (the default). Not to be changed while queries run.
  void set_ray_log(RayLog* log) { log_ = log; }
  RayLog* ray_log() const { return log_; }

 private:
  // Moves p off its surface along ng, on the side `towards` points to; the offset grows with the
  // scene's scale and with |p| (float spacing), so it works from millimetre to kilometre scenes.
  vec3 offset_point(const vec3& p, const vec3& ng, const vec3& towards) const {
    float magnitude = max_component(glm::abs(p));
    float eps = epsilon_ + 4e-6f * magnitude;
    return p + (glm::dot(ng, towards) >= 0.0f ? ng : -ng) * eps;
  }
  RTCGeometry new_triangle_geometry(const Scene& scene, int mesh, const mat4* transform);
  // Scene instance index of lane's hit after intersect16, kNoHit where it hit nothing or was inactive.
  uint32_t lane_instance(const RayPacket16& packet, int lane) const {
    const RTCHit16& hit = packet.rayhit.hit;
    return packet.valid[lane] && hit.geomID[lane] != RTC_INVALID_GEOMETRY_ID
               ? scene_instance(hit.instID[0][lane], hit.geomID[lane])
               : kNoHit;
  }
  // Scene instance index of a hit, from Embree's top-level and geometry ids.
  uint32_t scene_instance(uint32_t top_id, uint32_t geom_id) const {
    return top_id == static_top_id_ ? static_instances_[geom_id] : top_instances_[top_id];
  }

  RTCScene top_ = nullptr;
  RTCScene static_scene_ = nullptr;  // flattened static geometry (one BVH)
  uint32_t static_top_id_ = RTC_INVALID_GEOMETRY_ID;
  std::vector<uint32_t> static_instances_;                  // static scene geometry id -> scene instance
  std::vector<uint32_t> top_instances_;                     // top-level geometry id -> scene instance
  std::vector<RTCScene> mesh_scenes_;                       // per mesh, built when some instance of it is not flattened
  std::vector<std::pair<uint32_t, RTCGeometry>> animated_;  // (scene instance, its top-level geometry)
  std::vector<std::unique_ptr<struct AlphaMask>> alpha_masks_;  // per masked mesh, read by the filter
  float scene_radius_ = 1.0f;
  float epsilon_ = 1e-5f;
  RayLog* log_ = nullptr;
};

// Rays that neighbouring pixels trace independently (shadow rays, BSDF rays), traced 16 at a time in the
// order they are queued: add() queues a ray with a tag saying what its answer is for; every 16th add, and
// finish(), traces the packet (occlusion or closest hit) and calls answer(tag, packet, lane) for each of
// its rays in queue order (read the lane with Tracer::occluded_lane or Tracer::packet_hit).
template <class Tag, class Answer>
class RayQueue16 {
 public:
  RayQueue16(const Tracer& tracer, RayQuery query, Answer answer) : tracer_(tracer), query_(query), answer_(answer) {}
  void add(const Ray& ray, const Tag& tag) { add_if(true, ray, tag); }
  // add where `take`, without a branch on it (the ray goes into the next lane either way and stays only if taken):
  // for callers whose rays come at unpredictable places. `ray` must be readable either way.
  void add_if(bool take, const Ray& ray, const Tag& tag) {
    packet_.set(lanes_, ray);
    tags_[lanes_] = tag;
    lanes_ += take ? 1 : 0;
    if (lanes_ == 16) finish();
  }
  void finish() {
    if (lanes_ == 0) return;
    for (int k = lanes_; k < 16; ++k) packet_.set_inactive(k);
    if (query_ == RayQuery::Occluded)
      tracer_.occluded16(packet_);
    else
      tracer_.intersect16(packet_, false);
    for (int k = 0; k < lanes_; ++k) answer_(tags_[k], packet_, k);
    traced_ += uint64_t(lanes_);
    lanes_ = 0;
  }
  uint64_t traced() const { return traced_; }  // rays traced so far

 private:
  const Tracer& tracer_;
  RayQuery query_;
  Answer answer_;
  RayPacket16 packet_;
  Tag tags_[16];
  int lanes_ = 0;
  uint64_t traced_ = 0;
};
template <class Tag, class Answer>
RayQueue16<Tag, Answer> ray_queue16(const Tracer& tracer, RayQuery query, Answer answer) {
  return RayQueue16<Tag, Answer>(tracer, query, answer);
}

}  // namespace candela
