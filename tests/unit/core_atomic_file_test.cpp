// writeFileAtomically: the target holds the old bytes or the new, and a failure leaves no
// temporary behind.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "core/atomic_file.hpp"
#include "core/error.hpp"

namespace demlab {
namespace core_atomic_file_test {

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

// The temporary's name is unique: a user's own "PATH.tmp" is neither used nor removed, and
// the folder holds only the two files afterwards.
TEST(AtomicFile, LeavesAUsersTmpFileAlone) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("demlab-atomic-tmp-" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "scene.ckpt").string();
  { std::ofstream(path + ".tmp") << "the user's"; }
  writeFileAtomically(path, "new");
  EXPECT_EQ(slurp(path), "new");
  EXPECT_EQ(slurp(path + ".tmp"), "the user's");
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), {}), 2);
  std::filesystem::remove_all(dir);
}

TEST(AtomicFile, AFailingEncoderKeepsTheOldFileAndNamesItsReason) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("demlab-atomic-enc-" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "frame.png").string();
  writeFileAtomically(path, "old");
  try {
    writeFileAtomically(path, [](std::FILE*) { return std::string("encoder gave up"); }, "PNG");
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), (std::vector<std::string>{"DEMLAB", "IO", "PNG"}));
    EXPECT_EQ(std::string(e.what()), "error writing \"" + path + "\": encoder gave up");
  }
  EXPECT_EQ(slurp(path), "old");
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), {}), 1);
  std::filesystem::remove_all(dir);
}

TEST(AtomicFile, PosixMessagesAreWordedAsTclWordsThem) {
  EXPECT_EQ(posixMessage(ENOENT), "no such file or directory");
  EXPECT_EQ(posixMessage(0), "unknown error");
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

}  // namespace core_atomic_file_test
}  // namespace demlab
