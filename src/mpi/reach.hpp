// Which ranks need a ghost copy of an element: those owning an element whose bounding sphere
// comes within the skin of its own, so that every candidate pair of the serial neighbour
// search is seen by the owners of both its elements.
//
// CGrid's promise that elements of any size cost only their own reach must hold across ranks:
// one large element must not make every rank copy everything near its boundary. So a rank
// publishes its owned elements by size class (radii within a factor of two share one): per
// class, the box around the class's centres and its largest radius. An element is ghosted on
// rank k when it comes within its radius, the class's radius and the skin of one of k's class
// boxes: small elements near k's boundary, and near a large element of k only those within
// that element's reach. A tree over the ranks in the bisection's order (RCB halves, the low
// child floor(p/2) of p ranks), each node with the union of its ranks' boxes and their largest
// radius, keeps the search to the ranks nearby.
#pragma once

#include <vector>

#include "mpi/communicator.hpp"
#include "mpi/partition.hpp"

namespace demlab::mpi {

template <int D>
class ReachTable {
 public:
  // One size class of a rank's elements: the closed box of their centres and their largest
  // radius.
  struct Class {
    Box<D> centres;
    double radius = 0;
  };

  // Builds the table from every rank's owned elements (their centres and bounding radii).
  // Collective over comm.
  static ReachTable gather(const std::vector<Point<D>>& centres, const std::vector<double>& radii,
                           const Communicator& comm);

  // Returns the classes of one rank's elements (what gather sends), by increasing radius.
  static std::vector<Class> classesOf(const std::vector<Point<D>>& centres,
                                      const std::vector<double>& radii);

  // Returns the table of the ranks' classes (perRank[k]: rank k's), as gather would.
  static ReachTable of(std::vector<std::vector<Class>> perRank);

  // Returns rank k's classes.
  const std::vector<Class>& classes(int k) const { return classes_[static_cast<size_t>(k)]; }

  // Calls fn(k) for every rank k other than self that needs a ghost of the element at centre c
  // with bounding radius r: one of k's classes comes within r + its radius + skin of c. In rank
  // order.
  template <class Fn>
  void forEachRankNeeding(const Point<D>& c, double r, double skin, int self, Fn&& fn) const {
    if (!nodes_.empty()) visit(0, c, r + skin, self, fn);
  }

 private:
  struct Node {
    Box<D> bound;  // the union of the ranks' class boxes
    double radius = 0;
    int low = -1, high = -1, rank = -1;
  };
  std::vector<std::vector<Class>> classes_;  // per rank
  std::vector<Node> nodes_;                  // nodes_[0]: the root

  // Makes the node of ranks [first, first + count) and its subtree; returns its index.
  int build(int first, int count);

  template <class Fn>
  void visit(int n, const Point<D>& c, double reach, int self, Fn& fn) const {
    const Node& node = nodes_[static_cast<size_t>(n)];
    const double within = reach + node.radius;
    if (!(node.bound.distance2(c) < within * within)) return;
    if (node.rank >= 0) {
      if (node.rank == self) return;
      for (const Class& k : classes_[static_cast<size_t>(node.rank)]) {
        const double w = reach + k.radius;
        if (k.centres.distance2(c) < w * w) {
          fn(node.rank);
          return;
        }
      }
      return;
    }
    visit(node.low, c, reach, self, fn);
    visit(node.high, c, reach, self, fn);
  }
};

extern template class ReachTable<2>;
extern template class ReachTable<3>;

}  // namespace demlab::mpi
