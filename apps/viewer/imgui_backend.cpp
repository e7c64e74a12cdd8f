#include "apps/viewer/imgui_backend.h"

#include <imgui.h>

namespace candela {

static const char* kImGuiVertex = R"(#version 330 core
layout(location = 0) in vec2 position;
layout(location = 1) in vec2 uv_in;
layout(location = 2) in vec4 color_in;
uniform mat4 projection;
out vec2 uv;
out vec4 color;
void main() {
  uv = uv_in;
  color = color_in;
  gl_Position = projection * vec4(position, 0.0, 1.0);
})";
static const char* kImGuiFragment = R"(#version 330 core
in vec2 uv;
in vec4 color;
uniform sampler2D atlas;
out vec4 result;
void main() { result = color * texture(atlas, uv); })";

ImGuiBackend::ImGuiBackend(const GlFunctions& gl) : gl_(gl) {
  ImGui::CreateContext();
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = nullptr;
  io.BackendRendererName = "candela_gl33";
  io.BackendPlatformName = "candela_window_input";
  io.BackendFlags |= ImGuiBackendFlags_RendererHasVtxOffset;
  const std::pair<ImGuiKey_, int> keys[] = {{ImGuiKey_Tab, kKeyTab},
                                            {ImGuiKey_LeftArrow, kKeyLeft},
                                            {ImGuiKey_RightArrow, kKeyRight},
                                            {ImGuiKey_UpArrow, kKeyUp},
                                            {ImGuiKey_DownArrow, kKeyDown},
                                            {ImGuiKey_PageUp, kKeyPageUp},
                                            {ImGuiKey_PageDown, kKeyPageDown},
                                            {ImGuiKey_Home, kKeyHome},
                                            {ImGuiKey_End, kKeyEnd},
                                            {ImGuiKey_Insert, kKeyInsert},
                                            {ImGuiKey_Delete, kKeyDelete},
                                            {ImGuiKey_Backspace, kKeyBackspace},
                                            {ImGuiKey_Space, kKeySpace},
                                            {ImGuiKey_Enter, kKeyEnter},
                                            {ImGuiKey_Escape, kKeyEscape},
                                            {ImGuiKey_A, 'A'},
                                            {ImGuiKey_C, 'C'},
                                            {ImGuiKey_V, 'V'},
                                            {ImGuiKey_X, 'X'},
                                            {ImGuiKey_Y, 'Y'},
                                            {ImGuiKey_Z, 'Z'}};
  for (const auto& [imgui_key, ours] : keys) io.KeyMap[imgui_key] = ours;

  program_ = link_program(gl_, kImGuiVertex, kImGuiFragment);
  projection_location_ = gl_.GetUniformLocation(program_, "projection");
  texture_location_ = gl_.GetUniformLocation(program_, "atlas");
  gl_.GenVertexArrays(1, &vertex_array_);
  gl_.GenBuffers(1, &vertex_buffer_);
  gl_.GenBuffers(1, &index_buffer_);
  gl_.BindVertexArray(vertex_array_);
  gl_.BindBuffer(GL_ARRAY_BUFFER, vertex_buffer_);
  gl_.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, index_buffer_);  // recorded in the vertex array
  gl_.EnableVertexAttribArray(0);
  gl_.EnableVertexAttribArray(1);
  gl_.EnableVertexAttribArray(2);
  gl_.VertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, sizeof(ImDrawVert), (void*)offsetof(ImDrawVert, pos));
  gl_.VertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, sizeof(ImDrawVert), (void*)offsetof(ImDrawVert, uv));
  gl_.VertexAttribPointer(2, 4, GL_UNSIGNED_BYTE, GL_TRUE, sizeof(ImDrawVert), (void*)offsetof(ImDrawVert, col));
  gl_.BindVertexArray(0);

  unsigned char* pixels = nullptr;
  int width = 0, height = 0;
  io.Fonts->GetTexDataAsRGBA32(&pixels, &width, &height);
  gl_.GenTextures(1, &font_texture_);
  gl_.BindTexture(GL_TEXTURE_2D, font_texture_);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  gl_.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
  gl_.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, pixels);
  io.Fonts->SetTexID(reinterpret_cast<ImTextureID>(uintptr_t(font_texture_)));
}

ImGuiBackend::~ImGuiBackend() {
  gl_.DeleteTextures(1, &font_texture_);
  gl_.DeleteBuffers(1, &vertex_buffer_);
  gl_.DeleteBuffers(1, &index_buffer_);
  gl_.DeleteVertexArrays(1, &vertex_array_);
  gl_.DeleteProgram(program_);
  ImGui::DestroyContext();
}

