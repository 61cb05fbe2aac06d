// A Tcl value that holds a list of integers as its C++ array until a script reads it.
//
// Made as one Tcl list, the ids of a command that added half a million elements or a million
// bonds are a Tcl object each: a fifth of a second for a million and a half on a machine with
// slow page faults, and a command that has changed the scene can no longer be stopped by
// Ctrl-C, so those would be deaf. This value is made in the time of one copy of the array; Tcl
// asks for its text when a script first reads it (as a list, a string or a number), and makes
// the list from that, as it does for any value read from a file.
#pragma once

#include <tcl.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace demlab::tcl {

// The most integers such a value holds: its text must stay within Tcl's 2^31 bytes.
inline constexpr std::size_t kMaxIntListObj = (std::size_t(INT32_MAX) - 1) / 21;

// Returns a new Tcl object (reference count 0) whose value is the list of `values` in order,
// its text and list made only when something reads it. Takes the values over (a copy of a
// million ids faulted its pages in for tens of milliseconds); at most kMaxIntListObj of them.
Tcl_Obj* newIntListObj(std::vector<std::int64_t>&& values);

}  // namespace demlab::tcl
