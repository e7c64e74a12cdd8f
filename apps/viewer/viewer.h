#pragma once
// `candela view`: the interactive loop. Each frame: poll input, move the camera, render with the CPU
// Renderer, show the frame as a texture with the HUD over it. The same loop runs in a GLFW window or
// headless on OSMesa (then the camera can orbit on its own and the last framebuffer becomes a PNG).
#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "apps/renderer.h"
#include "apps/viewer/camera_controller.h"
#include "apps/viewer/dynamic_scale.h"
#include "apps/viewer/frame_display.h"
#include "apps/viewer/gl_context.h"
#include "apps/viewer/hud.h"
#include "apps/viewer/imgui_backend.h"

namespace candela {

struct ViewerOptions {
  int width = 640, height = 360;         // window (headless: framebuffer) size in pixels
  float scale = 1.0f;                    // render resolution = window resolution x scale (with a target: at most)
  float target_fps = 0.0f;               // > 0: dynamic resolution, the render scale adapts to hold this frame rate
  bool headless = false;                 // OSMesa off screen instead of a window
  int frames = 0;                        // stop after this many frames; 0 = until the window is closed
  std::string screenshot;                // after the last frame, the framebuffer (frame + HUD) as PNG
  float orbit_degrees_per_frame = 0.0f;  // the camera orbits its target on its own by this much per frame
  float fps = 30.0f;                     // scene time advances 1/fps seconds per frame
  float exposure = 1.0f;
  Aov view = Aov::Radiance;      // what is shown first
  int test_minimise_frame = -1;  // test hook: minimise the window for 3 frames starting at this frame
  bool hud = true;               // draw the HUD over the frame (false: --no-hud, the frame alone)
  bool quiet = false;
};

class Viewer {
 public:
  // Opens the window or headless context and builds the Renderer from a copy of `scene` (the one
  // Renderer of the viewer's life: settings and sizes change in place).
  // Throws std::runtime_error when no GL context can be had.
  Viewer(const Scene& scene, const RenderSettings& settings, const ViewerOptions& options);
  ~Viewer();

  // One frame of the loop; false once the window was closed or the frame count reached.
  bool step();
  // The framebuffer of the last frame drawn, as a PNG (atomic). Throws InputError when it cannot be written.
  void write_framebuffer(const std::string& path) const;
  const HudRect& hud_rect() const { return hud_rect_; }
  int frames_done() const { return frames_done_; }
  const std::vector<double>& frame_times() const { return frame_times_; }
  const Renderer& renderer() const { return *renderer_; }

 private:
  void apply_camera_input(const WindowInput& input, float dt);
  void configure_renderer(int width, int height);
  void save_view(const std::string& extension);

  ViewerOptions options_;
  std::unique_ptr<GlContext> context_;  // declared before everything that holds GL objects
  std::unique_ptr<GlFunctions> gl_;
  std::unique_ptr<FrameDisplay> display_;
  std::unique_ptr<ImGuiBackend> imgui_;
  std::unique_ptr<Renderer> renderer_;
  CameraController camera_;
  HudState hud_;
  HudRect hud_rect_;
  FrameHistory history_;
  int frames_done_ = 0;  // loop iterations, drawn or minimised
  int frame_index_ = 0;  // the Renderer's frame number (random streams)
  float scene_time_ = 0.0f;
  bool reconfigure_ = false;         // the HUD changed a setting: the Renderer takes the HUD's settings
  DynamicScale dynamic_scale_;       // dynamic resolution's factor on the HUD's scale (1 without a target)
  bool dynamic_resize_ = false;      // it changed: the next frame takes the new size without waiting
  std::vector<double> frame_times_;  // every drawn frame's loop time (ms), for the exit summary
  int framebuffer_width_ = 0, framebuffer_height_ = 0;  // of the last frame drawn
  int pending_width_ = 0, pending_height_ = 0;          // the latest render size asked for, and since when
  std::chrono::steady_clock::time_point pending_since_;
  double last_mouse_x_ = 0.0, last_mouse_y_ = 0.0;
  std::chrono::steady_clock::time_point last_step_;
};

// Runs the viewer until the window closes or `options.frames` frames are done, then writes the
// screenshot if one was asked for; returns the exit status. Prints a summary unless quiet.
int run_viewer(const Scene& scene, const RenderSettings& settings, const ViewerOptions& options);

}  // namespace candela
