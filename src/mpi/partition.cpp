#include "mpi/partition.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

namespace demlab::mpi {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kBins = 64;      // histogram bins a round
constexpr int kMaxRounds = 64;  // (about ten reach adjacent doubles; a bound, not a setting)

}  // namespace

template <int D>
Box<D> Box<D>::all() {
  Box b;
  b.lo.fill(-kInf);
  b.hi.fill(kInf);
  return b;
}

template <int D>
bool Box<D>::contains(const Point<D>& p) const {
  for (int a = 0; a < D; ++a) {
    if (!(lo[a] <= p[a] && p[a] < hi[a])) return false;
  }
  return true;
}

template <int D>
double Box<D>::distance2(const Point<D>& p) const {
  double d2 = 0;
  for (int a = 0; a < D; ++a) {
    const double d = std::max({lo[a] - p[a], 0.0, p[a] - hi[a]});
    d2 += d * d;
  }
  return d2;
}

template <int D>
int Partition<D>::ownerOf(const Point<D>& p) const {
  int n = 0;
  while (nodes_[static_cast<size_t>(n)].axis >= 0) {
    const Node& node = nodes_[static_cast<size_t>(n)];
    n = p[node.axis] < node.cut ? node.low : node.high;
  }
  return nodes_[static_cast<size_t>(n)].rank;
}

template <int D>
double Partition<D>::imbalance(const std::vector<double>& weightPerRank) {
  if (weightPerRank.empty()) return 1;
  double total = 0, most = 0;
  for (double w : weightPerRank) {
    total += w;
    most = std::max(most, w);
  }
  return total > 0 ? most * static_cast<double>(weightPerRank.size()) / total : 1;
}

namespace {

// One node being split: its axis, the weight below its cut to aim for, and the interval
// [ea, eb) of coordinates the cut is known to lie in, with the weights below each end.
struct Split {
  int node = 0;
  int axis = 0;
  double target = 0;
  double ea = 0, eb = 0;
  int64_t wa = 0, wb = 0;
  bool active = false;
};

// Returns interior edge i (1 .. kBins - 1) of [ea, eb): the same bits on every rank, rising
// with i, and no overflow where eb - ea exceeds the largest double (half the width, added twice).
double edgeOf(const Split& s, int i) {
  const double half = (0.5 * s.eb - 0.5 * s.ea) * (static_cast<double>(i) / kBins);
  return s.ea + half + half;
}

// Returns a cut inside box b on axis a when the node holds no point: the box's middle where
// it is finite, else a finite bound, else 0.
template <int D>
double emptyCut(const Box<D>& b, int a) {
  const bool lo = std::isfinite(b.lo[a]), hi = std::isfinite(b.hi[a]);
  if (lo && hi) return b.lo[a] + 0.5 * (b.hi[a] - b.lo[a]);
  if (lo) return b.lo[a];
  if (hi) return b.hi[a];
  return 0;
}

}  // namespace

