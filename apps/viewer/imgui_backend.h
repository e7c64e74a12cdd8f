#pragma once
// The two pieces of Dear ImGui that connect it to the viewer, written here because Debian's prebuilt
// OpenGL 3 backend loads GL through libGL/GLX, which draws nothing under OSMesa:
//  - platform: feeds one WindowInput per frame (sizes, mouse, keys, typed text) into ImGui's IO;
//  - renderer: draws ImGui's triangle lists with the GL functions of the current context (gl_functions.h).
// It owns the ImGui context: one ImGuiBackend per viewer.
#include "apps/viewer/gl_context.h"
#include "apps/viewer/gl_functions.h"

struct ImDrawData;

namespace candela {

class ImGuiBackend {
 public:
  // Creates the ImGui context, the font atlas texture and the shader. No .ini file is written.
  explicit ImGuiBackend(const GlFunctions& gl);
  ~ImGuiBackend();
  ImGuiBackend(const ImGuiBackend&) = delete;
  ImGuiBackend& operator=(const ImGuiBackend&) = delete;

  // Feeds this frame's input (dt seconds since the last frame) and starts an ImGui frame.
  void new_frame(const WindowInput& input, float dt);
  // Ends the ImGui frame and draws it over the framebuffer (alpha blended, scissored per draw command).
  // Cost: one vertex and index buffer upload per window, one draw call per command.
  void render(int framebuffer_width, int framebuffer_height);

 private:
  const GlFunctions& gl_;
  GLuint program_ = 0, vertex_array_ = 0, vertex_buffer_ = 0, index_buffer_ = 0, font_texture_ = 0;
  GLint projection_location_ = -1, texture_location_ = -1;
};

}  // namespace candela
