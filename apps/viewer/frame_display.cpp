#include "apps/viewer/frame_display.h"

#include <cstring>

namespace candela {

// One triangle covering the viewport, its corners from gl_VertexID (no vertex buffer); texture row 0 is
// the image's top row, so v runs downwards.
static const char* kBlitVertex = R"(#version 330 core
out vec2 uv;
void main() {
  vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
  uv = vec2(p.x, 1.0 - p.y);
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
})";
static const char* kBlitFragment = R"(#version 330 core
in vec2 uv;
uniform sampler2D frame;
out vec4 color;
void main() { color = vec4(texture(frame, uv).rgb, 1.0); })";

FrameDisplay::FrameDisplay(const GlFunctions& gl) : gl_(gl) {
  program_ = link_program(gl_, kBlitVertex, kBlitFragment);
  gl_.GenVertexArrays(1, &vertex_array_);  // core profile draws need a bound vertex array, even an empty one
  gl_.GenTextures(1, &texture_);
  gl_.BindTexture(GL_TEXTURE_2D, texture_);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

FrameDisplay::~FrameDisplay() {
  gl_.DeleteTextures(1, &texture_);
  gl_.DeleteVertexArrays(1, &vertex_array_);
  gl_.DeleteProgram(program_);
}

void FrameDisplay::upload(const Rgba8Image& frame) {
  gl_.BindTexture(GL_TEXTURE_2D, texture_);
  gl_.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
  if (frame.width != texture_width_ || frame.height != texture_height_) {
    texture_width_ = frame.width;
    texture_height_ = frame.height;
    gl_.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, frame.width, frame.height, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                   frame.pixels.data());
  } else {
    gl_.TexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, frame.width, frame.height, GL_RGBA, GL_UNSIGNED_BYTE,
                      frame.pixels.data());
  }
}

void FrameDisplay::draw(int framebuffer_width, int framebuffer_height) {
  gl_.Viewport(0, 0, framebuffer_width, framebuffer_height);
  gl_.Disable(GL_BLEND);
  gl_.Disable(GL_SCISSOR_TEST);
  gl_.ClearColor(0.0f, 0.0f, 0.0f, 1.0f);
  gl_.Clear(GL_COLOR_BUFFER_BIT);
  if (texture_width_ == 0) return;
  gl_.UseProgram(program_);
  gl_.ActiveTexture(GL_TEXTURE0);
  gl_.BindTexture(GL_TEXTURE_2D, texture_);
  gl_.Uniform1i(gl_.GetUniformLocation(program_, "frame"), 0);
  gl_.BindVertexArray(vertex_array_);
  gl_.DrawArrays(GL_TRIANGLES, 0, 3);
}

Rgba8Image FrameDisplay::read_framebuffer(int framebuffer_width, int framebuffer_height) const {
  Rgba8Image out{framebuffer_width, framebuffer_height,
                 std::vector<uint8_t>(size_t(framebuffer_width) * framebuffer_height * 4)};
  std::vector<uint8_t> bottom_up(out.pixels.size());
  gl_.PixelStorei(GL_PACK_ALIGNMENT, 1);
  gl_.ReadPixels(0, 0, framebuffer_width, framebuffer_height, GL_RGBA, GL_UNSIGNED_BYTE, bottom_up.data());
  size_t row = size_t(framebuffer_width) * 4;
  for (int y = 0; y < framebuffer_height; ++y)
    std::memcpy(&out.pixels[size_t(y) * row], &bottom_up[size_t(framebuffer_height - 1 - y) * row], row);
  for (size_t i = 3; i < out.pixels.size(); i += 4) out.pixels[i] = 255;  // what is seen is opaque
  return out;
}

}  // namespace candela
