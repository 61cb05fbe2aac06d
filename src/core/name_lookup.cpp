// The rules for names and tags, and the wording of their errors, kept in one place so that
// every kind of object reports them the same way.
#include "core/name_lookup.hpp"

namespace demlab {
namespace {

// Returns true if c may start a name: an ASCII letter, "_", or any byte of a multi-byte UTF-8
// character (so "α" is a name).
bool startsName(char c) {
  const auto u = static_cast<unsigned char>(c);
  return u >= 0x80 || u == '_' || (u >= 'a' && u <= 'z') || (u >= 'A' && u <= 'Z');
}

// Returns true if c may stand in a name: anything but white space, control characters and the
// characters that Tcl lists and scripts quote ({}[]"\$;), so that a name is one list element
// whatever list or script it is put in.
bool insideName(char c) {
  const auto u = static_cast<unsigned char>(c);
  if (u >= 0x80) return true;
  if (u <= ' ' || u == 0x7f) return false;
  for (char q : std::string_view("{}[]\"\\$;"))
    if (c == q) return false;
  return true;
}

// Returns why name is not a usable name ("" when it is).
std::string nameFault(std::string_view name) {
  if (name.empty() || !startsName(name.front())) return "must start with a letter or \"_\"";
  for (char c : name)
    if (!insideName(c))
      return "must hold no white space, control character or any of {}[]\"\\$;";
  return "";
}

}  // namespace

void checkObjectName(std::string_view kind, std::string_view name) {
  const std::string fault = nameFault(name);
  if (fault.empty()) return;
  throw Error("bad " + std::string(kind) + " name \"" + std::string(name) + "\": " + fault,
              {"VALUE", "NAME"});
}

void throwNameExists(std::string_view kind, std::string_view name) {
  throw Error(std::string(kind) + " \"" + std::string(name) + "\" already exists",
              {"EXISTS", "NAME"});
}

void throwNoSuchName(std::string_view kind, std::string_view name) {
  throw Error("no " + std::string(kind) + " named \"" + std::string(name) + "\"",
              {"LOOKUP", "NAME"});
}

void checkTagName(std::string_view tag) {
  const std::string fault = nameFault(tag);
  if (fault.empty()) return;
  throw Error("bad tag \"" + std::string(tag) + "\": " + fault, {"VALUE", "TAG"});
}

}  // namespace demlab
