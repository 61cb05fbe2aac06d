// InstanceInteractionManager: state that belongs to one pair of objects rather than to either
// of them: the tangential spring of a frictional contact now, bonds and their damage later.
//
// The DEM pattern it is built for: each step the contact pass touches every pair in contact
// (most of them were in contact the step before), new pairs appear, and at the end of the step
// sweep() drops the pairs that were not touched, i.e. the contacts that opened. It is an
// open-addressing hash table with linear probing (power-of-two size, load at most 3/4) whose
// buckets hold the key, the step the pair was last touched in, and the state itself, so a
// touch costs one cache miss at most, and prefetch() lets the contact loop hide even that.
// Deletion shifts the rest of the probe run back (no tombstones, so probes never slow down),
// and sweep() is one sequential pass over the table that deletes as it goes. Nothing is freed
// on removal: once the table has grown to the peak number of pairs, a run allocates nothing.
//
// Order: iteration (forEach, sweep's callbacks) runs over the table from its first empty
// bucket on. It depends only on the sequence of operations, so runs are deterministic, and
// re-inserting the pairs in that order into a table of the same bucketCount() rebuilds the very
// same layout. A checkpoint is taken between steps (after a sweep); a restore re-inserts the
// pairs in iteration order and then calls sweep(), which drops nothing and closes the step.
//
// A key is the ordered pair (first, second) of 32-bit object ids exactly as given: (a, b) and
// (b, a) are different pairs. The contact pass reports pairs with first < second, and a state
// with a direction (a spring vector) is kept in that orientation. Ids are handle slot indices
// (stable for an object's life, unlike dense indices); the pair (0xFFFFFFFF, 0xFFFFFFFF) marks
// empty buckets and is never a key (no handle has that index).
#pragma once

#include <cassert>
#include <cstdint>
#include <utility>
#include <vector>

namespace demlab {

// State: default-constructible and movable.
template <class State>
class InstanceInteractionManager {
 public:
  static constexpr uint32_t kReservedId = 0xFFFFFFFFu;

  struct Pair {
    uint32_t first;
    uint32_t second;
    friend bool operator==(const Pair&, const Pair&) = default;
    friend auto operator<=>(const Pair&, const Pair&) = default;
  };

  struct Touched {
    State& state;   // valid until the next insertion or removal
    bool inserted;  // true if the pair was new (state is value-initialised)
  };

  InstanceInteractionManager() { rehash(kMinBuckets); }

  // Returns the state of pair (a, b), made first as State{} if the pair is new, and marks the
  // pair as touched in the current step. May grow the table (no other change).
  Touched touch(uint32_t a, uint32_t b) {
    const uint64_t k = pack(a, b);
    size_t i = home(k);
    for (; table_[i].key != kEmptyKey; i = (i + 1) & mask_) {
      if (table_[i].key == k) {
        table_[i].stamp = epoch_;
        return {table_[i].state, false};
      }
    }
    if (4 * (size_ + 1) > 3 * table_.size()) {
      rehash(2 * table_.size());
      i = emptyBucketFor(k);
    }
    Bucket& slot = table_[i];
    slot.key = k;
    slot.stamp = epoch_;
    slot.state = State{};
    ++size_;
    return {slot.state, true};
  }

  // Hints that (a, b) will be touched soon: starts loading its home bucket into the cache.
  // A contact loop that prefetches a few pairs ahead overlaps the memory latency of the
  // lookups. Changes nothing.
  void prefetch(uint32_t a, uint32_t b) const noexcept {
    __builtin_prefetch(&table_[home(pack(a, b))], 1);
  }

  // Returns the state of (a, b), or null if the pair is not held. Marks nothing.
  State* find(uint32_t a, uint32_t b) noexcept {
    const size_t i = bucketOf(pack(a, b));
    return i == kNone ? nullptr : &table_[i].state;
  }
  const State* find(uint32_t a, uint32_t b) const noexcept {
    return const_cast<InstanceInteractionManager*>(this)->find(a, b);
  }

