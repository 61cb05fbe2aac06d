// Helpers shared by the renderer tests: one renderer per test program (making a GL context
// takes a good fraction of a second) and pixel classification.
#pragma once

#include <dirent.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <vector>

#include <cmath>
#include <memory>
#include <string>

#include "core/error.hpp"
#include "render/renderer.hpp"

namespace demlab::render::test {

// Returns the test program's renderer, made on first use.
inline Renderer& sharedRenderer() {
  static std::unique_ptr<Renderer> r = makeRenderer();
  return *r;
}

// Returns the channel (0 red, 1 green, 2 blue) that dominates pixel (x, y) by at least 80 levels
// over both others, or -1 when none does (background, grey, outline).
inline int dominant(const Image& img, double x, double y) {
  const auto p = img.pixel(int(x), int(y));
  for (int k = 0; k < 3; ++k)
    if (p[k] >= p[(k + 1) % 3] + 80 && p[k] >= p[(k + 2) % 3] + 80) return k;
  return -1;
}

// Returns whether pixel (x, y) is exactly the colour c (within tol levels per channel).
inline bool isColour(const Image& img, double x, double y, const Rgb& c, int tol = 2) {
  const auto p = img.pixel(int(x), int(y));
  for (int k = 0; k < 3; ++k)
    if (std::abs(int(p[k]) - int(std::lround(c[k] * 255))) > tol) return false;
  return true;
}

// A 200x200 frame looking down -z from (0, 0, 10), y up; orthographic: 20 pixels per unit.
inline RenderOptions topView(bool ortho) {
  RenderOptions o;
  o.width = o.height = 200;
  o.camera.automatic = false;
  o.camera.position = Vec3(0, 0, 10);
  o.camera.lookAt = Vec3::Zero();
  o.camera.up = Vec3::UnitY();
  o.camera.orthographic = ortho;
  o.camera.viewHeight = 10;
  o.camera.fov = 60;
  return o;
}

// Returns a frame of two spheres at an odd size (123x77, which catches row-stride mistakes),
// rendered by the shared renderer.
inline Image oddSizedFrame() {
  const std::vector<double> c = {0, 0, 0, 1, 0.5, 0}, r = {0.5, 0.3};
  RenderScene s;
  s.centres = c;
  s.radii = r;
  s.time = 1.5;
  RenderOptions o;
  o.width = 123;
  o.height = 77;
  return sharedRenderer().render(s, o);
}

inline bool isWhite(const Image& img, double x, double y) {
  return isColour(img, x, y, {1, 1, 1}, 0);
}

// Returns the code of the demlab::Error f throws, joined by spaces; "" when f does not throw.
template <class F>
std::string errorCode(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    std::string s;
    for (const auto& w : e.code()) s += (s.empty() ? "" : " ") + w;
    return s;
  }
  return "";
}

// A fresh empty folder under /tmp for one test.
struct TempDir {
  std::string path;
  TempDir() {
    char tmpl[] = "/tmp/demlab_render_test_XXXXXX";
    path = mkdtemp(tmpl);
  }
  ~TempDir() {
    for (const std::string& f : files()) std::remove((path + "/" + f).c_str());
    rmdir(path.c_str());
  }
  std::vector<std::string> files() const {
    std::vector<std::string> out;
    if (DIR* d = opendir(path.c_str())) {
      while (dirent* e = readdir(d))
        if (std::string(e->d_name) != "." && std::string(e->d_name) != "..")
          out.push_back(e->d_name);
      closedir(d);
    }
    return out;
  }
};

}  // namespace demlab::render::test
