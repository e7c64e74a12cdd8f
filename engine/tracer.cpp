#include "engine/tracer.h"

#include <pmmintrin.h>
#include <xmmintrin.h>

#include <cstring>
#include <mutex>

#include "engine/check.h"

namespace candela {

void enable_ftz_daz() {
  _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
  _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
}

static void embree_error(void*, RTCError code, const char* message) {
  std::fprintf(stderr, "Embree error %d: %s\n", int(code), message ? message : "");
}

// One device for the whole process: a second device would silently start a second thread pool.
static RTCDevice shared_device() {
  static RTCDevice device = [] {
    RTCDevice d = rtcNewDevice(nullptr);
    CHECK(d != nullptr);
    rtcSetDeviceErrorFunction(d, embree_error, nullptr);
    return d;
  }();
  return device;
}

void RayPacket16::set(int lane, const Ray& ray) {
  RTCRay16& r = rayhit.ray;
  r.org_x[lane] = ray.origin.x; r.org_y[lane] = ray.origin.y; r.org_z[lane] = ray.origin.z;
  r.dir_x[lane] = ray.direction.x; r.dir_y[lane] = ray.direction.y; r.dir_z[lane] = ray.direction.z;
  r.tnear[lane] = ray.tmin;
  r.tfar[lane] = ray.tmax;
  r.time[lane] = 0.0f;
  r.mask[lane] = 0xffffffffu;
  r.id[lane] = unsigned(lane);
  r.flags[lane] = 0;
  rayhit.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
  rayhit.hit.instID[0][lane] = RTC_INVALID_GEOMETRY_ID;
  valid[lane] = -1;
}

Hit RayPacket16::hit(int lane) const {
  Hit h;
  if (!valid[lane] || rayhit.hit.geomID[lane] == RTC_INVALID_GEOMETRY_ID) return h;
  h.t = rayhit.ray.tfar[lane];
  h.instance = rayhit.hit.instID[0][lane];
  h.prim = rayhit.hit.primID[lane];
  h.barycentric = vec2(rayhit.hit.u[lane], rayhit.hit.v[lane]);
  return h;
}

// Builds one BVH per mesh (once) and the instance level over them.
Tracer::Tracer(const Scene& scene) {
  RTCDevice device = shared_device();
  mesh_scenes_.reserve(scene.meshes.size());
  for (const Mesh& mesh : scene.meshes) {
    RTCScene s = rtcNewScene(device);
    rtcSetSceneBuildQuality(s, RTC_BUILD_QUALITY_HIGH);
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    // Embree allocates these buffers itself, with the 16-byte padding its SIMD loads need.
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          sizeof(vec3), mesh.positions.size()));
    std::memcpy(v, mesh.positions.data(), mesh.positions.size() * sizeof(vec3));
    auto* idx = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                               sizeof(uvec3), mesh.triangles.size()));
    std::memcpy(idx, mesh.triangles.data(), mesh.triangles.size() * sizeof(uvec3));
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(s, g, 0);
    rtcReleaseGeometry(g);
    rtcCommitScene(s);
    mesh_scenes_.push_back(s);
  }
  top_ = rtcNewScene(device);
  bool any_animated = false;
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    CHECK(inst.mesh >= 0 && size_t(inst.mesh) < mesh_scenes_.size());
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(g, mesh_scenes_[inst.mesh]);
    rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, &inst.transform[0][0]);
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(top_, g, unsigned(i));
    instance_geoms_.push_back(g);
    if (inst.animated) { animated_.push_back(uint32_t(i)); any_animated = true; }
  }
  rtcSetSceneFlags(top_, any_animated ? RTC_SCENE_FLAG_DYNAMIC : RTC_SCENE_FLAG_NONE);
  rtcCommitScene(top_);
  Bounds3 b = scene.bounds();
  scene_radius_ = b.empty() ? 1.0f : std::max(0.5f * b.diagonal(), 1e-6f);
  epsilon_ = 1e-5f * scene_radius_;
}

Tracer::~Tracer() {
  for (RTCGeometry g : instance_geoms_) rtcReleaseGeometry(g);
  if (top_) rtcReleaseScene(top_);
  for (RTCScene s : mesh_scenes_) rtcReleaseScene(s);
}

void Tracer::update_instances(const Scene& scene) {
  if (animated_.empty()) return;
  for (uint32_t i : animated_) {
    rtcSetGeometryTransform(instance_geoms_[i], 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, &scene.instances[i].transform[0][0]);
    rtcCommitGeometry(instance_geoms_[i]);
  }
  rtcCommitScene(top_);
}

Hit Tracer::intersect(const Ray& ray) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh;
  rh.ray.org_x = ray.origin.x; rh.ray.org_y = ray.origin.y; rh.ray.org_z = ray.origin.z;
  rh.ray.dir_x = ray.direction.x; rh.ray.dir_y = ray.direction.y; rh.ray.dir_z = ray.direction.z;
  rh.ray.tnear = ray.tmin; rh.ray.tfar = ray.tmax;
  rh.ray.time = 0.0f; rh.ray.mask = 0xffffffffu; rh.ray.id = 0; rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(top_, &ctx, &rh);
  Hit h;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return h;
  h.t = rh.ray.tfar;
  h.instance = rh.hit.instID[0];
  h.prim = rh.hit.primID;
  h.barycentric = vec2(rh.hit.u, rh.hit.v);
  return h;
}

bool Tracer::occluded(const Ray& ray) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRay r;
  r.org_x = ray.origin.x; r.org_y = ray.origin.y; r.org_z = ray.origin.z;
  r.dir_x = ray.direction.x; r.dir_y = ray.direction.y; r.dir_z = ray.direction.z;
  r.tnear = ray.tmin; r.tfar = ray.tmax;
  r.time = 0.0f; r.mask = 0xffffffffu; r.id = 0; r.flags = 0;
  rtcOccluded1(top_, &ctx, &r);
  return r.tfar < 0.0f;
}

void Tracer::intersect16(RayPacket16& packet, bool coherent) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  if (coherent) ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  rtcIntersect16(packet.valid, top_, &ctx, &packet.rayhit);
}

void Tracer::occluded16(RayPacket16& packet) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  rtcOccluded16(packet.valid, top_, &ctx, &packet.rayhit.ray);
}

// Moves p off its surface along ng, on the side `towards` points to; the offset grows with the
// scene's scale and with |p| (float spacing), so it works from millimetre to kilometre scenes.
vec3 Tracer::offset_point(const vec3& p, const vec3& ng, const vec3& towards) const {
  float magnitude = max_component(glm::abs(p));
  float eps = epsilon_ + 4e-6f * magnitude;
  return p + (glm::dot(ng, towards) >= 0.0f ? ng : -ng) * eps;
}

Ray Tracer::spawn_ray(const vec3& p, const vec3& ng, const vec3& d) const {
  return Ray{offset_point(p, ng, d), d, 0.0f, kInfinity};
}

Ray Tracer::spawn_ray_to(const vec3& p, const vec3& ng, const vec3& q, const vec3& nq) const {
  vec3 o = offset_point(p, ng, q - p);
  vec3 e = offset_point(q, nq, o - q);
  vec3 d = e - o;
  float len = glm::length(d);
  return Ray{o, d / std::max(len, 1e-30f), 0.0f, len * (1.0f - 1e-4f)};
}

}  // namespace candela