template <int D>
Partition<D> Partition<D>::bisect(const std::vector<Point<D>>& points,
                                  const std::vector<double>& weights, int parts,
                                  const Communicator& comm) {
  if (parts < 1) throw std::invalid_argument("partition: parts must be at least 1");
  if (!weights.empty() && weights.size() != points.size()) {
    throw std::invalid_argument("partition: one weight per point");
  }
  // Refused on every rank alike (a rank that threw alone would leave the others waiting in the
  // next reduction): a coordinate that is not finite, a weight that is negative or not finite.
  int64_t bad = 0;
  double heaviest = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    for (int a = 0; a < D; ++a) bad += !std::isfinite(points[i][a]);
    if (!weights.empty()) {
      bad += !(weights[i] >= 0 && std::isfinite(weights[i]));
      heaviest = std::max(heaviest, weights[i]);
    }
  }
  if (comm.sum(bad) > 0) {
    throw std::invalid_argument("partition: a point not finite or a weight not finite and >= 0");
  }
  // The weights as integers, so every sum is exact and reduced by MPI in one step whatever the
  // number of ranks (a sum of doubles in rank order gathers every rank's histogram to one):
  // 1 each without weights (counts), else scaled so that all of them sum to at most 2^62.
  std::vector<int64_t> quantum;
  if (!weights.empty()) {
    heaviest = comm.max(heaviest);
    const double n = static_cast<double>(comm.sum(static_cast<int64_t>(points.size())));
    if (heaviest > 0) {
      const double scale = std::ldexp(1.0, 62) / (n * heaviest);
      quantum.resize(points.size());
      for (size_t i = 0; i < points.size(); ++i) {
        quantum[i] = static_cast<int64_t>(weights[i] * scale);
      }
    }
  }
  const auto weightOf = [&](size_t i) { return quantum.empty() ? int64_t{1} : quantum[i]; };
  Partition out;
  Node root;
  root.box = Box<D>::all();
  root.ranks = parts;
  out.nodes_.push_back(root);
  std::vector<int> nodeOf(points.size(), 0);  // each point's node at the current level
  std::vector<int> level{0};
  while (!level.empty()) {
    std::vector<Split> splits;
    for (int n : level) {
      Node& node = out.nodes_[static_cast<size_t>(n)];
      if (node.ranks == 1) {
        node.rank = node.firstRank;
      } else {
        splits.push_back(Split{n});
      }
    }
    if (splits.empty()) break;
    const size_t m = splits.size();
    std::vector<int> slot(out.nodes_.size(), -1);
    for (size_t s = 0; s < m; ++s) slot[static_cast<size_t>(splits[s].node)] = static_cast<int>(s);
    // The extent and weight of each node's points, over all ranks.
    std::vector<double> lo(m * D, kInf), hi(m * D, -kInf);
    std::vector<int64_t> total(m, 0);
    for (size_t i = 0; i < points.size(); ++i) {
      const int s = slot[static_cast<size_t>(nodeOf[i])];
      if (s < 0) continue;
      for (int a = 0; a < D; ++a) {
        lo[s * D + a] = std::min(lo[s * D + a], points[i][a]);
        hi[s * D + a] = std::max(hi[s * D + a], points[i][a]);
      }
      total[static_cast<size_t>(s)] += weightOf(i);
    }
    comm.min(lo);
    comm.max(hi);
    comm.sum(total);
    for (size_t s = 0; s < m; ++s) {
      Split& sp = splits[s];
      const Node& node = out.nodes_[static_cast<size_t>(sp.node)];
      double spread = -1;
      for (int a = 0; a < D; ++a) {
        if (hi[s * D + a] - lo[s * D + a] > spread) {
          spread = hi[s * D + a] - lo[s * D + a];
          sp.axis = a;
        }
      }
      const int lowRanks = node.ranks / 2;
      sp.target = static_cast<double>(total[s]) * lowRanks / node.ranks;
      if (!(spread >= 0)) {  // no point: any cut inside the box
        sp.axis = 0;
        sp.ea = sp.eb = emptyCut(node.box, 0);
        continue;
      }
      sp.ea = lo[s * D + sp.axis];
      sp.eb = std::nextafter(hi[s * D + sp.axis], kInf);
      sp.wa = 0;
      sp.wb = total[s];
      sp.active = sp.target > 0 && std::nextafter(sp.ea, kInf) < sp.eb;
    }
    // Histogram refinement, all the level's nodes in one reduction a round.
    std::vector<int64_t> below(m * (kBins - 1));
    for (int round = 0; round < kMaxRounds; ++round) {
      bool any = false;
      for (const Split& sp : splits) any |= sp.active;
      if (!any) break;
      std::fill(below.begin(), below.end(), int64_t{0});
      for (size_t i = 0; i < points.size(); ++i) {
        const int s = slot[static_cast<size_t>(nodeOf[i])];
        if (s < 0 || !splits[static_cast<size_t>(s)].active) continue;
        const Split& sp = splits[static_cast<size_t>(s)];
        const double x = points[i][sp.axis];
        if (!(sp.ea <= x && x < sp.eb)) continue;
        // The first edge above x: x counts below it and every later one.
        // (A guess the two loops below correct.)
        const double guess = (0.5 * x - 0.5 * sp.ea) / (0.5 * sp.eb - 0.5 * sp.ea) * kBins;
        int bin = guess >= 0 && guess < kBins ? static_cast<int>(guess) : guess >= kBins ? kBins - 1 : 0;
        while (bin > 0 && x < edgeOf(sp, bin)) --bin;
        while (bin < kBins - 1 && x >= edgeOf(sp, bin + 1)) ++bin;
        if (bin < kBins - 1) below[static_cast<size_t>(s) * (kBins - 1) + bin] += weightOf(i);
      }
      comm.sum(below);
      for (size_t s = 0; s < m; ++s) {
        Split& sp = splits[s];
        if (!sp.active) continue;
        int64_t w = sp.wa, prevW = sp.wa;
        double prevEdge = sp.ea;
        bool found = false;
        for (int i = 1; i < kBins; ++i) {
          w += below[s * (kBins - 1) + static_cast<size_t>(i - 1)];
          const double e = edgeOf(sp, i);
          if (static_cast<double>(w) >= sp.target) {
            sp.ea = prevEdge;
            sp.wa = prevW;
            sp.eb = e;
            sp.wb = w;
            found = true;
            break;
          }
          prevEdge = e;
          prevW = w;
        }
        if (!found) {
          sp.ea = prevEdge;
          sp.wa = prevW;
        }
        sp.active = static_cast<double>(sp.wa) < sp.target && std::nextafter(sp.ea, kInf) < sp.eb;
      }
    }
    // The cuts and the children.
    std::vector<int> next;
    for (size_t s = 0; s < m; ++s) {
      const Split& sp = splits[s];
      const double cut = sp.target - static_cast<double>(sp.wa) <= static_cast<double>(sp.wb) - sp.target
                             ? sp.ea
                             : sp.eb;
      Node& node = out.nodes_[static_cast<size_t>(sp.node)];
      node.axis = sp.axis;
      node.cut = cut;
      Node low, high;
      low.box = high.box = node.box;
      low.box.hi[sp.axis] = cut;
      high.box.lo[sp.axis] = cut;
      low.firstRank = node.firstRank;
      low.ranks = node.ranks / 2;
      high.firstRank = node.firstRank + low.ranks;
      high.ranks = node.ranks - low.ranks;
      node.low = static_cast<int>(out.nodes_.size());
      node.high = node.low + 1;
      const int lowIndex = node.low, highIndex = node.high;
      out.nodes_.push_back(low);
      out.nodes_.push_back(high);
      next.push_back(lowIndex);
      next.push_back(highIndex);
    }
    for (size_t i = 0; i < points.size(); ++i) {
      const int s = slot[static_cast<size_t>(nodeOf[i])];
      if (s < 0) continue;
      const Node& node = out.nodes_[static_cast<size_t>(splits[static_cast<size_t>(s)].node)];
      nodeOf[i] = points[i][node.axis] < node.cut ? node.low : node.high;
    }
    level = std::move(next);
  }
  out.boxes_.resize(static_cast<size_t>(parts));
  for (const Node& node : out.nodes_) {
    if (node.axis < 0) out.boxes_[static_cast<size_t>(node.rank)] = node.box;
  }
  return out;
}

template struct Box<2>;
template struct Box<3>;
template class Partition<2>;
template class Partition<3>;

}  // namespace demlab::mpi
