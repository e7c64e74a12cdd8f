// `candela view`: the camera controller's math, dynamic resolution's controller, the headless display path against
// `candela render`, and resident memory over a long headless run.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "apps/viewer/camera_controller.h"
#include "apps/viewer/dynamic_scale.h"
#include "apps/viewer/viewer.h"
#include "engine/builtin_scenes.h"
#include "tests/settings_builder.h"

namespace candela {
namespace {

const CameraDesc kStart{vec3(1.0f, 2.0f, 6.0f), vec3(0.5f, 1.0f, -1.0f), vec3(0.0f, 1.0f, 0.0f), 45.0f};

TEST(CameraController, StillCameraIsBitIdentical) {
  CameraController c(kStart);
  EXPECT_EQ(c.desc().position, kStart.position);
  EXPECT_EQ(c.desc().target, kStart.target);
  EXPECT_EQ(c.desc().vfov_degrees, kStart.vfov_degrees);
}

TEST(CameraController, OrbitKeepsTargetAndDistance) {
  CameraController c(kStart);
  const float distance = glm::length(kStart.target - kStart.position);
  for (int i = 0; i < 100; ++i) {
    c.orbit(7.3f, i % 2 ? 3.1f : -2.2f);
    EXPECT_NEAR(glm::length(c.desc().target - c.desc().position), distance, 1e-4f * distance);
    EXPECT_LT(glm::length(c.desc().target - kStart.target), 1e-5f);
  }
  c.orbit(0.0f, 500.0f);  // pitch clamps short of the pole, where "up" would be undefined
  EXPECT_GT(c.forward().y, 0.999f);
  EXPECT_LT(c.forward().y, 1.0f);
  EXPECT_NEAR(glm::length(c.desc().target - c.desc().position), distance, 1e-4f * distance);
}

TEST(CameraController, ZoomScalesDistanceToTarget) {
  CameraController c(kStart);
  const float distance = c.distance();
  c.zoom(2.0f);
  EXPECT_NEAR(glm::length(c.desc().target - c.desc().position), distance * 0.81f, 1e-4f);
  EXPECT_LT(glm::length(c.desc().target - kStart.target), 1e-5f);
}

TEST(CameraController, FlyMovesAlongViewDirection) {
  CameraController c(kStart);
  const vec3 forward = glm::normalize(kStart.target - kStart.position);
  EXPECT_LT(glm::length(c.forward() - forward), 1e-5f);
  c.move(vec3(0.0f, 0.0f, 2.5f));
  EXPECT_LT(glm::length(c.desc().position - (kStart.position + 2.5f * forward)), 1e-4f);
  EXPECT_LT(glm::length(glm::normalize(c.desc().target - c.desc().position) - forward), 1e-5f);
  // Strafing right is perpendicular to the view and horizontal.
  vec3 before = c.desc().position;
  c.move(vec3(1.0f, 0.0f, 0.0f));
  vec3 step = c.desc().position - before;
  EXPECT_NEAR(glm::length(step), 1.0f, 1e-5f);
  EXPECT_NEAR(glm::dot(step, forward), 0.0f, 1e-5f);
  EXPECT_NEAR(step.y, 0.0f, 1e-5f);
}

TEST(CameraController, LookTurnsAboutTheEye) {
  CameraController c(kStart);
  c.look(30.0f, 0.0f);
  EXPECT_EQ(c.desc().position, kStart.position);
  const vec3 f = glm::normalize(kStart.target - kStart.position);
  EXPECT_NEAR(c.forward().y, f.y, 1e-5f);  // pitch unchanged
  const vec2 before = glm::normalize(vec2(f.x, f.z)), after = glm::normalize(vec2(c.forward().x, c.forward().z));
  EXPECT_NEAR(glm::degrees(std::acos(glm::dot(before, after))), 30.0f, 1e-2f);
  EXPECT_LT(glm::length(glm::normalize(c.desc().target - c.desc().position) - c.forward()), 1e-5f);
}

// Runs a shell command; returns its exit status.
int run(const std::string& command) {
  int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A headless `view` (extra options `view_options`, screenshot view.png, its log view.log) and a `render`
// (render.png) of the same 3 frames of cornell at 640x360 into `dir`; returns the viewer's log.
std::string view_and_render(const std::string& dir, const std::string& view_options) {
  std::filesystem::create_directories(dir);
  const std::string common = " builtin:cornell --width 640 --height 360 --seed 7 --frames 3 --method pt --max-depth 2 ";
  EXPECT_EQ(run(std::string(CANDELA_BINARY) + " view" + common + view_options + " --headless --screenshot " + dir +
                "/view.png 2> " + dir + "/view.log"),
            0);
  EXPECT_EQ(run(std::string(CANDELA_BINARY) + " render" + common + "-q --out " + dir + "/render.png"), 0);
  return read_text(dir + "/view.log");
}

// The largest channel difference of two pixels.
float pixel_difference(const Image& a, const Image& b, int x, int y) {
  vec3 diff = glm::abs(a.at(x, y) - b.at(x, y));
  return std::max(diff.x, std::max(diff.y, diff.z));
}

// The headless viewer draws what `candela render` writes. With --no-hud the screenshot is the frame alone
// and equals the render's PNG to within one 8-bit step per channel (the frame is tonemapped on the CPU as
// for PNG output and blitted 1:1 with texel-centred bilinear filtering, which reproduces each texel) over
// the whole frame; the compared fraction is asserted to be at least 80% (it is 100%; with the HUD drawn,
// only the 46% outside it could be compared).
TEST(ViewerHeadless, ScreenshotWithoutHudMatchesRender) {
  const std::string dir = std::string(CANDELA_TEST_OUTPUT_DIR) + "/viewer_no_hud";
  const std::string log = view_and_render(dir, "--no-hud");
  EXPECT_NE(log.find("HUD off"), std::string::npos) << log;
  Image view = read_image(dir + "/view.png"), render = read_image(dir + "/render.png");
  ASSERT_EQ(view.width, render.width);
  ASSERT_EQ(view.height, render.height);
  float worst = 0.0f;
  size_t compared = 0;
  for (int y = 0; y < view.height; ++y)
    for (int x = 0; x < view.width; ++x) {
      worst = std::max(worst, pixel_difference(view, render, x, y));
      ++compared;
    }
  const double fraction = double(compared) / (double(view.width) * view.height);
  std::printf("without the HUD: %zu pixels compared (%.1f%% of the frame), largest difference %.4f\n", compared,
              100.0 * fraction, worst);
  EXPECT_GE(fraction, 0.8);
  EXPECT_LE(worst, 1.0f / 255.0f + 1e-6f);
}

// With the HUD (the default), the screenshot still equals the render outside the HUD window (same
// tolerance) and differs clearly inside it (the HUD is drawn and legible text changes at least 20% of its
// pixels; a difference of more than 8 8-bit steps counts).
TEST(ViewerHeadless, ScreenshotMatchesRenderOutsideTheHud) {
  const std::string dir = std::string(CANDELA_TEST_OUTPUT_DIR) + "/viewer";
  const std::string log = view_and_render(dir, "");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(log, m, std::regex("HUD at (\\d+) (\\d+) size (\\d+) x (\\d+)"))) << log;
  const int hx = std::stoi(m[1]), hy = std::stoi(m[2]), hw = std::stoi(m[3]), hh = std::stoi(m[4]);
  Image view = read_image(dir + "/view.png"), render = read_image(dir + "/render.png");
  ASSERT_EQ(view.width, render.width);
  ASSERT_EQ(view.height, render.height);
  float worst_outside = 0.0f;
  size_t outside = 0, inside = 0, inside_differs = 0;
  for (int y = 0; y < view.height; ++y)
    for (int x = 0; x < view.width; ++x) {
      float d = pixel_difference(view, render, x, y);
      bool in_hud = x >= hx - 1 && x <= hx + hw && y >= hy - 1 && y <= hy + hh;  // one pixel of border slack
      if (in_hud) {
        ++inside;
        inside_differs += d > 8.0f / 255.0f;
      } else {
        ++outside;
        worst_outside = std::max(worst_outside, d);
      }
    }
  std::printf(
      "outside the HUD: %zu pixels (%.1f%% of the frame), largest difference %.4f; inside: %zu pixels, %.1f%% differ\n",
      outside, 100.0 * double(outside) / (double(view.width) * view.height), worst_outside, inside,
      100.0 * double(inside_differs) / double(inside));
  EXPECT_GT(outside, size_t(view.width) * view.height / 4);
  EXPECT_LE(worst_outside, 1.0f / 255.0f + 1e-6f);
  EXPECT_GT(double(inside_differs), 0.2 * double(inside));
}

// Resident set size of this process in kB (VmRSS of /proc/self/status).
long resident_kb() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
  return -1;
}

// 1,000 headless frames with an orbiting camera (every frame re-renders, re-uploads and redraws the HUD):
// resident memory may grow by at most 2 MB between frame 100 and frame 1000, i.e. no per-frame leak
// above ~2 kB.
TEST(ViewerHeadless, ResidentMemoryStableOver1000Frames) {
  const RenderSettings settings = testing::settings({{"method", "direct"}});
  ViewerOptions options;
  options.headless = true;
  options.width = 128;
  options.height = 96;
  options.frames = 1000;
  options.orbit_degrees_per_frame = 1.0f;
  Viewer viewer(make_builtin_scene("cornell"), settings, options);
  long at_100 = 0;
  while (viewer.step())
    if (viewer.frames_done() == 100) at_100 = resident_kb();
  long at_1000 = resident_kb();
  std::printf("VmRSS: frame 100 %ld kB, frame 1000 %ld kB, growth %ld kB\n", at_100, at_1000, at_1000 - at_100);
  EXPECT_EQ(viewer.frames_done(), 1000);
  EXPECT_GT(at_100, 0);
  EXPECT_LE(at_1000 - at_100, 2048);
}

// Dynamic resolution's controller on a model frame: t(f) = fixed + per_pixel f^2 ms at factor f, times a
// deterministic spread of +-8% (a fixed sequence), and the first frame after each move (the history restarting)
// twice as slow. Each case must settle where the median frame meets the target (30 FPS: 33.3 ms), the
// factor within a move of the largest that meets it, and stop moving. Case 1 is near the viewer at a 640x360
// window on 2026-12-06 (about 9 ms of display and HUD, 25 ms of render at 320x180 -> 100 ms at full size).
// Case 2 starts just over the target (45 ms at full size): the controller before, which aimed at the target
// itself and moved only when the factor was off by more than 10%, stopped there at a median of 34.8 ms (in a
// simulation of the same model; in the viewer it stopped at 33.5-35.8 ms). The others: all fixed cost over
// the target (the factor falls to its floor), and a frame that meets the target at full size.
TEST(DynamicScale, SettlesUnderTheTargetAndStays) {
  struct Case {
    double fixed, per_pixel;
    float expect_min, expect_max;  // the factor's settled range
  };
  const double target_ms = 1000.0 / 30.0;
  const double spread[7] = {1.0, 1.08, 0.95, 1.03, 0.92, 1.05, 0.97};
  for (const Case& c : {Case{9.0, 100.0, 0.40f, 0.50f}, Case{5.0, 40.0, 0.70f, 0.85f}, Case{40.0, 20.0, 0.1f, 0.1f},
                        Case{5.0, 20.0, 1.0f, 1.0f}}) {
    DynamicScale controller;
    int moves = 0, moves_late = 0;
    bool restarted = false;
    std::vector<double> late;
    for (int frame = 0; frame < 400; ++frame) {
      const double f = controller.factor();
      const double t = (c.fixed + c.per_pixel * f * f) * spread[frame % 7] * (restarted ? 2.0 : 1.0);
      restarted = controller.update(t, 30.0f, 0.1f);
      moves += restarted;
      if (frame >= 200) {
        moves_late += restarted;
        late.push_back(t);
      }
    }
    std::sort(late.begin(), late.end());
    std::printf("fixed %.0f ms, %.0f ms per full frame: factor %.3f after %d moves, median %.1f ms\n", c.fixed,
                c.per_pixel, controller.factor(), moves, late[late.size() / 2]);
    EXPECT_GE(controller.factor(), c.expect_min);
    EXPECT_LE(controller.factor(), c.expect_max);
    EXPECT_EQ(moves_late, 0);
    if (c.fixed < target_ms) {
      EXPECT_LE(late[late.size() / 2], target_ms);
    }
  }
  // Without a target the factor returns to 1.
  DynamicScale controller;
  for (int frame = 0; frame < 20; ++frame) controller.update(100.0, 30.0f, 0.1f);
  EXPECT_LT(controller.factor(), 1.0f);
  EXPECT_TRUE(controller.update(100.0, 0.0f, 0.1f));
  EXPECT_EQ(controller.factor(), 1.0f);
}

// Dynamic resolution (--target-fps): with a target no frame can meet (10,000 FPS) the render scale falls
// to its floor within 60 headless frames (320x180 window: at most 0.1 x 320 = 32 pixels wide, measured
// 32); with a target every frame meets (1 FPS) it stays at the full size; without a target it is
// untouched. Each step reconfigures the same Renderer (no new BVHs), so the run also exercises
// Renderer::apply_settings at changing sizes.
TEST(ViewerHeadless, DynamicResolutionFollowsTheTarget) {
  const RenderSettings settings = testing::settings({{"method", "direct"}});
  for (float target : {10000.0f, 1.0f, 0.0f}) {
    ViewerOptions options;
    options.headless = true;
    options.width = 320;
    options.height = 180;
    options.frames = 60;
    options.target_fps = target;
    options.orbit_degrees_per_frame = 1.0f;
    Viewer viewer(make_builtin_scene("cornell"), settings, options);
    while (viewer.step()) {
    }
    const int width = viewer.renderer().settings().width;
    std::printf("target %.0f FPS: render width after 60 frames %d\n", target, width);
    if (target > 1000.0f)
      EXPECT_LE(width, 32);
    else
      EXPECT_EQ(width, 320);
    EXPECT_EQ(viewer.frame_times().size(), 59u);
  }
}

}  // namespace
}  // namespace candela
