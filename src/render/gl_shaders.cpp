#include "render/gl_shaders.hpp"

#include <string>

#include "core/error.hpp"

namespace demlab::render {

// Per grain, repeated on its quad's 4 vertices (llvmpipe runs instanced draws one instance at a
// time; one indexed draw of 4n vertices took about a third less time at 1e5 grains): centre
// relative to the view anchor and radius; RGBA (alpha 255: draw the rotation mark); orientation
// angle. The corner comes from gl_VertexID. The quad is placed on the sphere's near side, so every
// depth the fragment shader writes is at or behind the quad's own depth: that is what
// layout(depth_greater) promises, and it lets a driver that honours it (GPU drivers; llvmpipe
// does not, hence occlusion.hpp) reject hidden fragments before shading them.
const char* const kGrainVertexShader = R"(#version 330 core
layout(location = 1) in vec4 sphere;
layout(location = 2) in vec4 colour;
layout(location = 3) in float angle;
uniform mat4 view;
uniform mat4 proj;
uniform int ortho;
uniform int flat2d;
uniform float viewportHeight;
out vec3 vPos;
out vec3 vLocal;
flat out vec3 vCentre;
flat out float vRadius;
flat out vec3 vColour;
flat out float vMark;
flat out float vAngle;
flat out float vPixel;
void main() {
  int k = gl_VertexID & 3;
  vec2 corner = vec2((k & 1) != 0 ? 1.0 : -1.0, (k & 2) != 0 ? 1.0 : -1.0);
  vec3 c = (view * vec4(sphere.xyz, 1.0)).xyz;
  float r = sphere.w;
  vec3 local;
  float scale = proj[1][1] * 0.5 * viewportHeight;
  if (ortho == 1 || flat2d == 1) {
    local = vec3(corner * r, flat2d == 1 ? 0.0 : r);
  } else {
    float d = length(c);
    if (d <= r * 1.0001) {  // eye inside the sphere: nothing sensible to draw
      gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
      return;
    }
    vec3 w = -c / d;
    vec3 t = abs(w.y) < 0.99 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
    vec3 u = normalize(cross(t, w));
    vec3 v = cross(w, u);
    float s = (d - r) * r / sqrt(d * d - r * r);
    local = w * r + (u * corner.x + v * corner.y) * s;
    scale /= max(-c.z, 1e-30);
  }
  vPos = c + local;
  vLocal = local;
  vCentre = c;
  vRadius = r;
  vColour = colour.rgb;
  vMark = colour.a;
  vAngle = angle;
  vPixel = 1.0 / max(r * scale, 1e-6);
  gl_Position = proj * vec4(vPos, 1.0);
}
)";

// Solves the ray-sphere intersection relative to the sphere's centre (vLocal is small), so a
// sphere far from the eye keeps float precision. rim is the ray's distance from the centre over
// the radius: 0 in the middle, 1 on the silhouette, which places the outline.
const char* const kSphereFragmentShader = R"(#version 330 core
#extension GL_ARB_conservative_depth : enable
#ifdef GL_ARB_conservative_depth
layout(depth_greater) out float gl_FragDepth;
#endif
uniform mat4 proj;
uniform int ortho;
uniform vec3 outlineColour;
uniform float outlinePx;
in vec3 vPos;
in vec3 vLocal;
flat in vec3 vCentre;
flat in float vRadius;
flat in vec3 vColour;
flat in float vPixel;
out vec4 fragColour;
void main() {
  vec3 rd = ortho == 1 ? vec3(0.0, 0.0, -1.0) : normalize(vPos);
  float r2 = vRadius * vRadius;
  float b = dot(vLocal, rd);
  vec3 perp = vLocal - b * rd;
  float h = r2 - dot(perp, perp);
  if (h < 0.0) discard;
  vec3 local = vLocal + (-b - sqrt(h)) * rd;
  vec3 n = local / vRadius;
  float z = vCentre.z + local.z;
  float ndc = ortho == 1 ? proj[2][2] * z + proj[3][2] : proj[3][2] / -z - proj[2][2];
  gl_FragDepth = 0.5 * ndc + 0.5;
  const vec3 light = vec3(0.40, 0.55, 0.73);
  float diffuse = max(dot(n, light), 0.0);
  float specular = max(dot(n, normalize(light - rd)), 0.0);
  specular *= specular;
  specular *= specular;
  specular *= specular;
  specular *= specular;
  specular *= specular;  // ^32
  vec3 col = vColour * (0.32 + 0.68 * diffuse) + vec3(0.22 * specular);
  float rim = sqrt(max(1.0 - h / r2, 0.0));
  if (rim > 1.0 - outlinePx * vPixel) col = outlineColour;
  fragColour = vec4(col, 1.0);
}
)";

