#pragma once
// The moving-camera check shared by the ReSTIR tests: a camera flying through `city` (whose cars and
// their lights move too), frame after frame, with every pixel of every frame required to be finite.
#include <gtest/gtest.h>

#include "apps/renderer.h"
#include "engine/builtin_scenes.h"
#include "tests/render_helpers.h"

namespace candela::testing {

// The camera of frame `frame`: the scene's camera moved steadily forward, sideways and down.
inline CameraDesc flythrough_camera(const CameraDesc& start, int frame) {
  CameraDesc c = start;
  c.position += vec3(0.4f * frame, -0.2f * frame, -0.8f * frame);
  c.target += vec3(0.3f * frame, 0.0f, -0.5f * frame);
  return c;
}

// Renders frames 0..frames-1 at 30 frames per second along the fly-through; fails the test at the first
// frame with a non-finite pixel.
inline void render_flythrough(Renderer& renderer, const CameraDesc& start, int frames) {
  for (int frame = 0; frame < frames; ++frame) {
    testing::render_checked(renderer, frame, frame / 30.0f, flythrough_camera(start, frame));
    for (const vec3& p : renderer.image().pixels) ASSERT_TRUE(is_finite(p)) << "frame " << frame;
  }
}

// `city` (seed 7) as it stands at frame `frame` of the fly-through: scene time and camera, for a
// reference render of that frame.
inline Scene flythrough_scene_at(const CameraDesc& start, int frame) {
  Scene scene = make_city_scene(7);
  scene.set_time(frame / 30.0f);
  scene.camera = flythrough_camera(start, frame);
  return scene;
}

}  // namespace candela::testing
