#include "mpi/reach.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <stdexcept>

namespace demlab::mpi {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Returns the empty box (its distance to any point is infinite).
template <int D>
Box<D> emptyBox() {
  Box<D> b;
  b.lo.fill(kInf);
  b.hi.fill(-kInf);
  return b;
}

}  // namespace

template <int D>
std::vector<typename ReachTable<D>::Class> ReachTable<D>::classesOf(
    const std::vector<Point<D>>& centres, const std::vector<double>& radii) {
  if (centres.size() != radii.size()) {
    throw std::invalid_argument("reach: one radius per centre");
  }
  // Keyed by the radius's binary exponent.
  std::map<int, Class> classes;
  for (size_t i = 0; i < centres.size(); ++i) {
    int exponent = 0;
    std::frexp(radii[i], &exponent);
    auto [it, fresh] = classes.try_emplace(exponent, Class{emptyBox<D>(), 0.0});
    Class& k = it->second;
    for (int a = 0; a < D; ++a) {
      k.centres.lo[a] = std::min(k.centres.lo[a], centres[i][a]);
      k.centres.hi[a] = std::max(k.centres.hi[a], centres[i][a]);
    }
    k.radius = std::max(k.radius, radii[i]);
  }
  std::vector<Class> out;
  for (const auto& [exponent, k] : classes) out.push_back(k);
  return out;
}

template <int D>
ReachTable<D> ReachTable<D>::of(std::vector<std::vector<Class>> perRank) {
  if (perRank.empty()) throw std::invalid_argument("reach: no rank");
  ReachTable table;
  table.classes_ = std::move(perRank);
  table.build(0, static_cast<int>(table.classes_.size()));
  return table;
}

template <int D>
ReachTable<D> ReachTable<D>::gather(const std::vector<Point<D>>& centres,
                                    const std::vector<double>& radii, const Communicator& comm) {
  // Refused on every rank alike (one throwing alone would leave the others in the exchange).
  int64_t bad = centres.size() != radii.size();
  for (size_t i = 0; i < centres.size() && i < radii.size(); ++i) {
    for (int a = 0; a < D; ++a) bad += !std::isfinite(centres[i][a]);
    bad += !(radii[i] >= 0 && std::isfinite(radii[i]));
  }
  if (comm.sum(bad) > 0) {
    throw std::invalid_argument("reach: a centre not finite or a radius not finite and >= 0");
  }
  const std::vector<Class> mine = classesOf(centres, radii);
  // Gathered on every rank as 2 D + 1 doubles a class.
  constexpr size_t kBytes = (2 * D + 1) * sizeof(double);
  std::vector<char> packed(mine.size() * kBytes);
  for (size_t c = 0; c < mine.size(); ++c) {
    char* p = packed.data() + c * kBytes;
    std::memcpy(p, mine[c].centres.lo.data(), D * sizeof(double));
    std::memcpy(p + D * sizeof(double), mine[c].centres.hi.data(), D * sizeof(double));
    std::memcpy(p + 2 * D * sizeof(double), &mine[c].radius, sizeof(double));
  }
  const std::vector<std::vector<char>> all = comm.gatherBytes(packed);
  std::vector<std::vector<Class>> perRank(all.size());
  for (size_t r = 0; r < all.size(); ++r) {
    for (size_t c = 0; c < all[r].size() / kBytes; ++c) {
      const char* p = all[r].data() + c * kBytes;
      Class k;
      std::memcpy(k.centres.lo.data(), p, D * sizeof(double));
      std::memcpy(k.centres.hi.data(), p + D * sizeof(double), D * sizeof(double));
      std::memcpy(&k.radius, p + 2 * D * sizeof(double), sizeof(double));
      perRank[r].push_back(k);
    }
  }
  return of(std::move(perRank));
}

template <int D>
int ReachTable<D>::build(int first, int count) {
  const int n = static_cast<int>(nodes_.size());
  nodes_.push_back(Node{emptyBox<D>()});
  if (count == 1) {
    Node& leaf = nodes_[static_cast<size_t>(n)];
    leaf.rank = first;
    for (const Class& k : classes_[static_cast<size_t>(first)]) {
      for (int a = 0; a < D; ++a) {
        leaf.bound.lo[a] = std::min(leaf.bound.lo[a], k.centres.lo[a]);
        leaf.bound.hi[a] = std::max(leaf.bound.hi[a], k.centres.hi[a]);
      }
      leaf.radius = std::max(leaf.radius, k.radius);
    }
    return n;
  }
  const int low = build(first, count / 2);
  const int high = build(first + count / 2, count - count / 2);
  Node& node = nodes_[static_cast<size_t>(n)];
  node.low = low;
  node.high = high;
  for (const int child : {low, high}) {
    const Node& c = nodes_[static_cast<size_t>(child)];
    for (int a = 0; a < D; ++a) {
      node.bound.lo[a] = std::min(node.bound.lo[a], c.bound.lo[a]);
      node.bound.hi[a] = std::max(node.bound.hi[a], c.bound.hi[a]);
    }
    node.radius = std::max(node.radius, c.radius);
  }
  return n;
}

template class ReachTable<2>;
template class ReachTable<3>;

}  // namespace demlab::mpi
