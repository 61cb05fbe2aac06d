// Tests of the LAMMPS data reader (src/io/lammps_data.hpp): well-formed files plain and gzip'd,
// every malformed case the reader promises to name, a large random file read back exactly,
// and the benchmark's real data files (../shared/bench/data, or $DEMLAB_BENCH_DATA).
#include "io/lammps_data.hpp"

#include <gtest/gtest.h>
#include <unistd.h>
#include <zlib.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "io/line_reader.hpp"

namespace demlab::io {
namespace lammps_data_test {

namespace fs = std::filesystem;

// A fresh temporary directory per test, removed afterwards.
class LammpsDataTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("demlab_io_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Writes text to dir_/name (plain) and returns the path.
  std::string writePlain(const std::string& name, const std::string& text) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }

  // Writes text gzip'd to dir_/name and returns the path.
  std::string writeGzip(const std::string& name, const std::string& text) {
    const std::string path = (dir_ / name).string();
    gzFile f = gzopen(path.c_str(), "wb");
    EXPECT_NE(f, nullptr);
    EXPECT_EQ(gzwrite(f, text.data(), static_cast<unsigned>(text.size())),
              static_cast<int>(text.size()));
    gzclose(f);
    return path;
  }

  fs::path dir_;
};

const char* kHeader =
    "LAMMPS data file written by a test\n"
    "\n"
    "3 atoms\n"
    "2 atom types\n"
    "0 bonds\n"
    "\n"
    "-1.0 2.0 xlo xhi\n"
    "0 1 ylo yhi   # a comment\n"
    "0 3e0 zlo zhi\n"
    "\n";

const std::string kGood = std::string(kHeader) +
                          "Masses\n"
                          "\n"
                          "1 1.0\n"
                          "2 2.0\n"
                          "\n"
                          "Atoms # sphere\n"
                          "\n"
                          "7 1 1.0e-3 2500 0.5 0.25 1.5\n"
                          "3 2 2e-3 1000.5 -1 0 0 0 0 0\n"
                          "5 1 0.001 2500.0 2.0 1.0 3.0   # on the box's corner\n"
                          "\n"
                          "Velocities\n"
                          "\n"
                          "5 0 0 -1 0 0 0\n"
                          "7 1 2 3 4 5 6\n"
                          "3 -1 -2 -3 -4 -5 -6\n";

// Checks the contents of kGood.
void expectGood(const SphereData& d) {
  EXPECT_EQ(d.title, "LAMMPS data file written by a test");
  EXPECT_EQ(d.atomTypes, 2u);
  EXPECT_EQ(d.boxLo, Vec3(-1, 0, 0));
  EXPECT_EQ(d.boxHi, Vec3(2, 1, 3));
  ASSERT_EQ(d.size(), 3u);
  EXPECT_EQ(d.ids, (std::vector<std::int64_t>{7, 3, 5}));
  EXPECT_EQ(d.types, (std::vector<int>{1, 2, 1}));
  EXPECT_EQ(d.diameters, (std::vector<Real>{1.0e-3, 2e-3, 0.001}));
  EXPECT_EQ(d.densities, (std::vector<Real>{2500, 1000.5, 2500}));
  EXPECT_EQ(d.positions[0], Vec3(0.5, 0.25, 1.5));
  EXPECT_EQ(d.positions[1], Vec3(-1, 0, 0));
  EXPECT_EQ(d.positions[2], Vec3(2, 1, 3));
  ASSERT_EQ(d.velocities.size(), 3u);
  ASSERT_EQ(d.angularVelocities.size(), 3u);
  EXPECT_EQ(d.velocities[0], Vec3(1, 2, 3));  // matched by id, not by line
  EXPECT_EQ(d.angularVelocities[0], Vec3(4, 5, 6));
  EXPECT_EQ(d.velocities[1], Vec3(-1, -2, -3));
  EXPECT_EQ(d.angularVelocities[1], Vec3(-4, -5, -6));
  EXPECT_EQ(d.velocities[2], Vec3(0, 0, -1));
}

// Returns the error readLammpsData(path) throws; fails the test if it throws none.
Error errorOf(const std::string& path) {
  try {
    readLammpsData(path);
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << "no error reading " << path;
  return Error("none", {});
}

// Expects readLammpsData(path) to throw with the given code words after DEMLAB and with every
// one of `parts` in its message.
void expectError(const std::string& path, std::vector<std::string> code,
                 std::vector<std::string> parts) {
  const Error e = errorOf(path);
  code.insert(code.begin(), "DEMLAB");
  EXPECT_EQ(e.code(), code) << e.what();
  for (const auto& p : parts) {
    EXPECT_NE(std::string(e.what()).find(p), std::string::npos)
        << "message \"" << e.what() << "\" lacks \"" << p << "\"";
  }
}

// Returns kGood with its first occurrence of `from` replaced by `to`.
std::string goodWith(const std::string& from, const std::string& to) {
  std::string s = kGood;
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return s.replace(at, from.size(), to);
}

TEST_F(LammpsDataTest, ReadsPlainFile) {
  expectGood(readLammpsData(writePlain("a.data", kGood)));
}

TEST_F(LammpsDataTest, ReadsGzipFileTheSame) {
  expectGood(readLammpsData(writeGzip("a.data.gz", kGood)));
}

TEST_F(LammpsDataTest, ReadsCrlfAndNoFinalNewline) {
  std::string crlf;
  for (char c : kGood) {
    if (c == '\n') crlf += '\r';
    crlf += c;
  }
  crlf.resize(crlf.size() - 2);  // drop the last "\r\n"
  expectGood(readLammpsData(writePlain("crlf.data", crlf)));
}

TEST_F(LammpsDataTest, VelocitiesAreOptional) {
  const std::string text = kGood.substr(0, kGood.find("Velocities"));
  const SphereData d = readLammpsData(writePlain("nov.data", text));
  EXPECT_EQ(d.size(), 3u);
  EXPECT_TRUE(d.velocities.empty());
  EXPECT_TRUE(d.angularVelocities.empty());
}

TEST_F(LammpsDataTest, MissingFile) {
  const std::string path = (dir_ / "nope.data.gz").string();
  expectError(path, {"IO", "OPEN"}, {"couldn't open \"" + path + "\": no such file or directory"});
}

TEST_F(LammpsDataTest, EmptyFile) {
  expectError(writePlain("empty.data", ""), {"IO", "FORMAT"}, {"file is empty"});
}

TEST_F(LammpsDataTest, TruncatedAtomLines) {
  // Cut inside the Atoms section: 2 of 3 lines remain.
  const std::string text = kGood.substr(0, kGood.find("5 1 0.001"));
  const std::string path = writePlain("cut.data", text);
  expectError(path, {"IO", "TRUNCATED"}, {"file ends after 2 of 3 atom lines", path});
  // The same cut inside a gzip'd file (complete stream).
  expectError(writeGzip("cut.data.gz", text), {"IO", "TRUNCATED"}, {"2 of 3 atom lines"});
}

TEST_F(LammpsDataTest, SectionInsideAtoms) {
  const std::string text = kGood.substr(0, kGood.find("5 1 0.001")) + "\nVelocities\n";
  expectError(writePlain("sec.data", text), {"IO", "TRUNCATED"},
              {"section \"Velocities\" after 2 of 3 atom lines", "line 21)"});
}

TEST_F(LammpsDataTest, TruncatedVelocities) {
  const std::string text = kGood.substr(0, kGood.find("3 -1 -2"));
  expectError(writePlain("vcut.data", text), {"IO", "TRUNCATED"}, {"2 of 3 velocity lines"});
}

TEST_F(LammpsDataTest, NoAtomsSection) {
  expectError(writePlain("noatoms.data", kHeader), {"IO", "TRUNCATED"},
              {"file ends before the Atoms section"});
}

TEST_F(LammpsDataTest, TruncatedGzipStream) {
  // Many atoms, so the compressed stream is long; then cut its bytes in half.
  std::string text =
      "t\n\n2000 atoms\n1 atom types\n0 1 xlo xhi\n0 1 ylo yhi\n0 1 zlo zhi\n\n"
      "Atoms\n\n";
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 1; i <= 2000; ++i) {
    char line[160];
    std::snprintf(line, sizeof line, "%d 1 %.17g 2500 %.17g %.17g %.17g\n", i, 0.01 + u(rng),
                  u(rng), u(rng), u(rng));
    text += line;
  }
  const std::string whole = writeGzip("whole.data.gz", text);
  ASSERT_EQ(readLammpsData(whole).size(), 2000u);
  std::ifstream in(whole, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_GT(bytes.size(), 1000u);
  const std::string cut = (dir_ / "half.data.gz").string();
  std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  expectError(cut, {"IO", "READ"}, {"unexpected end of gzip stream", cut});
}

TEST_F(LammpsDataTest, BadNumberNamesLine) {
  // kGood's atom lines are lines 18, 19 and 20.
  expectError(writePlain("bad.data", goodWith("2.0 1.0 3.0", "2.0 abc 3.0")), {"VALUE", "NUMBER"},
              {"expected floating-point number but got \"abc\"", "line 20)", "bad.data"});
  expectError(writePlain("bad2.data", goodWith("7 1 1.0e-3", "7 1.5 1.0e-3")), {"VALUE", "NUMBER"},
              {"expected integer but got \"1.5\"", "line 18)"});
  expectError(writePlain("bad3.data", goodWith("2500 0.5", "2500 0.5x")), {"VALUE", "NUMBER"},
              {"got \"0.5x\""});
  expectError(writePlain("bad4.data", goodWith("3 atoms", "three atoms")), {"IO", "FORMAT"},
              {"unknown section \"three atoms\"", "line 3)"});
  expectError(writePlain("bad5.data", goodWith("3 atoms", "3.5 atoms")), {"VALUE", "NUMBER"},
              {"expected integer but got \"3.5\"", "line 3)"});
}

TEST_F(LammpsDataTest, NonFiniteNumbers) {
  expectError(writePlain("nan.data", goodWith("0.5 0.25 1.5", "nan 0.25 1.5")), {"VALUE", "NUMBER"},
              {"bad x \"nan\": must be a finite number", "line 18)"});
  expectError(writePlain("inf.data", goodWith("0.5 0.25 1.5", "0.5 0.25 -inf")),
              {"VALUE", "NUMBER"}, {"bad z \"-inf\": must be a finite number"});
  expectError(writePlain("big.data", goodWith("2500 0.5", "1e999 0.5")), {"VALUE", "NUMBER"},
              {"bad density \"1e999\": must be a finite number"});
  expectError(writePlain("nanbox.data", goodWith("0 1 ylo", "0 NaN ylo")), {"VALUE", "NUMBER"},
              {"bad yhi \"NaN\"", "line 8)"});
  // An underflow is a tiny number, not an error.
  const SphereData d = readLammpsData(writePlain("tiny.data", goodWith("0.5 0.25", "1e-400 0.25")));
  EXPECT_EQ(d.positions[0].x(), 0);
}

TEST_F(LammpsDataTest, NonPositiveDiameterAndDensity) {
  expectError(writePlain("d0.data", goodWith("7 1 1.0e-3", "7 1 0")), {"VALUE", "DIAMETER"},
              {"bad diameter \"0\": must be a positive number", "line 18)"});
  expectError(writePlain("dn.data", goodWith("3 2 2e-3", "3 2 -2e-3")), {"VALUE", "DIAMETER"},
              {"bad diameter \"-2e-3\": must be a positive number", "line 19)"});
  expectError(writePlain("rho.data", goodWith("1000.5", "0.0")), {"VALUE", "DENSITY"},
              {"bad density \"0.0\": must be a positive number"});
}

TEST_F(LammpsDataTest, OutOfRangeValues) {
  expectError(writePlain("type.data", goodWith("3 2 2e-3", "3 3 2e-3")), {"VALUE", "TYPE"},
              {"bad atom type \"3\": must be between 1 and 2"});
  expectError(writePlain("id.data", goodWith("3 2 2e-3", "7 2 2e-3")), {"VALUE", "ID"},
              {"duplicate atom id \"7\"", "line 19)"});
  expectError(writePlain("id0.data", goodWith("3 2 2e-3", "0 2 2e-3")), {"VALUE", "ID"},
              {"bad atom id \"0\""});
  expectError(writePlain("pos.data", goodWith("0.5 0.25 1.5", "0.5 1.25 1.5")),
              {"VALUE", "POSITION"}, {"bad position of atom 7: y = 1.25 is outside the box"});
  expectError(writePlain("box.data", goodWith("0 3e0 zlo", "3 3 zlo")), {"VALUE", "BOX"},
              {"bad box \"3 3\": must have zlo < zhi"});
  expectError(writePlain("vid.data", goodWith("5 0 0 -1", "9 0 0 -1")), {"VALUE", "ID"},
              {"bad atom id \"9\" in Velocities: no such atom"});
  expectError(writePlain("count.data", goodWith("3 atoms", "-3 atoms")), {"VALUE", "COUNT"}, {});
  // The id index holds 32-bit entries; the count is refused before anything is sized for it.
  expectError(writePlain("huge.data", goodWith("3 atoms", "3000000000 atoms")), {"VALUE", "COUNT"},
              {"bad atom count 3000000000: at most 2147483646"});
}

TEST_F(LammpsDataTest, FormatErrors) {
  expectError(
      writePlain("f1.data", goodWith("7 1 1.0e-3 2500 0.5 0.25 1.5", "7 1 1.0e-3 2500 0.5")),
      {"IO", "FORMAT"}, {"bad atom line: has 5 fields", "line 18)"});
  expectError(writePlain("f2.data", goodWith("Atoms # sphere", "Atoms # atomic")), {"IO", "FORMAT"},
              {"bad atom style \"atomic\": must be sphere"});
  expectError(writePlain("f3.data", goodWith("0 1 ylo yhi   # a comment\n", "")), {"IO", "FORMAT"},
              {"before the header's \"ylo yhi\" line"});
  expectError(writePlain("f4.data", goodWith("0 3e0 zlo zhi\n", "0 3e0 zlo zhi\n0 0 0 xy xz yz\n")),
              {"IO", "FORMAT"}, {"triclinic"});
  expectError(writePlain("f5.data", goodWith("2 atom types\n", "")), {"IO", "FORMAT"},
              {"atom types"});
  // One atom line more than the header's count.
  expectError(
      writePlain("f6.data", goodWith("5 1 0.001 2500.0 2.0 1.0 3.0   # on the box's corner\n",
                                     "5 1 0.001 2500.0 2.0 1.0 3.0\n6 1 1 1 0 0 0\n")),
      {"IO", "FORMAT"}, {"outside any section", "line 21)"});
  expectError(writePlain("f7.data", kGood + "Atoms\n\n1 1 1 1 0 0 0\n"), {"IO", "FORMAT"},
              {"second Atoms section"});
}

// A large file (several reader chunks, one line longer than a chunk) read back bit for bit.
TEST_F(LammpsDataTest, LargeRandomFileReadsBackExactly) {
  const int n = 30000;
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<double> dia(n), rho(n), pos(3 * n);
  std::string text(300000, 'T');  // a title longer than the reader's chunk
  text += "\n\n" + std::to_string(n) +
          " atoms\n4 atom types\n0 10 xlo xhi\n-5 5 ylo yhi\n"
          "0 1e-2 zlo zhi\n\nAtoms # sphere\n\n";
  for (int i = 0; i < n; ++i) {
    dia[i] = 1e-4 + 1e-2 * u(rng);
    rho[i] = 100 + 5000 * u(rng);
    pos[3 * i] = 10 * u(rng);
    pos[3 * i + 1] = -5 + 10 * u(rng);
    pos[3 * i + 2] = 1e-2 * u(rng);
    char line[200];
    std::snprintf(line, sizeof line, "%d %d %.17g %.17g %.17g %.17g %.17g\n", n - i, 1 + i % 4,
                  dia[i], rho[i], pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]);
    text += line;
  }
  for (const std::string& path : {writePlain("big.data", text), writeGzip("big.data.gz", text)}) {
    const SphereData d = readLammpsData(path);
    ASSERT_EQ(d.size(), static_cast<std::size_t>(n));
    EXPECT_EQ(d.title.size(), 300000u);
    for (int i = 0; i < n; ++i) {
      ASSERT_EQ(d.ids[i], n - i);
      ASSERT_EQ(d.types[i], 1 + i % 4);
      ASSERT_EQ(d.diameters[i], dia[i]);
      ASSERT_EQ(d.densities[i], rho[i]);
      ASSERT_EQ(d.positions[i], Vec3(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]));
    }
  }
}

