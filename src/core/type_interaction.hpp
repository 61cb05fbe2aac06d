// TypeId and TypeInteractionManager: how the narrow phase and the contact laws pick the
// routine for a pair of objects by their types, in O(1), without a virtual call per contact.
//
// A TypeRegistry hands out small dense TypeIds by name ("sphere", "plane", ...), optionally
// tied to a C++ class. A TypeInteractionManager<Fn> is a dense n x n table of Fn. An asymmetric
// pair is written once, say (sphere, plane); the mirror cell (plane, sphere) is filled with the
// same Fn and a "swapped" mark, and dispatch() then passes the two objects in the registered
// order. So a routine is written for one orientation only, and results that have a direction
// (a contact normal from the first object to the second) must be flipped by the caller when
// the entry is swapped: lookup once per type pair or batch, then loop.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <typeindex>
#include <unordered_map>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "core/name_lookup.hpp"

namespace demlab {

struct TypeId {
  uint16_t value = 0;
  friend constexpr bool operator==(TypeId, TypeId) = default;
  friend constexpr auto operator<=>(TypeId, TypeId) = default;
};

class TypeRegistry {
 public:
  // A table of n x n cells per manager stays small (at most 64K cells) with this many types.
  static constexpr size_t kMaxTypes = 256;

  // kind: the word for a type in messages ("type", "geometry type", ...).
  explicit TypeRegistry(std::string kind = "type");

  // Registers a type. Returns its id, the next unused one (0, 1, 2, ...).
  // Throws demlab::Error, changing nothing: {VALUE NAME} for a malformed name, {EXISTS NAME} if
  // taken, {LIMIT TYPE} beyond kMaxTypes.
  TypeId add(std::string_view name);

  // Registers a type tied to the C++ class C (see id<C>()). Throws as add(name), and
  // {EXISTS TYPE} if C is registered already.
  template <class C>
  TypeId add(std::string_view name) {
    const std::type_index ti(typeid(C));
    if (byClass_.contains(ti)) {
      throw Error("C++ class of " + kind_ + " \"" + std::string(name) + "\" is already registered",
                  {"EXISTS", "TYPE"});
    }
    const TypeId id = add(name);
    byClass_.emplace(ti, id);
    return id;
  }

  // Returns the id of the type registered for the C++ class C.
  // Throws demlab::Error {LOOKUP TYPE} if C was not registered.
  template <class C>
  TypeId id() const {
    auto it = byClass_.find(std::type_index(typeid(C)));
    if (it == byClass_.end()) throwUnknownClass(typeid(C).name());
    return it->second;
  }

  // Returns the id of the type named `name`, or nothing.
  std::optional<TypeId> find(std::string_view name) const;

  // Returns the id of the type named `name`. Throws demlab::Error {LOOKUP NAME} if none.
  TypeId get(std::string_view name) const;

  // Returns the name of a registered type. Throws demlab::Error {LOOKUP TYPE} if id is unknown.
  const std::string& name(TypeId id) const;

  // Returns true if id names a registered type.
  bool contains(TypeId id) const noexcept { return id.value < names_.size(); }

  // Returns the number of registered types; their ids are 0 .. size()-1.
  size_t size() const noexcept { return names_.size(); }

  const std::string& kind() const noexcept { return kind_; }

 private:
  [[noreturn]] void throwUnknownClass(const char* mangled) const;

  std::string kind_;
  std::vector<std::string> names_;  // indexed by id
  std::unordered_map<std::string, TypeId> byName_;
  std::unordered_map<std::type_index, TypeId> byClass_;
};

// Fn: anything callable or not (a function pointer, a std::function, a struct of routines);
// it must be default-constructible and copyable.
template <class Fn>
class TypeInteractionManager {
 public:
  struct Entry {
    Fn fn{};
    uint8_t state = kEmpty;
    // Returns true if this cell is the mirror of a registered pair: call fn(b, a).
    bool swapped() const noexcept { return state == kSwapped; }
  };

