// The GL renderer: draws a RenderScene into a framebuffer object at antialias x the image size,
// reads it back, box-filters it down and draws the overlay. GL objects are created once and
// reused; only the instance buffers are refilled per frame.
#include <algorithm>
#include <cstring>
#include <memory>

#include "core/error.hpp"
#include "core/interrupt.hpp"
#include "render/colour_map.hpp"
#include "render/gl_api.hpp"
#include "render/gl_context.hpp"
#include "render/gl_shaders.hpp"
#include "render/layout.hpp"
#include "render/occlusion.hpp"
#include "render/overlay.hpp"
#include "render/png.hpp"
#include "render/renderer.hpp"
#include "render/text.hpp"
#include "render/view.hpp"
#include "render/wall_geometry.hpp"

namespace demlab::render {

void throwMissingGlFunction(const std::string& name) {
  throw Error("couldn't find OpenGL function \"" + name + "\"", {"RENDER", "CONTEXT"});
}

namespace {

struct GrainInstance {
  float centre[3], radius;
  std::uint8_t rgba[4];
  float angle;
};

class GlRenderer : public Renderer {
 public:
  GlRenderer() : context_(makeGlContext()) {
    gl_.load([this](const char* name) { return context_->procAddress(name); });
    const char* version = reinterpret_cast<const char*>(gl_.GetString(GL_RENDERER));
    name_ = context_->name() + ": " + (version ? version : "unknown GL renderer");
    try {
      sphereProgram_ = buildProgram(gl_, kGrainVertexShader, kSphereFragmentShader, "sphere");
      discProgram_ = buildProgram(gl_, kGrainVertexShader, kDiscFragmentShader, "disc");
      lineProgram_ = buildProgram(gl_, kLineVertexShader, kColourFragmentShader, "line");
      faceProgram_ = buildProgram(gl_, kFaceVertexShader, kColourFragmentShader, "face");
    } catch (...) {
      release();
      throw;
    }
    setUpVertexArrays();
    // Each call makes the context current on its caller, so the renderer may be made on one
    // thread and used on another (the snapshot commands make it on a thread of their own).
    context_->releaseCurrent();
  }

  ~GlRenderer() override { release(); }

  std::string name() const override { return name_; }

  Image render(const RenderScene& scene, const RenderOptions& options) override {
    checkScene(scene);
    checkOptions(options);
    const Typeface& face = defaultTypeface();
    const FrameLayout layout = frameLayout(scene, options, face);
    Image image = composeFrame(renderScene(scene, sceneOptions(options, layout)), layout, options);
    drawOverlay(image, scene, options, layout, face);
    return image;
  }

 private:
  // Returns the scene drawn over the whole of an image of options' size, without overlay.
  // The frame (antialias x the size) is drawn in strips of rows, each into a framebuffer of one
  // strip's size: the viewport is the whole frame, shifted down by the strip's first row, so
  // each strip gets exactly the pixels of one whole-frame draw. Strips bound the framebuffer
  // (allocating one of tens of megapixels took 0.3 s in one call) and the clear and each draw
  // call between two polls for Ctrl-C, where a grain filling such a frame took seconds.
  // Throws demlab::Error {INTERRUPTED} between strips and batches of grains.
  Image renderScene(const RenderScene& scene, const RenderOptions& options) {
    context_->makeCurrent();
    const int ss = options.antialias;
    const int w = options.width * ss, h = options.height * ss;
    const int strip =
        int(std::clamp(options.stripPixels / std::max(w, 1), 1L, static_cast<long>(h)));
    ensureFramebuffer(w, strip);
    pollInterrupt("snapshot");

    const View view = makeView(scene, options);
    pollInterrupt("snapshot");
    fillGrains(scene, options, view);
    wallGeometry(scene, sceneBounds(scene), view.anchor, options.wallAlpha, walls_);
    fillChains(scene, view);
    // Not zeroed (every byte is read back into): zeroing a frame of tens of megapixels took
    // a tenth of a second in one call, and the read-back of each strip touches its part.
    const size_t bytes = size_t(4) * w * h;
    if (bytes != pixelBytes_) {
      pixels_.reset();
      pixels_ = std::make_unique_for_overwrite<std::uint8_t[]>(bytes);
      pixelBytes_ = bytes;
    }
    gl_.PixelStorei(GL_PACK_ALIGNMENT, 1);
    try {
      for (int y = 0; y < h; y += strip) {
        drawStrip(scene, options, view, w, h, y);
        pollInterrupt("snapshot");
        gl_.BindFramebuffer(GL_FRAMEBUFFER, fbo_);
        gl_.ReadPixels(0, 0, w, std::min(strip, h - y), GL_RGBA, GL_UNSIGNED_BYTE,
                       &pixels_[size_t(4) * w * y]);
        gl_.BindFramebuffer(GL_FRAMEBUFFER, 0);
      }
    } catch (...) {
      // Interrupted between draw calls: the work queued is finished before the error goes
      // up, so that no GL work is left pending in the context.
      gl_.BindFramebuffer(GL_FRAMEBUFFER, 0);
      gl_.Finish();
      throw;
    }
    if (const GLenum err = gl_.GetError(); err != GL_NO_ERROR)
      throw Error("OpenGL error " + std::to_string(err) + " while rendering", {"RENDER", "GL"});

    Image image = downsample(options.width, options.height, ss);
    if (pixelBytes_ > kKeptPixelBytes) {  // a large frame's read-back is not kept
      pixels_.reset();
      pixelBytes_ = 0;
    }
    return image;
  }

