#pragma once
// Where the viewer draws: an OpenGL 3.3 core context behind one interface, either a GLFW window (needs an
// X display) or an off-screen OSMesa buffer (headless). Both hand out their GetProcAddress, so the
// same GL code (gl_functions.h) draws into either, and both report input as one WindowInput per frame.
#include <memory>
#include <string>
#include <vector>

namespace candela {

// A context's GetProcAddress (glfwGetProcAddress, OSMesaGetProcAddress): GL function pointers by name.
using GlProc = void (*)();
using GlGetProcAddress = GlProc (*)(const char* name);

// What happened since the last poll: sizes, the mouse, the keys the viewer and the HUD read.
struct WindowInput {
  int framebuffer_width = 0, framebuffer_height = 0;  // 0 x 0 while the window is minimised
  int window_width = 0, window_height = 0;            // in screen coordinates (mouse positions use these)
  bool close_requested = false;
  bool focused = true;
  double mouse_x = -1.0, mouse_y = -1.0;  // window coordinates; negative: no mouse
  bool mouse_down[3] = {};                // left, right, middle
  float scroll = 0.0f;                    // wheel steps since the last poll (up positive)
  // Keys held now, by the character printed on them ('W', 'A', ...), and the navigation keys ImGui's text
  // fields need; `typed` are the characters entered since the last poll.
  bool key_down[512] = {};
  bool shift = false, ctrl = false, alt = false, super = false;
  std::vector<unsigned> typed;
};

// Key indices in WindowInput::key_down besides printable ASCII (upper-case letters, digits).
enum ViewerKey : int {
  kKeyTab = 256,
  kKeyLeft,
  kKeyRight,
  kKeyUp,
  kKeyDown,
  kKeyPageUp,
  kKeyPageDown,
  kKeyHome,
  kKeyEnd,
  kKeyInsert,
  kKeyDelete,
  kKeyBackspace,
  kKeySpace,
  kKeyEnter,
  kKeyEscape
};

class GlContext {
 public:
  virtual ~GlContext() = default;
  virtual GlGetProcAddress proc_address() const = 0;
  // Processes pending window events and returns the input state. Cheap (no blocking).
  virtual WindowInput poll() = 0;
  // Shows the frame drawn into the back buffer (window: swap; headless: wait for the GL to finish).
  virtual void present() = 0;
  // Test hook: minimise (true) or restore (false) the window; a no-op off screen.
  virtual void set_minimised(bool minimised) = 0;
};

// A GLFW window with an OpenGL 3.3 core context, vsync off. Throws std::runtime_error when there is no
// display or no such context.
std::unique_ptr<GlContext> make_window_context(int width, int height, const std::string& title);
// An OSMesa (software, llvmpipe) OpenGL 3.3 core context drawing into a width x height RGBA buffer.
std::unique_ptr<GlContext> make_headless_context(int width, int height);

}  // namespace candela
