// LineReader: reads a text file line by line, gzip'd or plain (zlib decides from the first
// bytes, so a plain file needs no special case), counting lines for error messages.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace demlab::io {

class LineReader {
 public:
  // Opens path for reading. Throws Error {IO OPEN} (`couldn't open "path": no such file or
  // directory`) when it cannot be opened; nothing is left open then.
  explicit LineReader(std::string path);
  ~LineReader();
  LineReader(const LineReader&) = delete;
  LineReader& operator=(const LineReader&) = delete;

  // Reads the next line into `line` (without its "\n" or "\r\n"; valid until the next call)
  // and returns true, or returns false at the end of the file. Every 4096 lines it polls for
  // Ctrl-C (Error {INTERRUPTED}, core/interrupt.hpp). Throws Error {IO READ} when the
  // file cannot be read or a gzip stream is corrupt or cut short.
  bool next(std::string_view& line);

  // Returns the number of the line last returned by next(), counting from 1 (0 before any).
  std::size_t lineNumber() const { return lineNumber_; }

  // Returns `file "path" line n`, n the line last read: the place an error names, in
  // parentheses after its message (Error::within).
  std::string where() const {
    return "file \"" + path_ + "\" line " + std::to_string(lineNumber_);
  }
  // Returns the path as given to the constructor.
  const std::string& path() const { return path_; }

 private:
  // Reads the next chunk of decompressed bytes into buffer_ from begin_ on; returns false at
  // the end of the file. Throws as next() does.
  bool fill();

  std::string path_;
  void* file_ = nullptr;  // gzFile; void* keeps zlib.h out of this header
  std::vector<char> buffer_;
  std::size_t begin_ = 0;  // first unread byte of buffer_
  std::size_t end_ = 0;    // one past the last valid byte of buffer_
  bool eof_ = false;
  std::size_t lineNumber_ = 0;
};

}  // namespace demlab::io