  // Returns true if (a, b) is held.
  bool contains(uint32_t a, uint32_t b) const noexcept { return bucketOf(pack(a, b)) != kNone; }

  // Drops the pair (a, b). Returns true if it was held.
  bool erase(uint32_t a, uint32_t b) noexcept {
    const size_t i = bucketOf(pack(a, b));
    if (i == kNone) return false;
    eraseBucket(i);
    return true;
  }

  // Ends a step: calls onDrop(Pair, State&) for every pair not touched since the previous
  // sweep, in iteration order, drops those pairs, and starts a new step. Returns the number
  // dropped. onDrop (e.g. the energy ledger taking back a spring's stored energy) must not
  // change this manager.
  template <class OnDrop>
  size_t sweep(OnDrop&& onDrop) {
    const size_t dropped = eraseWhere([&](Bucket& b) {
      if (b.stamp == epoch_) return false;
      onDrop(unpack(b.key), b.state);
      return true;
    });
    ++epoch_;
    return dropped;
  }
  size_t sweep() {
    return sweep([](const Pair&, State&) {});
  }

  // Drops every pair that involves id (call it when the object is removed, so an object that
  // reuses the slot does not inherit its history). Returns the number dropped. One pass over
  // the table.
  size_t removeId(uint32_t id) noexcept {
    return eraseWhere([id](const Bucket& b) {
      const Pair p = unpack(b.key);
      return p.first == id || p.second == id;
    });
  }

  // Calls f(Pair, State&) for every pair, in iteration order. f must not add or remove pairs.
  template <class F>
  void forEach(F&& f) {
    const size_t start = firstEmpty();
    for (size_t n = 1, i = (start + 1) & mask_; n < table_.size(); ++n, i = (i + 1) & mask_) {
      if (table_[i].key != kEmptyKey) f(unpack(table_[i].key), table_[i].state);
    }
  }
  // The same, reading only: f(Pair, const State&).
  template <class F>
  void forEach(F&& f) const {
    const size_t start = firstEmpty();
    for (size_t n = 1, i = (start + 1) & mask_; n < table_.size(); ++n, i = (i + 1) & mask_) {
      if (table_[i].key != kEmptyKey) f(unpack(table_[i].key), table_[i].state);
    }
  }

  // Returns the number of pairs held.
  size_t size() const noexcept { return size_; }
  bool empty() const noexcept { return size_ == 0; }

  // Returns the number of buckets (a power of two; it only grows).
  size_t bucketCount() const noexcept { return table_.size(); }
  // Returns the bytes of heap the table holds.
  size_t heapBytes() const noexcept { return table_.capacity() * sizeof(Bucket); }

  // Makes room for n pairs, so that reaching n pairs allocates nothing more.
  void reserve(size_t n) { reserveBuckets(bucketsFor(n)); }

  // Grows the table to at least n buckets (rounded up to a power of two). A restore calls it
  // with the saved bucketCount() before re-inserting the pairs in iteration order.
  void reserveBuckets(size_t n) {
    size_t cap = kMinBuckets;
    while (cap < n) cap *= 2;
    if (cap > table_.size()) rehash(cap);
  }

  // Drops every pair; keeps the memory.
  void clear() noexcept {
    for (Bucket& b : table_) b.key = kEmptyKey;
    size_ = 0;
  }

  // Returns the bytes held, for memory reports and for tests that a steady state allocates
  // nothing.
  size_t memoryBytes() const noexcept { return table_.capacity() * sizeof(Bucket); }

 private:
  struct Bucket {
    uint64_t key;
    uint32_t stamp;  // the step in which the pair was last touched
    State state;
  };

  static constexpr uint64_t kEmptyKey = ~uint64_t{0};  // the pair (kReservedId, kReservedId)
  static constexpr size_t kNone = ~size_t{0};
  static constexpr size_t kMinBuckets = 16;

  static uint64_t pack(uint32_t a, uint32_t b) noexcept {
    assert(a != kReservedId || b != kReservedId);
    return uint64_t{a} << 32 | b;
  }
  static Pair unpack(uint64_t k) noexcept {
    return {static_cast<uint32_t>(k >> 32), static_cast<uint32_t>(k)};
  }

