// Writing a file so that a reader sees the old contents or the new, never a half-written file,
// and a crash or power loss after the call returns keeps the new contents: the bytes go to a
// temporary with a unique name beside the target (a user's own "PATH.tmp" is never touched),
// are synced to disk, and the temporary is renamed over the target.
#pragma once

#include <cstdio>
#include <functional>
#include <string>
#include <string_view>

namespace demlab {

// Returns strerror(err) with its first letter lowered, as Tcl words POSIX errors ("no such
// file or directory").
std::string posixMessage(int err);

// Writes into an open file; returns "" on success, else the encoder's reason for failing.
using FileEncoder = std::function<std::string(std::FILE*)>;

// Returns nothing. Writes path through encode, atomically and durably. Throws demlab::Error
// {IO OPEN} ("couldn't open "path" for writing: reason") when the temporary cannot be made and
// {IO WRITE} ("error writing "path": reason") when encoding, syncing or the rename fails; with
// kind given (e.g. "PNG"), both codes are {IO kind}. On failure no temporary is left and the
// target keeps its old contents; an exception from encode passes through the same way.
// Changes only path.
void writeFileAtomically(const std::string& path, const FileEncoder& encode,
                         std::string_view kind = {});

// The same for bytes already in memory.
void writeFileAtomically(const std::string& path, std::string_view bytes,
                         std::string_view kind = {});

// Returns the whole contents of path, read in chunks with a poll for Ctrl-C between them
// (core/interrupt.hpp). Throws demlab::Error {IO OPEN} ("couldn't open "path": reason"),
// {IO READ} ("error reading "path": reason") or {INTERRUPTED}. Changes nothing.
std::string readFileBytes(const std::string& path);

}  // namespace demlab
