// Words as they travel between ranks, each ended by a NUL; and a demlab::Error in that form (an
// error one rank met, raised on every rank): its message, then its code words after DEMLAB.
#pragma once

#include <string>
#include <vector>

#include "core/error.hpp"

namespace demlab::mpi {

// Appends the word w and its NUL to out. Changes out.
inline void appendWord(const std::string& w, std::vector<char>& out) {
  out.insert(out.end(), w.c_str(), w.c_str() + w.size() + 1);
}

// Returns the words of bytes [at, end) of b, as appendWord wrote them.
inline std::vector<std::string> wordsFromBytes(const std::vector<char>& b, size_t at = 0) {
  std::vector<std::string> words;
  while (at < b.size()) {
    words.emplace_back(b.data() + at);
    at += words.back().size() + 1;
  }
  return words;
}

// Appends e's wire form to out. Changes out.
inline void appendErrorBytes(const Error& e, std::vector<char>& out) {
  appendWord(e.what(), out);
  for (size_t k = 1; k < e.code().size(); ++k) appendWord(e.code()[k], out);
}

// Returns the Error whose wire form is bytes [at, end) of b, its message followed by suffix.
inline Error errorFromBytes(const std::vector<char>& b, size_t at, const std::string& suffix = "") {
  std::vector<std::string> words = wordsFromBytes(b, at);
  const std::string message = words.empty() ? "an error on another rank" : words.front();
  if (!words.empty()) words.erase(words.begin());
  return Error(message + suffix, words);
}

}  // namespace demlab::mpi
