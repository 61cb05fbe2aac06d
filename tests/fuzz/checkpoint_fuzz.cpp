// Fuzz target: the checkpoint reader. The input is a scene's bytes (the checksum is added
// here, so mutations reach the section readers instead of failing the checksum); whatever
// loads must also digest, clone and run a step without a crash, hang or sanitizer report.
// Errors of type demlab::Error are the expected outcome of a bad input.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "core/error.hpp"
#include "sim/scene_io.hpp"
#include "sim/simulation.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string scene(reinterpret_cast<const char*>(data), size);
  for (int dim : {2, 3}) {
    auto sim = demlab::sim::makeSimulation(dim);
    std::istringstream in(demlab::sim::sealCheckpoint(scene));
    try {
      sim->load(in);
    } catch (const demlab::Error&) {
      continue;
    }
    try {
      sim->stateDigest();
      sim->clone();
      if (sim->elementCount() <= 4096) sim->runSteps(1);
    } catch (const demlab::Error&) {
    }
  }
  return 0;
}
