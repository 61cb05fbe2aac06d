// Reading STL triangle meshes, ASCII and binary, as CAD programs write them.
//
// Binary: an 80-byte header, a little-endian uint32 triangle count, then 50 bytes a triangle
// (a normal, three corners as float32, a 2-byte attribute). A file is read as binary when its
// size is exactly 84 + 50 n for the count n it states (an ASCII file whose first 84 bytes happen
// to say so is vanishingly unlikely), and as ASCII otherwise: `solid name`, then `facet normal
// nx ny nz` / `outer loop` / three `vertex x y z` / `endloop` / `endfacet` per triangle, and
// `endsolid`; several solids in one file are read one after the other. The stored normals are
// ignored (CAD programs disagree about them); each triangle's is taken from its corners.
//
// Failures throw demlab::Error naming the file (and the line, for ASCII):
//   IO OPEN, IO READ     the file cannot be opened or read
//   IO FORMAT            a line or a size that the format does not allow there
//   IO TRUNCATED         a file that ends inside a facet
//   VALUE NUMBER         a coordinate that is not a finite number
//   LIMIT TRIANGLES      more than kMaxStlTriangles triangles (checked before anything is
//                        allocated for them)
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace demlab::io {

// The most triangles a mesh file may hold.
inline constexpr std::size_t kMaxStlTriangles = 20'000'000;

struct StlMesh {
  std::vector<std::array<double, 9>> triangles;  // three corners (x y z each) per triangle
  bool binary = false;
};

// Returns the triangles of the STL file at path. Throws as the header says; polls for Ctrl-C.
StlMesh readStl(const std::string& path);

// Writes triangles to path as an ASCII STL (solid name). Throws Error {IO WRITE}.
void writeStlAscii(const std::string& path, const std::vector<std::array<double, 9>>& triangles,
                   const std::string& name = "demlab");

}  // namespace demlab::io
