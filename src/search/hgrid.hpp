// HGrid: a hierarchical hashed grid in the style of MercuryDPM's HGrid (V. Ogarko and S. Luding,
// "A fast multilevel algorithm for contact detection of arbitrarily polydisperse objects",
// Comput. Phys. Commun. 183 (2012) 931-936), with levels chosen by a cost model as recommended
// by D. Krijgsman, V. Ogarko and S. Luding, "Optimal parameters for a hierarchical grid data
// structure for contact detection in arbitrarily polydisperse particle systems", Comp. Part.
// Mech. 1 (2014) 357-372. It is the strongest one-cell-per-object peer of CGrid.
//
// Levels. An object's size is its largest extent. Sizes are first sorted into bands a factor 2
// wide above the smallest size (edges at sqrt 2, 2 sqrt 2, ... times it, so integer size ratios
// and the rounding around them never straddle an edge; zero sizes join the smallest). Each
// occupied band starts as a level; then, greedily, the two neighbouring levels whose merge
// lowers the modelled cost most are merged, until no merge helps and at most maxLevels remain.
// The model counts hash probes and pair tests per level and per pair of levels, assuming the
// objects spread over their bounding box. A monodisperse input has one level; a bidisperse one
// two, unless the large objects are so many that one coarse level is cheaper; a power law a
// few, fewer than its octaves. A level's cell size is the largest size on it (times
// cellFactor >= 1), so cells fit each level's objects.
//
// Assignment. Each object goes to the one cell of its level that holds its lo corner. Because
// no extent on a level exceeds the cell size, two overlapping objects of one level lie in the
// same or adjacent cells, and an object of level m that overlaps a box B has its lo corner in
// the cells from cell(B.lo - largest extent of m) to cell(B.hi) of level m. The lo corner
// (rather than the centre) needs no halving and gives the same number of cells to visit.
//
// Search. Same level: every occupied cell tests its own pairs and the forward half of its
// 3^D - 1 neighbours (first nonzero offset positive), so each pair of cells is met once.
// Across levels, Ogarko and Luding's cross-level search: for each pair of levels, the cells of
// one level probe the cells of the other that their box covers (widened by the margin), so
// every cross-level pair is found once. The 2012 paper and MercuryDPM's default (TOPDOWN) let
// the coarse level search the fine one; MercuryDPM's BOTTOMUP goes the other way, and
// Krijgsman et al. show that which is cheaper depends on the distribution: top-down wins when
// the large objects are few (a wall probes the strip of fine cells it covers, once), bottom-up
// when they are many (each large ball would probe (size ratio)^D fine cells, where each small
// one probes 2^D coarse cells). So the direction is chosen per pair of levels by the same cost
// model, top-down on a tie. When a box covers more cells of the other level than that level
// has occupied cells, the occupied cells are scanned instead, so cost never depends on empty
// space.
//
// Storage. Cells are found through an open-addressing hash table (linear probing) of cell
// coordinates, one segment per level, each sized about twice its occupied cells; a small Bloom
// filter in front of it answers most probes of empty cells. There is no full grid array.
// Objects are counting-sorted into one flat array by (level, cell), with a copy of their boxes
// in that order. The cells of a level are ordered along a Morton curve (a radix sort of the
// occupied cells), so the neighbours a cell probes were mostly probed just before and are
// still in cache.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <utility>
#include <vector>

#include "search/broad_phase.hpp"
#include "search/configs.hpp"
#include "search/validate.hpp"

namespace demlab::search {

template <int D, class T>
class HGrid final : public BroadPhase<D, T> {
 public:
  // A level's search list is a 64-bit mask, so no more levels than this.
  static constexpr int kLevelLimit = 64;
  static constexpr int kDefaultMaxLevels = 16;

  // options.cellFactor scales every level's cell size from the largest object on that level;
  // 0 means 1, and values below 1 are raised to 1 because a cell smaller than its objects would
  // miss pairs. maxLevels is clamped to [1, kLevelLimit].
  explicit HGrid(const SearchOptions& options = {}, int maxLevels = kDefaultMaxLevels)
      : cellFactor_(options.cellFactor >= 1.0 ? options.cellFactor : 1.0),
        maxLevels_(std::clamp(maxLevels, 1, kLevelLimit)) {}

  std::string_view name() const override { return "hgrid"; }

  void findPairs(std::span<const Box<D, T>> boxes, std::vector<IndexPair>& out) override;

  std::size_t workingBytes() const override {
    return bytesOf(bandOf_) + bytesOf(order_) + bytesOf(cellOfRank_) + bytesOf(sortedIndex_) +
           bytesOf(sortedBox_) + bytesOf(cells_) + bytesOf(cellsSpare_) + bytesOf(table_) +
           bytesOf(filter_) + bytesOf(codes_) + bytesOf(codesSpare_) + bytesOf(perm_) +
           bytesOf(permSpare_) + bytesOf(rangeCache_) + bytesOf(rangeFound_);
  }

  // Returns the number of levels the last findPairs used (0 before the first call or for an
  // empty input). Changes nothing.
  int levelCount() const noexcept { return levelCount_; }

  // Returns the cell size of `level` in the last findPairs, in input units. Changes nothing.
  double cellSize(int level) const noexcept { return cellSize_[level] / scale_; }

  // Returns true if, in the last findPairs, the cells of `from` probed level `to` for the pairs
  // between the two (exactly one of the two directions is chosen). Changes nothing.
  bool searches(int from, int to) const noexcept { return (searches_[from] >> to) & 1u; }

 private:
  using Coords = std::array<int32_t, D>;

  struct Cell {
    Coords key;
    uint32_t begin;  // first position in sortedIndex_ / sortedBox_
    uint32_t end;    // one past the last
  };

  struct Slot {
    uint32_t cell;  // index into cells_, or kEmpty
    uint32_t tag;   // hash bits above the index
  };