  // Draws the rows from y of the w x h frame into the strip framebuffer (from its row 0).
  // Throws demlab::Error {INTERRUPTED} between batches of grains. Changes the GL state.
  void drawStrip(const RenderScene& scene, const RenderOptions& options, const View& view,
                 int w, int h, int y) {
    const int ss = options.antialias;
    gl_.BindFramebuffer(GL_FRAMEBUFFER, fbo_);
    gl_.Viewport(0, -y, w, h);
    const Rgb& bg = options.background;
    gl_.ClearColor(bg[0], bg[1], bg[2], 1);
    gl_.ClearDepth(1);
    gl_.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    gl_.Enable(GL_DEPTH_TEST);
    gl_.DepthFunc(GL_LESS);
    gl_.DepthMask(GL_TRUE);
    gl_.Disable(GL_BLEND);

    const Eigen::Matrix4f viewM = view.view.cast<float>(), projM = view.proj.cast<float>();
    const int ortho = view.orthographic ? 1 : 0;
    if (!grains_.empty()) {
      const GLuint p = scene.dim == 2 ? discProgram_ : sphereProgram_;
      gl_.UseProgram(p);
      setMatrices(p, viewM, projM);
      gl_.Uniform1i(uniform(p, "ortho"), ortho);
      gl_.Uniform1i(uniform(p, "flat2d"), scene.dim == 2 ? 1 : 0);
      gl_.Uniform1f(uniform(p, "viewportHeight"), float(h));
      const Rgb& oc = options.outlineColour;
      gl_.Uniform3f(uniform(p, "outlineColour"), oc[0], oc[1], oc[2]);
      gl_.Uniform1f(uniform(p, "outlinePx"), float(options.outlineWidth * ss));
      gl_.BindVertexArray(grainVao_);
      const size_t drawn = grains_.size() / 4;
      ensureQuadIndices(drawn);
      gl_.BindBuffer(GL_ARRAY_BUFFER, grainBuffer_);
      gl_.BufferData(GL_ARRAY_BUFFER, grains_.size() * sizeof(GrainInstance), grains_.data(),
                     GL_STREAM_DRAW);
      // In batches, each finished before the next, so Ctrl-C stops a frame of millions of
      // grains within one batch's drawing.
      constexpr size_t kBatch = size_t(1) << 12;
      for (size_t first = 0; first < drawn; first += kBatch) {
        pollInterrupt("snapshot");
        const size_t count = std::min(kBatch, drawn - first);
        gl_.DrawElements(GL_TRIANGLES, GLsizei(6 * count), GL_UNSIGNED_INT,
                         reinterpret_cast<const void*>(6 * first * sizeof(GLuint)));
        if (count < drawn) gl_.Finish();
      }
    }
    if (!meshFaces_.empty()) {
      // Opaque shapes, depth tested and written like the balls.
      gl_.UseProgram(faceProgram_);
      setMatrices(faceProgram_, viewM, projM);
      gl_.BindVertexArray(faceVao_);
      gl_.BindBuffer(GL_ARRAY_BUFFER, faceBuffer_);
      gl_.BufferData(GL_ARRAY_BUFFER, meshFaces_.size() * sizeof(FaceVertex), meshFaces_.data(),
                     GL_STREAM_DRAW);
      gl_.DrawArrays(GL_TRIANGLES, 0, GLsizei(meshFaces_.size()));
    }
    auto drawLines = [&](const std::vector<LineInstance>& lines, double halfWidth) {
      gl_.UseProgram(lineProgram_);
      setMatrices(lineProgram_, viewM, projM);
      gl_.Uniform1i(uniform(lineProgram_, "ortho"), ortho);
      gl_.Uniform1f(uniform(lineProgram_, "nearZ"), float(view.near));
      gl_.Uniform2f(uniform(lineProgram_, "viewport"), float(w), float(h));
      gl_.Uniform1f(uniform(lineProgram_, "halfWidth"), float(halfWidth));
      gl_.BindVertexArray(lineVao_);
      gl_.BindBuffer(GL_ARRAY_BUFFER, lineBuffer_);
      gl_.BufferData(GL_ARRAY_BUFFER, lines.size() * sizeof(LineInstance), lines.data(),
                     GL_STREAM_DRAW);
      gl_.DrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, GLsizei(lines.size()));
    };
    if (!walls_.lines.empty()) drawLines(walls_.lines, options.wallWidth * ss / 2);
    if (!walls_.triangles.empty()) {
      // Translucent faces last, tested against the grains' depth but not writing it, so a
      // grain behind a drum's mantle shows through.
      gl_.Enable(GL_BLEND);
      gl_.BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
      gl_.DepthMask(GL_FALSE);
      gl_.UseProgram(faceProgram_);
      setMatrices(faceProgram_, viewM, projM);
      gl_.BindVertexArray(faceVao_);
      gl_.BindBuffer(GL_ARRAY_BUFFER, faceBuffer_);
      gl_.BufferData(GL_ARRAY_BUFFER, walls_.triangles.size() * sizeof(FaceVertex),
                     walls_.triangles.data(), GL_STREAM_DRAW);
      gl_.DrawArrays(GL_TRIANGLES, 0, GLsizei(walls_.triangles.size()));
      gl_.DepthMask(GL_TRUE);
      gl_.Disable(GL_BLEND);
    }
    if (!chains_.empty()) {
      // Over everything, without depth test: a chain runs through the grains it joins.
      gl_.Disable(GL_DEPTH_TEST);
      drawLines(chains_, ss);
      gl_.Enable(GL_DEPTH_TEST);
    }
    gl_.BindVertexArray(0);
    gl_.Finish();
  }

