// The one place that knows how a GL context is made. The OSMesa version lives in
// gl_context_osmesa.cpp; Mesa dropped OSMesa in 25.1, and an EGL (surfaceless) back end would be
// a second file implementing this interface, with nothing else changed: the renderer draws
// into its own framebuffer object and never uses the context's default framebuffer.
#pragma once

#include <memory>
#include <string>

namespace demlab::render {

class GlContext {
 public:
  virtual ~GlContext() = default;

  // Returns nothing; makes the context current on the calling thread.
  virtual void makeCurrent() = 0;

  // Returns nothing; makes no context current on the calling thread, so that another thread
  // may make this one current (a context is current on at most one thread).
  virtual void releaseCurrent() = 0;

  // Returns the address of GL function name ("glDrawArrays"), nullptr when absent.
  virtual void* procAddress(const char* name) = 0;

  // Returns the back end's name, e.g. "osmesa".
  virtual std::string name() const = 0;
};

// Returns a current OpenGL 3.3 (or later) core-profile context. Throws demlab::Error
// {RENDER CONTEXT} when the platform cannot make one.
std::unique_ptr<GlContext> makeGlContext();

}  // namespace demlab::render
