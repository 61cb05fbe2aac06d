// The dimensions and coordinate types every search algorithm is compiled for, as one list.
// Each algorithm's header declares these instantiations extern and one source file in
// src/search defines them, so the tests and programs that include the registry link to one
// compiled copy instead of compiling every algorithm again (it was most of the build's time).
#pragma once

// Calls X(D, T) once per supported configuration.
#define DEMLAB_SEARCH_CONFIGS(X) \
  X(1, double)                   \
  X(2, double)                   \
  X(3, double)                   \
  X(4, double)                   \
  X(1, float)                    \
  X(2, float)                    \
  X(3, float)                    \
  X(4, float)