  // Returns the number of buckets that holds n pairs within the load limit.
  static size_t bucketsFor(size_t n) noexcept { return (4 * n + 2) / 3; }

  // Returns the home bucket of k. Folding the high word into the low one before the Fibonacci
  // multiply makes both ids reach the top bits the bucket index is taken from.
  size_t home(uint64_t k) const noexcept {
    return static_cast<size_t>(((k ^ (k >> 32)) * 0x9E3779B97F4A7C15ull) >> shift_);
  }

  // Returns the bucket holding k, or kNone.
  size_t bucketOf(uint64_t k) const noexcept {
    for (size_t i = home(k);; i = (i + 1) & mask_) {
      if (table_[i].key == k) return i;
      if (table_[i].key == kEmptyKey) return kNone;
    }
  }

  // Returns the first empty bucket on the probe path of k (k is not in the table).
  size_t emptyBucketFor(uint64_t k) const noexcept {
    size_t i = home(k);
    while (table_[i].key != kEmptyKey) i = (i + 1) & mask_;
    return i;
  }

  // Returns the lowest empty bucket; there is one, as the load stays below 1.
  size_t firstEmpty() const noexcept {
    size_t i = 0;
    while (table_[i].key != kEmptyKey) ++i;
    return i;
  }

  // Empties bucket i and shifts back the entries of its probe run that may move, so every key
  // stays reachable from its home bucket without tombstones. Entries only ever move backwards
  // within their run, to a bucket on their own probe path.
  void eraseBucket(size_t i) noexcept {
    for (size_t j = (i + 1) & mask_; table_[j].key != kEmptyKey; j = (j + 1) & mask_) {
      const size_t h = home(table_[j].key);
      // The entry at j may fill the hole at i if i lies on its probe path from h to j.
      if (((j - h) & mask_) >= ((j - i) & mask_)) {
        table_[i].key = table_[j].key;
        table_[i].stamp = table_[j].stamp;
        table_[i].state = std::move(table_[j].state);
        i = j;
      }
    }
    table_[i].key = kEmptyKey;
    --size_;
  }

  // Deletes every entry for which pred(Bucket&) is true, in one pass in iteration order; returns
  // how many. The pass starts after an empty bucket, which no probe path crosses, so a
  // backward shift only brings entries not yet visited into the hole, and the hole is
  // examined again.
  template <class Pred>
  size_t eraseWhere(Pred&& pred) {
    const size_t before = size_;
    const size_t start = firstEmpty();
    size_t i = (start + 1) & mask_;
    for (size_t n = 1; n < table_.size();) {
      if (table_[i].key != kEmptyKey && pred(table_[i])) {
        eraseBucket(i);
      } else {
        i = (i + 1) & mask_;
        ++n;
      }
    }
    return before - size_;
  }

  // Rebuilds the table with n buckets (a power of two), inserting the pairs in iteration order.
  void rehash(size_t n) {
    std::vector<Bucket> old(n);
    old.swap(table_);
    for (Bucket& b : table_) b.key = kEmptyKey;
    mask_ = n - 1;
    shift_ = 64;
    for (size_t m = n; m > 1; m >>= 1) --shift_;
    if (old.empty()) return;
    size_t start = 0;
    while (old[start].key != kEmptyKey) ++start;
    for (size_t k = 1, i = (start + 1) & (old.size() - 1); k < old.size();
         ++k, i = (i + 1) & (old.size() - 1)) {
      if (old[i].key == kEmptyKey) continue;
      Bucket& b = table_[emptyBucketFor(old[i].key)];
      b.key = old[i].key;
      b.stamp = old[i].stamp;
      b.state = std::move(old[i].state);
    }
  }

  std::vector<Bucket> table_;
  size_t mask_ = 0;
  int shift_ = 64;  // 64 - log2(bucket count)
  size_t size_ = 0;
  uint32_t epoch_ = 0;
};

}  // namespace demlab
