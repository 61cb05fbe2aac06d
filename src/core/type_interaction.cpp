// TypeRegistry: the non-template half of type_interaction.hpp.
#include "core/type_interaction.hpp"

namespace demlab {

TypeRegistry::TypeRegistry(std::string kind) : kind_(std::move(kind)) {}

TypeId TypeRegistry::add(std::string_view name) {
  checkObjectName(kind_, name);
  if (byName_.contains(std::string(name))) throwNameExists(kind_, name);
  if (names_.size() >= kMaxTypes) {
    throw Error("too many " + kind_ + "s: at most " + std::to_string(kMaxTypes), {"LIMIT", "TYPE"});
  }
  const TypeId id{static_cast<uint16_t>(names_.size())};
  names_.emplace_back(name);
  byName_.emplace(std::string(name), id);
  return id;
}

std::optional<TypeId> TypeRegistry::find(std::string_view name) const {
  auto it = byName_.find(std::string(name));
  if (it == byName_.end()) return std::nullopt;
  return it->second;
}

TypeId TypeRegistry::get(std::string_view name) const {
  auto it = byName_.find(std::string(name));
  if (it == byName_.end()) throwNoSuchName(kind_, name);
  return it->second;
}

const std::string& TypeRegistry::name(TypeId id) const {
  if (!contains(id)) {
    throw Error("unknown " + kind_ + " id " + std::to_string(id.value), {"LOOKUP", "TYPE"});
  }
  return names_[id.value];
}

void TypeRegistry::throwUnknownClass(const char* mangled) const {
  throw Error("C++ class \"" + std::string(mangled) + "\" is not a registered " + kind_,
              {"LOOKUP", "TYPE"});
}

}  // namespace demlab
