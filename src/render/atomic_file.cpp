#include "render/atomic_file.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

#include "core/error.hpp"

namespace demlab::render {

void writeFileAtomically(const std::string& path, const std::string& kind,
                         const FileEncoder& encode) {
  auto ioError = [&](const std::string& what, const std::string& reason) {
    return Error("couldn't " + what + " \"" + path + "\": " + reason, {"IO", kind});
  };
  // The temporary name shares the target's folder so rename is atomic (same file system).
  std::string tmp = path + ".XXXXXX";
  const int fd = mkstemp(tmp.data());
  if (fd < 0) throw ioError("open", std::strerror(errno));
  std::FILE* f = fdopen(fd, "wb");
  if (!f) {
    const int err = errno;
    close(fd);
    unlink(tmp.c_str());
    throw ioError("open", std::strerror(err));
  }
  const std::string reason = encode(f);
  const int werr = std::ferror(f) ? errno : 0;
  const bool closed = std::fclose(f) == 0;
  if (!reason.empty() || werr || !closed) {
    unlink(tmp.c_str());
    throw ioError("write", reason.empty() ? std::strerror(werr ? werr : EIO) : reason);
  }
  // mkstemp makes the file 0600; a frame should be readable like any file the user writes.
  const mode_t mask = umask(0);
  umask(mask);
  chmod(tmp.c_str(), 0666 & ~mask);
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const int err = errno;
    unlink(tmp.c_str());
    throw ioError("rename onto", std::strerror(err));
  }
}

}  // namespace demlab::render
