// GlContext over OSMesa (Mesa's off-screen GL; llvmpipe on a machine without a GPU).
#include <GL/osmesa.h>

#include <array>
#include <cstdint>

#include "core/error.hpp"
#include "render/gl_context.hpp"

namespace demlab::render {
namespace {

class OsMesaContext : public GlContext {
 public:
  OsMesaContext() {
    // No depth or stencil in OSMesa's own buffer: all drawing goes to the renderer's FBO.
    const int attribs[] = {OSMESA_FORMAT,
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
    ctx_ = OSMesaCreateContextAttribs(attribs, nullptr);
    if (!ctx_)
      throw Error("couldn't create an OpenGL 3.3 core context with OSMesa", {"RENDER", "CONTEXT"});
    makeCurrent();
  }
  ~OsMesaContext() override { OSMesaDestroyContext(ctx_); }

  void makeCurrent() override {
    if (!OSMesaMakeCurrent(ctx_, buffer_.data(), GL_UNSIGNED_BYTE, 1, 1))
      throw Error("couldn't make the OSMesa context current", {"RENDER", "CONTEXT"});
  }

  void releaseCurrent() override { OSMesaMakeCurrent(nullptr, nullptr, GL_UNSIGNED_BYTE, 0, 0); }

  void* procAddress(const char* name) override {
    return reinterpret_cast<void*>(OSMesaGetProcAddress(name));
  }

  std::string name() const override { return "osmesa"; }

 private:
  OSMesaContext ctx_ = nullptr;
  std::array<std::uint8_t, 4> buffer_{};  // the 1x1 default framebuffer OSMesa requires
};

}  // namespace

std::unique_ptr<GlContext> makeGlContext() {
  return std::make_unique<OsMesaContext>();
}

}  // namespace demlab::render

// OSMesa keeps the framebuffer it allocates in OSMesaMakeCurrent on a global list that
// OSMesaDestroyContext does not free (Mesa 22), which LeakSanitizer reports at exit in every
// program that renders. Likewise Tk's fonts (the viewer's window, through Xft) leave
// fontconfig's configuration, which only FcFini frees and Tk never calls. This hook tells
// LeakSanitizer to ignore leaks inside those two libraries only. It lives here because this
// file is linked into every program that makes a context; in builds without sanitizers it is an
// unused function.
extern "C" const char* __lsan_default_suppressions() {
  return "leak:libOSMesa.so\nleak:libfontconfig.so\n";
}