  static constexpr uint32_t kEmpty = std::numeric_limits<uint32_t>::max();
  // Band 0 holds points; positive sizes run from the smallest to the span, at most 2^30 apart
  // (see kSpanFraction), so they fall into at most 31 more bands.
  static constexpr int kBands = 32;
  // Cell sizes are at least (span of the input) * 2^-30, so a cell coordinate and its
  // neighbours fit an int32 and the rounding of coordinates (below 2^-21 cells) stays below
  // kSlack.
  static constexpr double kSpanFraction = 0x1p-30;
  // Cell sizes exceed the largest object on their level by this relative slack, which absorbs
  // the rounding of (x - origin) * (1 / size), so the one-cell margins proven in exact
  // arithmetic hold in floating point too.
  static constexpr double kSlack = 0x1p-16;
  // Keeps 1 / cell size finite when every coordinate is tiny.
  static constexpr double kMinCell = 1e-280;
  // A hash probe costs about as much as scanning this many cell records in order; a cell scans
  // another level's occupied cells instead of probing it when that is cheaper.
  static constexpr double kProbeCost = 4.0;
  // The cost of one pair test in the cost model, relative to one probe.
  static constexpr double kTestCost = 0.3;
  // Ranges of up to this many cells (3^D) are remembered between cells (see searchOtherLevel).
  static constexpr uint32_t kRangeCells = ([] {
    uint32_t n = 1;
    for (int k = 0; k < D; ++k) n *= 3;
    return n;
  })();
  static constexpr uint32_t kNoRange = std::numeric_limits<uint32_t>::max();
  // Digits of the radix sort of Morton codes.
  static constexpr int kRadixBits = 11;

  // Forward half of the 3^D - 1 neighbour offsets: those whose first nonzero entry is +1.
  static constexpr int kHalfStencil = ([] {
    int n = 1;
    for (int k = 0; k < D; ++k) n *= 3;
    return (n - 1) / 2;
  })();
  static constexpr std::array<Coords, kHalfStencil> kForward = ([] {
    std::array<Coords, kHalfStencil> offsets{};
    int count = 0, total = 1;
    for (int k = 0; k < D; ++k) total *= 3;
    for (int code = 0; code < total; ++code) {
      Coords d{};
      int rest = code;
      for (int k = D - 1; k >= 0; --k) {
        d[k] = rest % 3 - 1;
        rest /= 3;
      }
      int first = 0;
      for (int k = 0; k < D && first == 0; ++k) first = d[k];
      if (first > 0) offsets[count++] = d;
    }
    return offsets;
  })();

  // Returns the bytes v holds (its capacity). Changes nothing.
  template <class V>
  static std::size_t bytesOf(const std::vector<V>& v) {
    return v.capacity() * sizeof(V);
  }

  // Resizes v to `size`; if it must grow, reserves a quarter more (at most `bound`), so that a
  // later call whose count of cells moves a little does not allocate again.
  template <class V>
  static void resizeWithSlack(std::vector<V>& v, std::size_t size, std::size_t bound) {
    if (size > v.capacity()) v.reserve(std::max(size, std::min(bound, size + size / 4 + 64)));
    v.resize(size);
  }

  // Returns a well-mixed 64-bit hash of (level, key). Changes nothing.
  static uint64_t hashOf(int level, const Coords& key) noexcept {
    uint64_t h = 0x9e3779b97f4a7c15ull * static_cast<uint64_t>(level + 1);
    for (int k = 0; k < D; ++k) {
      h = (h ^ static_cast<uint32_t>(key[k])) * 0xbf58476d1ce4e5b9ull;
      h ^= h >> 29;
    }
    h *= 0x94d049bb133111ebull;
    return h ^ (h >> 32);
  }

  // Returns the slot tag of a hash: bits the slot index does not use, so equal tags are a
  // cheap first test before the keys are compared. Changes nothing.
  static uint32_t tagOf(uint64_t hash) noexcept { return static_cast<uint32_t>(hash >> 32); }

  // Returns true if the coordinates are equal (without the early exits of operator==, which
  // compiles to a call). Changes nothing.
  static bool sameKey(const Coords& a, const Coords& b) noexcept {
    bool same = true;
    for (int k = 0; k < D; ++k) same &= a[k] == b[k];
    return same;
  }

  // Returns the cell coordinate of x on axis k at `level`. x must be a coordinate of one of the
  // current boxes, so x * scale_ >= origin_[k] and the result lies in [0, 2^30 + 1]: the cast
  // truncates a non-negative value, which is floor. Changes nothing.
  int32_t coordOf(T x, int k, int level) const noexcept {
    return static_cast<int32_t>((static_cast<double>(x) * scale_ - origin_[k]) * invCell_[level]);
  }

  // Returns the lowest cell coordinate on axis k of `level` that can hold the lo corner of an
  // object of `level` overlapping a box whose lo is x: cell(x - largest extent on axis k), with
  // a slack larger than the rounding, clamped to 0 (no coordinate is lower). Changes nothing.
  int32_t lowCoordOf(T x, int k, int level) const noexcept {
    const double t =
        ((static_cast<double>(x) * scale_ - origin_[k]) - margin_[level][k]) * invCell_[level];
    return t > 0.0 ? static_cast<int32_t>(t) : 0;  // also 0 for NaN (0 * infinity)
  }

  // Returns the index in cells_ of the occupied cell (level, key), or kEmpty. Changes nothing.
  uint32_t find(int level, const Coords& key) const noexcept {
    return find(level, key, hashOf(level, key));
  }

  // The same, given h = hashOf(level, key).
  uint32_t find(int level, const Coords& key, uint64_t h) const noexcept {
    if (!mayHold(level, h)) return kEmpty;
    const Slot* segment = table_.data() + tableBase_[level];
    const std::size_t mask = tableMask_[level];
    const uint32_t tag = tagOf(h);
    for (std::size_t i = h & mask;; i = (i + 1) & mask) {
      const Slot s = segment[i];
      if (s.cell == kEmpty) return kEmpty;
      if (s.tag == tag && sameKey(cells_[s.cell].key, key)) return s.cell;
    }
  }

  // Returns false if no occupied cell of `level` has hash h, true if one may have. Changes
  // nothing.
  bool mayHold(int level, uint64_t h) const noexcept {
    const std::size_t bit = h >> filterShift_[level];
    return (filter_[filterBase_[level] + (bit >> 6)] >> (bit & 63)) & 1u;
  }