  // Returns nothing; fills chains_ with scene's force chains as lines between grain centres,
  // each wider (0.75 to 2.5 times the line program's half width) and darker the larger its
  // force is against the largest.
  void fillChains(const RenderScene& scene, const View& view) {
    chains_.clear();
    double fmax = 0;
    for (const ChainLink& l : scene.chains) fmax = std::max(fmax, l.force);
    if (!(fmax > 0)) return;
    for (const ChainLink& l : scene.chains) {
      const double t = l.force / fmax;
      LineInstance li;
      const Vec3 a = grainCentre(scene, l.a) - view.anchor, b = grainCentre(scene, l.b) - view.anchor;
      for (int k = 0; k < 3; ++k) li.a[k] = float(a[k]), li.b[k] = float(b[k]);
      const Rgb c = chainColour(t);
      for (int k = 0; k < 3; ++k) li.rgba[k] = toByte(c[k]);
      li.rgba[3] = 255;
      li.width = float(0.75 + 1.75 * t);
      chains_.push_back(li);
    }
  }

  GLint uniform(GLuint p, const char* name) { return gl_.GetUniformLocation(p, name); }

  void setMatrices(GLuint p, const Eigen::Matrix4f& v, const Eigen::Matrix4f& pr) {
    // Eigen stores column-major, as GL expects with transpose = GL_FALSE.
    gl_.UniformMatrix4fv(uniform(p, "view"), 1, GL_FALSE, v.data());
    gl_.UniformMatrix4fv(uniform(p, "proj"), 1, GL_FALSE, pr.data());
  }

