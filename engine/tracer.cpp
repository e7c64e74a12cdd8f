#include "engine/tracer.h"

#include <pmmintrin.h>
#include <xmmintrin.h>

#include <cstring>
#include <mutex>

#include "engine/check.h"
#include "engine/ray_log.h"
#include "engine/rng.h"

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

void RayPacket16::set_row4(int r, const vec3& origin, const float* dx, const float* dy, const float* dz, int n) {
  // From local copies of the origin and directions, so that each field is one 4-wide store (through the
  // references the compiler would have to assume every store may change them).
  const vec3 o = origin;
  float x[4], y[4], z[4];
  std::memcpy(x, dx, sizeof x), std::memcpy(y, dy, sizeof y), std::memcpy(z, dz, sizeof z);
  for (int k = 0, lane = 4 * r; k < 4; ++k, ++lane) {
    start(lane, o, 0.0f, kInfinity);
    rayhit.ray.dir_x[lane] = x[k], rayhit.ray.dir_y[lane] = y[k], rayhit.ray.dir_z[lane] = z[k];
    if (k >= n) set_inactive(lane);
  }
}

void Tracer::packet_hits_row4(const RayPacket16& packet, int r, uint32_t* instance, uint32_t* prim, float* u,
                              float* v) const {
  const RTCHit16& hit = packet.rayhit.hit;
  for (int k = 0; k < 4; ++k) instance[k] = lane_instance(packet, 4 * r + k);
  std::memcpy(prim, hit.primID + 4 * r, 4 * sizeof(uint32_t));
  std::memcpy(u, hit.u + 4 * r, 4 * sizeof(float));
  std::memcpy(v, hit.v + 4 * r, 4 * sizeof(float));
}

// What the alpha filter needs of a MASK or BLEND mesh: its UVs, triangles and the material's alpha inputs.
struct AlphaMask {
  const Mesh* mesh;
  const Material* material;
  const Texture* texture;  // null: alpha is the base colour factor's alone
};

// Base colour alpha (factor times texture) at hit i of a filter call.
static float hit_alpha(const AlphaMask& mask, const RTCFilterFunctionNArguments* args, unsigned i) {
  float alpha = mask.material->base_color.a;
  if (mask.texture && !mask.mesh->uv0.empty()) {
    const uvec3& tri = mask.mesh->triangles[RTCHitN_primID(args->hit, args->N, i)];
    float u = RTCHitN_u(args->hit, args->N, i), v = RTCHitN_v(args->hit, args->N, i);
    const std::vector<vec2>& uv =
        mask.material->base_color_tex.texcoord == 1 && !mask.mesh->uv1.empty() ? mask.mesh->uv1 : mask.mesh->uv0;
    vec2 st = uv[tri.x] * (1.0f - u - v) + uv[tri.y] * u + uv[tri.z] * v;
    alpha *= mask.texture->sample(mask.material->base_color_tex.apply(st)).a;
  }
  return alpha;
}

// A uniform number in [0, 1) that is a hash of ray i and the triangle it hit: the same ray through the same
// triangle always gets the same one (a re-traced shadow ray gives the same verdict, whatever the thread
// count), other rays get independent ones.
static float coverage_uniform(const RTCFilterFunctionNArguments* args, unsigned i) {
  RTCRayN* ray = args->ray;
  const unsigned n = args->N;
  float coords[6] = {RTCRayN_org_x(ray, n, i), RTCRayN_org_y(ray, n, i), RTCRayN_org_z(ray, n, i),
                     RTCRayN_dir_x(ray, n, i), RTCRayN_dir_y(ray, n, i), RTCRayN_dir_z(ray, n, i)};
  uint64_t h = mix64(uint64_t(RTCHitN_primID(args->hit, n, i)) << 32 | RTCHitN_instID(args->hit, n, i, 0));
  for (float c : coords) {
    uint32_t bits;
    std::memcpy(&bits, &c, 4);
    h = mix64(h ^ bits);
  }
  return float(h >> 40) * 0x1p-24f;
}

