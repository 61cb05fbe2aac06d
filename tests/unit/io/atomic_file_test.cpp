// writeFileAtomically: the target holds the old bytes or the new, and a failure leaves no
// temporary behind.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "core/error.hpp"
#include "io/atomic_file.hpp"

namespace demlab::io {
namespace {

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

TEST(AtomicFile, ReplacesTheTargetAndLeavesNoTemporary) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("demlab-atomic-" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "out.bin").string();
  writeFileAtomically(path, std::string("first\0bytes", 11));
  EXPECT_EQ(slurp(path), std::string("first\0bytes", 11));
  writeFileAtomically(path, "second");
  EXPECT_EQ(slurp(path), "second");
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
  std::filesystem::remove_all(dir);
}

TEST(AtomicFile, AMissingFolderIsAnOpenErrorAndWritesNothing) {
  const std::string path = "/nonexistent-demlab-folder/out.bin";
  try {
    writeFileAtomically(path, "x");
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), (std::vector<std::string>{"DEMLAB", "IO", "OPEN"}));
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
}

}  // namespace
}  // namespace demlab::io
