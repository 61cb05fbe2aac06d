#include "io/vtk_xml.hpp"

#include <zlib.h>

#include <algorithm>
#include <cstring>
#include <sstream>

#include "core/error.hpp"
#include "core/interrupt.hpp"
#include "core/thread_pool.hpp"

namespace demlab::io {

namespace {

// VTK's own default: blocks of 32 KiB decompress independently, so a reader can stream them.
constexpr size_t kBlockBytes = 32768;

// The header values are little-endian UInt64, like the data (x86-64 and AArch64 are).
void appendU64(std::string& out, uint64_t v) {
  char b[8];
  std::memcpy(b, &v, 8);
  out.append(b, 8);
}

// Returns n bytes at data as one zlib stream. Fast is level 1 with run-length matching only
// (Z_RLE): three to five times quicker than plain level 1 on arrays of doubles, whose bytes
// repeat little beyond the exponents, for files about 5% larger. Throws {IO WRITE}.
std::string deflateBlock(const char* data, size_t n, VtkCompression c) {
  z_stream z{};
  const bool fast = c == VtkCompression::Fast;
  if (deflateInit2(&z, fast ? Z_BEST_SPEED : Z_BEST_COMPRESSION, Z_DEFLATED, 15, 8,
                   fast ? Z_RLE : Z_DEFAULT_STRATEGY) != Z_OK)
    throw Error("zlib could not start compressing a VTK array", {"IO", "WRITE"});
  std::string out(deflateBound(&z, uLong(n)), '\0');
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data));
  z.avail_in = uInt(n);
  z.next_out = reinterpret_cast<Bytef*>(out.data());
  z.avail_out = uInt(out.size());
  const int r = deflate(&z, Z_FINISH);
  out.resize(z.total_out);
  deflateEnd(&z);
  if (r != Z_STREAM_END) throw Error("zlib could not compress a VTK array", {"IO", "WRITE"});
  return out;
}

// Appends the bytes of one array to the appended block in the file's encoding: raw (a UInt64
// byte count, then the bytes) or zlib (VTK's block header, then the compressed blocks).
void appendEncoded(std::string& out, const void* data, size_t bytes, VtkCompression c) {
  pollInterrupt("writing");  // between arrays, on this thread: nothing is written yet
  if (c == VtkCompression::None) {
    appendU64(out, bytes);
    out.append(static_cast<const char*>(data), bytes);
    return;
  }
  const size_t blocks = (bytes + kBlockBytes - 1) / kBlockBytes;
  std::vector<std::string> packed(blocks);
  // The blocks are independent deflate streams: they are compressed on the thread pool, each
  // into its own buffer, and laid out in order (the same bytes for any thread count).
  ThreadPool::global().forEach(blocks, [&](size_t k, unsigned) {
    if (interruptRequested()) return;  // the pool's threads skip; this one throws below
    packed[k] = deflateBlock(static_cast<const char*>(data) + k * kBlockBytes,
                             std::min(kBlockBytes, bytes - k * kBlockBytes), c);
  });
  pollInterrupt("writing");
  appendU64(out, blocks);
  appendU64(out, kBlockBytes);
  appendU64(out, bytes % kBlockBytes);  // 0: the last block is whole
  for (const std::string& p : packed) appendU64(out, p.size());
  for (const std::string& p : packed) out += p;
}

struct TypeInfo {
  const char* name;
  const void* data;
  size_t count;
  size_t size;
};

TypeInfo typeOf(const VtkArray& a) {
  return std::visit(
      [](const auto& v) -> TypeInfo {
        using T = typename std::decay_t<decltype(v)>::value_type;
        const char* n = std::is_same_v<T, double>    ? "Float64"
                        : std::is_same_v<T, float>   ? "Float32"
                        : std::is_same_v<T, int64_t> ? "Int64"
                        : std::is_same_v<T, int32_t> ? "Int32"
                                                     : "UInt8";
        return {n, v.data(), v.size(), sizeof(T)};
      },
      a.values);
}

// Returns s with XML's special characters escaped, for attribute values.
std::string xmlEscape(const std::string& s) {
  std::string out;
  for (char ch : s) {
    switch (ch) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += ch;
    }
  }
  return out;
}

// Builds one file: the XML header written as arrays are declared, their bytes gathered into
// the appended block with the offsets the declarations name.
class Writer {
 public:
  Writer(const char* type, VtkCompression c) : type_(type), c_(c) {
    xml_ << "<?xml version=\"1.0\"?>\n<VTKFile type=\"" << type
         << "\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\"";
    if (c != VtkCompression::None) xml_ << " compressor=\"vtkZLibDataCompressor\"";
    xml_ << ">\n";
  }
  std::ostringstream& xml() { return xml_; }

