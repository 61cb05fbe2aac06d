// Fuzz target: the LAMMPS data file reader (pack file ... -format lammps). The input is written
// to a temporary file, as the reader takes a path; it must give data or a demlab::Error.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "core/error.hpp"
#include "io/lammps_data.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string path = "/tmp/demlab-fuzz-lammps-" + std::to_string(getpid()) + ".data";
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return 0;
  std::fwrite(data, 1, size, f);
  std::fclose(f);
  try {
    demlab::io::readLammpsData(path);
  } catch (const demlab::Error&) {
  }
  std::remove(path.c_str());
  return 0;
}
