// Writing a file so that a reader sees the old contents or the new, never a half-written file:
// the bytes go to a temporary beside the target, which is then renamed over it.
#pragma once

#include <string>

namespace demlab::io {

// Returns nothing. Writes bytes to path through path + ".tmp" and a rename. Throws
// demlab::Error {IO OPEN} when the temporary cannot be created, {IO WRITE} when writing or the
// rename fails; then neither the temporary nor a changed target is left behind.
void writeFileAtomically(const std::string& path, const std::string& bytes);

}  // namespace demlab::io
