// Embree agrees with a brute-force intersector, packets agree with single rays, and spawned rays do not
// hit the surface they leave, at scene scales from millimetres to kilometres.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "engine/builtin_scenes.h"
#include "engine/rng.h"
#include "engine/surface.h"
#include "engine/tracer.h"

namespace candela {
namespace {

// Moller-Trumbore ray/triangle test in double precision (Moller & Trumbore 1997).
bool intersect_triangle(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& p0, const glm::dvec3& p1,
                        const glm::dvec3& p2, double& t) {
  glm::dvec3 e1 = p1 - p0, e2 = p2 - p0, pv = glm::cross(d, e2);
  double det = glm::dot(e1, pv);
  if (std::abs(det) < 1e-300) return false;
  glm::dvec3 tv = o - p0;
  double u = glm::dot(tv, pv) / det;
  if (u < 0.0 || u > 1.0) return false;
  glm::dvec3 qv = glm::cross(tv, e1);
  double v = glm::dot(d, qv) / det;
  if (v < 0.0 || u + v > 1.0) return false;
  t = glm::dot(e2, qv) / det;
  return t > 0.0;
}

struct BruteHit {
  double t = 1e300;
  uint32_t instance = kNoHit, prim = kNoHit;
};

BruteHit brute_force(const Scene& scene, const Ray& ray) {
  BruteHit best;
  for (uint32_t i = 0; i < scene.instances.size(); ++i) {
    const Mesh& mesh = scene.meshes[scene.instances[i].mesh];
    for (uint32_t p = 0; p < mesh.triangles.size(); ++p) {
      WorldTriangle w = world_triangle(scene, i, p);
      double t;
      if (intersect_triangle(glm::dvec3(ray.origin), glm::dvec3(ray.direction), glm::dvec3(w.p0), glm::dvec3(w.p1),
                             glm::dvec3(w.p2), t) &&
          t < best.t)
        best = {t, i, p};
    }
  }
  return best;
}

// The Cornell box plus a second, rotated and scaled instance of one of its box meshes.
Scene instanced_scene() {
  Scene s = make_cornell_scene();
  mat4 m = glm::scale(glm::rotate(glm::translate(mat4(1.0f), vec3(0.4f, 1.4f, 0.5f)), 0.7f, vec3(1, 1, 0)), vec3(0.3f));
  s.instances.push_back(Instance{int(s.meshes.size() - 1), m, m});
  return s;
}

TEST(Tracer, AgreesWithBruteForce) {
  Scene scene = instanced_scene();
  Tracer tracer(scene);
  Rng rng(1, 2);
  int hits = 0;
  for (int k = 0; k < 3000; ++k) {
    vec3 o(rng.next_float() * 1.8f - 0.9f, rng.next_float() * 1.9f + 0.05f, rng.next_float() * 1.8f - 0.9f);
    vec3 d = glm::normalize(vec3(rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() - 0.5f));
    Ray ray{o, d, 0.0f, kInfinity};
    Hit h = tracer.intersect(ray);
    BruteHit b = brute_force(scene, ray);
    ASSERT_EQ(h.valid(), b.instance != kNoHit) << "ray " << k;
    if (!h.valid()) continue;
    ++hits;
    EXPECT_NEAR(h.t, b.t, 1e-4 * std::max(1.0, b.t)) << "ray " << k;
    vec3 ph = o + d * h.t;
    WorldTriangle w = world_triangle(scene, h.instance, h.prim);
    vec3 pb = w.p0 * (1.0f - h.barycentric.x - h.barycentric.y) + w.p1 * h.barycentric.x + w.p2 * h.barycentric.y;
    EXPECT_LT(glm::length(ph - pb), 1e-4f) << "barycentrics disagree with t, ray " << k;
    if (h.instance != b.instance || h.prim != b.prim) {
      // Only a tie (the ray crosses a shared edge) may pick another triangle: it must be hit at the same t.
      double t_other;
      WorldTriangle o2 = world_triangle(scene, h.instance, h.prim);
      ASSERT_TRUE(intersect_triangle(glm::dvec3(o), glm::dvec3(d), glm::dvec3(o2.p0), glm::dvec3(o2.p1),
                                     glm::dvec3(o2.p2), t_other) ||
                  std::abs(h.t - b.t) < 1e-5)
          << "ray " << k;
    }
    Ray shadow{o, d, 0.0f, float(b.t) * 0.999f};
    EXPECT_FALSE(tracer.occluded(shadow)) << "ray " << k;
    shadow.tmax = float(b.t) * 1.001f;
    EXPECT_TRUE(tracer.occluded(shadow)) << "ray " << k;
  }
  EXPECT_GT(hits, 2400);  // the box is closed but for its front: most rays hit
}

TEST(Tracer, PacketsAgreeWithSingleRays) {
  Scene scene = instanced_scene();
  Tracer tracer(scene);
  Rng rng(5, 6);
  for (int batch = 0; batch < 200; ++batch) {
    RayPacket16 packet, shadow;
    Ray rays[16];
    for (int lane = 0; lane < 16; ++lane) {
      rays[lane] = Ray{vec3(0, 1, 3.5f), glm::normalize(vec3(rng.next_float() - 0.5f, rng.next_float() - 0.5f, -1.0f)),
                       0.0f, kInfinity};
      if (lane == 7) {
        packet.set_inactive(lane);
        continue;
      }
      packet.set(lane, rays[lane]);
    }
    tracer.intersect16(packet, true);
    for (int lane = 0; lane < 16; ++lane) {
      Hit single = tracer.intersect(rays[lane]);
      Hit packed = tracer.packet_hit(packet, lane);
      if (lane == 7) {
        EXPECT_FALSE(packed.valid());
        continue;
      }
      ASSERT_EQ(single.valid(), packed.valid());
      EXPECT_EQ(single.instance, packed.instance);
      EXPECT_EQ(single.prim, packed.prim);
      EXPECT_FLOAT_EQ(single.t, packed.t);
      Ray r = rays[lane];
      r.tmax = single.t * (lane % 2 ? 0.99f : 1.01f);
      shadow.set(lane, r);
    }
    shadow.set_inactive(7);
    tracer.occluded16(shadow);
    for (int lane = 0; lane < 16; ++lane)
      if (lane != 7) {
        EXPECT_EQ(Tracer::occluded_lane(shadow, lane), lane % 2 == 0 && tracer.intersect(rays[lane]).valid())
            << "lane " << lane;
      }
  }
}

// `scene` moved to `scale` and 3 x scale from the origin (every instance).
Scene scaled(Scene scene, float scale) {
  mat4 m = glm::scale(glm::translate(mat4(1.0f), vec3(3.0f * scale)), vec3(scale));
  for (Instance& inst : scene.instances) inst.transform = inst.prev_transform = m;
  return scene;
}

// A random point on triangle `w`: one in four anywhere, the others within 1e-4 (barycentric) of one of the
// three edges, where an offset that is too small lands on the neighbour across the edge.
vec3 point_near_edges(const WorldTriangle& w, Rng& rng, int k) {
  const float t = rng.next_float(), close = 1e-4f * rng.next_float();
  vec2 b(t, rng.next_float());  // (b1, b2): p = (1 - b1 - b2) p0 + b1 p1 + b2 p2
  switch (k % 4) {
    case 0:
      if (b.x + b.y > 1.0f) b = vec2(1.0f) - b;
      break;                                                // anywhere
    case 1: b = vec2(close, t * (1.0f - close)); break;     // near the edge p0-p2
    case 2: b = vec2(t * (1.0f - close), close); break;     // near the edge p0-p1
    case 3: b = vec2(t, 1.0f - t) * (1.0f - close); break;  // near the edge p1-p2
  }
  return w.p0 * (1.0f - b.x - b.y) + w.p1 * b.x + w.p2 * b.y;
}

// Counts the spawned rays (from points on every triangle of `scene`, near edges three times in four,
// random directions on both sides) that hit the surface they leave. A hit counts when it is on the origin's
// own triangle, or on a triangle of the same plane (a coplanar neighbour across a shared edge: normals
// parallel within 1e-4 and the origin within 1e-5 scene radii of its plane; a real occluder, such as
// the ceiling light 0.005 units under the ceiling, is farther), or, when `convex`, any hit of a ray
// leaving the outer side (nothing outside a convex closed mesh can be hit, so any hit is a neighbour).
struct SelfHits {
  int own = 0, neighbour = 0;  // hits of the origin's triangle, of another triangle of its surface
};
SelfHits self_hits(const Scene& scene, const Tracer& tracer, Rng& rng, int per_triangle, bool convex, int& trials) {
  SelfHits hits;
  const float plane_tolerance = 1e-5f * tracer.scene_radius();
  for (uint32_t i = 0; i < scene.instances.size(); ++i) {
    const Mesh& mesh = scene.meshes[scene.instances[i].mesh];
    for (uint32_t p = 0; p < mesh.triangles.size(); ++p) {
      const WorldTriangle w = world_triangle(scene, i, p);
      const vec3 ng = glm::normalize(w.normal());
      for (int k = 0; k < per_triangle; ++k) {
        const vec3 pos = point_near_edges(w, rng, k);
        const vec3 d = glm::normalize(vec3(rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() - 0.5f));
        const Hit h = tracer.intersect(tracer.spawn_ray(pos, ng, d));
        ++trials;
        if (!h.valid()) continue;
        const WorldTriangle hw = world_triangle(scene, h.instance, h.prim);
        const vec3 hn = glm::normalize(hw.normal());
        const bool same = h.instance == i && h.prim == p;
        const bool coplanar =
            std::abs(glm::dot(hn, ng)) > 1.0f - 1e-4f && std::abs(glm::dot(hn, pos - hw.p0)) < plane_tolerance;
        const bool leaves_convex = convex && glm::dot(d, ng) < 0.0f;  // the sphere's triangles face inwards
        hits.own += same;
        hits.neighbour += !same && (coplanar || leaves_convex);
      }
    }
  }
  return hits;
}

// Rays leaving a surface (both sides) never hit it again, neither its own triangle nor a neighbour, whether
// the scene is 1 mm or 10 km across and far from the origin: offsets are relative to the scene's scale and
// to |p|. Scenes: the Cornell box (quads of two coplanar triangles, boxes standing on the floor) and the
// furnace's closed icosphere (5,120 triangles, neighbours at an angle). Tolerance: none (0 hits).
TEST(Tracer, SpawnedRaysAvoidSelfIntersection) {
  for (float scale : {1e-3f, 1.0f, 1e4f}) {
    Rng rng(7, uint64_t(scale * 1000));
    int trials = 0;
    const Scene cornell = scaled(make_cornell_scene(), scale), sphere = scaled(make_furnace_scene(0.5f, 1.0f), scale);
    const SelfHits box = self_hits(cornell, Tracer(cornell), rng, 40, false, trials);
    const SelfHits ball = self_hits(sphere, Tracer(sphere), rng, 4, true, trials);
    std::printf("scale %g: %d rays; hits of the own triangle / of a neighbour: cornell %d / %d, sphere %d / %d\n",
                scale, trials, box.own, box.neighbour, ball.own, ball.neighbour);
    EXPECT_EQ(box.own + box.neighbour, 0) << "scale " << scale;
    EXPECT_EQ(ball.own + ball.neighbour, 0) << "scale " << scale;
  }
}

// glTF alphaMode MASK: where base colour alpha is below the cutoff, rays (and shadow rays) pass through.
// A masked quad at z = 0 whose texture is transparent for u < 1/2 hides an opaque quad at z = -1.
TEST(Tracer, AlphaMaskLetsRaysThrough) {
  Scene scene;
  Texture tex;
  tex.width = 2;
  tex.height = 1;
  tex.wrap_s = tex.wrap_t = Wrap::Clamp;
  tex.rgba = {255, 255, 255, 0, 255, 255, 255, 255};
  scene.textures.push_back(tex);
  Material masked, opaque;
  masked.alpha_mode = AlphaMode::Mask;
  masked.base_color_tex.texture = 0;
  scene.materials = {masked, opaque};
  for (int k = 0; k < 2; ++k) {
    Mesh quad;
    float z = -float(k);
    quad.positions = {vec3(-1, -1, z), vec3(1, -1, z), vec3(1, 1, z), vec3(-1, 1, z)};
    quad.uv0 = {vec2(0, 0), vec2(1, 0), vec2(1, 1), vec2(0, 1)};
    quad.triangles = {uvec3(0, 1, 2), uvec3(0, 2, 3)};
    quad.material = k;
    scene.meshes.push_back(quad);
    scene.instances.push_back(Instance{k});
  }
  Tracer tracer(scene);
  for (float x : {-0.8f, -0.3f, 0.3f, 0.8f}) {
    Ray ray{vec3(x, 0.1f, 1.0f), vec3(0, 0, -1), 0.0f, kInfinity};
    Hit h = tracer.intersect(ray);
    ASSERT_TRUE(h.valid());
    EXPECT_EQ(h.instance, x < 0.0f ? 1u : 0u) << "x " << x;
    ray.tmax = 1.5f;  // stops between the quads: occluded only where the mask is opaque
    EXPECT_EQ(tracer.occluded(ray), x > 0.0f) << "x " << x;
  }
}

}  // namespace
}  // namespace candela