// Embree filter (intersection and occlusion): MASK rejects hits where alpha < cutoff; BLEND keeps a hit with
// probability alpha (stochastic coverage: on average a surface of alpha 0.5 stops half the rays).
static void alpha_filter(const RTCFilterFunctionNArguments* args) {
  const auto* mask = static_cast<const AlphaMask*>(args->geometryUserPtr);
  const bool blend = mask->material->alpha_mode == AlphaMode::Blend;
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    float alpha = hit_alpha(*mask, args, i);
    bool keep = blend ? coverage_uniform(args, i) < alpha : alpha >= mask->material->alpha_cutoff;
    if (!keep) args->valid[i] = 0;
  }
}

// A triangle geometry of one mesh (vertices copied into Embree's padded buffers, optionally moved to
// world space), with the alpha filter attached when its material is masked.
RTCGeometry Tracer::new_triangle_geometry(const Scene& scene, int mesh_index, const mat4* transform) {
  const Mesh& mesh = scene.meshes[mesh_index];
  RTCDevice device = shared_device();
  RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<vec3*>(
      rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, sizeof(vec3), mesh.positions.size()));
  for (size_t k = 0; k < mesh.positions.size(); ++k)
    v[k] = transform ? transform_point(*transform, mesh.positions[k]) : mesh.positions[k];
  auto* idx = static_cast<uvec3*>(
      rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, sizeof(uvec3), mesh.triangles.size()));
  std::memcpy(idx, mesh.triangles.data(), mesh.triangles.size() * sizeof(uvec3));
  const Material& material = scene.materials[mesh.material];
  if (material.alpha_mode != AlphaMode::Opaque) {
    const Texture* tex = material.base_color_tex.valid() ? &scene.textures[material.base_color_tex.texture] : nullptr;
    alpha_masks_.push_back(std::make_unique<AlphaMask>(AlphaMask{&mesh, &material, tex}));
    rtcSetGeometryUserData(g, alpha_masks_.back().get());
    rtcSetGeometryIntersectFilterFunction(g, alpha_filter);
    rtcSetGeometryOccludedFilterFunction(g, alpha_filter);
  }
  rtcCommitGeometry(g);
  return g;
}

// Adds an instance of `child` with `transform` to the top level; returns its geometry id there.
static RTCGeometry attach_instance(RTCDevice device, RTCScene top, RTCScene child, const mat4& transform, uint32_t id) {
  RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
  rtcSetGeometryInstancedScene(g, child);
  rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, &transform[0][0]);
  rtcCommitGeometry(g);
  rtcAttachGeometryByID(top, g, id);
  return g;
}

// Builds the static BVH over flattened instances, per-mesh BVHs for the rest, and the top level.
Tracer::Tracer(const Scene& scene) {
  RTCDevice device = shared_device();
  std::vector<int> uses(scene.meshes.size(), 0);
  for (const Instance& inst : scene.instances) {
    CHECK(inst.mesh >= 0 && size_t(inst.mesh) < scene.meshes.size());
    ++uses[inst.mesh];
  }
  auto flattened = [&](const Instance& inst) { return !inst.animated && uses[inst.mesh] == 1; };

  for (uint32_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    if (!flattened(inst)) continue;
    if (!static_scene_) {
      static_scene_ = rtcNewScene(device);
      rtcSetSceneBuildQuality(static_scene_, RTC_BUILD_QUALITY_HIGH);
    }
    RTCGeometry g = new_triangle_geometry(scene, inst.mesh, &inst.transform);
    rtcAttachGeometryByID(static_scene_, g, uint32_t(static_instances_.size()));
    rtcReleaseGeometry(g);
    static_instances_.push_back(i);
  }

  mesh_scenes_.assign(scene.meshes.size(), nullptr);
  top_ = rtcNewScene(device);
  if (static_scene_) {
    rtcCommitScene(static_scene_);
    static_top_id_ = 0;
    top_instances_.push_back(kNoHit);
    rtcReleaseGeometry(attach_instance(device, top_, static_scene_, mat4(1.0f), static_top_id_));
  }
  for (uint32_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    if (flattened(inst)) continue;
    RTCScene& ms = mesh_scenes_[inst.mesh];
    if (!ms) {
      ms = rtcNewScene(device);
      rtcSetSceneBuildQuality(ms, RTC_BUILD_QUALITY_HIGH);
      RTCGeometry g = new_triangle_geometry(scene, inst.mesh, nullptr);
      rtcAttachGeometryByID(ms, g, 0);
      rtcReleaseGeometry(g);
      rtcCommitScene(ms);
    }
    uint32_t id = uint32_t(top_instances_.size());
    top_instances_.push_back(i);
    RTCGeometry g = attach_instance(device, top_, ms, inst.transform, id);
    if (inst.animated)
      animated_.push_back({i, g});
    else
      rtcReleaseGeometry(g);
  }
  rtcSetSceneFlags(top_, animated_.empty() ? RTC_SCENE_FLAG_NONE : RTC_SCENE_FLAG_DYNAMIC);
  rtcCommitScene(top_);
  Bounds3 b = scene.bounds();
  scene_radius_ = b.empty() ? 1.0f : std::max(0.5f * b.diagonal(), 1e-6f);
  epsilon_ = 1e-5f * scene_radius_;
}