  // Declares array a of tuples tuples (checked against its length) in the XML and appends
  // its bytes. Returns nothing; changes the file being built.
  void array(const VtkArray& a, size_t tuples, const char* where, const char* tag = "DataArray") {
    const TypeInfo t = typeOf(a);
    if (a.components < 1 || t.count != tuples * size_t(a.components)) {
      throw Error("VTK array \"" + a.name + "\" in " + where + " holds " + std::to_string(t.count) +
                      " values for " + std::to_string(tuples) + " tuples of " +
                      std::to_string(a.components),
                  {"VALUE", "VTK"});
    }
    xml_ << "<" << tag << " type=\"" << t.name << "\"";
    if (!a.name.empty()) xml_ << " Name=\"" << xmlEscape(a.name) << "\"";
    xml_ << " NumberOfComponents=\"" << a.components << "\"";
    if (std::strcmp(tag, "DataArray") != 0 || std::strcmp(where, "FieldData") == 0)
      xml_ << " NumberOfTuples=\"" << tuples << "\"";
    xml_ << " format=\"appended\" offset=\"" << data_.size() << "\"/>\n";
    appendEncoded(data_, t.data, t.count * t.size, c_);
  }

  // Declares the field data: numeric arrays of any length and string arrays, the latter in
  // VTK's ASCII form (each string's character codes, then 0).
  void fieldData(const std::vector<VtkArray>& numbers, const std::vector<VtkStrings>& strings) {
    if (numbers.empty() && strings.empty()) return;
    xml_ << "<FieldData>\n";
    for (const VtkArray& a : numbers) array(a, typeOf(a).count / size_t(a.components), "FieldData");
    for (const VtkStrings& s : strings) {
      xml_ << "<Array type=\"String\" Name=\"" << xmlEscape(s.name) << "\" NumberOfTuples=\""
           << s.values.size() << "\" format=\"ascii\">\n";
      for (const std::string& v : s.values) {
        for (unsigned char ch : v) xml_ << int(ch) << ' ';
        xml_ << "0\n";
      }
      xml_ << "</Array>\n";
    }
    xml_ << "</FieldData>\n";
  }

  // Reserves room for the appended block: grown by doubling, hundreds of megabytes were
  // copied (and their pages faulted in) in calls that Ctrl-C cannot stop.
  void reserve(size_t bytes) { data_.reserve(bytes); }

  // Returns the whole file. Call once, after everything is declared. The appended block is
  // copied in slices with a poll between them.
  std::string finish() {
    xml_ << "<AppendedData encoding=\"raw\">\n_";
    std::string out = xml_.str();
    constexpr char kTail[] = "\n</AppendedData>\n</VTKFile>\n";
    out.reserve(out.size() + data_.size() + sizeof kTail);
    for (size_t at = 0; at < data_.size(); at += kPollSliceBytes) {
      pollInterrupt("writing");
      out.append(data_, at, std::min(kPollSliceBytes, data_.size() - at));
    }
    out += kTail;
    return out;
  }

 private:
  const char* type_;
  VtkCompression c_;
  std::ostringstream xml_;
  std::string data_;
};

VtkArray int64Array(const char* name, const std::vector<int64_t>& v) {
  return {name, 1, v};
}

// Declares a cell block (Verts, Lines or Polys) from its connectivity and end offsets.
void cells(Writer& w, const char* tag, const std::vector<int64_t>& conn,
           const std::vector<int64_t>& ends) {
  w.xml() << "<" << tag << ">\n";
  w.array(int64Array("connectivity", conn), conn.size(), tag);
  w.array(int64Array("offsets", ends), ends.size(), tag);
  w.xml() << "</" << tag << ">\n";
}

}  // namespace