// 2D discs: flat colour, outline, and a radius from the centre towards the orientation angle,
// which turns with the grain and so shows rolling.
const char* const kDiscFragmentShader = R"(#version 330 core
uniform vec3 outlineColour;
uniform float outlinePx;
in vec3 vLocal;
flat in float vRadius;
flat in vec3 vColour;
flat in float vMark;
flat in float vAngle;
flat in float vPixel;
out vec4 fragColour;
void main() {
  vec2 q = vLocal.xy / vRadius;
  float rho = length(q);
  if (rho > 1.0) discard;
  vec3 col = vColour;
  if (vMark > 0.5) {
    vec2 dir = vec2(cos(vAngle), sin(vAngle));
    float along = dot(q, dir);
    float across = abs(dot(q, vec2(-dir.y, dir.x)));
    if (along > 0.0 && across < max(0.05, 0.75 * vPixel)) col = mix(col, outlineColour, 0.85);
  }
  if (rho > 1.0 - outlinePx * vPixel) col = outlineColour;
  fragColour = vec4(col, 1.0);
}
)";

// A segment a-b as a quad halfWidth pixels either side of its projection, with square caps.
// The segment is first cut at the near plane, so a wall passing behind the eye still draws.
const char* const kLineVertexShader = R"(#version 330 core
layout(location = 0) in vec2 corner;
layout(location = 1) in vec3 a;
layout(location = 2) in vec3 b;
layout(location = 3) in vec4 colour;
layout(location = 4) in float widthScale;
uniform mat4 view;
uniform mat4 proj;
uniform int ortho;
uniform float nearZ;
uniform vec2 viewport;
uniform float halfWidth;
out vec4 vColour;
void main() {
  vec3 ea = (view * vec4(a, 1.0)).xyz;
  vec3 eb = (view * vec4(b, 1.0)).xyz;
  if (ortho == 0) {
    float zn = -nearZ * 1.0001;
    if (ea.z > zn && eb.z > zn) {
      gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
      return;
    }
    if (ea.z > zn) ea = mix(ea, eb, (ea.z - zn) / (ea.z - eb.z));
    if (eb.z > zn) eb = mix(eb, ea, (eb.z - zn) / (eb.z - ea.z));
  }
  vec4 ca = proj * vec4(ea, 1.0);
  vec4 cb = proj * vec4(eb, 1.0);
  vec2 halfVp = 0.5 * viewport;
  vec2 d = (cb.xy / cb.w - ca.xy / ca.w) * halfVp;
  float len = length(d);
  vec2 dir = len > 1e-6 ? d / len : vec2(1.0, 0.0);
  vec2 nrm = vec2(-dir.y, dir.x);
  vec4 p = corner.x < 0.5 ? ca : cb;
  vec2 ext = ((corner.x < 0.5 ? -dir : dir) + nrm * corner.y) * halfWidth * widthScale;
  p.xy += ext / halfVp * p.w;
  gl_Position = p;
  vColour = colour;
}
)";

const char* const kFaceVertexShader = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec4 colour;
uniform mat4 view;
uniform mat4 proj;
out vec4 vColour;
void main() {
  vec3 n = normalize(mat3(view) * normal);
  float shade = 0.55 + 0.45 * abs(dot(n, vec3(0.40, 0.55, 0.73)));
  vColour = vec4(colour.rgb * shade, colour.a);
  gl_Position = proj * view * vec4(position, 1.0);
}
)";

const char* const kColourFragmentShader = R"(#version 330 core
in vec4 vColour;
out vec4 fragColour;
void main() { fragColour = vColour; }
)";

namespace {

GLuint compile(const GlApi& gl, GLenum type, const char* source, const char* what) {
  GLuint s = gl.CreateShader(type);
  gl.ShaderSource(s, 1, &source, nullptr);
  gl.CompileShader(s);
  GLint ok = 0;
  gl.GetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048] = "";
    gl.GetShaderInfoLog(s, sizeof log, nullptr, log);
    gl.DeleteShader(s);
    throw Error(std::string("couldn't compile the ") + what + " shader: " + log,
                {"RENDER", "SHADER"});
  }
  return s;
}

}  // namespace

GLuint buildProgram(const GlApi& gl, const char* vertex, const char* fragment, const char* what) {
  const GLuint vs = compile(gl, GL_VERTEX_SHADER, vertex, what);
  GLuint fs = 0;
  try {
    fs = compile(gl, GL_FRAGMENT_SHADER, fragment, what);
  } catch (...) {
    gl.DeleteShader(vs);
    throw;
  }
  const GLuint p = gl.CreateProgram();
  gl.AttachShader(p, vs);
  gl.AttachShader(p, fs);
  gl.LinkProgram(p);
  gl.DeleteShader(vs);
  gl.DeleteShader(fs);
  GLint ok = 0;
  gl.GetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[2048] = "";
    gl.GetProgramInfoLog(p, sizeof log, nullptr, log);
    gl.DeleteProgram(p);
    throw Error(std::string("couldn't link the ") + what + " program: " + log,
                {"RENDER", "SHADER"});
  }
  return p;
}

}  // namespace demlab::render
