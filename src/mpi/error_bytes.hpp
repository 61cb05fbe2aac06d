// A demlab::Error as it travels between ranks (an error one rank met, raised on every rank):
// its message and its code words after DEMLAB, each ended by a NUL.
#pragma once

#include <string>
#include <vector>

#include "core/error.hpp"

namespace demlab::mpi {

// Appends e's wire form to out. Changes out.
inline void appendErrorBytes(const Error& e, std::vector<char>& out) {
  const auto add = [&](const std::string& w) {
    out.insert(out.end(), w.c_str(), w.c_str() + w.size() + 1);
  };
  add(e.what());
  for (size_t k = 1; k < e.code().size(); ++k) add(e.code()[k]);
}

// Returns the Error whose wire form is bytes [at, end) of b, its message followed by suffix.
inline Error errorFromBytes(const std::vector<char>& b, size_t at, const std::string& suffix = "") {
  std::vector<std::string> words;
  while (at < b.size()) {
    words.emplace_back(b.data() + at);
    at += words.back().size() + 1;
  }
  const std::string message = words.empty() ? "an error on another rank" : words.front();
  if (!words.empty()) words.erase(words.begin());
  return Error(message + suffix, words);
}

}  // namespace demlab::mpi
