#include "apps/viewer/viewer.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <thread>

#include "engine/check.h"

namespace candela {

namespace {

// Degrees the camera turns per pixel of mouse drag (orbit and fly look).
constexpr float kOrbitDegreesPerPixel = 0.25f, kLookDegreesPerPixel = 0.15f;
constexpr std::chrono::milliseconds kResizeSettle(200);

// Render size for a framebuffer at `scale`: at least one pixel each way.
int scaled(int framebuffer_size, float scale) { return std::max(1, int(std::lround(framebuffer_size * scale))); }

}  // namespace

Viewer::Viewer(const Scene& scene, const RenderSettings& settings, const ViewerOptions& options)
    : options_(options), camera_(scene.default_camera()) {
  context_ = options.headless ? make_headless_context(options.width, options.height)
                              : make_window_context(options.width, options.height, "candela view");
  gl_ = std::make_unique<GlFunctions>(context_->proc_address());
  display_ = std::make_unique<FrameDisplay>(*gl_);
  imgui_ = std::make_unique<ImGuiBackend>(*gl_);
  hud_.settings = settings;
  hud_.scale = options.scale;
  hud_.target_fps = options.target_fps;
  hud_.exposure = options.exposure;
  hud_.view = options.view;
  WindowInput input = context_->poll();
  last_mouse_x_ = input.mouse_x;
  last_mouse_y_ = input.mouse_y;
  RenderSettings first = settings;
  first.width = scaled(std::max(input.framebuffer_width, 1), options.scale);
  first.height = scaled(std::max(input.framebuffer_height, 1), options.scale);
  renderer_ = std::make_unique<Renderer>(Scene(scene), first);
  last_step_ = std::chrono::steady_clock::now();
}

Viewer::~Viewer() = default;

// Gives the Renderer the HUD's settings at this size, in place (Renderer::apply_settings: history starts
// over, the BVHs and light list stay; a light sampler build at most).
void Viewer::configure_renderer(int width, int height) {
  RenderSettings settings = hud_.settings;
  settings.width = width;
  settings.height = height;
  renderer_->apply_settings(settings);
  reconfigure_ = false;
}

// Mouse and keys move the camera unless ImGui uses them: left drag orbits, the wheel zooms, right drag
// looks around, WASD (QE down/up) fly, shift four times faster. Headless: the scripted orbit.
void Viewer::apply_camera_input(const WindowInput& in, float dt) {
  if (options_.orbit_degrees_per_frame != 0.0f) camera_.orbit(options_.orbit_degrees_per_frame, 0.0f);
  const ImGuiIO& io = ImGui::GetIO();
  double dx = in.mouse_x - last_mouse_x_, dy = in.mouse_y - last_mouse_y_;
  last_mouse_x_ = in.mouse_x;
  last_mouse_y_ = in.mouse_y;
  if (!io.WantCaptureMouse) {
    if (in.mouse_down[0] && (dx != 0.0 || dy != 0.0))
      camera_.orbit(-float(dx) * kOrbitDegreesPerPixel, float(dy) * kOrbitDegreesPerPixel);
    if (in.mouse_down[1] && (dx != 0.0 || dy != 0.0))
      camera_.look(float(dx) * kLookDegreesPerPixel, -float(dy) * kLookDegreesPerPixel);
    if (in.scroll != 0.0f) camera_.zoom(in.scroll);
  }
  if (!io.WantCaptureKeyboard) {
    auto axis = [&](char plus, char minus) { return float(in.key_down[int(plus)]) - float(in.key_down[int(minus)]); };
    vec3 move(axis('D', 'A'), axis('E', 'Q'), axis('W', 'S'));
    if (move != vec3(0.0f)) camera_.move(move * camera_.fly_speed() * dt * (in.shift ? 4.0f : 1.0f));
  }
}

bool Viewer::step() {
  auto now = std::chrono::steady_clock::now();
  float dt = std::chrono::duration<float>(now - last_step_).count();
  double frame_ms = std::chrono::duration<double, std::milli>(now - last_step_).count();
  last_step_ = now;
  if (frames_done_ == options_.test_minimise_frame) context_->set_minimised(true);
  if (frames_done_ == options_.test_minimise_frame + 3) context_->set_minimised(false);
  WindowInput in = context_->poll();
  if (in.close_requested) return false;
  ++frames_done_;
  if (in.framebuffer_width > 0 && in.framebuffer_height > 0) {  // minimised: nothing to draw into
    imgui_->new_frame(in, dt);
    apply_camera_input(in, dt);
    // A new render size (window resized, scale dragged) waits until it has held for kResizeSettle, so a
    // drag reconfigures the Renderer once; meanwhile the last size is shown stretched. Dynamic resolution's
    // sizes apply at once (DynamicScale already waits between them).
    const float scale = hud_.scale * dynamic_scale_.factor();
    int width = scaled(in.framebuffer_width, scale), height = scaled(in.framebuffer_height, scale);
    if (width != pending_width_ || height != pending_height_) {
      pending_width_ = width;
      pending_height_ = height;
      pending_since_ = now;
    }
    bool resized = width != renderer_->settings().width || height != renderer_->settings().height;
    const bool settled = now - pending_since_ >= kResizeSettle || dynamic_resize_;
    if (reconfigure_ || (resized && settled)) configure_renderer(width, height);
    dynamic_resize_ = false;
    FrameStats stats = renderer_->render_frame(frame_index_, scene_time_, camera_.desc());
    display_->upload(aov_display_pixels(*renderer_, hud_.view, hud_.exposure));
    display_->draw(in.framebuffer_width, in.framebuffer_height);
    if (frames_done_ > 1) {  // the first step's time is the setup's
      frame_times_.push_back(frame_ms);
      // Dynamic resolution's factor on the HUD's scale, which keeps the render at least 0.1 of the window.
      constexpr float kMinScale = 0.1f;
      dynamic_resize_ = dynamic_scale_.update(frame_ms, hud_.target_fps, kMinScale / std::max(hud_.scale, kMinScale));
    }
    hud_.dynamic_scale = dynamic_scale_.factor();
    history_.push(frame_ms, std::move(stats));
    HudActions actions;  // without the HUD (--no-hud), ImGui draws nothing and nothing is clicked
    if (options_.hud) actions = draw_hud(hud_, history_, *renderer_, camera_.desc(), hud_rect_);
    imgui_->render(in.framebuffer_width, in.framebuffer_height);
    framebuffer_width_ = in.framebuffer_width;
    framebuffer_height_ = in.framebuffer_height;
    reconfigure_ = actions.settings_changed || actions.reset;
    if (actions.save_png) save_view(".png");
    if (actions.save_exr) save_view(".exr");
    if (options_.frames == 0 || frames_done_ < options_.frames) context_->present();  // the last frame stays readable
    ++frame_index_;
    if (!hud_.pause_time) scene_time_ = float(frame_index_) / options_.fps;
  } else {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));  // minimised: do not spin
  }
  return options_.frames == 0 || frames_done_ < options_.frames;
}

