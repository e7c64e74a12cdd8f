// The windowed GlContext: GLFW 3.3 window, OpenGL 3.3 core context, input polled once per frame.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <stdexcept>

#include "apps/viewer/gl_context.h"

namespace candela {
namespace {

// GLFW's error callback: keeps the last message for the exception thrown when setup fails.
std::string g_glfw_error;
void on_glfw_error(int, const char* description) { g_glfw_error = description; }

class GlfwWindow final : public GlContext {
 public:
  GlfwWindow(int width, int height, const std::string& title) {
    glfwSetErrorCallback(on_glfw_error);
    if (!glfwInit()) throw std::runtime_error("cannot open a window (no display? use --headless): " + g_glfw_error);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
    if (!window_) {
      glfwTerminate();
      throw std::runtime_error("cannot create an OpenGL 3.3 core window: " + g_glfw_error);
    }
    glfwMakeContextCurrent(window_);
    glfwSwapInterval(0);  // the CPU renderer sets the pace; vsync would only add latency
    glfwSetWindowUserPointer(window_, this);
    glfwSetScrollCallback(window_, [](GLFWwindow* w, double, double dy) {
      static_cast<GlfwWindow*>(glfwGetWindowUserPointer(w))->scroll_ += float(dy);
    });
    glfwSetCharCallback(window_, [](GLFWwindow* w, unsigned c) {
      static_cast<GlfwWindow*>(glfwGetWindowUserPointer(w))->typed_.push_back(c);
    });
  }
  ~GlfwWindow() override {
    glfwDestroyWindow(window_);
    glfwTerminate();
  }

  GlGetProcAddress proc_address() const override { return glfwGetProcAddress; }

  WindowInput poll() override {
    glfwPollEvents();
    WindowInput in;
    glfwGetFramebufferSize(window_, &in.framebuffer_width, &in.framebuffer_height);
    glfwGetWindowSize(window_, &in.window_width, &in.window_height);
    if (forced_minimised_) in.framebuffer_width = in.framebuffer_height = 0;
    in.close_requested = glfwWindowShouldClose(window_);
    in.focused = glfwGetWindowAttrib(window_, GLFW_FOCUSED);
    glfwGetCursorPos(window_, &in.mouse_x, &in.mouse_y);
    for (int b = 0; b < 3; ++b) in.mouse_down[b] = glfwGetMouseButton(window_, b) == GLFW_PRESS;
    in.scroll = scroll_;
    scroll_ = 0.0f;
    in.typed.swap(typed_);
    typed_.clear();
    auto down = [&](int key) { return glfwGetKey(window_, key) == GLFW_PRESS; };
    for (int c = GLFW_KEY_0; c <= GLFW_KEY_9; ++c) in.key_down[c] = down(c);  // GLFW numbers these as ASCII
    for (int c = GLFW_KEY_A; c <= GLFW_KEY_Z; ++c) in.key_down[c] = down(c);
    const int named[][2] = {{kKeyTab, GLFW_KEY_TAB},
                            {kKeyLeft, GLFW_KEY_LEFT},
                            {kKeyRight, GLFW_KEY_RIGHT},
                            {kKeyUp, GLFW_KEY_UP},
                            {kKeyDown, GLFW_KEY_DOWN},
                            {kKeyPageUp, GLFW_KEY_PAGE_UP},
                            {kKeyPageDown, GLFW_KEY_PAGE_DOWN},
                            {kKeyHome, GLFW_KEY_HOME},
                            {kKeyEnd, GLFW_KEY_END},
                            {kKeyInsert, GLFW_KEY_INSERT},
                            {kKeyDelete, GLFW_KEY_DELETE},
                            {kKeyBackspace, GLFW_KEY_BACKSPACE},
                            {kKeySpace, GLFW_KEY_SPACE},
                            {kKeyEnter, GLFW_KEY_ENTER},
                            {kKeyEscape, GLFW_KEY_ESCAPE}};
    for (const auto& [ours, glfw] : named) in.key_down[ours] = down(glfw);
    in.shift = down(GLFW_KEY_LEFT_SHIFT) || down(GLFW_KEY_RIGHT_SHIFT);
    in.ctrl = down(GLFW_KEY_LEFT_CONTROL) || down(GLFW_KEY_RIGHT_CONTROL);
    in.alt = down(GLFW_KEY_LEFT_ALT) || down(GLFW_KEY_RIGHT_ALT);
    in.super = down(GLFW_KEY_LEFT_SUPER) || down(GLFW_KEY_RIGHT_SUPER);
    return in;
  }

  void present() override { glfwSwapBuffers(window_); }

  // Iconifies or restores the window. Without a window manager (Xvfb in tests) iconifying changes nothing,
  // so while minimised the framebuffer is also reported as 0 x 0, as a window manager would make it.
  void set_minimised(bool minimised) override {
    forced_minimised_ = minimised;
    if (minimised)
      glfwIconifyWindow(window_);
    else
      glfwRestoreWindow(window_);
  }

 private:
  GLFWwindow* window_ = nullptr;
  float scroll_ = 0.0f;
  std::vector<unsigned> typed_;
  bool forced_minimised_ = false;
};

}  // namespace

std::unique_ptr<GlContext> make_window_context(int width, int height, const std::string& title) {
  return std::make_unique<GlfwWindow>(width, height, title);
}

}  // namespace candela