  // Returns nothing; makes the bound grain VAO's index buffer hold at least n quads (two
  // triangles over vertices 4i..4i+3 each).
  void ensureQuadIndices(size_t n) {
    if (n <= quadIndexCount_) return;
    const size_t m = std::max(n, 2 * quadIndexCount_);
    std::vector<GLuint> idx(6 * m);
    for (size_t i = 0; i < m; ++i) {
      const GLuint b = GLuint(4 * i);
      const GLuint q[6] = {b, b + 1, b + 2, b + 2, b + 1, b + 3};
      std::copy(q, q + 6, &idx[6 * i]);
    }
    gl_.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, indexBuffer_);
    gl_.BufferData(GL_ELEMENT_ARRAY_BUFFER, idx.size() * sizeof(GLuint), idx.data(),
                   GL_STATIC_DRAW);
    quadIndexCount_ = m;
  }

  // Returns nothing; fills grains_ with the 4 vertices of each grain that may be visible.
  void fillGrains(const RenderScene& scene, const RenderOptions& options, const View& view) {
    grainColours(scene, options, colours_);
    pollInterrupt("snapshot");
    const size_t n = scene.size();
    // A mesh's bounding sphere is no occluder (the shape leaves gaps in it): no culling then.
    if (scene.dim == 3 && options.cullHidden && scene.meshOf.empty()) {
      cullHiddenGrains(scene, view, keep_);
    } else {
      keep_.clear();
      for (size_t i = 0; i < n; ++i) {
        if (scene.meshOf.empty() || scene.meshOf[i] < 0) keep_.push_back(std::uint32_t(i));
      }
    }
    fillMeshes(scene, view);
    grains_.resize(4 * keep_.size());
    const bool marks = scene.dim == 2 && !scene.angles.empty();
    const Vec3& anchor = view.anchor;
    InterruptPoll poll("snapshot");
    for (size_t m = 0; m < keep_.size(); ++m) {
      poll();
      const size_t i = keep_[m];
      GrainInstance& g = grains_[4 * m];
      const Vec3 c = grainCentre(scene, i) - anchor;
      g.centre[0] = float(c.x());
      g.centre[1] = float(c.y());
      g.centre[2] = float(c.z());
      g.radius = float(scene.radii[i]);
      std::memcpy(g.rgba, &colours_[4 * i], 3);
      g.rgba[3] = marks ? 255 : 0;
      g.angle = marks ? float(scene.angles[i]) : 0.0f;
      grains_[4 * m + 1] = grains_[4 * m + 2] = grains_[4 * m + 3] = g;
    }
  }

