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
#include <memory>
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
    sendForward<T>(fill, comm);
    ghosts.resize(ghosts_);
    receiveForward<T>([&](size_t g, const T& value) { ghosts[g] = value; });
  }

  // forwardWith in halves, so that a rank works while the states travel: sendForward packs
  // fill(i, T&) of the owned elements the other ranks hold as ghosts and sends them;
  // receiveForward waits for this rank's ghosts and hands them to take(g, const T&) in ghost
  // order, straight from the message. Every rank of the plan calls both, in this order, with
  // the same T, before the plan's next exchange. Change the buffers.
  template <class T, class Fill>
  void sendForward(Fill&& fill, const Communicator& comm) const {
    static_assert(std::is_trivially_copyable_v<T>);
    Traffic& t = *traffic_;
    t.forward.receive();
    t.forward.finishSends();  // (out is about to be packed again)
    t.out.resize(to_.size());
    t.in.resize(from_.size());
    for (size_t i = 0; i < to_.size(); ++i) {
      t.out[i].resize(send_[i].size() * sizeof(T));
      char* p = t.out[i].data();
      for (const uint32_t e : send_[i]) {
        T value{};
        if (e != kRemoved) fill(e, value);
        std::memcpy(p, &value, sizeof(T));
        p += sizeof(T);
      }
    }
    for (size_t j = 0; j < from_.size(); ++j) t.in[j].resize(recv_[j] * sizeof(T));
    t.forward.post(comm, to_, t.out, from_, t.in);
  }
  template <class T, class Take>
  void receiveForward(Take&& take) const {
    Traffic& t = *traffic_;
    t.forward.receive();
    size_t g = 0;
    for (const auto& b : t.in) {
      for (const char* p = b.data(); p != b.data() + b.size(); p += sizeof(T)) {
        T value;
        std::memcpy(static_cast<void*>(&value), p, sizeof(T));
        take(g++, value);
      }
    }
  }

  // The way back: sends each ghost's value (ghosts[g], in ghost order) to the rank that owns
  // it, which calls add(i, value) for each value of its owned element i, by source rank
  // increasing, each source's in the order it was sent: so the sums an owner makes have the
  // same order every step. Every rank of the plan calls it. Changes the buffers.
  template <class T, class Add>
  void reverse(const std::vector<T>& ghosts, const Communicator& comm, Add&& add) const {
    if (ghosts.size() != ghosts_) throw std::invalid_argument("mpi: one value per ghost");
    sendBack<T>([&](size_t g, T& out) { out = ghosts[g]; }, comm);
    receiveBack<T>(add);
  }

  // reverse in halves: sendBack packs fill(g, T&) of every ghost (g in ghost order) and sends
  // each to its owner; receiveBack waits for the values of this rank's elements and calls
  // add(i, const T&) for each, in reverse's order. Every rank of the plan calls both, in this
  // order, with the same T, before the plan's next exchange. Change the buffers.
  template <class T, class Fill>
  void sendBack(Fill&& fill, const Communicator& comm) const {
    static_assert(std::is_trivially_copyable_v<T>);
    Traffic& t = *traffic_;
    t.back.receive();
    t.back.finishSends();
    t.backOut.resize(from_.size());
    t.backIn.resize(to_.size());
    size_t g = 0;
    for (size_t j = 0; j < from_.size(); ++j) {
      t.backOut[j].resize(recv_[j] * sizeof(T));
      char* p = t.backOut[j].data();
      for (size_t k = 0; k < recv_[j]; ++k, ++g, p += sizeof(T)) {
        T value;
        fill(g, value);
        std::memcpy(p, &value, sizeof(T));
      }
    }
    for (size_t i = 0; i < to_.size(); ++i) t.backIn[i].resize(send_[i].size() * sizeof(T));
    t.back.post(comm, from_, t.backOut, to_, t.backIn);
  }
  template <class T, class Add>
  void receiveBack(Add&& add) const {
    Traffic& t = *traffic_;
    t.back.receive();
    for (size_t i = 0; i < to_.size(); ++i) {
      const char* p = t.backIn[i].data();
      for (const uint32_t e : send_[i]) {
        T value;
        std::memcpy(static_cast<void*>(&value), p, sizeof(T));
        if (e != kRemoved) add(e, value);
        p += sizeof(T);
      }
    }
  }

  // Waits until this rank's messages of both ways have been taken (a run ends with none in
  // flight). Changes the requests held.
  void finishSends() const {
    traffic_->forward.finishSends();
    traffic_->back.finishSends();
  }

  GhostPlan() = default;
  // A copy plans the same messages with buffers of its own (none in flight).
  GhostPlan(const GhostPlan& o)
      : to_(o.to_), from_(o.from_), send_(o.send_), recv_(o.recv_), ghosts_(o.ghosts_) {}
  GhostPlan& operator=(const GhostPlan& o) {
    if (this != &o) *this = GhostPlan(o);
    return *this;
  }
  // The owned element `gone` was removed and the one at `from` took its place (from == gone:
  // none moved). Until the search that replaces the plan, the moved one is sent from there and
  // a zero value stands for the removed one (its ghosts are dropped at that search, before any
  // pair reads them); the way back gives it nothing. Changes the sent lists.
  void ownedRemoved(uint32_t gone, uint32_t from) {
    for (auto& list : send_) {
      for (uint32_t& e : list) {
        if (e == gone) {
          e = kRemoved;
        } else if (e == from) {
          e = gone;
        }
      }
    }
  }
  static constexpr uint32_t kRemoved = 0xFFFFFFFFu;

  GhostPlan(GhostPlan&&) noexcept = default;
  GhostPlan& operator=(GhostPlan&&) noexcept = default;

 private:
  std::vector<int> to_, from_;
  std::vector<std::vector<uint32_t>> send_;  // per rank of to_: the owned elements sent
  std::vector<size_t> recv_;                 // per rank of from_: the ghosts it sends
  size_t ghosts_ = 0;
  // The messages of both ways, kept from step to step, and their requests in flight (after
  // the buffers: destroyed first, ending the sends before the buffers go). One object, so a
  // plan replaced at a search ends its exchanges before its buffers are freed.
  struct Traffic {
    std::vector<std::vector<char>> out, in, backOut, backIn;
    PostedExchange forward, back;
  };
  std::unique_ptr<Traffic> traffic_ = std::make_unique<Traffic>();
};

}  // namespace demlab::mpi
