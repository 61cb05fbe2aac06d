#include "tcl/int_list_obj.hpp"

#include <charconv>
#include <utility>

namespace demlab::tcl {

namespace {

// The integers, shared by an object and its duplicates (Tcl duplicates a value before a
// script changes it; neither changes the integers, so they need no copy).
struct SharedInts {
  std::vector<std::int64_t> values;
  std::size_t refs = 1;
};

SharedInts* sharedOf(Tcl_Obj* o) { return static_cast<SharedInts*>(o->internalRep.twoPtrValue.ptr1); }

void freeIntRep(Tcl_Obj* o) {
  SharedInts* s = sharedOf(o);
  if (--s->refs == 0) delete s;
  o->typePtr = nullptr;
}

void dupIntRep(Tcl_Obj* from, Tcl_Obj* to);

// Writes the integers as a Tcl list's text, separated by single spaces (none needs quoting),
// into o->bytes (Tcl's allocator, as Tcl frees it). Throws nothing: Tcl panics if it cannot
// allocate, as it does for every string it makes.
void updateString(Tcl_Obj* o) {
  const std::vector<std::int64_t>& v = sharedOf(o)->values;
  // At most 20 characters and a space a number.
  const std::size_t most = v.size() * 21 + 1;
  char* text = Tcl_Alloc(static_cast<unsigned>(most));
  char* at = text;
  for (std::size_t k = 0; k < v.size(); ++k) {
    if (k) *at++ = ' ';
    at = std::to_chars(at, text + most, v[k]).ptr;
  }
  *at = '\0';
  o->bytes = text;
  o->length = static_cast<int>(at - text);
}

const Tcl_ObjType kIntListType = {"demlabIntList", freeIntRep, dupIntRep, updateString, nullptr};

void dupIntRep(Tcl_Obj* from, Tcl_Obj* to) {
  SharedInts* s = sharedOf(from);
  ++s->refs;
  to->internalRep.twoPtrValue.ptr1 = s;
  to->internalRep.twoPtrValue.ptr2 = nullptr;
  to->typePtr = &kIntListType;
}

}  // namespace

Tcl_Obj* newIntListObj(std::vector<std::int64_t>&& values) {
  auto* s = new SharedInts{std::move(values), 1};
  Tcl_Obj* o = Tcl_NewObj();
  Tcl_InvalidateStringRep(o);
  o->internalRep.twoPtrValue.ptr1 = s;
  o->internalRep.twoPtrValue.ptr2 = nullptr;
  o->typePtr = &kIntListType;
  return o;
}

}  // namespace demlab::tcl
