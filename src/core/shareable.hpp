// Shareable and Cloning: components that many objects use at once (10^6 grains may share one
// Material and one Geometry), with value semantics kept by copy-on-write.
//
// Ownership story: a Shareable<T> behaves like a T held by value. Copying it (a shallow clone)
// is cheap and shares the one T; reads go through const access; the only way to write is
// makeUnique(), which first copies the T if anyone else shares it. So changing the material of
// one grain never changes its neighbours', and a deep clone (a scene copied for a convergence
// study) is one whose every component already owns its own copy. std::shared_ptr keeps the
// count; the count is only trusted on the thread that edits the scene (the command layer,
// between steps); force loops on other threads may read through const references meanwhile.
#pragma once

#include <cassert>
#include <concepts>
#include <memory>
#include <utility>

namespace demlab {

// How deep a clone goes: kShallow shares the components, kDeep copies them.
enum class CloneDepth { kShallow, kDeep };

template <class T>
class Shareable {
 public:
  // An empty Shareable: it owns nothing and must be assigned before it is read.
  Shareable() = default;

  // Returns a Shareable owning a new U built from args. U may be T or any copyable class
  // derived from T; deep clones and makeUnique() copy it as a U, so the dynamic type survives
  // without T needing a virtual clone().
  template <class U = T, class... Args>
  static Shareable make(Args&&... args) {
    static_assert(std::derived_from<U, T> && std::copy_constructible<U>,
                  "a Shareable<T> holds a copyable T or a copyable class derived from T");
    Shareable s;
    s.p_ = std::make_shared<U>(std::forward<Args>(args)...);
    s.copy_ = [](const T& t) -> std::shared_ptr<T> {
      return std::make_shared<U>(static_cast<const U&>(t));
    };
    return s;
  }

  // Returns true if this Shareable owns a value.
  explicit operator bool() const noexcept { return p_ != nullptr; }

  // Returns the value, read-only (this must not be empty).
  const T& operator*() const noexcept {
    assert(p_);
    return *p_;
  }
  const T* operator->() const noexcept {
    assert(p_);
    return p_.get();
  }
  const T* get() const noexcept { return p_.get(); }

  // Returns how many Shareables own this value (0 if empty).
  long useCount() const noexcept { return p_.use_count(); }

  // Returns true if another Shareable owns the same value.
  bool isShared() const noexcept { return p_.use_count() > 1; }

  // Returns true if this and other own the very same value (both non-empty).
  bool sharesWith(const Shareable& other) const noexcept { return p_ && p_ == other.p_; }

  // Returns a writable reference to a value this Shareable alone owns. If the value was
  // shared, this first replaces it by a private copy; the other owners keep the old value.
  // Do not keep the reference across a copy of this Shareable: writes through it would then
  // be seen by the copy.
  T& makeUnique() {
    assert(p_);
    if (p_.use_count() > 1) p_ = copy_(*p_);
    return *p_;
  }

  // Returns a clone of this Shareable: with kShallow it shares the value (a plain copy), with
  // kDeep it owns a fresh copy of it. Changes nothing here.
  Shareable clone(CloneDepth depth) const {
    Shareable s = *this;
    if (depth == CloneDepth::kDeep && p_) s.p_ = copy_(*p_);
    return s;
  }

 private:
  using CopyFn = std::shared_ptr<T> (*)(const T&);

  std::shared_ptr<T> p_;
  CopyFn copy_ = nullptr;  // copies the value as its dynamic type
};

}  // namespace demlab