  // Appends the empty table and filter segments of `level` (the next level to be filled) to
  // table_ and filter_, sized for `expected` cells: at most half full, 8 to 16 filter bits per
  // cell.
  void openSegment(int level, std::size_t expected) {
    const std::size_t slots = std::bit_ceil(std::max<std::size_t>(16, 2 * expected));
    tableBase_[level] = table_.size();
    tableMask_[level] = slots - 1;
    resizeWithSlack(table_, table_.size() + slots, table_.size() + slots);
    std::fill(table_.begin() + tableBase_[level], table_.end(), Slot{kEmpty, 0});
    const std::size_t words = slots / 16;  // 4 bits per slot
    filterBase_[level] = filter_.size();
    filterShift_[level] = 64 - std::countr_zero(words * 64);
    resizeWithSlack(filter_, filter_.size() + words, filter_.size() + words);
    std::fill(filter_.begin() + filterBase_[level], filter_.end(), uint64_t{0});
  }

  // Returns the index of cell (level, key), appending it to cells_ (empty) if it is new. The
  // level's segment must be the last one opened; it doubles when it would pass half full.
  uint32_t findOrInsert(int level, const Coords& key) {
    const uint64_t h = hashOf(level, key);
    const uint32_t tag = tagOf(h);
    const std::size_t mask = tableMask_[level];
    Slot* segment = table_.data() + tableBase_[level];
    std::size_t i = h & mask;
    for (;; i = (i + 1) & mask) {
      const Slot s = segment[i];
      if (s.cell == kEmpty) break;
      if (s.tag == tag && sameKey(cells_[s.cell].key, key)) return s.cell;
    }
    const auto id = static_cast<uint32_t>(cells_.size());
    cells_.push_back({key, 0, 0});
    const std::size_t bit = h >> filterShift_[level];
    filter_[filterBase_[level] + (bit >> 6)] |= uint64_t{1} << (bit & 63);
    const std::size_t inLevel = cells_.size() - levelCellBegin_[level];
    if (2 * inLevel > mask + 1) {
      growSegment(level);
    } else {
      segment[i] = {id, tag};
    }
    return id;
  }

  // Doubles the table segment of `level` (the last one) and reinserts the level's cells. The
  // filter keeps its size: it only answers "maybe" more often.
  void growSegment(int level) {
    const std::size_t slots = 2 * (tableMask_[level] + 1);
    tableMask_[level] = slots - 1;
    resizeWithSlack(table_, tableBase_[level] + slots, 2 * (tableBase_[level] + slots));
    Slot* segment = table_.data() + tableBase_[level];
    std::fill(segment, segment + slots, Slot{kEmpty, 0});
    for (auto c = levelCellBegin_[level]; c < cells_.size(); ++c) {
      const uint64_t h = hashOf(level, cells_[c].key);
      std::size_t i = h & tableMask_[level];
      while (segment[i].cell != kEmpty) i = (i + 1) & tableMask_[level];
      segment[i] = {static_cast<uint32_t>(c), tagOf(h)};
    }
  }

  // Appends pairs to the caller's vector through a raw pointer. The vector is grown ahead of
  // the writes, so the overlap test can store every candidate and advance only on a hit, with
  // no hard-to-predict branch; the destructor trims the vector to the pairs written.
  class PairSink {
   public:
    explicit PairSink(std::vector<IndexPair>& out) : out_(out) {}
    PairSink(const PairSink&) = delete;
    PairSink& operator=(const PairSink&) = delete;
    ~PairSink() { out_.resize(count_); }

    // Returns room for k more pairs; grows the vector if needed.
    IndexPair* room(std::size_t k) {
      if (count_ + k > out_.size()) {
        out_.resize(std::max({count_ + k, 2 * out_.size(), std::size_t{1024}}));
      }
      return out_.data() + count_;
    }

    // Keeps the next k pairs written into room().
    void advance(std::size_t k) noexcept { count_ += k; }

   private:
    std::vector<IndexPair>& out_;
    std::size_t count_ = 0;
  };

  // Appends every overlapping pair (x, y), x in positions [xb, xe), y in [yb, ye), to sink.
  void crossPairs(uint32_t xb, uint32_t xe, uint32_t yb, uint32_t ye, PairSink& sink) const {
    for (uint32_t x = xb; x < xe; ++x) testRow(x, yb, ye, sink);
  }

  // Appends every pair (x, y), y in positions [yb, ye), whose boxes overlap, to sink.
  void testRow(uint32_t x, uint32_t yb, uint32_t ye, PairSink& sink) const {
    const Box<D, T> a = sortedBox_[x];
    const uint32_t ia = sortedIndex_[x];
    IndexPair* dst = sink.room(ye - yb);
    std::size_t hits = 0;
    for (uint32_t y = yb; y < ye; ++y) {
      const Box<D, T>& b = sortedBox_[y];
      unsigned hit = 1;
      for (int k = 0; k < D; ++k) {
        hit &=
            static_cast<unsigned>(a.lo[k] <= b.hi[k]) & static_cast<unsigned>(b.lo[k] <= a.hi[k]);
      }
      const uint32_t ib = sortedIndex_[y];
      dst[hits] = ia < ib ? IndexPair{ia, ib} : IndexPair{ib, ia};
      hits += hit;
    }
    sink.advance(hits);
  }

  // Per size band: objects, largest size, and per axis the sum and largest of the extents.
  struct BandStats {
    double count = 0.0;
    double size = 0.0;
    std::array<double, D> extentSum{};
    std::array<double, D> extentMax{};
  };

  // What the cost model knows of a level (scaled units).
  struct LevelModel {
    double count = 0.0;              // objects
    double cell = 0.0;               // cell size
    double inverse = 0.0;            // 1 / cell
    double domainCells = 1.0;        // cells of the input's bounding box
    double cells = 0.0;              // occupied cells (estimated, or counted)
    std::array<double, D> mean{};    // mean extent per axis
    std::array<double, D> margin{};  // largest extent per axis, plus slack
  };