// HUD buttons: the displayed AOV (write_aov: its values in EXR, as displayed in PNG); the outcome goes to
// the HUD's status line.
void Viewer::save_view(const std::string& extension) {
  std::string path = std::string(hud_.screenshot_base) + extension;
  try {
    write_aov(path, *renderer_, hud_.view, hud_.exposure);
    hud_.status = "wrote " + path;
  } catch (const InputError& e) {
    hud_.status = e.what();
  }
}

void Viewer::write_framebuffer(const std::string& path) const {
  if (framebuffer_width_ == 0) throw InputError(path + ": no frame was drawn (window minimised)");
  Rgba8Image pixels = display_->read_framebuffer(framebuffer_width_, framebuffer_height_);
  write_png_rgba8(path, pixels.width, pixels.height, pixels.pixels.data());
}

int run_viewer(const Scene& scene, const RenderSettings& settings, const ViewerOptions& options) {
  Viewer viewer(scene, settings, options);
  auto start = std::chrono::steady_clock::now();
  while (viewer.step()) {
  }
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!options.screenshot.empty()) viewer.write_framebuffer(options.screenshot);
  if (!options.quiet) {
    const HudRect& hud = viewer.hud_rect();
    std::fprintf(stderr, "view: %d frames in %.2f s (%.1f fps), ", viewer.frames_done(), seconds,
                 viewer.frames_done() / std::max(seconds, 1e-9));
    std::vector<double> t = viewer.frame_times();
    if (!t.empty()) {
      std::sort(t.begin(), t.end());
      auto at = [&](double q) { return t[std::min(t.size() - 1, size_t(q * double(t.size())))]; };
      std::fprintf(stderr, "frame ms median %.1f, p90 %.1f, p99 %.1f, max %.1f; last render size %dx%d, ", at(0.5),
                   at(0.9), at(0.99), t.back(), viewer.renderer().settings().width,
                   viewer.renderer().settings().height);
    }
    if (options.hud)
      std::fprintf(stderr, "HUD at %.0f %.0f size %.0f x %.0f\n", hud.x, hud.y, hud.width, hud.height);
    else
      std::fprintf(stderr, "HUD off\n");
    if (!options.screenshot.empty()) std::fprintf(stderr, "wrote %s\n", options.screenshot.c_str());
  }
  return 0;
}

}  // namespace candela
