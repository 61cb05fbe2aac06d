// The tangential springs of the grain-grain candidate pairs: one slot per contact, not per
// candidate.
//
// A neighbor search lists about twice as many candidate pairs as there are contacts (five
// times as many in a loose lattice), and a spring per candidate spent most of its memory on
// zeros: 112 bytes a grain in a dense 10k bed, against 55 for the contacts alone. Here each
// candidate holds a 4-byte slot number, kNoSlot while it does not touch, and the springs of
// the touching ones sit in a pool; a pair that stops touching gives its slot back (reused by
// the next pair that starts to), so the pool never holds more than the most contacts seen at
// once since the last search. A candidate without a slot has a zero spring: the values, and
// so every force and the state digest, are those of one spring per candidate.
//
// Between searches the candidates are fixed and the contact loops reach a spring through its
// candidate's slot, with no hashing. At a search SpringTransfer (history_store.hpp) takes the
// nonzero springs out and gives them to the new candidates in candidate order, so the pool
// starts each skin interval in the order the contact loops read it.
//
// The SIMD kernels see the pool through kernel::SpringSlots (contact_kernel.hpp): they test
// slots with vector compares and call acquire and release, defined once here, only for the
// pairs that start or stop touching.
#pragma once

#include <atomic>
#include <cstdint>
#include <vector>

#include "core/math.hpp"
#include "physics/contact.hpp"
#include "sim/contact_kernel.hpp"

namespace demlab::sim {

template <int D>
class PairSprings {
 public:
  static constexpr uint32_t kNoSlot = kernel::SpringSlots::kNoSlot;
  using History = physics::TangentialHistory<D>;

  // Returns the number of candidates covered (0 when the scene keeps no history).
  size_t size() const { return slotOf_.size(); }
  bool empty() const { return slotOf_.empty(); }

  // Makes n candidates without springs and frees the pool's memory when shrink (a search:
  // the new pool is sized for the springs carried over). Changes every member.
  void reset(size_t n, bool shrink) {
    if (shrink) {
      std::vector<uint32_t>(n, kNoSlot).swap(slotOf_);
      std::vector<History>().swap(pool_);
      std::vector<uint32_t>().swap(free_);
    } else {
      slotOf_.assign(n, kNoSlot);
      pool_.clear();
      free_.clear();
    }
  }

  // Frees everything. Changes every member.
  void clear() { reset(0, true); }

  // Makes room for n springs in the pool, exactly. Changes the pool's capacity.
  void reserve(size_t n) { pool_.reserve(n); }

  // Makes the pool safe for passes that run groups of candidates on several threads at once:
  // room for a spring per candidate, so a slot handed out never moves the pool (the room
  // untouched stays unbacked by memory), and slots handed out and given back one thread at a
  // time. Changes the pool's capacity.
  void prepareConcurrent() {
    if (pool_.capacity() < slotOf_.size()) pool_.reserve(slotOf_.size());
  }

  // Returns candidate k's spring (zero when it has no slot).
  VecD<D> spring(size_t k) const {
    return slotOf_[k] == kNoSlot ? VecD<D>::Zero() : pool_[slotOf_[k]].spring;
  }

  // Returns candidate k's history, giving it a zeroed slot first if it has none. The pointer
  // is valid until the next call that gives a slot. Changes slotOf_[k] and the pool.
  History* at(size_t k) {
    if (slotOf_[k] == kNoSlot) acquireSlot(k);
    return &pool_[slotOf_[k]];
  }

  // Returns candidate k's history (empty when it has no slot).
  History history(size_t k) const { return slotOf_[k] == kNoSlot ? History{} : pool_[slotOf_[k]]; }

  // Sets candidate k's spring to sp, without a drift velocity: a zero sp gives the slot back.
  // Changes the pool.
  void set(size_t k, const VecD<D>& sp) { set(k, History{sp}); }

  // Sets candidate k's history to h: an empty one gives the slot back. Changes the pool.
  void set(size_t k, const History& h) {
    if (h.empty()) {
      release(k);
    } else {
      *at(k) = h;
    }
  }