  // Returns nothing; fills meshFaces_ with the triangles of the grains drawn as meshes
  // (RenderScene::meshOf), placed and turned, lit by their flat normals, in their colours.
  void fillMeshes(const RenderScene& scene, const View& view) {
    meshFaces_.clear();
    for (size_t i = 0; i < scene.meshOf.size(); ++i) {
      if (scene.meshOf[i] < 0) continue;
      Mat3 r = Mat3::Identity();
      if (scene.dim == 3) {
        const double* q = &scene.orientations[4 * i];
        r = Quat(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix();
      } else if (!scene.angles.empty()) {
        r = AngleAxis(scene.angles[i], Vec3::UnitZ()).toRotationMatrix();
      }
      const Vec3 c = grainCentre(scene, i) - view.anchor;
      const std::vector<Vec3>& mesh = scene.meshes[size_t(scene.meshOf[i])];
      for (size_t t = 0; t + 2 < mesh.size(); t += 3) {
        const Vec3 p[3] = {c + r * mesh[t], c + r * mesh[t + 1], c + r * mesh[t + 2]};
        Vec3 nrm = (p[1] - p[0]).cross(p[2] - p[0]);
        nrm = nrm.squaredNorm() > 0 ? Vec3(nrm.normalized()) : Vec3::UnitZ();
        for (const Vec3& v : p) {
          FaceVertex f;
          for (int k = 0; k < 3; ++k) f.p[k] = float(v[k]), f.n[k] = float(nrm[k]);
          std::memcpy(f.rgba, &colours_[4 * i], 3);
          f.rgba[3] = 255;
          meshFaces_.push_back(f);
        }
      }
    }
  }

  void setUpVertexArrays() {
    const float ends[] = {0, -1, 0, 1, 1, -1, 1, 1};
    gl_.GenBuffers(1, &endBuffer_);
    gl_.BindBuffer(GL_ARRAY_BUFFER, endBuffer_);
    gl_.BufferData(GL_ARRAY_BUFFER, sizeof ends, ends, GL_STATIC_DRAW);
    gl_.GenBuffers(1, &grainBuffer_);
    gl_.GenBuffers(1, &lineBuffer_);
    gl_.GenBuffers(1, &faceBuffer_);
    gl_.GenBuffers(1, &indexBuffer_);

    auto attrib = [&](GLuint loc, GLint size, GLenum type, bool norm, GLsizei stride, size_t off,
                      GLuint divisor) {
      gl_.EnableVertexAttribArray(loc);
      gl_.VertexAttribPointer(loc, size, type, norm ? GL_TRUE : GL_FALSE, stride,
                              reinterpret_cast<const void*>(off));
      gl_.VertexAttribDivisor(loc, divisor);
    };
    gl_.GenVertexArrays(1, &grainVao_);
    gl_.BindVertexArray(grainVao_);
    gl_.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, indexBuffer_);
    gl_.BindBuffer(GL_ARRAY_BUFFER, grainBuffer_);
    constexpr GLsizei gs = sizeof(GrainInstance);
    attrib(1, 4, GL_FLOAT, false, gs, offsetof(GrainInstance, centre), 0);
    attrib(2, 4, GL_UNSIGNED_BYTE, true, gs, offsetof(GrainInstance, rgba), 0);
    attrib(3, 1, GL_FLOAT, false, gs, offsetof(GrainInstance, angle), 0);

    gl_.GenVertexArrays(1, &lineVao_);
    gl_.BindVertexArray(lineVao_);
    gl_.BindBuffer(GL_ARRAY_BUFFER, endBuffer_);
    attrib(0, 2, GL_FLOAT, false, 0, 0, 0);
    gl_.BindBuffer(GL_ARRAY_BUFFER, lineBuffer_);
    constexpr GLsizei ls = sizeof(LineInstance);
    attrib(1, 3, GL_FLOAT, false, ls, offsetof(LineInstance, a), 1);
    attrib(2, 3, GL_FLOAT, false, ls, offsetof(LineInstance, b), 1);
    attrib(3, 4, GL_UNSIGNED_BYTE, true, ls, offsetof(LineInstance, rgba), 1);
    attrib(4, 1, GL_FLOAT, false, ls, offsetof(LineInstance, width), 1);

    gl_.GenVertexArrays(1, &faceVao_);
    gl_.BindVertexArray(faceVao_);
    gl_.BindBuffer(GL_ARRAY_BUFFER, faceBuffer_);
    constexpr GLsizei fs = sizeof(FaceVertex);
    attrib(0, 3, GL_FLOAT, false, fs, offsetof(FaceVertex, p), 0);
    attrib(1, 3, GL_FLOAT, false, fs, offsetof(FaceVertex, n), 0);
    attrib(2, 4, GL_UNSIGNED_BYTE, true, fs, offsetof(FaceVertex, rgba), 0);
    gl_.BindVertexArray(0);
  }

