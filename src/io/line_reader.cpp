#include "io/line_reader.hpp"

#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/interrupt.hpp"

namespace demlab::io {
namespace {

constexpr std::size_t kChunk = 1 << 18;

}  // namespace

LineReader::LineReader(std::string path) : path_(std::move(path)), buffer_(kChunk) {
  errno = 0;
  gzFile f = gzopen(path_.c_str(), "rb");
  if (f == nullptr) {
    throw Error("couldn't open \"" + path_ + "\": " + posixMessage(errno), {"IO", "OPEN"});
  }
  gzbuffer(f, kChunk);
  file_ = f;
}

LineReader::~LineReader() {
  if (file_ != nullptr) gzclose(static_cast<gzFile>(file_));
}

bool LineReader::fill() {
  // Keep the unfinished line at the front; grow the buffer only when one line fills it.
  if (begin_ > 0) {
    std::copy(buffer_.begin() + begin_, buffer_.begin() + end_, buffer_.begin());
    end_ -= begin_;
    begin_ = 0;
  }
  if (end_ == buffer_.size()) buffer_.resize(buffer_.size() * 2);
  auto f = static_cast<gzFile>(file_);
  errno = 0;
  const int got = gzread(f, buffer_.data() + end_, static_cast<unsigned>(buffer_.size() - end_));
  int zerr = Z_OK;
  const char* zmsg = gzerror(f, &zerr);
  if (got < 0) {
    const std::string why = zerr == Z_ERRNO ? posixMessage(errno) : std::string(zmsg);
    throw Error("error reading \"" + path_ + "\": " + why, {"IO", "READ"});
  }
  if (got == 0) {
    // zlib reports a gzip stream cut short only here, as Z_BUF_ERROR at the end of the input.
    if (zerr == Z_BUF_ERROR) {
      throw Error("error reading \"" + path_ + "\": unexpected end of gzip stream (file truncated)",
                  {"IO", "READ"});
    }
    eof_ = true;
    return false;
  }
  end_ += static_cast<std::size_t>(got);
  return true;
}

bool LineReader::next(std::string_view& line) {
  if ((lineNumber_ & 4095u) == 4095u) pollInterrupt("reading");
  std::size_t searched = begin_;
  for (;;) {
    const char* base = buffer_.data();
    const void* nl = std::memchr(base + searched, '\n', end_ - searched);
    if (nl != nullptr) {
      const std::size_t pos = static_cast<const char*>(nl) - base;
      std::size_t stop = pos;
      if (stop > begin_ && base[stop - 1] == '\r') --stop;
      line = std::string_view(base + begin_, stop - begin_);
      begin_ = pos + 1;
      ++lineNumber_;
      return true;
    }
    if (eof_) break;
    const std::size_t pending = end_ - begin_;
    if (!fill()) break;
    searched = pending;  // fill() moved the pending bytes to the front
  }
  if (begin_ == end_) return false;
  // The last line has no newline.
  std::size_t stop = end_;
  if (buffer_[stop - 1] == '\r') --stop;
  line = std::string_view(buffer_.data() + begin_, stop - begin_);
  begin_ = end_;
  ++lineNumber_;
  return true;
}

}  // namespace demlab::io
