// The tangential springs of the shape contact pass (sim/shape_contacts.hpp): one per contact
// point, keyed by the pair's slots and the point's feature (ShapeSpringKey).
//
// Why not a map: the pass visits the same points in the same order from step to step between
// neighbour searches, so the springs are kept as two arrays, last step's and this step's, in the
// order the pass touched them. A point looks first at the place after the last one found (a hit
// in the common case: no search, no tree, no allocation), and only when that misses (a new point,
// a new search) in a hash table of last step's springs (open addressing, linear probing), made
// once in such a step: linear in the springs, where sorting them would not be. A spring not
// touched in a step is dropped with last step's array. Lookups are by key, so the results do not
// depend on the storage order; checkpoints write the springs sorted by key.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "physics/contact.hpp"

namespace demlab::sim {

// The key of one contact point's tangential spring in a pair with a non-ball element: the two
// slots (a wall's as wallPairId) and the point's feature.
struct ShapeSpringKey {
  uint32_t a, b, point;
  friend auto operator<=>(const ShapeSpringKey&, const ShapeSpringKey&) = default;
};

template <int D>
class ShapeSpringStore {
 public:
  using History = physics::TangentialHistory<D>;
  struct Entry {
    ShapeSpringKey key;
    History h;
  };

  // Starts a step: every spring is last step's until touched. Changes the store.
  void beginStep() {
    next_.clear();
    next_.reserve(springs_.size() + springs_.size() / 8 + 16);
    cursor_ = 0;
    indexed_ = false;
  }
  // Returns the spring of key for this step: last step's, or a zero spring for a new point.
  // The pointer is valid until the next touch. Changes the store.
  History* touch(const ShapeSpringKey& key) {
    const History* h = last(key);
    next_.push_back({key, h != nullptr ? *h : History{}});
    return &next_.back().h;
  }
  // Returns last step's spring of key, or null, without keeping it for this step (a pass that
  // learns only later which points touch: keep() them then). Changes the lookup's cursor.
  const History* last(const ShapeSpringKey& key) {
    if (cursor_ < springs_.size() && springs_[cursor_].key == key) return &springs_[cursor_++].h;
    if (!indexed_) buildIndex();
    const uint32_t at = find(key);
    if (at == kNone) return nullptr;
    cursor_ = at + 1;
    return &springs_[at].h;
  }
  // Keeps h as key's spring for this step. Changes the store.
  void keep(const ShapeSpringKey& key, const History& h) { next_.push_back({key, h}); }
  // Ends a step: this step's springs become the store; those not touched are dropped.
  void endStep() { springs_.swap(next_); }

  size_t size() const { return springs_.size(); }
  size_t heapBytes() const {
    return (springs_.capacity() + next_.capacity()) * sizeof(Entry) + index_.capacity() * sizeof(uint32_t);
  }
  // Returns the springs sorted by key (checkpoints). Changes nothing.
  std::vector<Entry> sorted() const {
    std::vector<Entry> out = springs_;
    std::sort(out.begin(), out.end(), [](const Entry& x, const Entry& y) { return x.key < y.key; });
    return out;
  }
  // Adds the spring of key, between steps (a checkpoint's, whose keys come sorted: a key equal
  // to the last one added replaces it). Changes the store.
  void put(const ShapeSpringKey& key, const History& h) {
    if (!springs_.empty() && springs_.back().key == key) {
      springs_.back().h = h;
      return;
    }
    springs_.push_back({key, h});
  }
  // Drops the springs whose key satisfies drop, between steps. Changes the store.
  template <class Drop>
  void eraseIf(Drop drop) {
    std::erase_if(springs_, [&](const Entry& e) { return drop(e.key); });
  }
  void clear() { springs_.clear(); }

 private:
  std::vector<Entry> springs_;  // last step's, in the order they were touched
  std::vector<Entry> next_;     // this step's
  static constexpr uint32_t kNone = 0xffffffffu;

  static uint64_t hash(const ShapeSpringKey& k) {
    uint64_t h = (uint64_t{k.a} << 32 | k.b) * 0x9e3779b97f4a7c15ull;
    h ^= (h >> 29) + uint64_t{k.point} * 0xbf58476d1ce4e5b9ull;
    return h ^ (h >> 32);
  }
  // Fills index_ with springs_'s positions by key: a power-of-two table at most half full.
  void buildIndex() {
    size_t size = 16;
    while (size < 2 * springs_.size()) size *= 2;
    index_.assign(size, kNone);
    const size_t mask = size - 1;
    for (uint32_t i = 0; i < springs_.size(); ++i) {
      size_t slot = hash(springs_[i].key) & mask;
      while (index_[slot] != kNone) slot = (slot + 1) & mask;
      index_[slot] = i;
    }
    indexed_ = true;
  }
  // Returns the position of key in springs_, or kNone.
  uint32_t find(const ShapeSpringKey& key) const {
    const size_t mask = index_.size() - 1;
    for (size_t slot = hash(key) & mask; index_[slot] != kNone; slot = (slot + 1) & mask) {
      if (springs_[index_[slot]].key == key) return index_[slot];
    }
    return kNone;
  }

  std::vector<uint32_t> index_;  // a hash table of springs_'s positions, made on a step's first miss
  size_t cursor_ = 0;
  bool indexed_ = false;
};

}  // namespace demlab::sim
