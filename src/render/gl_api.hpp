// The GL functions the renderer uses, as a table of pointers filled through the context's
// getProcAddress: the library links OSMesa alone (no libGL), and an EGL back end would fill the
// same table through eglGetProcAddress.
#pragma once

#include <GL/glcorearb.h>

#include <string>

namespace demlab::render {

#define DEMLAB_GL_FUNCTIONS(X)                                 \
  X(PFNGLGETSTRINGPROC, GetString)                             \
  X(PFNGLGETERRORPROC, GetError)                               \
  X(PFNGLGETINTEGERVPROC, GetIntegerv)                         \
  X(PFNGLVIEWPORTPROC, Viewport)                               \
  X(PFNGLCLEARCOLORPROC, ClearColor)                           \
  X(PFNGLCLEARDEPTHPROC, ClearDepth)                           \
  X(PFNGLCLEARPROC, Clear)                                     \
  X(PFNGLSCISSORPROC, Scissor)                                 \
  X(PFNGLENABLEPROC, Enable)                                   \
  X(PFNGLDISABLEPROC, Disable)                                 \
  X(PFNGLDEPTHFUNCPROC, DepthFunc)                             \
  X(PFNGLDEPTHMASKPROC, DepthMask)                             \
  X(PFNGLBLENDFUNCPROC, BlendFunc)                             \
  X(PFNGLPIXELSTOREIPROC, PixelStorei)                         \
  X(PFNGLREADPIXELSPROC, ReadPixels)                           \
  X(PFNGLFINISHPROC, Finish)                                   \
  X(PFNGLDRAWARRAYSPROC, DrawArrays)                           \
  X(PFNGLDRAWARRAYSINSTANCEDPROC, DrawArraysInstanced)         \
  X(PFNGLDRAWELEMENTSPROC, DrawElements)                       \
  X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays)                 \
  X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays)           \
  X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)                 \
  X(PFNGLGENBUFFERSPROC, GenBuffers)                           \
  X(PFNGLDELETEBUFFERSPROC, DeleteBuffers)                     \
  X(PFNGLBINDBUFFERPROC, BindBuffer)                           \
  X(PFNGLBUFFERDATAPROC, BufferData)                           \
  X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer)         \
  X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray) \
  X(PFNGLVERTEXATTRIBDIVISORPROC, VertexAttribDivisor)         \
  X(PFNGLCREATESHADERPROC, CreateShader)                       \
  X(PFNGLDELETESHADERPROC, DeleteShader)                       \
  X(PFNGLSHADERSOURCEPROC, ShaderSource)                       \
  X(PFNGLCOMPILESHADERPROC, CompileShader)                     \
  X(PFNGLGETSHADERIVPROC, GetShaderiv)                         \
  X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog)               \
  X(PFNGLCREATEPROGRAMPROC, CreateProgram)                     \
  X(PFNGLDELETEPROGRAMPROC, DeleteProgram)                     \
  X(PFNGLATTACHSHADERPROC, AttachShader)                       \
  X(PFNGLLINKPROGRAMPROC, LinkProgram)                         \
  X(PFNGLGETPROGRAMIVPROC, GetProgramiv)                       \
  X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog)             \
  X(PFNGLUSEPROGRAMPROC, UseProgram)                           \
  X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)           \
  X(PFNGLUNIFORM1IPROC, Uniform1i)                             \
  X(PFNGLUNIFORM1FPROC, Uniform1f)                             \
  X(PFNGLUNIFORM2FPROC, Uniform2f)                             \
  X(PFNGLUNIFORM3FPROC, Uniform3f)                             \
  X(PFNGLUNIFORMMATRIX4FVPROC, UniformMatrix4fv)               \
  X(PFNGLGENFRAMEBUFFERSPROC, GenFramebuffers)                 \
  X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers)           \
  X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)                 \
  X(PFNGLFRAMEBUFFERRENDERBUFFERPROC, FramebufferRenderbuffer) \
  X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, CheckFramebufferStatus)   \
  X(PFNGLGENRENDERBUFFERSPROC, GenRenderbuffers)               \
  X(PFNGLDELETERENDERBUFFERSPROC, DeleteRenderbuffers)         \
  X(PFNGLBINDRENDERBUFFERPROC, BindRenderbuffer)               \
  X(PFNGLRENDERBUFFERSTORAGEPROC, RenderbufferStorage)

struct GlApi {
#define DEMLAB_GL_MEMBER(type, name) type name = nullptr;
  DEMLAB_GL_FUNCTIONS(DEMLAB_GL_MEMBER)
#undef DEMLAB_GL_MEMBER

  // Returns nothing; fills every pointer through getProc. Throws demlab::Error {RENDER CONTEXT}
  // naming the first function the context lacks.
  template <class GetProc>
  void load(GetProc getProc);
};

// Throws the error GlApi::load reports for a missing function.
[[noreturn]] void throwMissingGlFunction(const std::string& name);

template <class GetProc>
void GlApi::load(GetProc getProc) {
#define DEMLAB_GL_LOAD(type, name)                    \
  name = reinterpret_cast<type>(getProc("gl" #name)); \
  if (!name) throwMissingGlFunction("gl" #name);
  DEMLAB_GL_FUNCTIONS(DEMLAB_GL_LOAD)
#undef DEMLAB_GL_LOAD
}

}  // namespace demlab::render
