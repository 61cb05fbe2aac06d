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

}  // namespace

void checkObjectName(std::string_view kind, std::string_view name) {
  if (!name.empty() && startsName(name.front())) return;
  throw Error("bad " + std::string(kind) + " name \"" + std::string(name) +
                  "\": must start with a letter or \"_\"",
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
  if (!tag.empty() && startsName(tag.front())) return;
  throw Error("bad tag \"" + std::string(tag) + "\": must start with a letter or \"_\"",
              {"VALUE", "TAG"});
}

}  // namespace demlab
