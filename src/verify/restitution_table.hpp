// The restitution table of doc/verification.md: the rebound of head-on impacts through the
// Simulation API against the restitution asked for, for both laws and both Hertz dampings.
#pragma once

#include <string>

namespace demlab::verify {

// Returns the markdown section "## Restitution" (heading, how it is measured, the table for
// e = 0.05 ... 0.95), the same bytes on every run: writeReport puts it in the report, and a
// test checks that doc/verification.md holds it. Changes nothing.
std::string restitutionSection();

}  // namespace demlab::verify
