// VTK's XML file formats, as ParaView and VTK's readers take them: PolyData (.vtp), ImageData
// (.vti) and the time-series collection (.pvd). Arrays go into one appended binary block, each
// compressed with zlib in VTK's block layout (vtkZLibDataCompressor, UInt64 headers) or stored
// raw; little-endian, as the header says. Only the format lives here: what a scene writes is in
// output/scene_vtk.hpp.
#pragma once

#include <cstdint>
#include <string>
#include <variant>
#include <vector>

namespace demlab::io {

// One named data array: components values per tuple, tuples one after another.
struct VtkArray {
  std::string name;
  int components = 1;
  std::variant<std::vector<double>, std::vector<float>, std::vector<int64_t>,
               std::vector<int32_t>, std::vector<uint8_t>>
      values;
};

// A string array of FieldData (whole-dataset data): names that integer arrays index, such as
// the materials of a "material" array.
struct VtkStrings {
  std::string name;
  std::vector<std::string> values;
};

// Points with vertices (one per point), lines or polygons, and their data. A file holds one
// kind of cell in practice; VTK orders the cell data verts, lines, polys.
struct VtkPolyData {
  std::vector<double> points;           // 3 per point
  bool vertexPerPoint = false;          // a vertex cell for every point (particles)
  std::vector<int64_t> lines;           // point pairs
  std::vector<int64_t> polyConnectivity;
  std::vector<int64_t> polyOffsets;     // the end of each polygon in polyConnectivity
  std::vector<VtkArray> pointData, cellData;
  std::vector<VtkStrings> fieldStrings;
  std::vector<VtkArray> fieldData;      // e.g. TIME (1 tuple)
};

// A regular grid of points: dims[k] points along axis k from origin, spacing apart; point data
// with x varying fastest.
struct VtkImageData {
  double origin[3] = {0, 0, 0};
  double spacing[3] = {1, 1, 1};
  int64_t dims[3] = {1, 1, 1};
  std::vector<VtkArray> pointData;
  std::vector<VtkArray> fieldData;
};

enum class VtkCompression { None, Fast, Best };

// Returns the bytes of a .vtp file holding d. Throws demlab::Error {VALUE VTK} when an array's
// length does not match its points or cells (a writer's bug, caught before any file exists).
std::string vtpBytes(const VtkPolyData& d, VtkCompression c);

// Returns the bytes of a .pvtp file (a parallel PolyData) made of the .vtp files pieces (paths
// relative to it), each holding the arrays of layout under the same names, types and
// components (layout's values are not read): the pieces of a distributed run's ranks.
std::string pvtpBytes(const VtkPolyData& layout, const std::vector<std::string>& pieces);

// Returns the bytes of a .vti file holding d (same errors).
std::string vtiBytes(const VtkImageData& d, VtkCompression c);

// One entry of a .pvd collection: the file (relative to the .pvd) at a time.
struct PvdEntry {
  double time = 0;
  std::string file;
  int part = 0;
};

// Returns the bytes of a .pvd collection listing entries in order.
std::string pvdBytes(const std::vector<PvdEntry>& entries);

}  // namespace demlab::io