std::string vtpBytes(const VtkPolyData& d, VtkCompression c) {
  if (d.points.size() % 3 != 0) throw Error("VTK points must come in threes", {"VALUE", "VTK"});
  const size_t points = d.points.size() / 3;
  const size_t verts = d.vertexPerPoint ? points : 0, lines = d.lines.size() / 2,
               polys = d.polyOffsets.size();
  Writer w("PolyData", c);
  // The raw bytes of every array (compressed ones take less), and a header each.
  size_t raw = 64 * (8 + d.pointData.size() + d.cellData.size()) + d.points.size() * 8 +
               verts * 16 + d.lines.size() * 8 + lines * 8 +
               (d.polyConnectivity.size() + d.polyOffsets.size()) * 8;
  for (const auto* list : {&d.pointData, &d.cellData}) {
    for (const VtkArray& a : *list) {
      const TypeInfo t = typeOf(a);
      raw += t.count * t.size;
    }
  }
  w.reserve(raw);
  w.xml() << "<PolyData>\n";
  w.fieldData(d.fieldData, d.fieldStrings);
  w.xml() << "<Piece NumberOfPoints=\"" << points << "\" NumberOfVerts=\"" << verts
          << "\" NumberOfLines=\"" << lines << "\" NumberOfStrips=\"0\" NumberOfPolys=\"" << polys
          << "\">\n<PointData>\n";
  for (const VtkArray& a : d.pointData) w.array(a, points, "PointData");
  w.xml() << "</PointData>\n<CellData>\n";
  for (const VtkArray& a : d.cellData) w.array(a, verts + lines + polys, "CellData");
  w.xml() << "</CellData>\n<Points>\n";
  w.array({"Points", 3, d.points}, points, "Points");
  w.xml() << "</Points>\n";
  if (verts) {
    std::vector<int64_t> conn(points), ends(points);
    for (size_t k = 0; k < points; ++k) conn[k] = int64_t(k), ends[k] = int64_t(k + 1);
    cells(w, "Verts", conn, ends);
  }
  if (lines) {
    std::vector<int64_t> ends(lines);
    for (size_t k = 0; k < lines; ++k) ends[k] = int64_t(2 * k + 2);
    cells(w, "Lines", d.lines, ends);
  }
  if (polys) cells(w, "Polys", d.polyConnectivity, d.polyOffsets);
  w.xml() << "</Piece>\n</PolyData>\n";
  return w.finish();
}

std::string vtiBytes(const VtkImageData& d, VtkCompression c) {
  Writer w("ImageData", c);
  const int64_t* n = d.dims;
  w.xml().precision(17);
  w.xml() << "<ImageData WholeExtent=\"0 " << n[0] - 1 << " 0 " << n[1] - 1 << " 0 " << n[2] - 1
          << "\" Origin=\"" << d.origin[0] << ' ' << d.origin[1] << ' ' << d.origin[2]
          << "\" Spacing=\"" << d.spacing[0] << ' ' << d.spacing[1] << ' ' << d.spacing[2]
          << "\">\n";
  w.fieldData(d.fieldData, {});
  w.xml() << "<Piece Extent=\"0 " << n[0] - 1 << " 0 " << n[1] - 1 << " 0 " << n[2] - 1
          << "\">\n<PointData>\n";
  const size_t points = size_t(n[0] * n[1] * n[2]);
  for (const VtkArray& a : d.pointData) w.array(a, points, "PointData");
  w.xml() << "</PointData>\n</Piece>\n</ImageData>\n";
  return w.finish();
}

std::string pvdBytes(const std::vector<PvdEntry>& entries) {
  std::ostringstream x;
  x.precision(17);
  x << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" "
       "byte_order=\"LittleEndian\">\n<Collection>\n";
  for (const PvdEntry& e : entries) {
    x << "<DataSet timestep=\"" << e.time << "\" group=\"\" part=\"" << e.part << "\" file=\""
      << xmlEscape(e.file) << "\"/>\n";
  }
  x << "</Collection>\n</VTKFile>\n";
  return x.str();
}

std::string pvtpBytes(const VtkPolyData& layout, const std::vector<std::string>& pieces) {
  std::ostringstream x;
  x << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PPolyData\" version=\"1.0\" "
       "byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<PPolyData GhostLevel=\"0\">\n";
  const auto declare = [&](const std::vector<VtkArray>& arrays, const char* tag) {
    if (arrays.empty()) return;
    x << "<" << tag << ">\n";
    for (const VtkArray& a : arrays) {
      x << "<PDataArray type=\"" << typeOf(a).name << "\" Name=\"" << xmlEscape(a.name)
        << "\" NumberOfComponents=\"" << a.components << "\"/>\n";
    }
    x << "</" << tag << ">\n";
  };
  declare(layout.pointData, "PPointData");
  declare(layout.cellData, "PCellData");
  x << "<PPoints>\n<PDataArray type=\"Float64\" NumberOfComponents=\"3\"/>\n</PPoints>\n";
  for (const std::string& p : pieces) x << "<Piece Source=\"" << xmlEscape(p) << "\"/>\n";
  x << "</PPolyData>\n</VTKFile>\n";
  return x.str();
}

}  // namespace demlab::io
