// bench_render: seconds per frame of the OSMesa renderer, as CSV on stdout.
//
// Usage: bench_render [-n N,...] [-size WxH] [-aa A,...] [-dim 2|3] [-frames F] [-png file]
//                     [-cull 0|1] [-strip P,...]
// -strip: the frame's strips of at most P pixels (RenderOptions::stripPixels; default the
// renderer's), each value a row of its own, so one run compares strip sizes side by side.
// Columns: grains, dimension, image size, supersampling factor, strip pixels, wall-clock and CPU
// (all threads)
// seconds per frame, the first frame's seconds, frames averaged, the fraction of grains drawn
// after occlusion culling, seconds to write the PNG.
// The scene is a dense random packing filling a box (3D) or rectangle (2D), seen by the
// automatic camera, coloured by a viridis field, with a time stamp and a legend: what a snapshot
// of a settled bed looks like. The first frame (context warm-up, shader compile) is reported
// apart from the mean over the next F frames.
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "render/occlusion.hpp"
#include "render/png.hpp"
#include "render/renderer.hpp"
#include "render/view.hpp"

using namespace demlab;
using namespace demlab::render;

namespace {

std::vector<long> parseList(const std::string& s) {
  std::vector<long> v;
  std::stringstream in(s);
  std::string item;
  while (std::getline(in, item, ',')) v.push_back(std::stol(item));
  return v;
}

// Returns the CPU seconds (user + system, all threads) the process has used: on a shared
// machine the wall time per frame depends on the neighbours, this does not.
double cpuSeconds() {
  rusage u;
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + u.ru_stime.tv_sec + 1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

double seconds(auto t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<long> ns = {1000, 10000, 100000}, aas = {1, 2}, strips = {RenderOptions{}.stripPixels};
  int width = 1280, height = 720, dim = 3, frames = 5;
  std::string png;
  bool cull = true;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i], v = argv[i + 1];
    if (a == "-n")
      ns = parseList(v);
    else if (a == "-aa")
      aas = parseList(v);
    else if (a == "-size")
      std::sscanf(v.c_str(), "%dx%d", &width, &height);
    else if (a == "-dim")
      dim = std::stoi(v);
    else if (a == "-frames")
      frames = std::stoi(v);
    else if (a == "-cull")
      cull = std::stoi(v) != 0;
    else if (a == "-png")
      png = v;
    else if (a == "-strip")
      strips = parseList(v);
    else {
      std::fprintf(stderr,
                   "bad option \"%s\": must be -n, -size, -aa, -dim, -frames, -png, -cull or -strip\n",
                   a.c_str());
      return 1;
    }
  }
  std::unique_ptr<Renderer> renderer = makeRenderer();
  std::fprintf(stderr, "renderer: %s\n", renderer->name().c_str());
  std::printf(
      "n,dim,width,height,antialias,strip_pixels,seconds_per_frame,cpu_seconds_per_frame,"
      "first_frame_seconds,"
      "frames,drawn_fraction,png_seconds\n");
  for (long n : ns) {
    // Grains of radius r in a box of aspect 2:1(:1) at a volume (area) fraction of about 0.5.
    std::mt19937_64 rng(42);
    const double r = 1, phi = 0.5;
    const double vol = dim == 3 ? n * 4.18879 * r * r * r / phi : n * 3.14159 * r * r / phi;
    const double side = dim == 3 ? std::cbrt(vol / 2) : std::sqrt(vol / 2);
    std::uniform_real_distribution<double> u(0, 1), rad(0.7 * r, 1.3 * r);
    std::vector<double> centres, radii, speed, angles;
    for (long i = 0; i < n; ++i) {
      centres.push_back(2 * side * u(rng));
      centres.push_back(side * u(rng));
      if (dim == 3) centres.push_back(side * u(rng));
      radii.push_back(rad(rng));
      speed.push_back(u(rng));
      angles.push_back(6.28 * u(rng));
    }
    RenderScene scene;
    scene.dim = dim;
    scene.centres = centres;
    scene.radii = radii;
    scene.field = speed;
    scene.fieldName = "speed";
    scene.angles = angles;
    scene.time = 1.25;
    for (long aa : aas) {
      for (long strip : strips) {
        RenderOptions opt;
        opt.stripPixels = strip;
        opt.width = width;
        opt.height = height;
        opt.antialias = int(aa);
        opt.cullHidden = cull;
        auto t0 = std::chrono::steady_clock::now();
        Image img = renderer->render(scene, opt);
        const double first = seconds(t0);
        t0 = std::chrono::steady_clock::now();
        const double c0 = cpuSeconds();
        for (int f = 0; f < frames; ++f) img = renderer->render(scene, opt);
        const double each = seconds(t0) / frames, cpu = (cpuSeconds() - c0) / frames;
        // The fraction of grains left after occlusion culling (1 in 2D, where none is done).
        std::vector<std::uint32_t> keep;
        if (dim == 3 && cull) cullHiddenGrains(scene, makeView(scene, opt), keep);
        const double drawn = dim == 3 && cull ? double(keep.size()) / n : 1.0;
        // Writing the frame (libpng, then rename) to png, or to /tmp when no file was asked for.
        const std::string out = png.empty() ? "/tmp/bench_render_frame.png" : png;
        t0 = std::chrono::steady_clock::now();
        writePng(img, out);
        const double pngSeconds = seconds(t0);
        if (png.empty()) std::remove(out.c_str());
        std::printf("%ld,%d,%d,%d,%ld,%ld,%.4f,%.4f,%.4f,%d,%.3f,%.4f\n", n, dim, width, height, aa,
                    strip, each, cpu, first, frames, drawn, pngSeconds);
        std::fflush(stdout);
      }
    }
  }
  return 0;
}
