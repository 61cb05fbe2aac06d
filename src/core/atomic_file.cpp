#include "core/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <cstring>
#include <memory>
#include <mutex>
#include <system_error>
#include <thread>

#include "core/background_work.hpp"
#include "core/error.hpp"
#include "core/free_aside.hpp"
#include "core/interrupt.hpp"

namespace demlab {

std::string posixMessage(int err) {
  std::string s = err != 0 ? std::strerror(err) : "unknown error";
  if (!s.empty()) s[0] = static_cast<char>(std::tolower(static_cast<unsigned char>(s[0])));
  return s;
}

namespace {

// Returns nothing. Syncs the folder holding path, so the rename itself survives a crash; a
// file system that cannot sync folders (EINVAL) is left as it is.
void syncFolderOf(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  const std::string dir = slash == std::string::npos ? "." : slash == 0 ? "/" : path.substr(0, slash);
  const int fd = open(dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (fd < 0) return;
  fsync(fd);
  close(fd);
}

// The state a sync shares with the thread that runs it.
struct SyncJob {
  std::mutex m;
  std::condition_variable cv;
  std::FILE* f = nullptr;
  bool done = false;       // the sync returned
  bool abandoned = false;  // the caller left: the thread closes f
  int err = 0;             // the sync's errno, 0 when it succeeded
};

// Returns the errno of flushing and syncing f to disk (0: done; EINVAL, a file that cannot be
// synced, counts as done). The sync (a second or more for hundreds of megabytes on a slow disk,
// in a call no signal ends) runs on a thread of its own while this one polls Ctrl-C; stopped,
// it unlinks tmp, leaves the thread to finish the sync and close f, and throws {INTERRUPTED}
// ("writing "path" interrupted"). Changes f's file on disk.
int syncPolled(std::FILE* f, const std::string& tmp, const std::string& path) {
  if (std::fflush(f) != 0) return errno;
  const auto sync = [](std::FILE* file) {
    return fsync(fileno(file)) != 0 && errno != EINVAL ? errno : 0;
  };
  auto job = std::make_shared<SyncJob>();
  job->f = f;
  try {
    std::thread([job, sync, work = std::make_unique<BackgroundWork>()] {
      const int err = sync(job->f);
      std::lock_guard<std::mutex> lock(job->m);
      job->done = true;
      job->err = err;
      if (job->abandoned) std::fclose(job->f);
      job->cv.notify_all();
    }).detach();
  } catch (const std::system_error&) {  // no thread to be had: the sync here, unpolled
    return sync(f);
  }
  std::unique_lock<std::mutex> lock(job->m);
  while (!job->done) {
    job->cv.wait_for(lock, std::chrono::milliseconds(5));
    if (!job->done && interruptRequested()) {
      job->abandoned = true;
      lock.unlock();
      unlink(tmp.c_str());
      throw Error("writing \"" + path + "\" interrupted", {"INTERRUPTED"});
    }
  }
  return job->err;
}

}  // namespace

void writeFileAtomically(const std::string& path, const FileEncoder& encode,
                         std::string_view kind) {
  const std::string openCode = kind.empty() ? "OPEN" : std::string(kind);
  const std::string writeCode = kind.empty() ? "WRITE" : std::string(kind);
  auto writeError = [&](const std::string& reason) {
    return Error("error writing \"" + path + "\": " + reason, {"IO", writeCode});
  };
  struct stat target;
  if (stat(path.c_str(), &target) == 0 && S_ISDIR(target.st_mode)) {
    throw Error("couldn't open \"" + path + "\" for writing: it is a directory",
                {"IO", openCode});
  }
  // The temporary shares the target's folder so the rename is atomic (one file system).
  std::string tmp = path + ".XXXXXX";
  const int fd = mkstemp(tmp.data());
  if (fd < 0) {
    throw Error("couldn't open \"" + path + "\" for writing: " + posixMessage(errno),
                {"IO", openCode});
  }
  std::FILE* f = fdopen(fd, "wb");
  if (!f) {
    const int err = errno;
    close(fd);
    unlink(tmp.c_str());
    throw writeError(posixMessage(err));
  }
  std::string reason;
  try {
    reason = encode(f);
  } catch (...) {  // an encoder's own error (Ctrl-C, say): no temporary is left either
    std::fclose(f);
    unlink(tmp.c_str());
    throw;
  }
  if (reason.empty() && std::ferror(f)) reason = posixMessage(errno ? errno : EIO);
  if (reason.empty()) {
    const int err = syncPolled(f, tmp, path);  // stopped: throws, f left to its thread to close
    if (err != 0) reason = posixMessage(err);
  }
  if (std::fclose(f) != 0 && reason.empty()) reason = posixMessage(errno);
  if (!reason.empty()) {
    unlink(tmp.c_str());
    throw writeError(reason);
  }
  // mkstemp makes the file 0600; the result should be readable like any file the user writes.
  const mode_t mask = umask(0);
  umask(mask);
  chmod(tmp.c_str(), 0666 & ~mask);
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const int err = errno;
    unlink(tmp.c_str());
    throw writeError(posixMessage(err));
  }
  syncFolderOf(path);
}

void writeFileAtomically(const std::string& path, std::string_view bytes, std::string_view kind) {
  writeFileAtomically(
      path,
      [&](std::FILE* f) -> std::string {
        // In slices with a poll between them: hundreds of megabytes take a tenth of a second
        // to copy into the page cache.
        for (size_t at = 0; at < bytes.size(); at += kPollSliceBytes) {
          pollInterrupt("writing \"" + path + "\"");
          const size_t n = std::min(kPollSliceBytes, bytes.size() - at);
          if (std::fwrite(bytes.data() + at, 1, n, f) != n) return posixMessage(errno ? errno : EIO);
        }
        return "";
      },
      kind);
}

std::string readFileBytes(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw Error("couldn't open \"" + path + "\": " + posixMessage(errno), {"IO", "OPEN"});
  std::string bytes;
  const FreeAsideOnThrow aside(bytes);  // stopped: what was read goes back aside
  constexpr size_t kChunk = size_t(1) << 20;
  try {
    // A regular file's size is known: one allocation instead of a doubling string's copies,
    // each of which faulted in fresh pages (pipes and devices grow as they go).
    struct stat st;
    if (::fstat(::fileno(f), &st) == 0 && S_ISREG(st.st_mode) && st.st_size > 0) {
      bytes.reserve(static_cast<size_t>(st.st_size) + kChunk);
    }
    for (;;) {
      pollInterrupt("reading");
      const size_t at = bytes.size();
      bytes.resize(at + kChunk);
      const size_t got = std::fread(bytes.data() + at, 1, kChunk, f);
      bytes.resize(at + got);
      if (got < kChunk) break;
    }
    if (std::ferror(f))
      throw Error("error reading \"" + path + "\": " + posixMessage(errno), {"IO", "READ"});
  } catch (...) {
    std::fclose(f);
    throw;
  }
  std::fclose(f);
  return bytes;
}

}  // namespace demlab