  void ensureFramebuffer(int w, int h) {
    if (fbo_ && fboWidth_ == w && fboHeight_ == h) return;
    releaseFramebuffer();
    gl_.GenRenderbuffers(1, &colourRb_);
    gl_.BindRenderbuffer(GL_RENDERBUFFER, colourRb_);
    gl_.RenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, w, h);
    gl_.GenRenderbuffers(1, &depthRb_);
    gl_.BindRenderbuffer(GL_RENDERBUFFER, depthRb_);
    gl_.RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, w, h);
    gl_.GenFramebuffers(1, &fbo_);
    gl_.BindFramebuffer(GL_FRAMEBUFFER, fbo_);
    gl_.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colourRb_);
    gl_.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depthRb_);
    const GLenum status = gl_.CheckFramebufferStatus(GL_FRAMEBUFFER);
    gl_.BindFramebuffer(GL_FRAMEBUFFER, 0);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
      releaseFramebuffer();
      throw Error("couldn't make a " + std::to_string(w) + "x" + std::to_string(h) +
                      " framebuffer (status " + std::to_string(status) + ")",
                  {"RENDER", "FRAMEBUFFER"});
    }
    fboWidth_ = w;
    fboHeight_ = h;
  }

  // Returns the final image: the mean of each ss x ss block of the read-back pixels, flipped so
  // row 0 is the top (GL's row 0 is the bottom).
  Image downsample(int width, int height, int ss) const {
    Image img = blankImage(width, height);
    const int w = width * ss, h = height * ss;
    const unsigned n = unsigned(ss * ss), round = n / 2;
    for (int y = 0; y < height; ++y) {
      if ((y & 63) == 0) pollInterrupt("snapshot");
      std::uint8_t* out = img.at(0, height - 1 - y);
      for (int x = 0; x < width; ++x) {
        unsigned sum[3] = {0, 0, 0};
        for (int j = 0; j < ss; ++j) {
          const std::uint8_t* row = &pixels_[(size_t(y * ss + j) * w + size_t(x) * ss) * 4];
          for (int i = 0; i < ss; ++i)
            for (int k = 0; k < 3; ++k) sum[k] += row[4 * i + k];
        }
        for (int k = 0; k < 3; ++k) out[4 * x + k] = std::uint8_t((sum[k] + round) / n);
        out[4 * x + 3] = 255;
      }
    }
    (void)h;
    return img;
  }

  void releaseFramebuffer() {
    if (fbo_) gl_.DeleteFramebuffers(1, &fbo_);
    if (colourRb_) gl_.DeleteRenderbuffers(1, &colourRb_);
    if (depthRb_) gl_.DeleteRenderbuffers(1, &depthRb_);
    fbo_ = colourRb_ = depthRb_ = 0;
    fboWidth_ = fboHeight_ = 0;
  }

  void release() {
    if (!gl_.DeleteProgram) return;
    context_->makeCurrent();
    releaseFramebuffer();
    for (GLuint* p : {&sphereProgram_, &discProgram_, &lineProgram_, &faceProgram_})
      if (*p) gl_.DeleteProgram(*p), *p = 0;
    for (GLuint* b : {&indexBuffer_, &endBuffer_, &grainBuffer_, &lineBuffer_, &faceBuffer_})
      if (*b) gl_.DeleteBuffers(1, b), *b = 0;
    for (GLuint* a : {&grainVao_, &lineVao_, &faceVao_})
      if (*a) gl_.DeleteVertexArrays(1, a), *a = 0;
  }

  std::unique_ptr<GlContext> context_;
  GlApi gl_;
  std::string name_;
  GLuint sphereProgram_ = 0, discProgram_ = 0, lineProgram_ = 0, faceProgram_ = 0;
  GLuint indexBuffer_ = 0, endBuffer_ = 0, grainBuffer_ = 0, lineBuffer_ = 0, faceBuffer_ = 0;
  GLuint grainVao_ = 0, lineVao_ = 0, faceVao_ = 0;
  GLuint fbo_ = 0, colourRb_ = 0, depthRb_ = 0;
  int fboWidth_ = 0, fboHeight_ = 0;
  size_t quadIndexCount_ = 0;
  std::vector<GrainInstance> grains_;
  std::vector<std::uint8_t> colours_;
  std::vector<std::uint32_t> keep_;
  static constexpr size_t kKeptPixelBytes = size_t(1) << 26;
  std::unique_ptr<std::uint8_t[]> pixels_;  // the read-back frame, 4 bytes a pixel
  size_t pixelBytes_ = 0;
  WallGeometry walls_;
  std::vector<FaceVertex> meshFaces_;  // the grains drawn as meshes (fillMeshes)
  std::vector<LineInstance> chains_;   // the force chains (fillChains)
};

}  // namespace

std::unique_ptr<Renderer> makeRenderer() {
  return std::make_unique<GlRenderer>();
}

void renderPng(Renderer& renderer, const RenderScene& scene, const RenderOptions& options,
               const std::string& path) {
  writePng(renderer.render(scene, options), path);
}

}  // namespace demlab::render
