#pragma once
// Shows a CPU-rendered frame: the 8-bit image goes into one texture, a fullscreen triangle blits it over
// the whole framebuffer (scaled with bilinear filtering when the render resolution differs), and the
// framebuffer can be read back as what a person would have seen.
#include <cstdint>
#include <vector>

#include "apps/aovs.h"
#include "apps/viewer/gl_functions.h"

namespace candela {

class FrameDisplay {
 public:
  explicit FrameDisplay(const GlFunctions& gl);
  ~FrameDisplay();
  FrameDisplay(const FrameDisplay&) = delete;
  FrameDisplay& operator=(const FrameDisplay&) = delete;

  // Uploads the frame into the texture (reallocated only when its size changes). Cost: one copy of the image.
  void upload(const Rgba8Image& frame);
  // Clears the framebuffer_width x framebuffer_height framebuffer and draws the texture over all of it.
  void draw(int framebuffer_width, int framebuffer_height);
  // Reads the framebuffer back, flipped so that row 0 is the top, alpha set opaque. Cost: a GPU -> CPU copy and a sync.
  Rgba8Image read_framebuffer(int framebuffer_width, int framebuffer_height) const;

 private:
  const GlFunctions& gl_;
  GLuint program_ = 0, vertex_array_ = 0, texture_ = 0;
  int texture_width_ = 0, texture_height_ = 0;
};

}  // namespace candela
