// The VTK XML writer's encoding, byte by byte: VTK's zlib block header, raw arrays, offsets,
// and the refusal of arrays that do not fit their points. (tests/tcl/dump.test reads whole
// files with VTK's own readers.)
#include <gtest/gtest.h>
#include <zlib.h>

#include <cstring>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "io/vtk_xml.hpp"

namespace demlab::io {
namespace vtk_xml_test {

uint64_t u64(const std::string& b, size_t at) {
  uint64_t v;
  std::memcpy(&v, b.data() + at, 8);
  return v;
}

// Returns the appended block: the bytes after the '_' that starts it.
std::string appended(const std::string& file) {
  const size_t at = file.find("<AppendedData encoding=\"raw\">\n_");
  EXPECT_NE(at, std::string::npos);
  return file.substr(at + std::strlen("<AppendedData encoding=\"raw\">\n_"));
}

VtkImageData grid(size_t n) {
  VtkImageData d;
  d.dims[0] = int64_t(n);
  std::vector<double> v(n);
  for (size_t k = 0; k < n; ++k) v[k] = 0.5 * double(k) + 1e-3 * double(k % 7);
  d.pointData.push_back({"value", 1, v});
  return d;
}

TEST(VtkXml, ZlibBlocksFollowVtkHeaderLayout) {
  const size_t n = 5000;  // 40000 bytes: a whole 32 KiB block and a partial one
  const VtkImageData d = grid(n);
  const std::string file = vtiBytes(d, VtkCompression::Fast);
  EXPECT_NE(file.find("compressor=\"vtkZLibDataCompressor\""), std::string::npos);
  EXPECT_NE(file.find("offset=\"0\""), std::string::npos);
  const std::string a = appended(file);
  ASSERT_EQ(u64(a, 0), 2u);
  EXPECT_EQ(u64(a, 8), 32768u);
  EXPECT_EQ(u64(a, 16), 40000u - 32768u);
  std::string raw;
  size_t at = 40;
  for (int k = 0; k < 2; ++k) {
    const uint64_t packed = u64(a, 24 + 8 * size_t(k));
    std::vector<Bytef> out(32768);
    uLongf got = out.size();
    ASSERT_EQ(uncompress(out.data(), &got, reinterpret_cast<const Bytef*>(a.data() + at), packed),
              Z_OK);
    raw.append(reinterpret_cast<const char*>(out.data()), got);
    at += packed;
  }
  ASSERT_EQ(raw.size(), 40000u);
  EXPECT_EQ(std::memcmp(raw.data(), std::get<std::vector<double>>(d.pointData[0].values).data(),
                        raw.size()),
            0);
}

TEST(VtkXml, WholeLastBlockIsMarkedZero) {
  const std::string a = appended(vtiBytes(grid(4096), VtkCompression::Best));  // exactly 32 KiB
  EXPECT_EQ(u64(a, 0), 1u);
  EXPECT_EQ(u64(a, 16), 0u);
}

TEST(VtkXml, RawArraysCarryTheirByteCountAndNextOffset) {
  VtkPolyData d;
  d.points = {0, 0, 0, 1, 2, 3};
  d.pointData.push_back({"id", 1, std::vector<int32_t>{7, 9}});
  const std::string file = vtpBytes(d, VtkCompression::None);
  EXPECT_EQ(file.find("compressor"), std::string::npos);
  const std::string a = appended(file);
  ASSERT_EQ(u64(a, 0), 8u);  // two Int32
  int32_t ids[2];
  std::memcpy(ids, a.data() + 8, 8);
  EXPECT_EQ(ids[0], 7);
  EXPECT_EQ(ids[1], 9);
  // The points come next, at the offset the XML names.
  EXPECT_NE(file.find("offset=\"16\""), std::string::npos);
  EXPECT_EQ(u64(a, 16), 48u);
}

TEST(VtkXml, AnArrayThatDoesNotFitItsPointsIsRefused) {
  VtkPolyData d;
  d.points = {0, 0, 0, 1, 1, 1};
  d.pointData.push_back({"velocity", 3, std::vector<double>{1, 2, 3}});
  try {
    vtpBytes(d, VtkCompression::Fast);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), (std::vector<std::string>{"DEMLAB", "VALUE", "VTK"}));
    EXPECT_NE(std::string(e.what()).find("\"velocity\""), std::string::npos);
  }
}

TEST(VtkXml, CollectionListsEveryEntryInOrder) {
  const std::string p = pvdBytes({{0.5, "a_000000.vtp", 0}, {1.25, "a&b.vtp", 0}});
  const size_t first = p.find("timestep=\"0.5\""), second = p.find("timestep=\"1.25\"");
  ASSERT_NE(first, std::string::npos);
  ASSERT_NE(second, std::string::npos);
  EXPECT_LT(first, second);
  EXPECT_NE(p.find("file=\"a&amp;b.vtp\""), std::string::npos);
}

TEST(VtkXml, ParallelIndexDeclaresThePiecesArraysAndListsThemInOrder) {
  VtkPolyData layout;
  layout.vertexPerPoint = true;
  layout.pointData.push_back({"id", 1, std::vector<int64_t>{}});
  layout.pointData.push_back({"velocity", 3, std::vector<double>{}});
  layout.cellData.push_back({"a&b", 1, std::vector<int32_t>{}});
  const std::string p = pvtpBytes(layout, {"bed_elements_r0.vtp", "bed_elements_r1.vtp"});
  EXPECT_NE(p.find("type=\"PPolyData\""), std::string::npos);
  EXPECT_NE(p.find("<PDataArray type=\"Int64\" Name=\"id\" NumberOfComponents=\"1\"/>"),
            std::string::npos);
  EXPECT_NE(p.find("<PDataArray type=\"Float64\" Name=\"velocity\" NumberOfComponents=\"3\"/>"),
            std::string::npos);
  EXPECT_NE(p.find("<PCellData>\n<PDataArray type=\"Int32\" Name=\"a&amp;b\""), std::string::npos);
  const size_t first = p.find("<Piece Source=\"bed_elements_r0.vtp\"/>");
  const size_t second = p.find("<Piece Source=\"bed_elements_r1.vtp\"/>");
  ASSERT_NE(first, std::string::npos);
  ASSERT_NE(second, std::string::npos);
  EXPECT_LT(first, second);
  // A part without cell data declares no PCellData.
  layout.cellData.clear();
  EXPECT_EQ(pvtpBytes(layout, {"x.vtp"}).find("PCellData"), std::string::npos);
}

}  // namespace vtk_xml_test
}  // namespace demlab::io