Tracer::~Tracer() {
  for (auto& [instance, g] : animated_) rtcReleaseGeometry(g);
  rtcReleaseScene(top_);
  if (static_scene_) rtcReleaseScene(static_scene_);
  for (RTCScene s : mesh_scenes_)
    if (s) rtcReleaseScene(s);
}

void Tracer::update_instances(const Scene& scene) {
  if (animated_.empty()) return;
  for (auto& [instance, g] : animated_) {
    rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, &scene.instances[instance].transform[0][0]);
    rtcCommitGeometry(g);
  }
  rtcCommitScene(top_);
}

Hit Tracer::intersect(const Ray& ray) const {
  if (log_) log_->record(ray, RayQuery::Intersect);
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh;
  rh.ray.org_x = ray.origin.x;
  rh.ray.org_y = ray.origin.y;
  rh.ray.org_z = ray.origin.z;
  rh.ray.dir_x = ray.direction.x;
  rh.ray.dir_y = ray.direction.y;
  rh.ray.dir_z = ray.direction.z;
  rh.ray.tnear = ray.tmin;
  rh.ray.tfar = ray.tmax;
  rh.ray.time = 0.0f;
  rh.ray.mask = 0xffffffffu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(top_, &ctx, &rh);
  Hit h;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return h;
  h.t = rh.ray.tfar;
  h.instance = scene_instance(rh.hit.instID[0], rh.hit.geomID);
  h.prim = rh.hit.primID;
  h.barycentric = vec2(rh.hit.u, rh.hit.v);
  return h;
}

bool Tracer::occluded(const Ray& ray) const {
  if (log_) log_->record(ray, RayQuery::Occluded);
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRay r;
  r.org_x = ray.origin.x;
  r.org_y = ray.origin.y;
  r.org_z = ray.origin.z;
  r.dir_x = ray.direction.x;
  r.dir_y = ray.direction.y;
  r.dir_z = ray.direction.z;
  r.tnear = ray.tmin;
  r.tfar = ray.tmax;
  r.time = 0.0f;
  r.mask = 0xffffffffu;
  r.id = 0;
  r.flags = 0;
  rtcOccluded1(top_, &ctx, &r);
  return r.tfar < 0.0f;
}

void Tracer::intersect16(RayPacket16& packet, bool coherent) const {
  if (log_) log_->record(packet, RayQuery::Intersect, coherent);
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  if (coherent) ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  rtcIntersect16(packet.valid, top_, &ctx, &packet.rayhit);
}

void Tracer::occluded16(RayPacket16& packet) const {
  if (log_) log_->record(packet, RayQuery::Occluded, false);
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  rtcOccluded16(packet.valid, top_, &ctx, &packet.rayhit.ray);
}

}  // namespace candela
