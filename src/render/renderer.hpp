// Renderer: turns a RenderScene into an Image. The interface knows nothing of GL; the OSMesa
// back end (makeRenderer) draws grains as ray-cast impostors on instanced quads. A renderer owns
// its GL context and buffers and reuses them from frame to frame, so a snapshot module creates
// one renderer and calls render for every frame. Not thread-safe: one thread per renderer.
#pragma once

#include <memory>
#include <string>

#include "render/image.hpp"
#include "render/scene.hpp"

namespace demlab::render {

class Renderer {
 public:
  virtual ~Renderer() = default;

  // Returns the frame of scene as options say. Checks both first (checkScene, checkOptions)
  // and throws demlab::Error on a bad one, drawing nothing. Changes only the renderer's cached
  // GL buffers.
  virtual Image render(const RenderScene& scene, const RenderOptions& options) = 0;

  // Returns the back end's name and its GL renderer string, e.g. "osmesa: llvmpipe (...)".
  virtual std::string name() const = 0;
};

// Returns a new OSMesa renderer, its context current on no thread (each call makes it current
// on its caller, one thread at a time). Throws demlab::Error {RENDER CONTEXT} when no GL 3.3
// core context can be made.
std::unique_ptr<Renderer> makeRenderer();

// Returns nothing; renders scene and writes it to path as PNG (writePng). Changes the file only.
void renderPng(Renderer& renderer, const RenderScene& scene, const RenderOptions& options,
               const std::string& path);

}  // namespace demlab::render
