// Occlusion culling of 3D grains on the CPU, before anything goes to GL.
//
// llvmpipe runs a fragment shader that writes gl_FragDepth on every covered pixel before the
// depth test, so in a dense 3D packing (depth complexity 10 to 30) nearly all the work is spent
// on grains that end up hidden. This pass removes grains that are certainly hidden, so the image
// is unchanged (a test compares frames with and without it):
//   1. Each grain is an occluder over the cells wholly inside the circle where the plane through
//      its centre, parallel to the image, cuts it. Inside that circle
//      the grain's visible surface is nearer than the centre plane, so every cell keeps the
//      nearest centre-plane distance drawn over it (a conservative depth).
//   2. A grain is hidden when every cell its screen bounding box touches holds an occluder
//      nearer than the grain's nearest point (centre distance minus radius). It is also dropped
//      when its bounding box lies outside the image.
// A grain never occludes itself (its centre plane is behind its nearest point).
#pragma once

#include <cstdint>
#include <vector>

#include "render/scene.hpp"
#include "render/view.hpp"

namespace demlab::render {

// Returns nothing; replaces keep with the indices, increasing, of the grains of a 3D scene that
// may be visible in view. cellSize is the occlusion grid's cell in final-image pixels, made
// larger for a huge frame so that the grid has at most 4 million cells (the test stays
// conservative with any cell size). Throws demlab::Error {INTERRUPTED}: Ctrl-C is polled per
// grain and per 64 grid rows.
void cullHiddenGrains(const RenderScene& scene, const View& view, std::vector<std::uint32_t>& keep,
                      int cellSize = 1);

}  // namespace demlab::render
