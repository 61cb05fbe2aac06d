#include "io/lammps_data.hpp"

#include <sys/stat.h>

#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string_view>

#include "core/error.hpp"
#include "io/line_reader.hpp"

namespace demlab::io {
namespace {

constexpr std::size_t kMaxTokens = 12;

// A line split at blanks, at most kMaxTokens fields; count says how many there were in all.
struct Tokens {
  std::array<std::string_view, kMaxTokens> field;
  std::size_t count = 0;
  std::string_view operator[](std::size_t i) const { return field[i]; }
};

bool isBlank(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
}
bool isAlpha(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z');
}

// Returns s without leading and trailing blanks.
std::string_view trim(std::string_view s) {
  while (!s.empty() && isBlank(s.front())) s.remove_prefix(1);
  while (!s.empty() && isBlank(s.back())) s.remove_suffix(1);
  return s;
}

// Returns the fields of s (blank-separated).
Tokens split(std::string_view s) {
  Tokens t;
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && isBlank(s[i])) ++i;
    if (i == s.size()) break;
    std::size_t j = i;
    while (j < s.size() && !isBlank(s[j])) ++j;
    if (t.count < kMaxTokens) t.field[t.count] = s.substr(i, j - i);
    ++t.count;
    i = j;
  }
  return t;
}

// Returns whether line is a LAMMPS data-file section keyword.
bool isSectionKeyword(std::string_view line) {
  static constexpr std::array<std::string_view, 11> kPlain{
      "Atoms",  "Velocities", "Masses", "Ellipsoids", "Lines",    "Triangles",
      "Bodies", "Bonds",      "Angles", "Dihedrals",  "Impropers"};
  for (auto k : kPlain) {
    if (line == k) return true;
  }
  return line.size() > 7 && line.substr(line.size() - 7) == " Coeffs";
}

bool allWords(const Tokens& t, std::size_t from) {
  if (t.count > kMaxTokens) return false;
  for (std::size_t i = from; i < t.count; ++i) {
    for (char c : t[i]) {
      if (!isAlpha(c)) return false;
    }
  }
  return true;
}

// The dense index of every atom id read so far: an open-addressing table of (index + 1) over
// the ids array, sized once for the header's count. One block of 8 to 16 bytes per atom, where
// a node-based hash map took a small block per atom (40-odd bytes each, freed into holes of
// the heap that stay resident through the run that follows).
// Returns the most atom lines a file of path's size can hold: an atom line has at least 14
// characters ("1 1 1 1 0 0 0" and its newline); a gzip'd file inflates at most 1032-fold.
std::int64_t atomsTheFileCanHold(const std::string& path) {
  struct stat st;
  if (stat(path.c_str(), &st) != 0) return 0;  // the reader's open reports the error
  unsigned char magic[2] = {0, 0};
  if (std::FILE* f = std::fopen(path.c_str(), "rb")) {
    if (std::fread(magic, 1, 2, f) != 2) magic[0] = 0;
    std::fclose(f);
  }
  const bool gz = magic[0] == 0x1f && magic[1] == 0x8b;
  return std::int64_t(st.st_size) * (gz ? 1032 : 1) / 14;
}

class IdIndex {
 public:
  static constexpr std::size_t kNone = static_cast<std::size_t>(-1);

  // Makes room for n ids; forgets any recorded.
  void reset(std::size_t n) {
    std::size_t size = 16;
    while (size < 2 * n) size *= 2;
    table_.assign(size, 0);
    mask_ = size - 1;
  }

  // Records that ids[index] is at index, unless that id is recorded already; returns whether it
  // was new. ids[index] must be set; at most the reset() count may be recorded.
  bool insert(const std::vector<std::int64_t>& ids, std::size_t index) {
    for (std::size_t b = bucket(ids[index]);; b = (b + 1) & mask_) {
      if (table_[b] == 0) {
        table_[b] = static_cast<uint32_t>(index + 1);
        return true;
      }
      if (ids[table_[b] - 1] == ids[index]) return false;
    }
  }

  // Returns the index of id, or kNone.
  std::size_t find(const std::vector<std::int64_t>& ids, std::int64_t id) const {
    for (std::size_t b = bucket(id);; b = (b + 1) & mask_) {
      if (table_[b] == 0) return kNone;
      if (ids[table_[b] - 1] == id) return table_[b] - 1;
    }
  }

 private:
  // Returns the first bucket of id (a multiplicative hash: ids are often consecutive).
  std::size_t bucket(std::int64_t id) const {
    return static_cast<std::size_t>((static_cast<uint64_t>(id) * 0x9E3779B97F4A7C15ull) >> 20) &
           mask_;
  }

  std::vector<uint32_t> table_;
  std::size_t mask_ = 0;
};

