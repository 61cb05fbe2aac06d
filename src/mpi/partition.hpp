// The spatial decomposition of a distributed run: recursive coordinate bisection (RCB) of the
// elements' centres into one box per rank, balanced on element count or on a measured cost.
//
// Each node of the bisection splits its box across the axis along which its points spread
// most (not the box's longest: a settled bed fills only the bottom of its box, and a cut through
// the empty top balances nothing), where the weight below is its ranks' share: the low child
// takes floor(p/2) of its p ranks. The root box is all of space, so every point has an owner
// however far it flies. The cut is found by histogram refinement: each round every rank counts
// its points of every open node into 64 bins, the counts are summed over the ranks (one
// reduction for all the nodes of a level), and the bin where the weight below crosses the
// target becomes the next interval; about ten rounds reach adjacent doubles. A point on a cut
// belongs to the high side.
//
// The weights are summed as integers (1 a point, or the weights scaled so that all of them sum
// to at most 2^62): every sum is exact and MPI reduces it in one step for any number of ranks.
// So the same code partitions one rank's points (Communicator::self()) and all ranks' (the
// world) to the same bits, which the tests check.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "mpi/communicator.hpp"

namespace demlab::mpi {

template <int D>
using Point = std::array<double, D>;

// An axis-aligned box: the points p with lo[a] <= p[a] < hi[a] on every axis a (infinite
// bounds allowed).
template <int D>
struct Box {
  Point<D> lo, hi;

  // Returns the box of all space.
  static Box all();
  // Returns true if p lies in the box.
  bool contains(const Point<D>& p) const;
  // Returns the squared distance from p to the box (0 inside).
  double distance2(const Point<D>& p) const;
  bool operator==(const Box&) const = default;
};

template <int D>
class Partition {
 public:
  // One node of the bisection: a leaf holds a rank; an inner node splits its box at cut on
  // axis, points below going to low, the others to high.
  struct Node {
    Box<D> box;
    int axis = -1;  // -1: a leaf
    double cut = 0;
    int low = -1, high = -1;  // children (node indices)
    int rank = -1;            // a leaf's rank
    int firstRank = 0, ranks = 1;
  };

  // Returns the number of boxes (ranks).
  int parts() const { return static_cast<int>(boxes_.size()); }
  // Returns rank k's box.
  const Box<D>& box(int k) const { return boxes_[static_cast<size_t>(k)]; }
  const std::vector<Node>& nodes() const { return nodes_; }

  // Returns the rank whose box holds p.
  int ownerOf(const Point<D>& p) const;

  // Calls fn(rank) for every rank whose box is nearer to p than reach (squared: reach2), in
  // rank order.
  template <class Fn>
  void forEachNear(const Point<D>& p, double reach2, Fn&& fn) const {
    visitNear(0, p, reach2, fn);
  }

  // Returns the largest weight of a box over the mean (1: balanced), from the weights each
  // rank's box holds.
  static double imbalance(const std::vector<double>& weightPerRank);

  // Builds the partition of every rank's points into `parts` boxes (parts >= 1). weights: one
  // per point, or empty for 1 each. Collective over comm: every rank calls it with its own
  // points and the same parts.
  static Partition bisect(const std::vector<Point<D>>& points, const std::vector<double>& weights,
                          int parts, const Communicator& comm);

 private:
  std::vector<Node> nodes_;
  std::vector<Box<D>> boxes_;

  template <class Fn>
  void visitNear(int n, const Point<D>& p, double reach2, Fn& fn) const {
    const Node& node = nodes_[static_cast<size_t>(n)];
    if (!(node.box.distance2(p) < reach2)) return;
    if (node.axis < 0) {
      fn(node.rank);
      return;
    }
    visitNear(node.low, p, reach2, fn);
    visitNear(node.high, p, reach2, fn);
  }
};

extern template struct Box<2>;
extern template struct Box<3>;
extern template class Partition<2>;
extern template class Partition<3>;

}  // namespace demlab::mpi
