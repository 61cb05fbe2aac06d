// The ghosts of one skin interval (doc/plans/mpi.md, "The step"): made at a neighbour search
// from the reach table, then used every step to send the owned elements' states to the ranks
// that hold them as ghosts, point to point with those ranks only (a step's exchange must not
// grow with the number of ranks). The receiving ranks learn at the search, in one exchange of
// counts, whom to expect and how many; the ghosts arrive in the same order every step (source
// rank by source rank, each in its owned order), so a ghost keeps its place in the receiving
// rank's arrays for the whole interval.
#pragma once

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <type_traits>
#include <vector>

#include "mpi/communicator.hpp"
#include "mpi/reach.hpp"

namespace demlab::mpi {

template <int D>
class GhostPlan {
 public:
  // Makes the plan from this rank's owned elements (centres and bounding radii, the order of
  // its arrays) and the table every rank gathered: element i is sent to every rank the table
  // says needs it. Collective over comm.
  static GhostPlan make(const ReachTable<D>& table, const std::vector<Point<D>>& centres,
                        const std::vector<double>& radii, double skin, const Communicator& comm) {
    GhostPlan plan;
    const size_t p = static_cast<size_t>(comm.size());
    std::vector<std::vector<uint32_t>> lists(p);
    for (size_t i = 0; i < centres.size(); ++i) {
      table.forEachRankNeeding(centres[i], radii[i], skin, comm.rank(), [&](int k) {
        lists[static_cast<size_t>(k)].push_back(static_cast<uint32_t>(i));
      });
    }
    std::vector<std::vector<char>> counts(p, std::vector<char>(sizeof(uint64_t)));
    for (size_t k = 0; k < p; ++k) {
      const uint64_t n = lists[k].size();
      std::memcpy(counts[k].data(), &n, sizeof n);
      if (n > 0) {
        plan.to_.push_back(static_cast<int>(k));
        plan.send_.push_back(std::move(lists[k]));
      }
    }
    const std::vector<std::vector<char>> got = comm.exchange(counts);
    for (size_t k = 0; k < p; ++k) {
      uint64_t n = 0;
      std::memcpy(&n, got[k].data(), sizeof n);
      if (n > 0) {
        plan.from_.push_back(static_cast<int>(k));
        plan.recv_.push_back(static_cast<size_t>(n));
        plan.ghosts_ += static_cast<size_t>(n);
      }
    }
    return plan;
  }

  // Returns the number of ghosts this rank receives.
  size_t ghosts() const { return ghosts_; }
  // Returns the copies this rank sends a step (an element sent to two ranks counts twice).
  size_t sent() const {
    size_t n = 0;
    for (const auto& s : send_) n += s.size();
    return n;
  }
  // Returns the ranks this rank sends to and receives from, increasing.
  const std::vector<int>& sendRanks() const { return to_; }
  const std::vector<int>& receiveRanks() const { return from_; }

  // Sends owned[i] of every owned element a rank holds as a ghost and sets ghosts to the
  // ghosts' values, in ghost order. Every rank of the plan calls it, with the owned elements of
  // make(). The message buffers are the plan's, kept from step to step: a step allocates
  // nothing once they have grown. Changes ghosts and the buffers.
  template <class T>
  void forward(const std::vector<T>& owned, const Communicator& comm, std::vector<T>& ghosts) const {
    forwardWith([&](uint32_t e, T& out) { out = owned[e]; }, comm, ghosts);
  }

  // forward, with each owned element's value made by fill(i, T&) as it is packed (no array of
  // every owned element's value first).
  template <class T, class Fill>
  void forwardWith(Fill&& fill, const Communicator& comm, std::vector<T>& ghosts) const {
    static_assert(std::is_trivially_copyable_v<T>);
    out_.resize(to_.size());
    in_.resize(from_.size());
    for (size_t i = 0; i < to_.size(); ++i) {
      out_[i].resize(send_[i].size() * sizeof(T));
      char* p = out_[i].data();
      for (const uint32_t e : send_[i]) {
        T value;
        fill(e, value);
        std::memcpy(p, &value, sizeof(T));
        p += sizeof(T);
      }
    }
    for (size_t j = 0; j < from_.size(); ++j) in_[j].resize(recv_[j] * sizeof(T));
    comm.exchangeWith(to_, out_, from_, in_);
    ghosts.resize(ghosts_);
    size_t at = 0;
    for (const auto& b : in_) {
      if (!b.empty()) std::memcpy(static_cast<void*>(ghosts.data() + at), b.data(), b.size());
      at += b.size() / sizeof(T);
    }
  }

  // The way back: sends each ghost's value (ghosts[g], in ghost order) to the rank that owns
  // it, which calls add(i, value) for each value of its owned element i, by source rank
  // increasing, each source's in the order it was sent: so the sums an owner makes have the
  // same order every step. Every rank of the plan calls it. Changes the buffers.
  template <class T, class Add>
  void reverse(const std::vector<T>& ghosts, const Communicator& comm, Add&& add) const {
    static_assert(std::is_trivially_copyable_v<T>);
    if (ghosts.size() != ghosts_) throw std::invalid_argument("mpi: one value per ghost");
    backOut_.resize(from_.size());
    backIn_.resize(to_.size());
    size_t at = 0;
    for (size_t j = 0; j < from_.size(); ++j) {
      backOut_[j].resize(recv_[j] * sizeof(T));
      if (recv_[j] > 0) {
        std::memcpy(backOut_[j].data(), static_cast<const void*>(ghosts.data() + at),
                    backOut_[j].size());
      }
      at += recv_[j];
    }
    for (size_t i = 0; i < to_.size(); ++i) backIn_[i].resize(send_[i].size() * sizeof(T));
    comm.exchangeWith(from_, backOut_, to_, backIn_);
    for (size_t i = 0; i < to_.size(); ++i) {
      const char* p = backIn_[i].data();
      for (const uint32_t e : send_[i]) {
        T value;
        std::memcpy(static_cast<void*>(&value), p, sizeof(T));
        add(e, value);
        p += sizeof(T);
      }
    }
  }

 private:
  std::vector<int> to_, from_;
  std::vector<std::vector<uint32_t>> send_;  // per rank of to_: the owned elements sent
  std::vector<size_t> recv_;                 // per rank of from_: the ghosts it sends
  size_t ghosts_ = 0;
  mutable std::vector<std::vector<char>> out_, in_;  // forward()'s messages, reused
  mutable std::vector<std::vector<char>> backOut_, backIn_;  // reverse()'s
};

}  // namespace demlab::mpi