// Parses the file line by line; one instance per readLammpsData call.
class Parser {
 public:
  explicit Parser(const std::string& path) : in_(path), maxAtoms_(atomsTheFileCanHold(path)) {}

  SphereData run();

 private:
  // Throws Error(message + where, code): every error names the file and the current line.
  [[noreturn]] void fail(const std::string& message, std::vector<std::string> code) const {
    throw Error(message, std::move(code)).within(in_.where());
  }

  // Reads the next line that is not blank once comments are cut, into `line` (trimmed) and
  // `comment` (the text after "#", trimmed); returns false at the end of the file.
  bool nextContent(std::string_view& line, std::string_view& comment);

  Real real(std::string_view s, const char* what) const;
  std::int64_t integer(std::string_view s) const;

  void header(const Tokens& t);
  void atoms(std::string_view comment);
  void velocities();
  // Skips the lines of an unknown section; returns true with `line` holding the next section
  // keyword, or false at the end of the file.
  bool skipSection(std::string_view& line, std::string_view& comment);

  LineReader in_;
  SphereData d_;
  std::int64_t atomCount_ = -1;
  std::int64_t maxAtoms_;
  std::array<bool, 3> haveBox_{false, false, false};
  bool haveTypes_ = false;
  bool haveAtoms_ = false;
  bool haveVelocities_ = false;
  IdIndex index_;
};

bool Parser::nextContent(std::string_view& line, std::string_view& comment) {
  std::string_view raw;
  while (in_.next(raw)) {
    comment = {};
    const std::size_t hash = raw.find('#');
    if (hash != std::string_view::npos) {
      comment = trim(raw.substr(hash + 1));
      raw = raw.substr(0, hash);
    }
    line = trim(raw);
    if (!line.empty()) return true;
  }
  return false;
}

Real Parser::real(std::string_view s, const char* what) const {
  std::string_view digits = s;
  if (digits.size() > 1 && digits[0] == '+' && digits[1] != '-') digits.remove_prefix(1);
  double v = 0;
  const auto [ptr, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), v);
  if (ptr != digits.data() + digits.size() || digits.empty() ||
      (ec != std::errc() && ec != std::errc::result_out_of_range)) {
    fail("expected floating-point number but got \"" + std::string(s) + "\"", {"VALUE", "NUMBER"});
  }
  if (ec == std::errc::result_out_of_range) {
    // from_chars leaves v unset out of range; strtod tells underflow (a tiny value, kept)
    // from overflow (HUGE_VAL, refused below).
    v = std::strtod(std::string(digits).c_str(), nullptr);
  }
  if (!std::isfinite(v) || std::abs(v) == HUGE_VAL) {
    fail(std::string("bad ") + what + " \"" + std::string(s) + "\": must be a finite number",
         {"VALUE", "NUMBER"});
  }
  return v;
}

std::int64_t Parser::integer(std::string_view s) const {
  std::string_view digits = s;
  if (digits.size() > 1 && digits[0] == '+' && digits[1] != '-') digits.remove_prefix(1);
  std::int64_t v = 0;
  const auto [ptr, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), v);
  if (ec != std::errc() || ptr != digits.data() + digits.size() || digits.empty()) {
    fail("expected integer but got \"" + std::string(s) + "\"", {"VALUE", "NUMBER"});
  }
  return v;
}

void Parser::header(const Tokens& t) {
  static constexpr std::array<const char*, 3> kLo{"xlo", "ylo", "zlo"};
  static constexpr std::array<const char*, 3> kHi{"xhi", "yhi", "zhi"};
  if (t.count == 2 && t[1] == "atoms") {
    atomCount_ = integer(t[0]);
    if (atomCount_ < 0) {
      fail("bad atom count \"" + std::string(t[0]) + "\": must be a non-negative integer",
           {"VALUE", "COUNT"});
    }
    return;
  }
  if (t.count == 3 && t[1] == "atom" && t[2] == "types") {
    const std::int64_t n = integer(t[0]);
    if (n < 1) {
      fail("bad atom type count \"" + std::string(t[0]) + "\": must be a positive integer",
           {"VALUE", "COUNT"});
    }
    d_.atomTypes = static_cast<std::size_t>(n);
    haveTypes_ = true;
    return;
  }
  for (int k = 0; k < 3; ++k) {
    if (t.count == 4 && t[2] == kLo[k] && t[3] == kHi[k]) {
      const Real lo = real(t[0], kLo[k]), hi = real(t[1], kHi[k]);
      if (!(lo < hi)) {
        fail("bad box \"" + std::string(t[0]) + " " + std::string(t[1]) + "\": must have " +
                 kLo[k] + " < " + kHi[k],
             {"VALUE", "BOX"});
      }
      d_.boxLo[k] = lo;
      d_.boxHi[k] = hi;
      haveBox_[k] = true;
      return;
    }
  }
  if (t.count == 6 && t[3] == "xy" && t[4] == "xz" && t[5] == "yz") {
    fail("triclinic box (\"xy xz yz\") not supported: the box must be orthogonal",
         {"IO", "FORMAT"});
  }
  // Other header lines are a count followed by words ("0 bonds", "4 extra bond per atom").
  if (t.count >= 2 && allWords(t, 1)) {
    integer(t[0]);
    return;
  }
  fail(
      "unexpected line in the header: must be \"N atoms\", \"N atom types\", \"lo hi xlo xhi\" "
      "or a section keyword such as \"Atoms\"",
      {"IO", "FORMAT"});
}