void ImGuiBackend::new_frame(const WindowInput& in, float dt) {
  ImGuiIO& io = ImGui::GetIO();
  io.DisplaySize = ImVec2(float(in.window_width), float(in.window_height));
  if (in.window_width > 0 && in.window_height > 0)
    io.DisplayFramebufferScale = ImVec2(float(in.framebuffer_width) / float(in.window_width),
                                        float(in.framebuffer_height) / float(in.window_height));
  io.DeltaTime = dt > 0.0f ? dt : 1e-4f;
  io.MousePos =
      in.focused && in.mouse_x >= 0.0 ? ImVec2(float(in.mouse_x), float(in.mouse_y)) : ImVec2(-FLT_MAX, -FLT_MAX);
  for (int b = 0; b < 3; ++b) io.MouseDown[b] = in.mouse_down[b];
  io.MouseWheel += in.scroll;
  for (int k = 0; k < 512; ++k) io.KeysDown[k] = in.key_down[k];
  io.KeyShift = in.shift;
  io.KeyCtrl = in.ctrl;
  io.KeyAlt = in.alt;
  io.KeySuper = in.super;
  for (unsigned c : in.typed) io.AddInputCharacter(c);
  ImGui::NewFrame();
}

void ImGuiBackend::render(int framebuffer_width, int framebuffer_height) {
  ImGui::Render();
  const ImDrawData* data = ImGui::GetDrawData();
  if (framebuffer_width <= 0 || framebuffer_height <= 0 || !data || data->CmdListsCount == 0) return;
  gl_.Viewport(0, 0, framebuffer_width, framebuffer_height);
  gl_.Enable(GL_BLEND);
  gl_.BlendEquation(GL_FUNC_ADD);
  gl_.BlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  gl_.Disable(GL_CULL_FACE);
  gl_.Disable(GL_DEPTH_TEST);
  gl_.Enable(GL_SCISSOR_TEST);
  // Orthographic projection of ImGui's display rectangle onto clip space, y down.
  const float l = data->DisplayPos.x, r = l + data->DisplaySize.x, t = data->DisplayPos.y, b = t + data->DisplaySize.y;
  const float projection[16] = {2.0f / (r - l),    0, 0, 0, 0, 2.0f / (t - b), 0, 0, 0, 0, -1, 0, (r + l) / (l - r),
                                (t + b) / (b - t), 0, 1};
  gl_.UseProgram(program_);
  gl_.UniformMatrix4fv(projection_location_, 1, GL_FALSE, projection);
  gl_.Uniform1i(texture_location_, 0);
  gl_.ActiveTexture(GL_TEXTURE0);
  gl_.BindVertexArray(vertex_array_);
  const ImVec2 scale = data->FramebufferScale;
  for (int n = 0; n < data->CmdListsCount; ++n) {
    const ImDrawList* list = data->CmdLists[n];
    gl_.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(list->VtxBuffer.Size) * sizeof(ImDrawVert), list->VtxBuffer.Data,
                   GL_STREAM_DRAW);
    gl_.BufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(list->IdxBuffer.Size) * sizeof(ImDrawIdx), list->IdxBuffer.Data,
                   GL_STREAM_DRAW);
    for (const ImDrawCmd& cmd : list->CmdBuffer) {
      // Clip rectangle in framebuffer pixels; GL's scissor origin is the bottom-left corner.
      float x0 = (cmd.ClipRect.x - l) * scale.x, y0 = (cmd.ClipRect.y - t) * scale.y;
      float x1 = (cmd.ClipRect.z - l) * scale.x, y1 = (cmd.ClipRect.w - t) * scale.y;
      if (x1 <= x0 || y1 <= y0) continue;
      gl_.Scissor(GLint(x0), GLint(framebuffer_height - y1), GLsizei(x1 - x0), GLsizei(y1 - y0));
      gl_.BindTexture(GL_TEXTURE_2D, GLuint(reinterpret_cast<uintptr_t>(cmd.TextureId)));
      gl_.DrawElementsBaseVertex(GL_TRIANGLES, GLsizei(cmd.ElemCount),
                                 sizeof(ImDrawIdx) == 2 ? GL_UNSIGNED_SHORT : GL_UNSIGNED_INT,
                                 (void*)(cmd.IdxOffset * sizeof(ImDrawIdx)), GLint(cmd.VtxOffset));
    }
  }
  gl_.Disable(GL_SCISSOR_TEST);
  gl_.Disable(GL_BLEND);
  gl_.BindVertexArray(0);
}

}  // namespace candela
