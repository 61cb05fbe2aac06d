// The GLSL 3.30 core programs: grains as ray-cast impostors on instanced quads (spheres) or flat
// discs with a rotation mark (2D), wall lines as screen-space quads of a fixed pixel width, and
// translucent wall faces.
#pragma once

#include "render/gl_api.hpp"

namespace demlab::render {

extern const char* const kGrainVertexShader;
extern const char* const kSphereFragmentShader;
extern const char* const kDiscFragmentShader;
extern const char* const kLineVertexShader;
extern const char* const kFaceVertexShader;
extern const char* const kColourFragmentShader;

// Returns a linked program built from the two sources. Throws demlab::Error {RENDER SHADER} with
// the compiler's log on failure, leaving no GL objects behind.
GLuint buildProgram(const GlApi& gl, const char* vertex, const char* fragment, const char* what);

}  // namespace demlab::render