void Parser::atoms(std::string_view comment) {
  if (haveAtoms_) fail("second Atoms section", {"IO", "FORMAT"});
  if (atomCount_ < 0) fail("Atoms section before the header's \"N atoms\" line", {"IO", "FORMAT"});
  if (!haveTypes_)
    fail("Atoms section before the header's \"N atom types\" line", {"IO", "FORMAT"});
  static constexpr std::array<const char*, 3> kAxis{"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    if (!haveBox_[k]) {
      fail(std::string("Atoms section before the header's \"") + kAxis[k] + "lo " + kAxis[k] +
               "hi\" line",
           {"IO", "FORMAT"});
    }
  }
  if (!comment.empty() && split(comment)[0] != "sphere") {
    fail("bad atom style \"" + std::string(split(comment)[0]) + "\": must be sphere",
         {"IO", "FORMAT"});
  }
  haveAtoms_ = true;
  const auto n = static_cast<std::size_t>(atomCount_);
  if (atomCount_ >= INT32_MAX) {
    fail("bad atom count " + std::to_string(atomCount_) + ": at most " +
             std::to_string(INT32_MAX - 1),
         {"VALUE", "COUNT"});
  }
  // The header's count sizes the arrays, so it is checked against what the file can hold
  // before anything is allocated: a header claiming 10^8 atoms over a few lines fails here.
  if (atomCount_ > maxAtoms_) {
    fail("bad atom count " + std::to_string(atomCount_) + ": the file can hold at most " +
             std::to_string(maxAtoms_) + " atom lines",
         {"IO", "FORMAT"});
  }
  d_.ids.reserve(n);
  d_.types.reserve(n);
  d_.diameters.reserve(n);
  d_.densities.reserve(n);
  d_.positions.reserve(n);
  index_.reset(n);
  std::string_view line, c;
  for (std::size_t i = 0; i < n; ++i) {
    if (!nextContent(line, c)) {
      std::ostringstream os;
      os << "file ends after " << i << " of " << n << " atom lines";
      fail(os.str(), {"IO", "TRUNCATED"});
    }
    const Tokens t = split(line);
    if (t.count != 7 && t.count != 10) {
      if (isAlpha(line.front())) {
        std::ostringstream os;
        os << "section \"" << line << "\" after " << i << " of " << n << " atom lines";
        fail(os.str(), {"IO", "TRUNCATED"});
      }
      std::ostringstream os;
      os << "bad atom line: has " << t.count
         << " fields, must be \"id type diameter density x y z\" (and optionally 3 image flags)";
      fail(os.str(), {"IO", "FORMAT"});
    }
    const std::int64_t id = integer(t[0]);
    const std::int64_t type = integer(t[1]);
    const Real diameter = real(t[2], "diameter");
    const Real density = real(t[3], "density");
    Vec3 x;
    for (int k = 0; k < 3; ++k) x[k] = real(t[4 + k], kAxis[k]);
    if (t.count == 10) {
      for (int k = 0; k < 3; ++k) integer(t[7 + k]);
    }
    if (id < 1)
      fail("bad atom id \"" + std::string(t[0]) + "\": must be a positive integer",
           {"VALUE", "ID"});
    if (type < 1 || type > static_cast<std::int64_t>(d_.atomTypes)) {
      fail("bad atom type \"" + std::string(t[1]) + "\": must be between 1 and " +
               std::to_string(d_.atomTypes),
           {"VALUE", "TYPE"});
    }
    if (!(diameter > 0)) {
      fail("bad diameter \"" + std::string(t[2]) + "\": must be a positive number",
           {"VALUE", "DIAMETER"});
    }
    if (!(density > 0)) {
      fail("bad density \"" + std::string(t[3]) + "\": must be a positive number",
           {"VALUE", "DENSITY"});
    }
    for (int k = 0; k < 3; ++k) {
      if (x[k] < d_.boxLo[k] || x[k] > d_.boxHi[k]) {
        std::ostringstream os;
        os << "bad position of atom " << id << ": " << kAxis[k] << " = " << t[4 + k]
           << " is outside the box [" << d_.boxLo[k] << ", " << d_.boxHi[k] << "]";
        fail(os.str(), {"VALUE", "POSITION"});
      }
    }
    d_.ids.push_back(id);
    if (!index_.insert(d_.ids, d_.ids.size() - 1)) {
      fail("duplicate atom id \"" + std::string(t[0]) + "\"", {"VALUE", "ID"});
    }
    d_.types.push_back(static_cast<int>(type));
    d_.diameters.push_back(diameter);
    d_.densities.push_back(density);
    d_.positions.push_back(x);
    d_.lines.push_back(in_.lineNumber());
  }
}

