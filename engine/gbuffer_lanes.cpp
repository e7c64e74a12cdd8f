// The G-buffer kernel (gbuffer_lanes.h), compiled once per instruction set by Highway's foreach_target.h and
// dispatched at run time. Each step names the scalar function whose arithmetic it repeats, in the same order
// (engine/surface.cpp world_triangle and surface_at, engine/camera.h Camera::view_depth and Camera::project,
// engine/gbuffer.cpp write_pixel).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "engine/gbuffer_lanes.cpp"
#include <cstring>

#include "hwy/cache_control.h"

#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"
#include "engine/lanes-inl.h"
#include "engine/gbuffer_lanes.h"
#include "engine/surface.h"

HWY_BEFORE_NAMESPACE();
namespace candela {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using F = GBufferInstances::Field;

// Per-frame constants of the kernel: the two cameras and the background, broadcast once.
struct Cameras {
  V3 eye, forward;                                 // Camera::view_depth
  V3 prev_eye, prev_forward, prev_right, prev_up;  // Camera::project of the previous camera
  V prev_tan_x, prev_tan_y, prev_width, prev_height;
  V3 environment;
  bool still;  // the cameras are equal: only animated instances move
};

V3 broadcast(D d, const vec3& v) { return {hn::Set(d, v.x), hn::Set(d, v.y), hn::Set(d, v.z)}; }
V3 neg(const V3& v) { return {hn::Neg(v.x), hn::Neg(v.y), hn::Neg(v.z)}; }
V3 sub(const V3& a, const V3& b) { return {hn::Sub(a.x, b.x), hn::Sub(a.y, b.y), hn::Sub(a.z, b.z)}; }
V3 select(M m, const V3& a, const V3& b) {
  return {hn::IfThenElse(m, a.x, b.x), hn::IfThenElse(m, a.y, b.y), hn::IfThenElse(m, a.z, b.z)};
}
V3 zero_unless(M m, const V3& a) {
  return {hn::IfThenElseZero(m, a.x), hn::IfThenElseZero(m, a.y), hn::IfThenElseZero(m, a.z)};
}
// a w + b u + c v in glm's order: (a w + b u) + c v.
V3 interpolate(const V3& a, const V3& b, const V3& c, V w, V u, V v) {
  auto one = [&](V x, V y, V z) { return hn::Add(hn::Add(hn::Mul(x, w), hn::Mul(y, u)), hn::Mul(z, v)); };
  return {one(a.x, b.x, c.x), one(a.y, b.y, c.y), one(a.z, b.z, c.z)};
}

// The instance records' fields for every lane: one broadcast per field where the vector's hits share an
// instance (most vectors: neighbouring pixels see the same object), else a table of lanes per field.
struct Records {
  const float* uniform;  // the hits' common record, or null: read `table`
  const float* table;    // kFields vectors: field k of each lane's record (0 in lanes without a hit)
  V operator()(D d, int k) const {
    return uniform ? hn::Set(d, uniform[k]) : hn::Load(d, table + size_t(k) * hn::Lanes(d));
  }
  V3 vec3_at(D d, int k) const { return {(*this)(d, k), (*this)(d, k + 1), (*this)(d, k + 2)}; }
  // transform_point: row r of m * vec4(p, 1) as glm evaluates it, (m0 x + m1 y) + (m2 z + m3 * 1).
  V3 transform_point(D d, int k, const V3& p) const {
    auto row = [&](int r) {
      const V m0 = (*this)(d, k + r), m1 = (*this)(d, k + 3 + r), m2 = (*this)(d, k + 6 + r),
              m3 = (*this)(d, k + 9 + r);
      return hn::Add(hn::Add(hn::Mul(m0, p.x), hn::Mul(m1, p.y)), hn::Add(hn::Mul(m2, p.z), m3));
    };
    return {row(0), row(1), row(2)};
  }
  // mat3 * vec3 as glm evaluates it: (m0 x + m1 y) + m2 z.
  V3 transform_vector(D d, int k, const V3& v) const {
    auto row = [&](int r) {
      const V m0 = (*this)(d, k + r), m1 = (*this)(d, k + 3 + r), m2 = (*this)(d, k + 6 + r);
      return hn::Add(hn::Add(hn::Mul(m0, v.x), hn::Mul(m1, v.y)), hn::Mul(m2, v.z));
    };
    return {row(0), row(1), row(2)};
  }
};
// The Records of a vector of hits: finds the vector's distinct instances (a scan per instance); where there is
// more than one, fills `table` (kFields vectors) with each field blended from their records, ~2 operations per
// field and instance instead of a gather per field read.
Records instance_records(D d, const float* records, const uint32_t* lane_instance, VU instance, M hit, float* table) {
  const DU du;
  constexpr int kMax = HWY_MAX_BYTES / sizeof(float);
  uint32_t ids[kMax];
  M masks[kMax];
  int distinct = 0;
  for (M todo = hit; !hn::AllFalse(d, todo); ++distinct) {
    ids[distinct] = lane_instance[hn::FindKnownFirstTrue(d, todo)];
    masks[distinct] = hn::RebindMask(d, hn::Eq(instance, hn::Set(du, ids[distinct])));
    todo = hn::AndNot(masks[distinct], todo);
  }
  // No hit: any record will do, no plane keeps its fields.
  if (distinct <= 1) return {records + size_t(distinct == 1 ? ids[0] : 0) * GBufferInstances::kFields, nullptr};
  for (int k = 0; k < GBufferInstances::kFields; ++k) {
    V field = hn::Zero(d);
    for (int j = 0; j < distinct; ++j)
      field =
          hn::IfThenElse(masks[j], hn::Set(d, records[size_t(ids[j]) * GBufferInstances::kFields + size_t(k)]), field);
    hn::Store(field, d, table + size_t(k) * hn::Lanes(d));
  }
  return {nullptr, table};
}

// Slots [s, s + count) of a row of hits as one vector (count <= lanes; later lanes count as misses): their
// instances, which lanes hit, and the hits' records (`table`: kRecordTable floats the records may point into).
constexpr size_t kRecordTable = GBufferInstances::kFields * (HWY_MAX_BYTES / sizeof(float));
struct Hits {
  VU instance;
  M hit;
  Records records;
};
Hits hits_at(D d, const GBufferInstances& instances, const PrimaryHitLanes& h, int s, int count, float* table) {
  const DU du;
  const VU no_hit = hn::Set(du, kNoHit);
  const VU instance = hn::IfThenElse(hn::FirstN(du, size_t(count)), hn::Load(du, h.instance + s), no_hit);
  const M hit = hn::RebindMask(d, hn::Ne(instance, no_hit));
  return {instance, hit, instance_records(d, instances.records.data(), h.instance + s, instance, hit, table)};
}

M is_finite(D d, const V3& v) {
  const V inf = hn::Set(d, kInfinity);
  return hn::And(hn::And(hn::Lt(hn::Abs(v.x), inf), hn::Lt(hn::Abs(v.y), inf)), hn::Lt(hn::Abs(v.z), inf));
}

// Camera::project of the previous camera: `film` gets the film position where `valid`.
void project(D d, const Cameras& c, const V3& p, M& valid, V& film_x, V& film_y) {
  const V3 v = sub(p, c.prev_eye);
  const V z = dot(v, c.prev_forward);
  const V one = hn::Set(d, 1.0f), half = hn::Set(d, 0.5f);
  valid = hn::Not(hn::Le(z, hn::Zero(d)));
  const V sx = hn::Div(dot(v, c.prev_right), hn::Mul(z, c.prev_tan_x));
  const V sy = hn::Div(dot(v, c.prev_up), hn::Mul(z, c.prev_tan_y));
  film_x = hn::Mul(hn::Mul(hn::Add(sx, one), half), c.prev_width);
  film_y = hn::Mul(hn::Mul(hn::Sub(one, sy), half), c.prev_height);
}

// Stores lanes [0, n) of each vector at dst (n <= lanes): a whole vector at an aligned address (the planes are
// cache-line aligned) as streaming stores, which skip reading the lines they overwrite; a part of a row
// through a buffer.
template <class T, class Vec, class Tag>
void store_first(Tag t, Vec v, int n, T* dst) {
  if (n == int(hn::Lanes(t))) {
    if (reinterpret_cast<uintptr_t>(dst) % (sizeof(T) * hn::Lanes(t)) == 0) return hn::Stream(v, t, dst);
    return hn::StoreU(v, t, dst);
  }
  HWY_ALIGN T buffer[16];
  hn::Store(v, t, buffer);
  std::memcpy(dst, buffer, sizeof(T) * size_t(n));
}
// The same for `count` floats already in an aligned buffer.
void stream_floats(D d, const float* buffer, size_t count, float* dst) {
  if (reinterpret_cast<uintptr_t>(dst) % (sizeof(float) * hn::Lanes(d)) != 0)
    return (void)std::memcpy(dst, buffer, sizeof(float) * count);
  for (size_t k = 0; k < count; k += hn::Lanes(d)) hn::Stream(hn::Load(d, buffer + k), d, dst + k);
}
void store_first(D d, const V3& v, int n, vec3* dst) {
  HWY_ALIGN float buffer[48];
  hn::StoreInterleaved3(v.x, v.y, v.z, d, buffer);
  if (n == int(hn::Lanes(d))) return stream_floats(d, buffer, 3 * size_t(n), &dst->x);
  std::memcpy(dst, buffer, sizeof(vec3) * size_t(n));
}
void store_first(D d, V x, V y, int n, vec2* dst) {
  HWY_ALIGN float buffer[32];
  hn::StoreInterleaved2(x, y, d, buffer);
  if (n == int(hn::Lanes(d))) return stream_floats(d, buffer, 2 * size_t(n), &dst->x);
  std::memcpy(dst, buffer, sizeof(vec2) * size_t(n));
}

// floor(v + 0.5) as an integer: engine/math.h round_nearest.
VI round_nearest(D d, V v) { return hn::ConvertTo(DI(), hn::Floor(hn::Add(v, hn::Set(d, 0.5f)))); }
// engine/octahedral.h oct_encode: the L1 projection, the lower half folded over, 16 bits per coordinate.
VU oct_encode(D d, const V3& n) {
  const V one = hn::Set(d, 1.0f), half = hn::Set(d, 0.5f);
  const V l1 = hn::Add(hn::Add(hn::Abs(n.x), hn::Abs(n.y)), hn::Abs(n.z));
  const V x = hn::Div(n.x, l1), y = hn::Div(n.y, l1);
  const M lower = hn::Lt(n.z, hn::Zero(d));
  const V fx = hn::IfThenElse(lower, hn::Mul(hn::Sub(one, hn::Abs(y)), hn::CopySign(one, x)), x);
  const V fy = hn::IfThenElse(lower, hn::Mul(hn::Sub(one, hn::Abs(x)), hn::CopySign(one, y)), y);
  auto quantise = [&](V v) {
    const V clamped = min_of(max_of(v, hn::Set(d, -1.0f)), one);
    return hn::BitCast(DU(), round_nearest(d, hn::Mul(hn::Add(hn::Mul(clamped, half), half), hn::Set(d, 65535.0f))));
  };
  return hn::Or(quantise(fx), hn::ShiftLeft<16>(quantise(fy)));
}
// engine/packed_surface.cpp unorm8: [0, 1] in 8 bits.
VU unorm8(D d, V v) {
  const V clamped = min_of(max_of(v, hn::Zero(d)), hn::Set(d, 1.0f));
  return hn::BitCast(DU(), round_nearest(d, hn::Mul(clamped, hn::Set(d, 255.0f))));
}
// engine/packed_surface.cpp pack_surface: writes lanes [0, n) at dst, whole vectors with streaming stores.
void store_packed(D d, M hit, const V3& position, V depth, const V3& ns, const V3& ng, const V3& albedo,
                  const V3& material, const V3& specular_f0, int n, PackedSurface* dst) {
  static_assert(sizeof(PackedSurface) == 8 * sizeof(float), "a packed surface is 8 floats");
  const DU du;
  const V one = hn::Set(d, 1.0f), zero = hn::Zero(d);
  auto sqrt_unit = [&](V v) { return hn::Sqrt(min_of(max_of(v, zero), one)); };  // glm::clamp, then sqrt
  const VU a = hn::Or(hn::Or(unorm8(d, sqrt_unit(albedo.x)), hn::ShiftLeft<8>(unorm8(d, sqrt_unit(albedo.y)))),
                      hn::ShiftLeft<16>(unorm8(d, sqrt_unit(albedo.z))));
  const V f0 = hn::Sqrt(max_of3(specular_f0.x, specular_f0.y, specular_f0.z));  // max_component
  const VU m = hn::Or(hn::Or(unorm8(d, material.x), hn::ShiftLeft<8>(unorm8(d, material.y))),
                      hn::Or(hn::ShiftLeft<16>(unorm8(d, material.z)), hn::ShiftLeft<24>(unorm8(d, f0))));
  const VU none = hn::Zero(du);
  const auto hit_u = hn::RebindMask(du, hit);
  // Each pixel's 8 fields as 4 pairs of 32-bit values, written as interleaved 64-bit lanes. InterleaveLower and
  // InterleaveUpper pair lanes 0-1 and 2-3 of each 128-bit block, so the lanes are first permuted for the lower
  // halves to hold pixels [0, N/2) in order and the upper ones [N/2, N).
  const int lanes = int(hn::Lanes(d));
  HWY_ALIGN int32_t order[HWY_MAX_BYTES / sizeof(float)];
  for (int lane = 0; lane < lanes; ++lane) order[lane] = ((lane & 3) < 2 ? 0 : lanes / 2) + 2 * (lane / 4) + (lane & 1);
  const auto permute = hn::SetTableIndices(du, order);
  auto field = [&](VU v) { return hn::TableLookupLanes(v, permute); };
  auto bits = [&](V v) { return field(hn::BitCast(du, v)); };
  const VU fields[8] = {bits(hn::IfThenElseZero(hit, position.x)),
                        bits(hn::IfThenElseZero(hit, position.y)),
                        bits(hn::IfThenElseZero(hit, position.z)),
                        bits(hn::IfThenElse(hit, depth, hn::Set(d, kInfinity))),
                        field(hn::IfThenElse(hit_u, oct_encode(d, ns), none)),
                        field(hn::IfThenElse(hit_u, oct_encode(d, ng), none)),
                        field(hn::IfThenElse(hit_u, a, none)),
                        field(hn::IfThenElse(hit_u, m, none))};
  const hn::Repartition<uint64_t, DU> d64;
  HWY_ALIGN uint64_t records[4 * HWY_MAX_BYTES / sizeof(uint64_t) * 2];
  auto pairs = [&](bool upper, uint64_t* out) {
    auto pair = [&](int k) {
      return hn::BitCast(d64, upper ? hn::InterleaveUpper(du, fields[k], fields[k + 1])
                                    : hn::InterleaveLower(du, fields[k], fields[k + 1]));
    };
    hn::StoreInterleaved4(pair(0), pair(2), pair(4), pair(6), d64, out);
  };
  pairs(false, records);
  pairs(true, records + 2 * size_t(lanes));
  if (n == lanes) return stream_floats(d, reinterpret_cast<const float*>(records), 8 * size_t(n), &dst->position.x);
  std::memcpy(dst, records, sizeof(PackedSurface) * size_t(n));
}

// The hit triangles' object-space corners p[k] and vertex normals n[k] (0 where the mesh has none, and in lanes
// without a hit), world_triangle's and surface_at's inputs. Loaded once per distinct triangle of the vector and
// broadcast into the lanes that hit it: neighbouring pixels mostly see one triangle, so this is ~20 scalar
// loads and ~40 vector operations per triangle rather than per lane.
void triangle_corners(D d, const GBufferInstances& instances, const PrimaryHitLanes& h, int s, VU instance, M hit,
                      V3 p[3], V3 n[3]) {
  const DU du;
  const VU prim = hn::Load(du, h.prim + s);
  for (int k = 0; k < 3; ++k) p[k] = n[k] = V3{hn::Zero(d), hn::Zero(d), hn::Zero(d)};
  for (M todo = hit; !hn::AllFalse(d, todo);) {
    const size_t lane = hn::FindKnownFirstTrue(d, todo);
    const uint32_t i = h.instance[size_t(s) + lane], t = h.prim[size_t(s) + lane];
    const M same = hn::RebindMask(d, hn::And(hn::Eq(instance, hn::Set(du, i)), hn::Eq(prim, hn::Set(du, t))));
    const GBufferInstances::MeshArrays& a = instances.meshes[i];
    const uint32_t* tri = a.triangles + size_t(t) * 3;
    for (int k = 0; k < 3; ++k) {
      const float* corner = a.positions + size_t(tri[k]) * 3;
      p[k] = {hn::IfThenElse(same, hn::Set(d, corner[0]), p[k].x), hn::IfThenElse(same, hn::Set(d, corner[1]), p[k].y),
              hn::IfThenElse(same, hn::Set(d, corner[2]), p[k].z)};
      if (!a.normals) continue;
      const float* normal = a.normals + size_t(tri[k]) * 3;
      n[k] = {hn::IfThenElse(same, hn::Set(d, normal[0]), n[k].x), hn::IfThenElse(same, hn::Set(d, normal[1]), n[k].y),
              hn::IfThenElse(same, hn::Set(d, normal[2]), n[k].z)};
    }
    todo = hn::AndNot(same, todo);
  }
}

// One vector of hits' surfaces, surface_at's arithmetic for plain materials: world_triangle, the position, the
// geometric and shading normals turned to wo's side, whether wo sees the front face, and the emission.
struct Surface {
  V3 position, ng, ns;
  M front;
  V3 emission;
};
Surface surface(D d, const GBufferInstances& instances, const PrimaryHitLanes& h, int s, VU instance, M hit,
                const Records& r, const V3& wo) {
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  const V u = hn::Load(d, h.u + s), v = hn::Load(d, h.v + s);
  // world_triangle: the corners in world space.
  V3 p[3], vn[3];
  triangle_corners(d, instances, h, s, instance, hit, p, vn);
  for (int k = 0; k < 3; ++k) p[k] = r.transform_point(d, F::kTransform, p[k]);
  // surface_at: position, the front face's normal, the side wo sees.
  const V w = hn::Sub(hn::Sub(one, u), v);
  const V3 position = interpolate(p[0], p[1], p[2], w, u, v);
  const V3 face = cross(sub(p[1], p[0]), sub(p[2], p[0]));
  const V3 n_front = normalize(d, select(hn::Gt(r(d, F::kMirrored), zero), neg(face), face));
  const M front = hn::Ge(dot(n_front, wo), zero);
  const V3 ng = select(front, n_front, neg(n_front));
  // surface_at: the interpolated vertex normal through the normal matrix, on the front side, then on wo's.
  const V3 interpolated =
      normalize(d, r.transform_vector(d, F::kNormalMatrix, interpolate(vn[0], vn[1], vn[2], w, u, v)));
  V3 ns = select(hn::Gt(r(d, F::kHasNormals), zero), interpolated, n_front);
  ns = select(is_finite(d, ns), ns, n_front);
  ns = select(hn::Lt(dot(ns, n_front), zero), neg(ns), ns);
  ns = select(front, ns, neg(ns));
  ns = select(hn::Le(dot(ns, wo), hn::Set(d, 1e-4f)), ng, ns);
  // surface_at: the material's emission on the front side or both (kEmission is 0 unless it emits).
  const V3 emission = zero_unless(hn::Or(front, hn::Gt(r(d, F::kDoubleSided), zero)), r.vec3_at(d, F::kEmission));
  return {position, ng, ns, front, emission};
}

// One vector of slots [s, s + lanes): writes the first `count` of them to pixels [pixel, pixel + n).
void shade(D d, const GBufferInstances& instances, const Cameras& c, const PrimaryHitLanes& h, int s, int count,
           size_t pixel, GBuffer& out) {
  const DU du;
  const V zero = hn::Zero(d);
  HWY_ALIGN float table[kRecordTable];
  const Hits hits = hits_at(d, instances, h, s, count, table);
  const VU& instance = hits.instance;
  const M hit = hits.hit;
  const Records& r = hits.records;
  const V3 dir = load3(d, h.dir[0], h.dir[1], h.dir[2], s);
  const V film_x = hn::Load(d, h.film[0] + s), film_y = hn::Load(d, h.film[1] + s);

  const Surface surf = surface(d, instances, h, s, instance, hit, r, neg(dir));
  const V3& position = surf.position;
  const V3 &ng = surf.ng, &ns = surf.ns, &emission = surf.emission;

  // write_pixel: depth, the motion vector of the point (through last frame's instance transform if animated)
  // or, for a miss, of the direction (Camera::project of prev_eye + dir); 0 where neither moved.
  // Skipped where nothing moves: a still camera and no animated hit (most vectors of most frames).
  const V depth = dot(sub(position, c.eye), c.forward);
  const M animated = hn::And(hit, hn::Gt(r(d, F::kAnimated), zero));
  const bool any_animated = !hn::AllFalse(d, animated);
  V motion_x = zero, motion_y = zero;
  if (!c.still || any_animated) {
    const V3 moved =
        any_animated ? select(animated, r.transform_point(d, F::kPrevFromCurrent, position), position) : position;
    const V3 far_point{hn::Add(c.prev_eye.x, dir.x), hn::Add(c.prev_eye.y, dir.y), hn::Add(c.prev_eye.z, dir.z)};
    M projected;
    V prev_x, prev_y;
    project(d, c, select(hit, moved, far_point), projected, prev_x, prev_y);
    if (c.still) projected = hn::And(projected, animated);
    motion_x = hn::IfThenElseZero(projected, hn::Sub(prev_x, film_x));
    motion_y = hn::IfThenElseZero(projected, hn::Sub(prev_y, film_y));
  }
  store_first(d, motion_x, motion_y, count, out.motion.data() + pixel);

  // surface_at: the material's constants.
  const V3 material{r(d, F::kRoughness), r(d, F::kMetallic), r(d, F::kSpecular)};
  store_first(d, zero_unless(hit, position), count, out.position.data() + pixel);
  store_first(d, zero_unless(hit, ns), count, out.shading_normal.data() + pixel);
  store_first(d, zero_unless(hit, ng), count, out.geometric_normal.data() + pixel);
  store_first(d, hn::IfThenElse(hit, depth, hn::Set(d, kInfinity)), count, out.depth.data() + pixel);
  store_first(d, zero_unless(hit, r.vec3_at(d, F::kBaseColor)), count, out.albedo.data() + pixel);
  store_first(d, zero_unless(hit, material), count, out.material.data() + pixel);
  store_first(d, zero_unless(hit, r.vec3_at(d, F::kSpecularF0)), count, out.specular_f0.data() + pixel);
  store_first(d, select(hit, emission, c.environment), count, out.emission.data() + pixel);
  if (!out.packed.empty())
    store_packed(d, hit, position, depth, ns, ng, r.vec3_at(d, F::kBaseColor), material, r.vec3_at(d, F::kSpecularF0),
                 count, out.packed.data() + pixel);
  store_first(du, instance, count, out.instance.data() + pixel);
}

// Film positions (the pixel plus its jitter) and Camera::direction through them: normalize(forward +
// right ((2x / width - 1) tan_x) - up ((2y / height - 1) tan_y)).
void PrimaryRaysLanes(const Camera& camera, int x0, int y, int count, const float* jitter_x, const float* jitter_y,
                      PrimaryHitLanes& row, vec2* jitter) {
  const D d;
  const DI di;
  const V two = hn::Set(d, 2.0f), one = hn::Set(d, 1.0f), half = hn::Set(d, 0.5f), row_y = hn::Set(d, float(y));
  const V width = hn::Set(d, float(camera.width())), height = hn::Set(d, float(camera.height()));
  const V tan_x = hn::Set(d, camera.tan_half_x()), tan_y = hn::Set(d, camera.tan_half_y());
  const V3 forward = broadcast(d, camera.forward()), right = broadcast(d, camera.right()),
           up = broadcast(d, camera.up());
  const int lanes = int(hn::Lanes(d));
  for (int s = 0; s < count; s += lanes) {
    const int n = std::min(lanes, count - s);
    const M valid = hn::FirstN(d, size_t(n));
    const V jx = jitter_x ? hn::IfThenElseZero(valid, hn::Load(d, jitter_x + s)) : half;
    const V jy = jitter_y ? hn::IfThenElseZero(valid, hn::Load(d, jitter_y + s)) : half;
    store_first(d, jx, jy, n, jitter + s);
    const V film_x = hn::Add(hn::ConvertTo(d, hn::Iota(di, x0 + s)), jx), film_y = hn::Add(row_y, jy);
    hn::Store(film_x, d, row.film[0] + s);
    hn::Store(film_y, d, row.film[1] + s);
    const V a = hn::Mul(hn::Sub(hn::Div(hn::Mul(two, film_x), width), one), tan_x);
    const V b = hn::Mul(hn::Sub(hn::Div(hn::Mul(two, film_y), height), one), tan_y);
    auto axis = [&](V f, V r, V u) { return hn::Sub(hn::Add(f, hn::Mul(r, a)), hn::Mul(u, b)); };
    store3(
        d,
        normalize(d, {axis(forward.x, right.x, up.x), axis(forward.y, right.y, up.y), axis(forward.z, right.z, up.z)}),
        row.dir[0], row.dir[1], row.dir[2], s);
  }
}

void ShadeGBufferLanes(const GBufferInstances& instances, const Camera& camera, const Camera& prev_camera, bool still,
                       const vec3& environment, const PrimaryHitLanes& hits, int count, size_t first_pixel,
                       GBuffer& out) {
  const D d;
  const Cameras c{broadcast(d, camera.position()),
                  broadcast(d, camera.forward()),
                  broadcast(d, prev_camera.position()),
                  broadcast(d, prev_camera.forward()),
                  broadcast(d, prev_camera.right()),
                  broadcast(d, prev_camera.up()),
                  hn::Set(d, prev_camera.tan_half_x()),
                  hn::Set(d, prev_camera.tan_half_y()),
                  hn::Set(d, float(prev_camera.width())),
                  hn::Set(d, float(prev_camera.height())),
                  broadcast(d, environment),
                  still};
  const int lanes = int(hn::Lanes(d));
  for (int s = 0; s < count; s += lanes)
    shade(d, instances, c, hits, s, std::min(lanes, count - s), first_pixel + size_t(s), out);
  hwy::FlushStream();  // the streaming stores are seen before any later store
}

// surface_at for slots [0, count) of `hits` on plain materials (others and misses are left alone): the fields of
// SurfacePoint a path vertex reads, in lanes, then written out slot by slot.
void SurfacePointsLanes(const GBufferInstances& instances, const PrimaryHitLanes& hits, int count, SurfacePoint* out) {
  const D d;
  const int lanes = int(hn::Lanes(d));
  constexpr int kMax = HWY_MAX_BYTES / sizeof(float);
  for (int s = 0; s < count; s += lanes) {
    HWY_ALIGN float table[kRecordTable];
    const Hits at = hits_at(d, instances, hits, s, std::min(lanes, count - s), table);
    const V3 wo = neg(load3(d, hits.dir[0], hits.dir[1], hits.dir[2], s));
    const Surface surf = surface(d, instances, hits, s, at.instance, at.hit, at.records, wo);
    const V3& emission = surf.emission;
    // The lanes' values, then each plain hit's SurfacePoint from them.
    HWY_ALIGN float lane[13][kMax];
    const V values[13] = {surf.position.x,
                          surf.position.y,
                          surf.position.z,
                          surf.ng.x,
                          surf.ng.y,
                          surf.ng.z,
                          surf.ns.x,
                          surf.ns.y,
                          surf.ns.z,
                          emission.x,
                          emission.y,
                          emission.z,
                          hn::IfThenElseZero(surf.front, hn::Set(d, 1.0f))};
    for (int k = 0; k < 13; ++k) hn::Store(values[k], d, lane[k]);
    for (int j = 0; j < lanes && s + j < count; ++j) {
      const uint32_t id = hits.instance[s + j];
      if (!instances.in_lanes(id)) continue;
      const float* record = instances.records.data() + size_t(id) * GBufferInstances::kFields;
      SurfacePoint& sp = out[s + j];
      sp.position = vec3(lane[0][j], lane[1][j], lane[2][j]);
      sp.geometric_normal = vec3(lane[3][j], lane[4][j], lane[5][j]);
      sp.shading_normal = vec3(lane[6][j], lane[7][j], lane[8][j]);
      sp.base_color = vec3(record[F::kBaseColor], record[F::kBaseColor + 1], record[F::kBaseColor + 2]);
      sp.metallic = record[F::kMetallic];
      sp.roughness = record[F::kRoughness];
      sp.specular = record[F::kSpecular];
      sp.specular_f0 = vec3(record[F::kSpecularF0], record[F::kSpecularF0 + 1], record[F::kSpecularF0 + 2]);
      sp.emission = vec3(lane[9][j], lane[10][j], lane[11][j]);
      sp.instance = id;
      sp.prim = hits.prim[s + j];
      sp.front_face = lane[12][j] > 0.0f;
    }
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace candela
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace candela {

HWY_EXPORT(ShadeGBufferLanes);
HWY_EXPORT(PrimaryRaysLanes);
HWY_EXPORT(SurfacePointsLanes);

void surface_points_lanes(const GBufferInstances& instances, const PrimaryHitLanes& hits, int count,
                          SurfacePoint* out) {
  HWY_DYNAMIC_DISPATCH(SurfacePointsLanes)(instances, hits, count, out);
}

void primary_rays_lanes(const Camera& camera, int x0, int y, int count, const float* jitter_x, const float* jitter_y,
                        PrimaryHitLanes& row, vec2* jitter) {
  HWY_DYNAMIC_DISPATCH(PrimaryRaysLanes)(camera, x0, y, count, jitter_x, jitter_y, row, jitter);
}

GBufferInstances::GBufferInstances(const Scene& scene)
    : records(std::max<size_t>(scene.instances.size(), 1) * kFields, 0.0f),
      meshes(scene.instances.size()),
      prev_from_current(scene.instances.size(), mat4(1.0f)),
      plain(scene.instances.size(), 0) {
  for (size_t k = 0; k < scene.instances.size(); ++k) {
    const Instance& inst = scene.instances[k];
    const Mesh& mesh = scene.meshes[inst.mesh];
    const Material& m = scene.materials[mesh.material];
    if (inst.animated) prev_from_current[k] = inst.prev_transform * glm::inverse(inst.transform);
    meshes[k] = {&mesh.triangles.data()->x, &mesh.positions.data()->x,
                 mesh.normals.empty() ? nullptr : &mesh.normals.data()->x};
    float* r = records.data() + k * kFields;
    auto put = [&](int field, const float* values, int count) { std::copy(values, values + count, r + field); };
    for (int c = 0; c < 4; ++c) put(kTransform + 3 * c, &inst.transform[c].x, 3);
    const mat3 nm = normal_matrix(inst.transform);
    for (int c = 0; c < 3; ++c) put(kNormalMatrix + 3 * c, &nm[c].x, 3);
    for (int c = 0; c < 4; ++c) put(kPrevFromCurrent + 3 * c, &prev_from_current[k][c].x, 3);
    put(kBaseColor, &m.base_color.x, 3);
    r[kMetallic] = m.metallic;
    r[kRoughness] = m.roughness;
    r[kSpecular] = m.specular;
    const vec3 f0 = dielectric_f0(m.ior, m.specular_color);
    put(kSpecularF0, &f0.x, 3);
    if (m.emissive()) put(kEmission, &m.emission.x, 3);
    r[kMirrored] = glm::determinant(mat3(inst.transform)) < 0.0f;
    r[kAnimated] = inst.animated;
    r[kDoubleSided] = m.double_sided;
    r[kHasNormals] = !mesh.normals.empty();
    plain[k] = !m.base_color_tex.valid() && !m.metallic_roughness_tex.valid() && !m.specular_tex.valid() &&
               !m.specular_color_tex.valid() && !m.normal_tex.valid() && !m.emissive_tex.valid();
    all_plain = all_plain && plain[k];
  }
}

void shade_gbuffer_lanes(const GBufferInstances& instances, const Camera& camera, const Camera& prev_camera, bool still,
                         const vec3& environment, const PrimaryHitLanes& hits, int count, size_t first_pixel,
                         GBuffer& out) {
  HWY_DYNAMIC_DISPATCH(ShadeGBufferLanes)
  (instances, camera, prev_camera, still, environment, hits, count, first_pixel, out);
}

}  // namespace candela
#endif  // HWY_ONCE
