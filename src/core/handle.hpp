// Identifiers: generational handles and the pool that issues them.
//
// A Handle names one object for its whole life: a slot index plus the slot's generation at the
// time the object was made. When the object is removed its slot's generation moves on, so an
// old handle kept by a script, a bond or a behaviour is recognised as stale instead of silently
// naming whatever object reuses the slot.
//
// The pool does not hold the objects. Their hot state lives in dense arrays owned elsewhere
// (positions, velocities, ...), one entry per live object with no holes; the pool maps a handle
// to its dense index and, when an object is removed, tells the owner of each dense array which
// entry to move into the hole (swap-remove), so the arrays stay packed for the force loop.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "core/interrupt.hpp"

namespace demlab {

// Kind is an empty tag type that keeps handles of different kinds of objects apart at compile
// time: Handle<ElementKind> does not convert to Handle<WallKind>.
template <class Kind = void>
struct Handle {
  uint32_t index = 0;
  uint32_t generation = 0;  // live objects have odd generations; 0 is the null handle

  // Returns true for the default-constructed handle, which never names an object.
  constexpr bool isNull() const noexcept { return generation == 0; }

  // Returns the handle packed into 64 bits (generation high, index low), e.g. for a Tcl wide int.
  constexpr uint64_t bits() const noexcept { return uint64_t{generation} << 32 | index; }

  // Returns the id scripts and files see: a handle's first life gets the id of its slot (0, 1,
  // 2, ...); each reuse of a slot adds 2^32, so a stale id never names the object that took
  // its slot.
  constexpr int64_t scriptId() const noexcept {
    return int64_t(uint64_t((generation - 1) / 2) << 32 | index);
  }

  // Returns the handle whose bits() is b.
  static constexpr Handle fromBits(uint64_t b) noexcept {
    return Handle{static_cast<uint32_t>(b), static_cast<uint32_t>(b >> 32)};
  }

  friend constexpr bool operator==(Handle, Handle) = default;
  friend constexpr auto operator<=>(Handle, Handle) = default;
};

// Returns the text form of h used in error messages: the id scripts see (scriptId) for a
// handle of a live or removed object (odd generation, every handle a script can name), else
// "index:generation" (the null handle, a free slot's).
template <class Kind>
std::string toString(Handle<Kind> h) {
  if (h.generation & 1u) return std::to_string(h.scriptId());
  return std::to_string(h.index) + ":" + std::to_string(h.generation);
}

// How the dense arrays follow a removal: the entry at `from` (the last one) moves to `to`, then
// every array shrinks by one. from == to when the removed entry was the last.
struct SwapRemove {
  uint32_t from;
  uint32_t to;
};

// Applies m to one dense array: moves its last entry into the hole and pops the back.
template <class Array>
void applySwapRemove(Array& a, SwapRemove m) {
  if (m.from != m.to) a[m.to] = std::move(a[m.from]);
  a.pop_back();
}

// HandlePool: a slot map without the payload. Slots are recycled last-freed-first (the slot's
// memory, and the dense entries near it, are the most likely to be warm). Each slot's
// generation is odd while it is live and even while it is free; a slot whose generation would
// wrap to 0 after 2^31 reuses is retired rather than recycled, so no handle is ever repeated.
template <class Kind = void>
class HandlePool {
 public:
  using HandleT = Handle<Kind>;

  // The whole state, for checkpoints: restoring it makes later allocations return exactly the
  // handles the saved pool would have returned.
  struct State {
    std::vector<uint32_t> generations;  // per slot
    std::vector<uint32_t> freeSlots;    // bottom to top of the recycling stack
    std::vector<HandleT> dense;         // live handles in dense order
  };

  // kind: the object's name in error messages ("element", "wall", ...).
  explicit HandlePool(std::string kind = "object") : kind_(std::move(kind)) {}

  // Returns a new live handle; its dense index is the old size(), i.e. the caller appends its
  // dense entries. Changes the slot table and may reuse the most recently freed slot.
  HandleT allocate() {
    uint32_t index;
    if (!freeSlots_.empty()) {
      index = freeSlots_.back();
      freeSlots_.pop_back();
    } else {
      if (slots_.size() >= kMaxSlots) {
        throw Error("too many " + kind_ + "s: at most " + std::to_string(kMaxSlots),
                    {"LIMIT", "HANDLE"});
      }
      index = static_cast<uint32_t>(slots_.size());
      slots_.push_back({0, 0});
    }
    Slot& s = slots_[index];
    s.generation += 1;  // even (free) -> odd (live)
    s.dense = static_cast<uint32_t>(dense_.size());
    const HandleT h{index, s.generation};
    dense_.push_back(h);
    return h;
  }

  // Removes the object h names. Returns the swap-remove every dense array must apply.
  // Throws demlab::Error {LOOKUP HANDLE} if h is null, stale or never issued; changes nothing
  // then.
  SwapRemove free(HandleT h) {
    const uint32_t to = denseIndex(h);
    const uint32_t from = static_cast<uint32_t>(dense_.size() - 1);
    if (from != to) {
      dense_[to] = dense_[from];
      slots_[dense_[to].index].dense = to;
    }
    dense_.pop_back();
    Slot& s = slots_[h.index];
    s.generation += 1;  // odd (live) -> even (free); wraps to 0 after the last odd value
    if (s.generation != 0) freeSlots_.push_back(h.index);
    return {from, to};
  }

  // Returns true if h names a live object of this pool.
  bool valid(HandleT h) const noexcept {
    return (h.generation & 1u) && h.index < slots_.size() &&
           slots_[h.index].generation == h.generation;
  }

  // Returns the dense index of the live object h names.
  // Throws demlab::Error {LOOKUP HANDLE} with the reason if h is not live.
  uint32_t denseIndex(HandleT h) const {
    if (!valid(h)) throwInvalid(h);
    return slots_[h.index].dense;
  }