  // Drops the candidates k for which drop(k) is true, giving their slots back; the others keep
  // their springs, in their order. Changes slotOf_ and the free list.
  template <class Drop>
  void eraseCandidates(Drop&& drop) {
    size_t kept = 0;
    for (size_t k = 0; k < slotOf_.size(); ++k) {
      if (drop(k)) {
        release(k);
      } else {
        slotOf_[kept++] = slotOf_[k];
      }
    }
    slotOf_.resize(kept);
  }

  // Gives candidate k's slot back, if it has one (the pair stopped touching). Changes
  // slotOf_[k] and the free list.
  void release(size_t k) {
    const uint32_t slot = slotOf_[k];
    if (slot == kNoSlot) return;
    lock_.lock();
    free_.push_back(slot);
    lock_.unlock();
    slotOf_[k] = kNoSlot;
  }

  // Returns the view the SIMD kernels read and change; valid while this object lives and
  // nothing but the kernel changes it.
  // base: the first candidate the pass sees (a group's), whose slot is slotOf[0].
  kernel::SpringSlots slots(size_t base = 0) {
    static_assert(D != 3 || sizeof(History) == kernel::kSpringStride * sizeof(double));
    kernel::SpringSlots s;
    s.slotOf = slotOf_.data() + base;
    s.base = base;
    s.data = reinterpret_cast<double*>(pool_.data());
    s.owner = this;
    s.acquire = &acquireThunk;
    s.release = &releaseThunk;
    return s;
  }

  // Returns the histories one per candidate (empty without a slot).
  std::vector<History> perCandidate() const {
    std::vector<History> out(slotOf_.size());
    for (size_t k = 0; k < slotOf_.size(); ++k) out[k] = history(k);
    return out;
  }

  // Returns the springs in use (slots handed out and not given back).
  size_t live() const { return pool_.size() - free_.size(); }

  // Returns the bytes of heap held (capacities).
  size_t heapBytes() const {
    return slotOf_.capacity() * sizeof(uint32_t) + pool_.capacity() * sizeof(History) +
           free_.capacity() * sizeof(uint32_t);
  }

 private:
  // Gives candidate k (without a slot) a zeroed one: a given-back slot if there is one, else a
  // new one; a full pool grows by an eighth (a doubled copy would hold up to twice the
  // springs' memory until the next search). Changes slotOf_[k], the pool and the free list.
  void acquireSlot(size_t k) {
    uint32_t slot;
    lock_.lock();
    if (!free_.empty()) {
      slot = free_.back();
      free_.pop_back();
      pool_[slot] = History{};
    } else {
      if (pool_.size() == pool_.capacity()) pool_.reserve(pool_.size() + pool_.size() / 8 + 16);
      slot = static_cast<uint32_t>(pool_.size());
      pool_.emplace_back();
    }
    lock_.unlock();
    slotOf_[k] = slot;
  }

  static double* acquireThunk(void* owner, size_t k) {
    auto* self = static_cast<PairSprings*>(owner);
    self->acquireSlot(k);
    return reinterpret_cast<double*>(self->pool_.data());
  }
  static void releaseThunk(void* owner, size_t k) { static_cast<PairSprings*>(owner)->release(k); }

  std::vector<uint32_t> slotOf_;  // per candidate: its slot in pool_, or kNoSlot
  std::vector<History> pool_;     // the springs, by slot
  std::vector<uint32_t> free_;    // slots given back, reused first

  // A spin lock over the free list and the pool's end (taken only when a pair starts or stops
  // touching); copies of the springs get a lock of their own.
  struct SpinLock {
    std::atomic<bool> held{false};
    SpinLock() = default;
    SpinLock(const SpinLock&) {}
    SpinLock& operator=(const SpinLock&) { return *this; }
    void lock() {
      while (held.exchange(true, std::memory_order_acquire)) {
        while (held.load(std::memory_order_relaxed)) {
        }
      }
    }
    void unlock() { held.store(false, std::memory_order_release); }
  };
  SpinLock lock_;
};

}  // namespace demlab::sim
