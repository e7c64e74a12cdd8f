// The G-buffer pass: planes describe the visible surface, and motion vectors point to where the same
// surface point was in the previous frame, for a moving camera and for moving instances.
#include <gtest/gtest.h>

#include <cstring>
#include <glm/gtc/matrix_transform.hpp>

#include "engine/builtin_scenes.h"
#include "engine/gbuffer.h"
#include "engine/gltf_loader.h"
#include "engine/simd_targets.h"
#include "engine/surface.h"
#include "tests/test_util.h"

namespace candela {
namespace {

struct TwoFrames {
  GBuffer prev, cur;
};

// Renders the G-buffer of `scene` at time t0 from camera a, then at t1 from camera b (no jitter).
TwoFrames render_two_frames(Scene& scene, const CameraDesc& a, const CameraDesc& b, float t0, float t1, int w, int h) {
  TwoFrames f;
  RayCounter rays;
  scene.set_time(t0);
  scene.set_time(t0);
  Tracer tracer(scene);
  Camera ca(a, w, h), cb(b, w, h);
  trace_gbuffer(scene, tracer, ca, ca, GBufferParams{1, 0, false}, f.prev, rays);
  scene.set_time(t1);
  tracer.update_instances(scene);
  trace_gbuffer(scene, tracer, cb, ca, GBufferParams{1, 1, false}, f.cur, rays);
  EXPECT_EQ(rays.count.load(), uint64_t(2 * w * h));
  return f;
}

// Where pixel i's motion vector lands in the previous frame, or -1 outside the image.
int64_t reprojected_pixel(const GBuffer& g, size_t i) {
  int x = int(i % g.width), y = int(i / g.width);
  vec2 p = vec2(x, y) + g.jitter[i] + g.motion[i];
  int px = int(std::floor(p.x)), py = int(std::floor(p.y));
  if (px < 0 || py < 0 || px >= g.width || py >= g.height) return -1;
  return int64_t(py) * g.width + px;
}

// Also: under a still camera, a still scene's motion vectors are exactly 0, hits and misses, in both the
// scalar and the SIMD path (projecting the points back gave rounding noise of ~1e-4 pixels of either sign).
TEST(GBuffer, PlanesDescribeTheVisibleSurface) {
  Scene scene = make_cornell_scene();
  Tracer tracer(scene);
  Camera cam(scene.default_camera(), 64, 48);
  for (bool simd : {true, false}) {
    GBuffer g;
    RayCounter rays;
    trace_gbuffer(scene, tracer, cam, cam, GBufferParams{1, 0, true, simd}, g, rays);
    int hits = 0, moving = 0;
    for (size_t i = 0; i < g.size(); ++i) {
      if (g.motion[i] != vec2(0.0f)) ++moving;
      if (!g.hit(i)) {
        EXPECT_EQ(g.depth[i], kInfinity);
        continue;
      }
      ++hits;
      EXPECT_NEAR(glm::length(g.shading_normal[i]), 1.0f, 1e-4f);
      EXPECT_GT(glm::dot(g.geometric_normal[i], cam.position() - g.position[i]), 0.0f) << "normal faces the camera";
      EXPECT_NEAR(g.depth[i], cam.view_depth(g.position[i]), 1e-4f);
    }
    EXPECT_GT(hits, int(g.size() / 2));
    EXPECT_LT(hits, int(g.size())) << "some rays miss";
    EXPECT_EQ(moving, 0) << "still camera, still scene, simd " << simd;
  }
}

// The camera moves: for pixels whose surface was visible last frame, following the motion vector lands
// on last frame's pixel showing the same point (within the spacing of pixels there). Disocclusions and
// edges may fail; at least 95% of the pixels must land right.
TEST(GBuffer, MotionVectorsFollowTheCamera) {
  Scene scene = make_cornell_scene();
  CameraDesc a = scene.default_camera(), b = a;
  b.position += vec3(0.15f, 0.05f, -0.2f);
  b.target += vec3(0.05f, 0.0f, 0.0f);
  const int w = 160, h = 120;
  TwoFrames f = render_two_frames(scene, a, b, 0.0f, 0.0f, w, h);
  Camera ca(a, w, h);
  int checked = 0, right = 0;
  for (size_t i = 0; i < f.cur.size(); ++i) {
    if (!f.cur.hit(i)) continue;
    int64_t j = reprojected_pixel(f.cur, i);
    if (j < 0) continue;
    ++checked;
    // The landing point is at most 0.71 pixels from that pixel's centre. One pixel at the previous depth
    // spans depth * 2 tan(fov/2) / height across the view, 1 / cos(theta) times more along a tilted surface.
    if (!f.prev.hit(size_t(j))) continue;
    float pixel_size = f.prev.depth[j] * 2.0f * std::tan(glm::radians(0.5f * a.vfov_degrees)) / h;
    vec3 view = glm::normalize(ca.position() - f.prev.position[j]);
    float cos_theta = std::max(0.05f, std::abs(glm::dot(view, f.prev.geometric_normal[j])));
    if (glm::length(f.prev.position[j] - f.cur.position[i]) < pixel_size / cos_theta) ++right;
  }
  EXPECT_GT(checked, w * h / 2);
  EXPECT_GT(right, 0.95 * checked) << right << " of " << checked;
}

// The cars of builtin:city move, the camera stays: car pixels reproject onto the same car last frame.
TEST(GBuffer, MotionVectorsFollowMovingInstances) {
  Scene scene = make_city_scene(7);
  CameraDesc cam = scene.default_camera();
  const int w = 320, h = 180;
  TwoFrames f = render_two_frames(scene, cam, cam, 1.0f, 1.0f + 1.0f / 30.0f, w, h);
  int car_pixels = 0, same_car = 0, moving = 0;
  for (size_t i = 0; i < f.cur.size(); ++i) {
    if (!f.cur.hit(i) || !scene.instances[f.cur.instance[i]].animated) continue;
    ++car_pixels;
    if (glm::length(f.cur.motion[i]) > 0.05f) ++moving;
    int64_t j = reprojected_pixel(f.cur, i);
    if (j >= 0 && f.prev.instance[j] == f.cur.instance[i]) ++same_car;
  }
  ASSERT_GT(car_pixels, 50);
  EXPECT_GT(moving, 0.9 * car_pixels);
  EXPECT_GT(same_car, 0.85 * car_pixels) << same_car << " of " << car_pixels;
  // Static surfaces under a still camera do not move, exactly.
  for (size_t i = 0; i < f.cur.size(); ++i)
    if (f.cur.hit(i) && !scene.instances[f.cur.instance[i]].animated) {
      ASSERT_EQ(f.cur.motion[i], vec2(0.0f));
    }
}

// How many pixels of plane `a` differ from `b` in any bit.
template <class T>
int differing_pixels(const Plane<T>& a, const Plane<T>& b) {
  int differ = 0;
  for (size_t i = 0; i < a.size(); ++i) differ += std::memcmp(&a[i], &b[i], sizeof(T)) != 0;
  return differ;
}

// The SIMD kernel against surface_at (GBufferParams::simd = false) on every instruction set: every plane
// identical to the bit, for jittered rays from a moving camera (misses' motion, partial tile rows at
// 203x101), moving instances (city's cars), a mirrored instance and, with the shared scenes, a textured,
// normal-mapped glTF (the kernel leaves those hits to surface_at). The packed surfaces too.
TEST(GBuffer, LanesGiveTheScalarBits) {
  std::vector<std::pair<std::string, Scene>> scenes;
  scenes.emplace_back("cornell", make_cornell_scene());
  scenes.emplace_back("manylights", make_manylights_scene(64, 3));
  scenes.emplace_back("city", make_city_scene(7));
  Scene mirrored = make_cornell_scene();
  mirrored.instances.back().transform = glm::scale(mirrored.instances.back().transform, vec3(-1.0f, 1.0f, 1.0f));
  scenes.emplace_back("cornell, mirrored instance", std::move(mirrored));
  if (std::string helmet = testing::shared_scene_file("DamagedHelmet/glTF/DamagedHelmet.gltf"); !helmet.empty())
    scenes.emplace_back("DamagedHelmet", load_gltf(helmet));
  for (auto& [name, scene] : scenes) {
    scene.set_time(1.0f);
    Tracer tracer(scene);
    CameraDesc a = scene.default_camera(), b = a;
    b.position += 0.03f * (a.target - a.position) + vec3(0.01f, 0.02f, 0.0f);
    const Camera prev(a, 203, 101), cur(b, 203, 101);
    scene.set_time(1.0f + 1.0f / 30.0f);
    tracer.update_instances(scene);
    RayCounter rays;
    GBuffer reference;
    trace_gbuffer(scene, tracer, cur, prev, GBufferParams{5, 1, true, false, true}, reference, rays);
    ASSERT_EQ(reference.packed.size(), reference.size());
    for_each_simd_target([&](const char* target) {
      GBuffer lanes;
      trace_gbuffer(scene, tracer, cur, prev, GBufferParams{5, 1, true, true, true}, lanes, rays);
      SCOPED_TRACE(name + ", " + target);
      EXPECT_EQ(differing_pixels(lanes.position, reference.position), 0);
      EXPECT_EQ(differing_pixels(lanes.shading_normal, reference.shading_normal), 0);
      EXPECT_EQ(differing_pixels(lanes.geometric_normal, reference.geometric_normal), 0);
      EXPECT_EQ(differing_pixels(lanes.depth, reference.depth), 0);
      EXPECT_EQ(differing_pixels(lanes.albedo, reference.albedo), 0);
      EXPECT_EQ(differing_pixels(lanes.material, reference.material), 0);
      EXPECT_EQ(differing_pixels(lanes.specular_f0, reference.specular_f0), 0);
      EXPECT_EQ(differing_pixels(lanes.emission, reference.emission), 0);
      EXPECT_EQ(differing_pixels(lanes.instance, reference.instance), 0);
      EXPECT_EQ(differing_pixels(lanes.motion, reference.motion), 0);
      EXPECT_EQ(differing_pixels(lanes.jitter, reference.jitter), 0);
      EXPECT_EQ(differing_pixels(lanes.packed, reference.packed), 0);
    });
  }
}

}  // namespace
}  // namespace candela