  void computeLevels(std::span<const Box<D, T>> boxes);
  LevelModel modelOf(int first, int last) const;
  static double sameLevelCost(const LevelModel& a);
  static double crossCost(const LevelModel& a, const LevelModel& b, bool& fromA);
  void chooseLevels();
  void buildCells(std::span<const Box<D, T>> boxes);
  void sortCellsAlongMortonCurve();
  void chooseDirections();
  void searchLevel(int level, PairSink& sink);
  double rangeCells(const Box<D, T>& box, int other) const;
  void searchOtherLevel(uint32_t xb, uint32_t xe, const Box<D, T>& cover, int other,
                        PairSink& sink);

  // Settings.
  double cellFactor_;
  int maxLevels_;

  // Geometry of the last call, in scaled units (coordinates times scale_).
  double scale_ = 1.0;  // 0.5 when the input's span would overflow a double
  std::array<double, D> origin_{};
  int levelCount_ = 0;
  std::array<double, kLevelLimit> cellSize_{};
  std::array<double, kLevelLimit> invCell_{};
  std::array<std::array<double, D>, kLevelLimit> meanExtent_{};  // per level and axis
  // Per level and axis: the largest extent with a slack above rounding (see lowCoordOf).
  std::array<std::array<double, D>, kLevelLimit> margin_{};
  std::array<std::size_t, kLevelLimit> tableBase_{}, tableMask_{};  // table segment per level
  std::array<std::size_t, kLevelLimit> filterBase_{};  // filter segment per level, in words
  std::array<int, kLevelLimit> filterShift_{};         // 64 - log2(filter bits) per level
  // Cells per level in the last call, to size the table segments if the levels are alike.
  std::array<uint32_t, kLevelLimit> lastLevelCells_{};
  int lastLevelCount_ = 0;
  std::array<double, kLevelLimit> density_{};     // per level: objects per cell of the domain
  std::array<uint64_t, kLevelLimit> searches_{};  // per level: the other levels its cells probe
  std::array<uint32_t, kLevelLimit + 1> levelObjectBegin_{};  // positions in order_
  std::array<uint32_t, kLevelLimit + 1> levelCellBegin_{};    // indices in cells_
  std::array<double, D> span_{};  // extent of the input's bounding box per axis
  double minCell_ = 1.0;          // no cell is smaller (see kSpanFraction)
  std::array<BandStats, kBands> band_{};
  int maxBand_ = 0;
  std::array<uint8_t, kBands> bandLevel_{};  // per band: its level

