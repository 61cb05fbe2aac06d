// The dimensions and coordinate types every search algorithm is compiled for, as one list.
// Each algorithm's header declares these instantiations extern and one source file in
// src/search defines them, so the tests and programs that include the registry link to one
// compiled copy instead of compiling every algorithm again (it was most of the build's time).
#pragma once

// Calls X(C, D, T) once per supported configuration; C is passed through (a class template's
// name, or anything else X wants).
#define DEMLAB_SEARCH_CONFIGS(X, C) \
  X(C, 1, double)                   \
  X(C, 2, double)                   \
  X(C, 3, double)                   \
  X(C, 4, double)                   \
  X(C, 1, float)                    \
  X(C, 2, float)                    \
  X(C, 3, float)                    \
  X(C, 4, float)

// One configuration of class template C: declared in its header, defined in its source file.
#define DEMLAB_SEARCH_EXTERN_CLASS(C, D, T) extern template class C<D, T>;
#define DEMLAB_SEARCH_INSTANTIATE_CLASS(C, D, T) template class C<D, T>;
