// readStl and writeStlAscii (io/stl.hpp).
#include "io/stl.hpp"

#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "core/error.hpp"
#include "core/interrupt.hpp"
#include "io/line_reader.hpp"

namespace demlab::io {

namespace {

[[noreturn]] void failFile(const std::string& path, const std::string& message,
                           std::vector<std::string> code) {
  throw Error(message, std::move(code)).within("file \"" + path + "\"");
}

// Returns the words of line, split at blanks.
std::vector<std::string_view> words(std::string_view line) {
  std::vector<std::string_view> out;
  size_t k = 0;
  while (k < line.size()) {
    while (k < line.size() && (line[k] == ' ' || line[k] == '\t' || line[k] == '\r')) ++k;
    const size_t start = k;
    while (k < line.size() && line[k] != ' ' && line[k] != '\t' && line[k] != '\r') ++k;
    if (k > start) out.push_back(line.substr(start, k - start));
  }
  return out;
}

StlMesh readBinary(const std::string& path, std::uint32_t count) {
  std::ifstream in(path, std::ios::binary);
  if (!in) failFile(path, "couldn't read the mesh", {"IO", "READ"});
  in.seekg(84);
  StlMesh m;
  m.binary = true;
  m.triangles.resize(count);
  InterruptPoll poll("reading the mesh");
  char rec[50];
  for (std::uint32_t t = 0; t < count; ++t) {
    poll();
    if (!in.read(rec, 50)) failFile(path, "couldn't read triangle " + std::to_string(t + 1), {"IO", "READ"});
    for (int k = 0; k < 9; ++k) {
      std::uint32_t bits;
      std::memcpy(&bits, rec + 12 + 4 * k, 4);
      if constexpr (std::endian::native == std::endian::big) bits = __builtin_bswap32(bits);
      const float x = std::bit_cast<float>(bits);
      if (!std::isfinite(x)) {
        failFile(path, "bad coordinate in triangle " + std::to_string(t + 1) + ": must be a finite number",
                 {"VALUE", "NUMBER"});
      }
      m.triangles[t][k] = x;
    }
  }
  return m;
}

StlMesh readAscii(const std::string& path) {
  LineReader in(path);
  const auto fail = [&](const std::string& message, std::vector<std::string> code) {
    throw Error(message, std::move(code)).within(in.where());
  };
  StlMesh m;
  std::string_view line;
  // The states: outside a solid, in a solid between facets, and in a facet's loop with the
  // corners read so far.
  enum { Outside, InSolid, InFacet, InLoop, LoopDone } state = Outside;
  std::array<double, 9> tri{};
  int corners = 0;
  bool any = false;
  while (in.next(line)) {
    const std::vector<std::string_view> w = words(line);
    if (w.empty()) continue;
    const std::string_view key = w[0];
    if (key == "solid" && state == Outside) {
      state = InSolid;
      any = true;
    } else if (key == "endsolid" && state == InSolid) {
      state = Outside;
    } else if (key == "facet" && state == InSolid) {
      if (w.size() != 5 || w[1] != "normal") fail("bad facet line: expected \"facet normal nx ny nz\"", {"IO", "FORMAT"});
      state = InFacet;
    } else if (key == "outer" && state == InFacet) {
      if (w.size() != 2 || w[1] != "loop") fail("bad line: expected \"outer loop\"", {"IO", "FORMAT"});
      state = InLoop;
      corners = 0;
    } else if (key == "vertex" && state == InLoop) {
      if (w.size() != 4) fail("bad vertex line: expected \"vertex x y z\"", {"IO", "FORMAT"});
      if (corners == 3) fail("bad facet: more than three vertices", {"IO", "FORMAT"});
      for (int k = 0; k < 3; ++k) {
        double x = 0;
        const auto [p, ec] = std::from_chars(w[k + 1].data(), w[k + 1].data() + w[k + 1].size(), x);
        if (ec != std::errc() || p != w[k + 1].data() + w[k + 1].size() || !std::isfinite(x)) {
          fail("bad coordinate \"" + std::string(w[k + 1]) + "\": must be a finite number", {"VALUE", "NUMBER"});
        }
        tri[3 * corners + k] = x;
      }
      corners += 1;
    } else if (key == "endloop" && state == InLoop) {
      if (corners != 3) fail("bad facet: " + std::to_string(corners) + " vertices, a triangle has three", {"IO", "FORMAT"});
      state = LoopDone;
    } else if (key == "endfacet" && state == LoopDone) {
      if (m.triangles.size() == kMaxStlTriangles) {
        fail("too many triangles: at most " + std::to_string(kMaxStlTriangles), {"LIMIT", "TRIANGLES"});
      }
      m.triangles.push_back(tri);
      state = InSolid;
    } else {
      fail("bad line \"" + std::string(line.substr(0, 40)) + "\": not what an STL file has here", {"IO", "FORMAT"});
    }
  }
  if (!any) failFile(path, "bad mesh: neither a binary STL nor an ASCII one (\"solid ...\")", {"IO", "FORMAT"});
  if (state != Outside) fail("the file ends inside a solid", {"IO", "TRUNCATED"});
  return m;
}

}  // namespace

StlMesh readStl(const std::string& path) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) {
    throw Error("couldn't open \"" + path + "\": " + ec.message(), {"IO", "OPEN"});
  }
  if (size >= 84) {
    std::ifstream in(path, std::ios::binary);
    char head[84];
    if (!in.read(head, 84)) failFile(path, "couldn't read the mesh", {"IO", "READ"});
    std::uint32_t count;
    std::memcpy(&count, head + 80, 4);
    if constexpr (std::endian::native == std::endian::big) count = __builtin_bswap32(count);
    if (size == 84 + 50 * std::uintmax_t{count}) {
      if (count > kMaxStlTriangles) {
        failFile(path, "too many triangles: at most " + std::to_string(kMaxStlTriangles), {"LIMIT", "TRIANGLES"});
      }
      return readBinary(path, count);
    }
  }
  return readAscii(path);
}

void writeStlAscii(const std::string& path, const std::vector<std::array<double, 9>>& triangles,
                   const std::string& name) {
  std::ofstream out(path);
  if (!out) throw Error("couldn't open \"" + path + "\" for writing", {"IO", "WRITE"});
  out.precision(17);
  out << "solid " << name << "\n";
  for (const auto& t : triangles) {
    out << "  facet normal 0 0 0\n    outer loop\n";
    for (int c = 0; c < 3; ++c) out << "      vertex " << t[3 * c] << " " << t[3 * c + 1] << " " << t[3 * c + 2] << "\n";
    out << "    endloop\n  endfacet\n";
  }
  out << "endsolid " << name << "\n";
  if (!out.flush()) throw Error("couldn't write \"" + path + "\"", {"IO", "WRITE"});
}

}  // namespace demlab::io
