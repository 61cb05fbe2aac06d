// Atomic file replacement shared by the image writers: the bytes go to a temporary file in the
// target's folder, which is renamed over the target, so a reader (a movie maker polling the
// folder) never sees half a frame and a failed write leaves any old file untouched.
#pragma once

#include <cstdio>
#include <functional>
#include <string>

namespace demlab::render {

// Writes into an open file; returns "" on success, else the encoder's reason for failing.
using FileEncoder = std::function<std::string(std::FILE*)>;

// Returns nothing; writes path through encode, atomically. Throws demlab::Error {IO <kind>}
// ("couldn't open/write/rename onto "path": reason") and leaves no temporary file behind.
// Changes only path.
void writeFileAtomically(const std::string& path, const std::string& kind,
                         const FileEncoder& encode);

}  // namespace demlab::render