  // Buffers reused between calls.
  std::vector<uint8_t> bandOf_;        // per object: its size band
  std::vector<uint32_t> order_;        // object indices sorted by level
  std::vector<uint32_t> cellOfRank_;   // per position of order_: its cell
  std::vector<uint32_t> sortedIndex_;  // object indices sorted by (level, cell)
  std::vector<Box<D, T>> sortedBox_;   // their boxes, in the same order
  std::vector<Cell> cells_;            // occupied cells, grouped by level
  std::vector<Cell> cellsSpare_;       // cells_ before the Morton sort
  // Hash of key -> cells_ index, one segment per level, so a level with few cells has a small
  // segment that stays in cache while the cells of a large level probe it.
  std::vector<Slot> table_;
  // A one-hash Bloom filter of the occupied cells, one segment per level with 8 to 16 bits per
  // cell: most probes of empty cells end in it, and it stays in cache when the table does not.
  std::vector<uint64_t> filter_;
  std::vector<uint64_t> codes_, codesSpare_;  // Morton codes of cells, radix sort buffers
  // Per other level: the last range a cell probed there, and the cells found in it.
  struct RangeCache {
    Coords lo{}, hi{};
    uint32_t count = 0;
  };
  std::vector<RangeCache> rangeCache_;
  std::vector<uint32_t> rangeFound_;        // kRangeCells per level
  std::vector<uint32_t> perm_, permSpare_;  // cell indices, radix sort buffers
};

template <int D, class T>
void HGrid<D, T>::findPairs(std::span<const Box<D, T>> boxes, std::vector<IndexPair>& out) {
  out.clear();
  validateBoxes<D, T>(boxes);
  levelCount_ = boxes.empty() ? 0 : 1;
  searches_.fill(0);
  if (boxes.size() < 2) return;
  computeLevels(boxes);
  buildCells(boxes);
  chooseDirections();
  if (rangeCache_.size() < static_cast<std::size_t>(levelCount_)) {
    rangeCache_.resize(kBands);
    rangeFound_.resize(kBands * kRangeCells);
  }
  PairSink sink(out);
  for (int level = 0; level < levelCount_; ++level) searchLevel(level, sink);
}

// Sets scale_, origin_, span_, minCell_, each object's band (bandOf_) and the band statistics,
// then the levels (see chooseLevels).
template <int D, class T>
void HGrid<D, T>::computeLevels(std::span<const Box<D, T>> boxes) {
  const std::size_t n = boxes.size();
  std::array<double, D> lo, hi;
  lo.fill(std::numeric_limits<double>::max());
  hi.fill(std::numeric_limits<double>::lowest());
  for (const auto& b : boxes) {
    for (int k = 0; k < D; ++k) {
      lo[k] = std::min(lo[k], static_cast<double>(b.lo[k]));
      hi[k] = std::max(hi[k], static_cast<double>(b.hi[k]));
    }
  }
  // Halving every coordinate keeps spans and extents of boxes near +-DBL_MAX finite; it is
  // monotone, so the cell arithmetic stays conservative.
  scale_ = 1.0;
  for (int k = 0; k < D; ++k) {
    if (!std::isfinite(hi[k] - lo[k])) scale_ = 0.5;
  }
  double span = 0.0;
  for (int k = 0; k < D; ++k) {
    origin_[k] = lo[k] * scale_;
    span_[k] = hi[k] * scale_ - origin_[k];
    span = std::max(span, span_[k]);
  }
  minCell_ = std::max(span * kSpanFraction, kMinCell);

  // Band 0 holds the points: zero-size objects, and specks smaller than minCell_. Their cell is
  // minCell_, so they spread over cells however dense they are, and the model lets them probe
  // the levels of larger objects (bottom-up) rather than be probed. (Joining them to the
  // smallest positive size would put every point in one cell when that size is large.)
  auto extentOf = [this](const Box<D, T>& b, int k) {
    return static_cast<double>(b.hi[k]) * scale_ - static_cast<double>(b.lo[k]) * scale_;
  };
  double minPositive = std::numeric_limits<double>::infinity();
  for (const auto& b : boxes) {
    double e = 0.0;
    for (int k = 0; k < D; ++k) e = std::max(e, extentOf(b, k));
    if (e >= minCell_) minPositive = std::min(minPositive, e);
  }
  const double floorSize = std::isfinite(minPositive) ? minPositive : minCell_;

  // Band b > 0 holds the sizes in [2^(b - 3/2), 2^(b - 1/2)) times the smallest size (band 1
  // from the smallest size up to sqrt 2 times it). Offsetting the edges by half an octave
  // keeps the common integer size ratios (2, 4, 8, ...) and the rounding around them inside
  // one band.
  bandOf_.resize(n);
  band_.fill(BandStats{});
  maxBand_ = 0;
  for (std::size_t i = 0; i < n; ++i) {
    std::array<double, D> ext;
    double e = 0.0;
    for (int k = 0; k < D; ++k) {
      ext[k] = extentOf(boxes[i], k);
      e = std::max(e, ext[k]);
    }
    int band = 0;
    if (e >= minCell_) {
      // e / floorSize * sqrt 2 is a normal number >= 1, whose binary exponent is floor(log2).
      const auto bits = std::bit_cast<uint64_t>(e / floorSize * 1.4142135623730951);
      band = std::min(static_cast<int>((bits >> 52) & 0x7ff) - 1023 + 1, kBands - 1);
    } else {
      e = minCell_;
    }
    bandOf_[i] = static_cast<uint8_t>(band);
    BandStats& stats = band_[band];
    stats.count += 1.0;
    stats.size = std::max(stats.size, e);
    for (int k = 0; k < D; ++k) {
      stats.extentSum[k] += ext[k];
      stats.extentMax[k] = std::max(stats.extentMax[k], ext[k]);
    }
    maxBand_ = std::max(maxBand_, band);
  }
  chooseLevels();
}

// Returns the statistics of a level made of the bands [first, last]. Changes nothing.
template <int D, class T>
typename HGrid<D, T>::LevelModel HGrid<D, T>::modelOf(int first, int last) const {
  LevelModel m;
  double size = 0.0;
  for (int b = first; b <= last; ++b) {
    m.count += band_[b].count;
    size = std::max(size, band_[b].size);
    for (int k = 0; k < D; ++k) {
      m.mean[k] += band_[b].extentSum[k];
      m.margin[k] = std::max(m.margin[k], band_[b].extentMax[k]);
    }
  }
  // An infinite size (only for extents near DBL_MAX) gives an inverse of 0: one cell per
  // level, which is slow but still finds every pair.
  m.cell = std::max(size * cellFactor_ * (1.0 + kSlack), minCell_);
  m.inverse = 1.0 / m.cell;
  // The cells of the input's bounding box, and the ones occupied if the objects were spread
  // over it at random (Poisson); a flat axis counts one cell.
  double domainCells = 1.0;
  for (int k = 0; k < D; ++k) {
    if (m.count > 0.0) m.mean[k] /= m.count;
    // The relative slack covers rounding near the extent, the absolute one (a fraction of the
    // cell) rounding when the extent is tiny or zero.
    m.margin[k] = m.margin[k] * (1.0 + kSlack) + m.cell * kSlack;
    domainCells *= std::max(1.0, std::min(span_[k] * m.inverse, 1e18));
  }
  m.domainCells = domainCells;
  m.cells = domainCells * -std::expm1(-m.count / domainCells);
  return m;
}

// Returns the estimated cost, in probe units, of the pairs inside level a: a half stencil of
// probes per occupied cell, and the pair tests among the objects of neighbouring cells.
// Changes nothing.
template <int D, class T>
double HGrid<D, T>::sameLevelCost(const LevelModel& a) {
  const double perCell = a.count / a.domainCells;  // objects per cell, occupied or not
  return a.cells * kHalfStencil + kTestCost * a.count * perCell * (kHalfStencil + 0.5);
}

// Returns the estimated cost of the pairs between levels a and b, in the cheaper direction,
// and sets fromA to true if that is the cells of a probing b. Changes nothing else.
template <int D, class T>
double HGrid<D, T>::crossCost(const LevelModel& a, const LevelModel& b, bool& fromA) {
  auto oneWay = [](const LevelModel& from, const LevelModel& to) {
    double covered = 1.0;
    for (int k = 0; k < D; ++k) {
      double per = (from.mean[k] + to.margin[k]) * to.inverse + 1.0;
      if (!(per <= 1e18)) per = 1e18;  // overflow, or 0 * infinity
      covered *= per;
    }
    const double probes = from.cells * std::min(covered, to.cells / kProbeCost);
    const double tests = from.count * covered * (to.count / to.domainCells);
    return probes + kTestCost * tests;
  };
  const double ab = oneWay(a, b), ba = oneWay(b, a);
  fromA = ab <= ba;
  return std::min(ab, ba);
}

// Groups the occupied bands into levels: each band its own level, then, greedily, the merge of
// two neighbouring levels that lowers the estimated total cost most, until no merge lowers it
// and at most maxLevels_ remain. This is Krijgsman, Ogarko and Luding's recipe (pick the levels
// that minimise the modelled cost of the search) with the model reduced to probes and tests.
// Sets levelCount_, bandLevel_, cellSize_, invCell_, meanExtent_ and margin_.
template <int D, class T>
void HGrid<D, T>::chooseLevels() {
  std::array<int, kBands> first{}, last{};
  std::array<LevelModel, kBands> model;
  int count = 0;
  for (int b = 0; b <= maxBand_; ++b) {
    if (band_[b].count == 0.0) continue;
    first[count] = last[count] = b;
    model[count] = modelOf(b, b);
    ++count;
  }
  std::array<double, kBands> same;
  std::array<std::array<double, kBands>, kBands> cross;
  bool unused;
  for (int i = 0; i < count; ++i) {
    same[i] = sameLevelCost(model[i]);
    for (int j = 0; j < i; ++j) cross[i][j] = cross[j][i] = crossCost(model[i], model[j], unused);
  }
  while (count > 1) {
    int best = -1;
    double bestDelta = std::numeric_limits<double>::infinity();
    LevelModel bestModel;
    for (int i = 0; i + 1 < count; ++i) {
      const LevelModel merged = modelOf(first[i], last[i + 1]);
      double delta = sameLevelCost(merged) - same[i] - same[i + 1] - cross[i][i + 1];
      for (int j = 0; j < count; ++j) {
        if (j == i || j == i + 1) continue;
        delta += crossCost(merged, model[j], unused) - cross[i][j] - cross[i + 1][j];
      }
      if (delta < bestDelta) {
        bestDelta = delta;
        best = i;
        bestModel = merged;
      }
    }
    if (!(bestDelta < 0.0) && count <= maxLevels_) break;
    // Merge levels best and best + 1 into best, and close the gap.
    last[best] = last[best + 1];
    model[best] = bestModel;
    for (int i = best + 1; i + 1 < count; ++i) {
      first[i] = first[i + 1];
      last[i] = last[i + 1];
      model[i] = model[i + 1];
      same[i] = same[i + 1];
      for (int j = 0; j < count; ++j) cross[i][j] = cross[i + 1][j];
    }
    for (int i = 0; i < count; ++i) {
      for (int j = best + 1; j + 1 < count; ++j) cross[i][j] = cross[i][j + 1];
    }
    --count;
    same[best] = sameLevelCost(model[best]);
    for (int j = 0; j < count; ++j) {
      if (j != best) cross[best][j] = cross[j][best] = crossCost(model[best], model[j], unused);
    }
  }
  levelCount_ = count;
  for (int level = 0; level < count; ++level) {
    for (int b = first[level]; b <= last[level]; ++b) bandLevel_[b] = static_cast<uint8_t>(level);
    cellSize_[level] = model[level].cell;
    invCell_[level] = model[level].inverse;
    meanExtent_[level] = model[level].mean;
    margin_[level] = model[level].margin;
  }
}

// Fills order_, cells_, the hash table and filter, sortedIndex_ and sortedBox_: objects grouped
// by level, then by cell, with every level's cells contiguous in cells_ and in Morton order.
template <int D, class T>
void HGrid<D, T>::buildCells(std::span<const Box<D, T>> boxes) {
  const auto n = static_cast<uint32_t>(boxes.size());
  // Counting sort by level, so cells are created level by level.
  levelObjectBegin_.fill(0);
  for (uint32_t i = 0; i < n; ++i) ++levelObjectBegin_[bandLevel_[bandOf_[i]] + 1];
  for (int level = 0; level < levelCount_; ++level) {
    levelObjectBegin_[level + 1] += levelObjectBegin_[level];
  }
  order_.resize(n);
  if (levelCount_ == 1) {
    for (uint32_t i = 0; i < n; ++i) order_[i] = i;
  } else {
    std::array<uint32_t, kLevelLimit> next;
    std::copy_n(levelObjectBegin_.begin(), kLevelLimit, next.begin());
    for (uint32_t i = 0; i < n; ++i) order_[next[bandLevel_[bandOf_[i]]]++] = i;
  }

  // Size each level's table segment for about as many cells as last time if the levels look
  // the same, else for one cell per object; cells_ likewise.
  const bool alike = lastLevelCount_ == levelCount_;
  std::size_t expectedCells = 0;
  for (int level = 0; level < levelCount_; ++level) {
    const uint32_t objects = levelObjectBegin_[level + 1] - levelObjectBegin_[level];
    if (!alike) lastLevelCells_[level] = objects;
    lastLevelCells_[level] = std::min(lastLevelCells_[level], objects);
    expectedCells += lastLevelCells_[level];
  }
  table_.clear();
  filter_.clear();
  cells_.clear();
  if (cells_.capacity() < expectedCells + expectedCells / 4 + 64) {
    cells_.reserve(std::min<std::size_t>(n, expectedCells + expectedCells / 4 + 64));
  }
  cellOfRank_.resize(n);
  for (int level = 0; level < levelCount_; ++level) {
    levelCellBegin_[level] = static_cast<uint32_t>(cells_.size());
    openSegment(level, lastLevelCells_[level]);
    for (uint32_t r = levelObjectBegin_[level]; r < levelObjectBegin_[level + 1]; ++r) {
      const Box<D, T>& b = boxes[order_[r]];
      Coords key;
      for (int k = 0; k < D; ++k) key[k] = coordOf(b.lo[k], k, level);
      const uint32_t c = findOrInsert(level, key);
      cellOfRank_[r] = c;
      ++cells_[c].end;  // a count for now
    }
    lastLevelCells_[level] = static_cast<uint32_t>(cells_.size()) - levelCellBegin_[level];
  }
  lastLevelCount_ = levelCount_;
  levelCellBegin_[levelCount_] = static_cast<uint32_t>(cells_.size());
  sortCellsAlongMortonCurve();

  // Counting sort by cell; stable, so objects keep their level order within a cell.
  uint32_t sum = 0;
  for (Cell& c : cells_) {
    c.begin = sum;
    sum += c.end;
    c.end = c.begin;  // a cursor for now, the end once every object is placed
  }
  sortedIndex_.resize(n);
  sortedBox_.resize(n);
  for (uint32_t r = 0; r < n; ++r) {
    const uint32_t i = order_[r];
    const uint32_t pos = cells_[cellOfRank_[r]].end++;
    sortedIndex_[pos] = i;
    sortedBox_[pos] = boxes[i];
  }
}

// Reorders the cells of each level along a Morton (Z-order) curve of their coordinates, and
// renumbers the table slots and cellOfRank_ to match. On inputs in random order this makes the
// search several times faster: neighbouring cells sit close in memory and are visited close in
// time. Coordinates wider than 64 / D bits keep their low bits, which only costs locality.
template <int D, class T>
void HGrid<D, T>::sortCellsAlongMortonCurve() {
  const auto m = static_cast<uint32_t>(cells_.size());
  const std::size_t bound = cellOfRank_.size();  // at most one cell per object
  resizeWithSlack(codes_, m, bound);
  resizeWithSlack(codesSpare_, m, bound);
  resizeWithSlack(perm_, m, bound);
  resizeWithSlack(permSpare_, m, bound);
  for (int level = 0; level < levelCount_; ++level) {
    const uint32_t first = levelCellBegin_[level], last = levelCellBegin_[level + 1];
    if (last - first < 3) {
      for (uint32_t c = first; c < last; ++c) perm_[c] = c;
      continue;
    }
    Coords low = cells_[first].key, high = low;
    for (uint32_t c = first; c < last; ++c) {
      for (int k = 0; k < D; ++k) {
        low[k] = std::min(low[k], cells_[c].key[k]);
        high[k] = std::max(high[k], cells_[c].key[k]);
      }
    }
    int bits = 0;
    for (int k = 0; k < D; ++k) {
      bits =
          std::max(bits, static_cast<int>(std::bit_width(static_cast<uint32_t>(high[k] - low[k]))));
    }
    bits = std::min(bits, 64 / D);
    for (uint32_t c = first; c < last; ++c) {
      uint64_t code = 0;
      for (int k = 0; k < D; ++k) {
        const auto v = static_cast<uint64_t>(static_cast<uint32_t>(cells_[c].key[k] - low[k]));
        for (int b = 0; b < bits; ++b) code |= ((v >> b) & 1u) << (b * D + k);
      }
      codes_[c] = code;
      perm_[c] = c;
    }
    // Least significant digit first; each pass is a stable counting sort.
    for (int shift = 0; shift < bits * D; shift += kRadixBits) {
      std::array<uint32_t, (1u << kRadixBits) + 1> start{};
      for (uint32_t c = first; c < last; ++c) {
        ++start[((codes_[c] >> shift) & ((1u << kRadixBits) - 1)) + 1];
      }
      start[0] = first;
      for (std::size_t d = 1; d < start.size(); ++d) start[d] += start[d - 1];
      for (uint32_t c = first; c < last; ++c) {
        const uint32_t to = start[(codes_[c] >> shift) & ((1u << kRadixBits) - 1)]++;
        codesSpare_[to] = codes_[c];
        permSpare_[to] = perm_[c];
      }
      for (uint32_t c = first; c < last; ++c) {
        codes_[c] = codesSpare_[c];
        perm_[c] = permSpare_[c];
      }
    }
  }
  // perm_[new] = old; permSpare_[old] = new.
  // Copying back (rather than swapping the two vectors) keeps each buffer's capacity where
  // its own use needs it, so later calls do not allocate.
  resizeWithSlack(cellsSpare_, m, bound);
  std::copy(cells_.begin(), cells_.end(), cellsSpare_.begin());
  for (uint32_t c = 0; c < m; ++c) {
    permSpare_[perm_[c]] = c;
    cells_[c] = cellsSpare_[perm_[c]];
  }
  for (Slot& s : table_) {
    if (s.cell != kEmpty) s.cell = permSpare_[s.cell];
  }
  for (uint32_t& c : cellOfRank_) c = permSpare_[c];
}

// Sets searches_ (for each pair of levels, which one probes the other, by the cost model with
// the counted cells of each level) and density_.
template <int D, class T>
void HGrid<D, T>::chooseDirections() {
  searches_.fill(0);
  if (levelCount_ < 2) return;
  std::array<LevelModel, kLevelLimit> model;
  for (int level = 0; level < levelCount_; ++level) {
    model[level].count = levelObjectBegin_[level + 1] - levelObjectBegin_[level];
    model[level].cells = levelCellBegin_[level + 1] - levelCellBegin_[level];
    model[level].cell = cellSize_[level];
    model[level].inverse = invCell_[level];
    model[level].mean = meanExtent_[level];
    model[level].margin = margin_[level];
    double domainCells = 1.0;
    for (int k = 0; k < D; ++k) {
      domainCells *= std::max(1.0, std::min(span_[k] * invCell_[level], 1e18));
    }
    model[level].domainCells = domainCells;
    density_[level] = model[level].count / domainCells;
  }
  for (int coarse = 1; coarse < levelCount_; ++coarse) {
    for (int fine = 0; fine < coarse; ++fine) {
      bool fromCoarse = false;
      crossCost(model[coarse], model[fine], fromCoarse);
      if (fromCoarse) {
        searches_[coarse] |= uint64_t{1} << fine;
      } else {
        searches_[fine] |= uint64_t{1} << coarse;
      }
    }
  }
}

// Appends to out the pairs level `level` is responsible for: pairs inside each cell, pairs with
// the forward neighbour cells, and pairs with the other levels it probes.
template <int D, class T>
void HGrid<D, T>::searchLevel(int level, PairSink& sink) {
  const uint32_t cellBegin = levelCellBegin_[level], cellEnd = levelCellBegin_[level + 1];
  const bool alone = cellEnd - cellBegin == 1;
  // The probes are software-pipelined: the neighbours of the next cell are hashed and their
  // filter words prefetched while this cell is probed, and the boxes of the neighbours found
  // are prefetched before the tests, so cache misses overlap with work instead of stalling it.
  std::array<std::array<Coords, kHalfStencil>, 2> keys;
  std::array<std::array<uint64_t, kHalfStencil>, 2> hashes;
  std::array<uint32_t, kHalfStencil> found;
  auto prepare = [&](uint32_t c) {
    auto& k2 = keys[c & 1];
    auto& h2 = hashes[c & 1];
    for (int i = 0; i < kHalfStencil; ++i) {
      for (int k = 0; k < D; ++k) k2[i][k] = cells_[c].key[k] + kForward[i][k];
      h2[i] = hashOf(level, k2[i]);
      __builtin_prefetch(&filter_[filterBase_[level] + ((h2[i] >> filterShift_[level]) >> 6)]);
    }
  };
  if (!alone) prepare(cellBegin);
  for (uint32_t c = cellBegin; c < cellEnd; ++c) {
    const Cell& cell = cells_[c];
    int nFound = 0;
    if (!alone) {
      if (c + 1 < cellEnd) prepare(c + 1);
      for (int i = 0; i < kHalfStencil; ++i) {
        const uint32_t other = find(level, keys[c & 1][i], hashes[c & 1][i]);
        if (other != kEmpty) {
          __builtin_prefetch(&sortedBox_[cells_[other].begin]);
          found[nFound++] = other;
        }
      }
    }
    for (uint32_t x = cell.begin; x + 1 < cell.end; ++x) testRow(x, x + 1, cell.end, sink);
    for (int i = 0; i < nFound; ++i) {
      crossPairs(cell.begin, cell.end, cells_[found[i]].begin, cells_[found[i]].end, sink);
    }
    if (searches_[level] == 0) continue;
    if (c == cellBegin) {
      for (RangeCache& cache : rangeCache_) cache.count = kNoRange;
    }
    // One range for the whole cell: its objects share most of the cells they cover.
    Box<D, T> cover = sortedBox_[cell.begin];
    for (uint32_t x = cell.begin + 1; x < cell.end; ++x) {
      for (int k = 0; k < D; ++k) {
        cover.lo[k] = std::min(cover.lo[k], sortedBox_[x].lo[k]);
        cover.hi[k] = std::max(cover.hi[k], sortedBox_[x].hi[k]);
      }
    }
    for (uint64_t mask = searches_[level]; mask != 0; mask &= mask - 1) {
      const int other = std::countr_zero(mask);
      if (cell.end - cell.begin > 1) {
        // Several objects in one cell: their common range is probed once, but every object is
        // tested against everything found in it. For large objects over a fine level each
        // one's own range probes and tests less, so the model decides.
        const double common = rangeCells(cover, other);
        if (common > kRangeCells) {
          const double n = cell.end - cell.begin;
          double own = 0.0;
          for (uint32_t x = cell.begin; x < cell.end; ++x) own += rangeCells(sortedBox_[x], other);
          const double perCell = density_[other];
          if (common * (1.0 + kTestCost * n * perCell) > own * (1.0 + kTestCost * perCell)) {
            for (uint32_t x = cell.begin; x < cell.end; ++x) {
              searchOtherLevel(x, x + 1, sortedBox_[x], other, sink);
            }
            continue;
          }
        }
      }
      searchOtherLevel(cell.begin, cell.end, cover, other, sink);
    }
  }
}

// Returns the number of cells of level `other` that searchOtherLevel visits for `box`.
// Changes nothing.
template <int D, class T>
double HGrid<D, T>::rangeCells(const Box<D, T>& box, int other) const {
  double count = 1.0;
  for (int k = 0; k < D; ++k) {
    count *=
        static_cast<double>(coordOf(box.hi[k], k, other) - lowCoordOf(box.lo[k], k, other) + 1);
  }
  return count;
}

// Appends to sink every overlapping pair of an object in positions [xb, xe) (whose boxes
// `cover` bounds) with an object of level `other`.
template <int D, class T>
void HGrid<D, T>::searchOtherLevel(uint32_t xb, uint32_t xe, const Box<D, T>& cover, int other,
                                   PairSink& sink) {
  // An object of `other` that overlaps `cover` has its lo corner between cover.lo minus the
  // largest extent of `other` and cover.hi.
  Coords lo, hi;
  double count = 1.0;
  for (int k = 0; k < D; ++k) {
    lo[k] = lowCoordOf(cover.lo[k], k, other);
    hi[k] = coordOf(cover.hi[k], k, other);
    count *= static_cast<double>(hi[k] - lo[k] + 1);
  }
  // Cells in Morton order that are much finer than `other` mostly share their range there with
  // the cell before, so small ranges are remembered with the cells found in them.
  RangeCache& cache = rangeCache_[other];
  uint32_t* remembered = rangeFound_.data() + other * kRangeCells;
  if (cache.count != kNoRange) {
    bool inside = true;
    for (int k = 0; k < D; ++k) inside &= cache.lo[k] <= lo[k] && hi[k] <= cache.hi[k];
    if (inside) {
      for (uint32_t i = 0; i < cache.count; ++i) {
        const Cell& candidate = cells_[remembered[i]];
        crossPairs(xb, xe, candidate.begin, candidate.end, sink);
      }
      return;
    }
  }
  const uint32_t first = levelCellBegin_[other], last = levelCellBegin_[other + 1];
  const bool remember = count <= kRangeCells;
  if (remember) {
    cache.lo = lo;
    cache.hi = hi;
    cache.count = 0;
  }
  if (count * kProbeCost > static_cast<double>(last - first)) {
    for (uint32_t c = first; c < last; ++c) {
      const Cell& candidate = cells_[c];
      bool inside = true;
      for (int k = 0; k < D; ++k) {
        inside &= candidate.key[k] >= lo[k] && candidate.key[k] <= hi[k];
      }
      if (inside) {
        crossPairs(xb, xe, candidate.begin, candidate.end, sink);
        if (remember) remembered[cache.count++] = c;
      }
    }
    return;
  }
  Coords key = lo;
  for (;;) {
    const uint32_t c = find(other, key);
    if (c != kEmpty) {
      crossPairs(xb, xe, cells_[c].begin, cells_[c].end, sink);
      if (remember) remembered[cache.count++] = c;
    }
    int k = D - 1;
    while (k >= 0 && key[k] == hi[k]) {
      key[k] = lo[k];
      --k;
    }
    if (k < 0) break;
    ++key[k];
  }
}

// Compiled once, in src/search (see search/configs.hpp).
DEMLAB_SEARCH_CONFIGS(DEMLAB_SEARCH_EXTERN_CLASS, HGrid)

}  // namespace demlab::search
