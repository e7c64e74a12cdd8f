// The headless GlContext: an OSMesa OpenGL 3.3 core context rendering into a buffer in memory.
#include <GL/osmesa.h>

#include <stdexcept>

#include "apps/viewer/gl_context.h"

namespace candela {
namespace {

// OSMesaGetProcAddress with the loader's signature.
GlProc osmesa_proc(const char* name) { return reinterpret_cast<GlProc>(OSMesaGetProcAddress(name)); }

class OsMesaContext final : public GlContext {
 public:
  OsMesaContext(int width, int height) : width_(width), height_(height), buffer_(size_t(width) * height) {
    const int attributes[] = {OSMESA_FORMAT,
                              OSMESA_RGBA,
                              OSMESA_DEPTH_BITS,
                              0,
                              OSMESA_STENCIL_BITS,
                              0,
                              OSMESA_PROFILE,
                              OSMESA_CORE_PROFILE,
                              OSMESA_CONTEXT_MAJOR_VERSION,
                              3,
                              OSMESA_CONTEXT_MINOR_VERSION,
                              3,
                              0};
    context_ = OSMesaCreateContextAttribs(attributes, nullptr);
    if (!context_) throw std::runtime_error("cannot create an OSMesa OpenGL 3.3 core context");
    if (!OSMesaMakeCurrent(context_, buffer_.data(), GL_UNSIGNED_BYTE, width, height)) {
      OSMesaDestroyContext(context_);
      throw std::runtime_error("cannot make the OSMesa context current");
    }
    finish_ = reinterpret_cast<void (*)()>(OSMesaGetProcAddress("glFinish"));
  }
  ~OsMesaContext() override { OSMesaDestroyContext(context_); }

  GlGetProcAddress proc_address() const override { return osmesa_proc; }

  WindowInput poll() override {
    WindowInput in;
    in.framebuffer_width = in.window_width = width_;
    in.framebuffer_height = in.window_height = height_;
    return in;
  }

  void present() override { finish_(); }
  void set_minimised(bool) override {}

 private:
  int width_, height_;
  std::vector<uint32_t> buffer_;  // RGBA8, the default framebuffer
  OSMesaContext context_ = nullptr;
  void (*finish_)() = nullptr;
};

}  // namespace

std::unique_ptr<GlContext> make_headless_context(int width, int height) {
  return std::make_unique<OsMesaContext>(width, height);
}

}  // namespace candela
