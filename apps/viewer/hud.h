#pragma once
// The viewer's heads-up display (Dear ImGui): frame time and FPS, per-stage milliseconds of the recent
// frames as a stacked graph with a legend, rays per frame, live renderer settings (method, light
// sampler, ReSTIR DI parameters, denoiser, max depth, resolution scale), the debug view, reset and
// screenshots. It edits a HudState and reports what the viewer must do; it never touches the Renderer.
#include <deque>
#include <string>

#include "apps/renderer.h"
#include "apps/aovs.h"

namespace candela {

// The last frames' wall time (whole viewer loop: render, display, HUD) and renderer stats.
class FrameHistory {
 public:
  static constexpr size_t kCapacity = 120;
  void push(double frame_ms, FrameStats stats);
  size_t size() const { return frames_.size(); }
  double frame_ms(size_t i) const { return frames_[i].frame_ms; }
  const FrameStats& stats(size_t i) const { return frames_[i].stats; }

 private:
  struct Entry {
    double frame_ms;
    FrameStats stats;
  };
  std::deque<Entry> frames_;
};

// What the HUD edits.
struct HudState {
  RenderSettings settings;     // the settings the next frame should use
  float scale = 1.0f;          // render resolution / window resolution (with a target FPS: at most)
  float target_fps = 0.0f;     // dynamic resolution's target (0: off)
  float dynamic_scale = 1.0f;  // shown: dynamic resolution's factor on `scale`
  Aov view = Aov::Radiance;
  float exposure = 1.0f;
  bool pause_time = false;                     // freeze scene time (animated scenes then accumulate too)
  char screenshot_base[256] = "candela_view";  // screenshots go to BASE.png / BASE.exr
  std::string status;                          // last screenshot result or error, shown under the buttons
};

struct HudActions {
  bool settings_changed = false;  // settings or scale: the viewer reconfigures the Renderer
  bool reset = false;             // drop accumulation and history
  bool save_png = false, save_exr = false;
};

// Where the HUD window was drawn, in window coordinates (for tests and the exit summary).
struct HudRect {
  float x = 0, y = 0, width = 0, height = 0;
};

// Draws the HUD window at the top-left corner (between ImGui new_frame and render). `renderer` is the one
// that rendered the frame being shown; `camera` its camera. Cost: a few hundred ImGui widgets.
HudActions draw_hud(HudState& state, const FrameHistory& history, const Renderer& renderer, const CameraDesc& camera,
                    HudRect& rect);

}  // namespace candela
