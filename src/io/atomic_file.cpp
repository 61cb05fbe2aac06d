#include "io/atomic_file.hpp"

#include <cstdio>
#include <fstream>

#include "core/error.hpp"

namespace demlab::io {

void writeFileAtomically(const std::string& path, const std::string& bytes) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    if (!f) throw Error("couldn't open \"" + path + "\" for writing", {"IO", "OPEN"});
    f << bytes;
    if (!f.flush()) {
      std::remove(tmp.c_str());
      throw Error("error writing \"" + path + "\"", {"IO", "WRITE"});
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw Error("couldn't rename \"" + tmp + "\" to \"" + path + "\"", {"IO", "WRITE"});
  }
}

}  // namespace demlab::io