  // Returns the dense index of h, or npos if h is not live. Never throws.
  uint32_t findDense(HandleT h) const noexcept { return valid(h) ? slots_[h.index].dense : kNpos; }

  // Returns the handle of the object at dense index i (i < size()).
  HandleT handleAt(uint32_t i) const noexcept { return dense_[i]; }

  // Returns the dense index of the live object in slot index, or npos if the slot is free,
  // retired or was never made (keys by slot alone: the parked pair histories). Never throws.
  uint32_t findDenseAt(uint32_t index) const noexcept {
    return index < slots_.size() && (slots_[index].generation & 1u) ? slots_[index].dense : kNpos;
  }

  // Returns the live handles in dense order: iterating it visits every live object once.
  std::span<const HandleT> handles() const noexcept { return dense_; }
  auto begin() const noexcept { return dense_.begin(); }
  auto end() const noexcept { return dense_.end(); }

  // Returns the number of live objects.
  uint32_t size() const noexcept { return static_cast<uint32_t>(dense_.size()); }
  bool empty() const noexcept { return dense_.empty(); }

  // Returns the number of slots ever made (live, free or retired): an upper bound for index.
  uint32_t slotCount() const noexcept { return static_cast<uint32_t>(slots_.size()); }

  // Reserves room for n live objects; changes capacity only.
  void reserve(uint32_t n) {
    slots_.reserve(n);
    dense_.reserve(n);
  }

  // Makes the reserved room for n handles resident, the pool unchanged (touchRoom,
  // core/interrupt.hpp). Throws {INTERRUPTED}, the pool as it was.
  void touchRoom(uint32_t n, std::string_view what) {
    demlab::touchRoom(slots_, n, Slot{0, 0}, what);
    demlab::touchRoom(dense_, n, HandleT{}, what);
  }

  // Returns the bytes of heap the pool's tables hold (their capacity).
  std::size_t heapBytes() const noexcept {
    return slots_.capacity() * sizeof(Slot) + freeSlots_.capacity() * sizeof(uint32_t) +
           dense_.capacity() * sizeof(HandleT);
  }

  // Removes every object. Generations are kept and bumped, so handles issued before stay stale.
  void clear() {
    while (!dense_.empty()) free(dense_.back());
  }

  // Returns a copy of the whole state.
  State saveState() const {
    State st;
    st.generations.reserve(slots_.size());
    for (const Slot& s : slots_) st.generations.push_back(s.generation);
    st.freeSlots = freeSlots_;
    st.dense = dense_;
    return st;
  }

  // Replaces the whole state with st. Throws demlab::Error {VALUE HANDLE} if st is not a state
  // some pool could be in (a live slot missing from dense, a free slot listed twice, ...);
  // changes nothing then.
  void restoreState(const State& st) {
    std::vector<Slot> slots(st.generations.size(), Slot{0, kNpos});
    for (size_t i = 0; i < slots.size(); ++i) slots[i].generation = st.generations[i];
    auto bad = [&](const std::string& why) {
      throw Error("bad " + kind_ + " handle state: " + why, {"VALUE", "HANDLE"});
    };
    for (size_t d = 0; d < st.dense.size(); ++d) {
      const HandleT h = st.dense[d];
      if (h.index >= slots.size() || slots[h.index].generation != h.generation ||
          !(h.generation & 1u) || slots[h.index].dense != kNpos) {
        bad("dense entry " + std::to_string(d) + " is not a live slot listed once");
      }
      slots[h.index].dense = static_cast<uint32_t>(d);
    }
    std::vector<bool> listed(slots.size(), false);
    for (uint32_t i : st.freeSlots) {
      if (i >= slots.size() || (slots[i].generation & 1u) || slots[i].generation == 0 ||
          listed[i]) {
        bad("free slot " + std::to_string(i) + " is live, retired or listed twice");
      }
      listed[i] = true;
    }
    for (size_t i = 0; i < slots.size(); ++i) {
      const uint32_t g = slots[i].generation;
      if ((g & 1u) ? slots[i].dense == kNpos : (g != 0 && !listed[i])) {
        bad("slot " + std::to_string(i) + " is neither in use nor free");
      }
    }
    slots_ = std::move(slots);
    freeSlots_ = st.freeSlots;
    dense_ = st.dense;
  }

  static constexpr uint32_t kNpos = 0xFFFFFFFFu;
  // Index kNpos is kept out of use so that no valid handle has it, and dense indices fit in
  // 31 bits, so a contact record can keep a wall flag beside one (sim/scene.hpp).
  static constexpr uint32_t kMaxSlots = 0x7FFFFFFFu;

 private:
  struct Slot {
    uint32_t generation;
    uint32_t dense;  // dense index while live
  };

  [[noreturn]] void throwInvalid(HandleT h) const {
    // A retired slot (generation 0) has issued every odd generation.
    const bool issued =
        (h.generation & 1u) && h.index < slots_.size() &&
        (slots_[h.index].generation == 0 || h.generation < slots_[h.index].generation);
    throw Error("invalid " + kind_ + " id \"" + toString(h) +
                    "\": " + (issued ? "the " + kind_ + " was removed" : "no such " + kind_),
                {"LOOKUP", "HANDLE"});
  }

  std::string kind_;
  std::vector<Slot> slots_;
  std::vector<uint32_t> freeSlots_;
  std::vector<HandleT> dense_;
};

}  // namespace demlab

template <class Kind>
struct std::hash<demlab::Handle<Kind>> {
  size_t operator()(demlab::Handle<Kind> h) const noexcept {
    return std::hash<uint64_t>{}(h.bits());
  }
};