  // types must outlive this manager; it may grow meanwhile. what: the word for an entry in
  // messages ("intersection routine", "contact law", ...).
  explicit TypeInteractionManager(const TypeRegistry& types, std::string what = "interaction")
      : types_(&types), what_(std::move(what)) {}

  // Registers fn for the ordered pair (a, b), and as the swapped entry of (b, a).
  // Throws demlab::Error, changing nothing: {LOOKUP TYPE} if a or b is not registered,
  // {EXISTS INTERACTION} if (a, b) or (b, a) was registered already.
  void add(TypeId a, TypeId b, Fn fn) {
    const std::string& na = types_->name(a);
    const std::string& nb = types_->name(b);
    if (find(a, b) != nullptr) {
      throw Error(
          what_ + " for " + types_->kind() + "s \"" + na + "\" and \"" + nb + "\" already exists",
          {"EXISTS", "INTERACTION"});
    }
    if (types_->size() > stride_) grow(types_->size());
    cells_[cell(b, a)] = Entry{fn, kSwapped};  // overwritten below when a == b
    cells_[cell(a, b)] = Entry{std::move(fn), kDirect};
    written_.emplace_back(a, b);
  }

  // Returns the entry for (a, b), or null if no routine serves that pair. O(1), never throws.
  const Entry* find(TypeId a, TypeId b) const noexcept {
    if (a.value >= stride_ || b.value >= stride_) return nullptr;
    const Entry& e = cells_[cell(a, b)];
    return e.state == kEmpty ? nullptr : &e;
  }

  // Returns the entry for (a, b). Throws demlab::Error {LOOKUP INTERACTION}, naming both types,
  // if no routine serves the pair ({LOOKUP TYPE} if a type is not registered at all).
  const Entry& get(TypeId a, TypeId b) const {
    if (const Entry* e = find(a, b)) return *e;
    throw Error("no " + what_ + " for " + types_->kind() + "s \"" + types_->name(a) + "\" and \"" +
                    types_->name(b) + "\"",
                {"LOOKUP", "INTERACTION"});
  }

  // Returns true if a routine serves (a, b), in either registered orientation.
  bool has(TypeId a, TypeId b) const noexcept { return find(a, b) != nullptr; }

  // Returns fn(x, y, rest...) for the entry of (ta, tb), or fn(y, x, rest...) if the entry is
  // swapped, so fn always sees its objects in the order it was registered for. Throws as get().
  template <class X, class Y, class... Rest>
  decltype(auto) dispatch(TypeId ta, TypeId tb, X&& x, Y&& y, Rest&&... rest) const {
    const Entry& e = get(ta, tb);
    if (e.swapped()) {
      return std::invoke(e.fn, std::forward<Y>(y), std::forward<X>(x), std::forward<Rest>(rest)...);
    }
    return std::invoke(e.fn, std::forward<X>(x), std::forward<Y>(y), std::forward<Rest>(rest)...);
  }

  // Returns the pairs as they were registered (the written orientation), in registration order.
  const std::vector<std::pair<TypeId, TypeId>>& pairs() const noexcept { return written_; }

 private:
  static constexpr uint8_t kEmpty = 0, kDirect = 1, kSwapped = 2;

  size_t cell(TypeId a, TypeId b) const noexcept { return size_t{a.value} * stride_ + b.value; }

  // Re-lays the table out for n types (n > stride_), keeping every entry.
  void grow(size_t n) {
    std::vector<Entry> cells(n * n);
    for (size_t a = 0; a < stride_; ++a) {
      for (size_t b = 0; b < stride_; ++b) cells[a * n + b] = std::move(cells_[a * stride_ + b]);
    }
    cells_ = std::move(cells);
    stride_ = n;
  }

  const TypeRegistry* types_;
  std::string what_;
  size_t stride_ = 0;  // number of types the table is laid out for
  std::vector<Entry> cells_;
  std::vector<std::pair<TypeId, TypeId>> written_;
};

}  // namespace demlab
