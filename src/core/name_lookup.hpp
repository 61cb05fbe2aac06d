// NameLookup: the optional, unique, user-given name of an object, both ways (name -> handle and
// handle -> name). TagTable (tag_table.hpp, included here) gives objects any number of shared
// tags. Together with the handles of handle.hpp they are the thesis's Identifiers: every object
// has a handle, may have one name, and may carry tags.
//
// Names are what scripts type, so the rules about them live here: a name starts with a letter
// or "_" (a leading digit would read as a handle, a leading "-" as an option), and every error
// is worded the way Tcl words its own (`element "foo" already exists`, `no element named "foo"`).
// Names are not on any hot path; the maps are ordered so that listings are sorted and the same
// in every run.
#pragma once

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "core/error.hpp"
#include "core/tag_table.hpp"

namespace demlab {

// Throws demlab::Error {VALUE NAME} unless name can name an object of this kind: not empty,
// starting with a letter (any non-ASCII byte counts as one) or "_", and holding no white space,
// control character or any of {}[]"\$; (so it stays one element of any list). Changes nothing.
void checkObjectName(std::string_view kind, std::string_view name);

// Throws demlab::Error {EXISTS NAME}: `<kind> "<name>" already exists`.
[[noreturn]] void throwNameExists(std::string_view kind, std::string_view name);

// Throws demlab::Error {LOOKUP NAME}: `no <kind> named "<name>"`.
[[noreturn]] void throwNoSuchName(std::string_view kind, std::string_view name);

// H: any copyable handle type with std::hash and == (normally Handle<Kind>).
template <class H>
class NameLookup {
 public:
  // kind: the object's name in error messages ("element", "material", ...).
  explicit NameLookup(std::string kind = "object") : kind_(std::move(kind)) {}

  // byHandle_ points at the keys of byName_, so a copy rebuilds it over its own keys (a
  // memberwise copy would point into the source). Moving keeps the nodes, hence the pointers.
  NameLookup(const NameLookup& other) : kind_(other.kind_), byName_(other.byName_) {
    for (const auto& [name, h] : byName_) byHandle_.emplace(h, &name);
  }
  NameLookup& operator=(const NameLookup& other) {
    if (this != &other) *this = NameLookup(other);
    return *this;
  }
  NameLookup(NameLookup&&) noexcept = default;
  NameLookup& operator=(NameLookup&&) noexcept = default;

  // Gives h the name `name`. Throws demlab::Error, changing nothing, if the name is malformed
  // {VALUE NAME}, taken {EXISTS NAME}, or h already has a name {EXISTS NAME} (rename it).
  void add(std::string_view name, H h) {
    checkObjectName(kind_, name);
    if (byName_.contains(name)) throwNameExists(kind_, name);
    if (auto it = byHandle_.find(h); it != byHandle_.end()) {
      throw Error("can't name " + kind_ + " \"" + std::string(name) + "\": it is already named \"" +
                      *it->second + "\"",
                  {"EXISTS", "NAME"});
    }
    auto [pos, inserted] = byName_.emplace(std::string(name), h);
    try {
      byHandle_.emplace(h, &pos->first);
    } catch (...) {
      byName_.erase(pos);
      throw;
    }
  }

  // Renames the object named oldName to newName; renaming to the same name does nothing.
  // Throws demlab::Error, changing nothing, if oldName is unknown {LOOKUP NAME}, newName is
  // malformed {VALUE NAME} or taken {EXISTS NAME}.
  void rename(std::string_view oldName, std::string_view newName) {
    auto it = byName_.find(oldName);
    if (it == byName_.end()) throwNoSuchName(kind_, oldName);
    if (oldName == newName) return;
    checkObjectName(kind_, newName);
    if (byName_.contains(newName)) throwNameExists(kind_, newName);
    std::string key(newName);  // made before the extract, so a bad_alloc loses nothing
    auto node = byName_.extract(it);
    node.key() = std::move(key);
    auto pos = byName_.insert(std::move(node)).position;
    byHandle_[pos->second] = &pos->first;
  }

  // Forgets the name of h. Returns true if h had one.
  bool remove(H h) {
    auto it = byHandle_.find(h);
    if (it == byHandle_.end()) return false;
    byName_.erase(*it->second);
    byHandle_.erase(it);
    return true;
  }

  // Returns the handle named `name`, or nothing.
  std::optional<H> find(std::string_view name) const {
    auto it = byName_.find(name);
    if (it == byName_.end()) return std::nullopt;
    return it->second;
  }

  // Returns the handle named `name`. Throws demlab::Error {LOOKUP NAME} if there is none.
  H get(std::string_view name) const {
    auto it = byName_.find(name);
    if (it == byName_.end()) throwNoSuchName(kind_, name);
    return it->second;
  }

  // Returns the name of h, or nothing. The view stays valid until h is renamed or removed.
  std::optional<std::string_view> nameOf(H h) const {
    auto it = byHandle_.find(h);
    if (it == byHandle_.end()) return std::nullopt;
    return std::string_view(*it->second);
  }

  // Returns every name, sorted (byte order).
  std::vector<std::string_view> names() const {
    std::vector<std::string_view> out;
    out.reserve(byName_.size());
    for (const auto& [name, h] : byName_) out.push_back(name);
    return out;
  }

  // Calls f(name, handle) for every named object, in name order.
  template <class F>
  void forEach(F&& f) const {
    for (const auto& [name, h] : byName_) f(std::string_view(name), h);
  }

  size_t size() const noexcept { return byName_.size(); }
  const std::string& kind() const noexcept { return kind_; }

  // Forgets every name.
  void clear() noexcept {
    byName_.clear();
    byHandle_.clear();
  }

 private:
  std::string kind_;
  std::map<std::string, H, std::less<>> byName_;
  // Points at the keys of byName_: map nodes never move, so the name is stored once.
  std::unordered_map<H, const std::string*> byHandle_;
};

}  // namespace demlab