void Parser::velocities() {
  if (haveVelocities_) fail("second Velocities section", {"IO", "FORMAT"});
  if (!haveAtoms_) fail("Velocities section before the Atoms section", {"IO", "FORMAT"});
  haveVelocities_ = true;
  const std::size_t n = d_.size();
  d_.velocities.assign(n, Vec3::Zero());
  d_.angularVelocities.assign(n, Vec3::Zero());
  std::vector<bool> seen(n, false);
  std::string_view line, c;
  for (std::size_t i = 0; i < n; ++i) {
    if (!nextContent(line, c)) {
      std::ostringstream os;
      os << "file ends after " << i << " of " << n << " velocity lines";
      fail(os.str(), {"IO", "TRUNCATED"});
    }
    const Tokens t = split(line);
    if (t.count != 7) {
      std::ostringstream os;
      os << "bad velocity line: has " << t.count << " fields, must be \"id vx vy vz wx wy wz\"";
      fail(os.str(), {"IO", "FORMAT"});
    }
    const std::int64_t id = integer(t[0]);
    const std::size_t at = index_.find(d_.ids, id);
    if (at == IdIndex::kNone) {
      fail("bad atom id \"" + std::string(t[0]) + "\" in Velocities: no such atom",
           {"VALUE", "ID"});
    }
    if (seen[at]) {
      fail("duplicate atom id \"" + std::string(t[0]) + "\" in Velocities", {"VALUE", "ID"});
    }
    seen[at] = true;
    Vec3 v, w;
    for (int k = 0; k < 3; ++k) v[k] = real(t[1 + k], "velocity");
    for (int k = 0; k < 3; ++k) w[k] = real(t[4 + k], "angular velocity");
    d_.velocities[at] = v;
    d_.angularVelocities[at] = w;
  }
}

bool Parser::skipSection(std::string_view& line, std::string_view& comment) {
  while (nextContent(line, comment)) {
    if (isAlpha(line.front())) return true;
  }
  return false;
}

SphereData Parser::run() {
  std::string_view raw;
  if (!in_.next(raw)) fail("file is empty: expected a LAMMPS data file", {"IO", "FORMAT"});
  d_.title = std::string(trim(raw));

  std::string_view line, comment;
  bool more = nextContent(line, comment);
  // The header runs up to the first section keyword (a line starting with a letter).
  while (more && !isAlpha(line.front())) {
    header(split(line));
    more = nextContent(line, comment);
  }
  while (more) {
    if (isAlpha(line.front()) && !isSectionKeyword(line)) {
      fail("unknown section \"" + std::string(line.substr(0, 60)) +
               "\": must be a LAMMPS section keyword such as \"Atoms\"",
           {"IO", "FORMAT"});
    }
    if (!isAlpha(line.front())) {
      fail("unexpected line \"" + std::string(line.substr(0, 60)) +
               "\" outside any section (more atom lines than the header's \"" +
               std::to_string(atomCount_) + " atoms\"?)",
           {"IO", "FORMAT"});
    }
    if (line == "Atoms") {
      atoms(comment);
    } else if (line == "Velocities") {
      velocities();
    } else {
      more = skipSection(line, comment);
      continue;
    }
    more = nextContent(line, comment);
  }

  if (atomCount_ < 0) fail("no \"N atoms\" line in the header", {"IO", "FORMAT"});
  if (!haveAtoms_ && atomCount_ > 0) {
    fail("file ends before the Atoms section", {"IO", "TRUNCATED"});
  }
  if (!haveAtoms_) {  // an empty system may leave out the section, not the box
    for (int k = 0; k < 3; ++k) {
      if (!haveBox_[k]) fail("no box bounds in the header", {"IO", "FORMAT"});
    }
  }
  return std::move(d_);
}

}  // namespace

SphereData readLammpsData(const std::string& path) {
  return Parser(path).run();
}

std::string sceneName(const std::string& path) {
  std::string s = std::filesystem::path(path).filename().string();
  for (std::string_view ext : {".gz", ".data"}) {
    if (s.size() > ext.size() && s.ends_with(ext)) s.resize(s.size() - ext.size());
  }
  return s;
}

}  // namespace demlab::io