TEST_F(LammpsDataTest, LineReaderCountsLines) {
  const std::string path = writePlain("lines.txt", "a\r\n\nbb\nccc");
  LineReader r(path);
  std::string_view line;
  std::vector<std::string> got;
  while (r.next(line)) got.emplace_back(line);
  EXPECT_EQ(got, (std::vector<std::string>{"a", "", "bb", "ccc"}));
  EXPECT_EQ(r.lineNumber(), 4u);
  EXPECT_FALSE(r.next(line));
}

// The benchmark's data files: counts, boxes and sizes as the README describes them.
struct BenchFile {
  const char* stem;
  std::size_t n;
  Vec3 hi;
  Real dmin, dmax;
};

TEST(LammpsDataBench, ReadsTheBenchmarkDataFiles) {
  const char* env = std::getenv("DEMLAB_BENCH_DATA");
  const fs::path dir = env != nullptr ? fs::path(env) : fs::path(DEMLAB_BENCH_DATA_DIR);
  if (!fs::exists(dir / "mono_10k.data.gz")) {
    GTEST_SKIP() << "no benchmark data at " << dir << " (set DEMLAB_BENCH_DATA)";
  }
  const std::vector<BenchFile> files = {
      {"mono_10k", 10000, Vec3(0.022, 0.022, 0.0286), 1e-3, 1e-3},
      {"mono_10k_dense", 10000, Vec3(0.022, 0.022, 0.0286), 1e-3, 1e-3},
      {"mono_100k", 100000, Vec3(0.055, 0.055, 0.0451), 1e-3, 1e-3},
      {"mono_100k_dense", 100000, Vec3(0.055, 0.055, 0.0451), 1e-3, 1e-3},
      {"poly_20k", 20000, Vec3(0.1375, 0.1375, 0.1815), 0.5e-3, 5e-3},
      {"poly_20k_dense", 20000, Vec3(0.1375, 0.1375, 0.1815), 0.5e-3, 5e-3},
  };
  for (const auto& f : files) {
    SCOPED_TRACE(f.stem);
    const SphereData d = readLammpsData((dir / (std::string(f.stem) + ".data.gz")).string());
    ASSERT_EQ(d.size(), f.n);
    EXPECT_EQ(d.atomTypes, 1u);
    EXPECT_EQ(d.boxLo, Vec3::Zero());
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(d.boxHi[k], f.hi[k], 1e-12);
    std::set<std::int64_t> ids(d.ids.begin(), d.ids.end());
    EXPECT_EQ(ids.size(), f.n);
    EXPECT_EQ(*ids.begin(), 1);
    EXPECT_EQ(*ids.rbegin(), static_cast<std::int64_t>(f.n));
    for (std::size_t i = 0; i < d.size(); ++i) {
      ASSERT_EQ(d.types[i], 1);
      ASSERT_EQ(d.densities[i], 2500);
      ASSERT_GE(d.diameters[i], f.dmin * (1 - 1e-9));
      ASSERT_LE(d.diameters[i], f.dmax * (1 + 1e-9));
      // Every sphere lies inside the box with its whole radius (the walls are the box faces),
      // give or take the settled overlap with a wall.
      for (int k = 0; k < 3; ++k) {
        ASSERT_GE(d.positions[i][k], 0.45 * d.diameters[i]);
        ASSERT_LE(d.positions[i][k], f.hi[k] - (k < 2 ? 0.45 * d.diameters[i] : 0));
      }
    }
  }
}

}  // namespace lammps_data_test
}  // namespace demlab::io
