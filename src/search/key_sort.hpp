// Linear-time sorting of small integer keys, shared by the grid algorithms: a counting sort
// when the keys span a range comparable to their number, an LSD radix sort (8-bit digits,
// skipping digits every key shares) otherwise, and insertion sort for tiny inputs. Time is
// O(m + range) or O(m * digits), never O(m log m), so a grid stays linear in N whatever the
// spread of the scene.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

namespace demlab::search {

// Reusable scratch space for sortByKey; keeping it in the caller makes repeated sorts
// allocation-free once the buffers have grown to the largest input seen.
struct KeySortScratch {
  std::vector<uint32_t> counts;
  std::vector<uint32_t> items;
  std::vector<uint32_t> keys;
  std::vector<uint32_t> keysOut;

  // Returns the bytes held by the buffers.
  std::size_t bytes() const {
    return 4 * (counts.capacity() + items.capacity() + keys.capacity() + keysOut.capacity());
  }
};

// Sorts items[0..m) stably by key(item) into out[0..m); key returns uint32_t. Changes `out`
// and `scratch`, never `items`. Returns nothing.
template <class KeyFn>
void sortByKey(const uint32_t* items, uint32_t* out, std::size_t m, KeyFn key,
               KeySortScratch& scratch) {
  if (m == 0) return;
  // Runs that arrive in order (common: Subdividers receive their objects nearly sorted)
  // cost one comparison each.
  std::size_t ordered = 1;
  while (ordered < m && key(items[ordered - 1]) <= key(items[ordered])) ++ordered;
  if (ordered == m) {
    std::copy(items, items + m, out);
    return;
  }
  if (m <= 24) {
    // Insertion sort: cheaper than any counting pass for the handful of objects in a row.
    for (std::size_t i = 0; i < m; ++i) {
      const uint32_t item = items[i];
      const uint32_t k = key(item);
      std::size_t j = i;
      while (j > 0 && key(out[j - 1]) > k) {
        out[j] = out[j - 1];
        --j;
      }
      out[j] = item;
    }
    return;
  }
  uint32_t kmin = UINT32_MAX, kmax = 0;
  for (std::size_t i = 0; i < m; ++i) {
    const uint32_t k = key(items[i]);
    kmin = std::min(kmin, k);
    kmax = std::max(kmax, k);
  }
  const uint64_t range = uint64_t{kmax} - kmin + 1;
  auto& counts = scratch.counts;
  if (range <= 4 * m + 256) {
    counts.assign(range + 1, 0);
    for (std::size_t i = 0; i < m; ++i) ++counts[key(items[i]) - kmin + 1];
    for (std::size_t b = 1; b <= range; ++b) counts[b] += counts[b - 1];
    for (std::size_t i = 0; i < m; ++i) out[counts[key(items[i]) - kmin]++] = items[i];
    return;
  }
  // LSD radix sort on (key - kmin), 8 bits a pass, passes only over the digits in use.
  auto& keys = scratch.keys;
  auto& keysOut = scratch.keysOut;
  auto& tmp = scratch.items;
  keys.resize(m);
  keysOut.resize(m);
  tmp.resize(m);
  for (std::size_t i = 0; i < m; ++i) {
    keys[i] = key(items[i]) - kmin;
    tmp[i] = items[i];
  }
  const uint32_t spread = kmax - kmin;
  counts.resize(257);
  for (int shift = 0; shift < 32 && (spread >> shift) != 0; shift += 8) {
    std::fill(counts.begin(), counts.end(), 0u);
    for (std::size_t i = 0; i < m; ++i) ++counts[((keys[i] >> shift) & 0xFF) + 1];
    for (int b = 1; b <= 256; ++b) counts[b] += counts[b - 1];
    for (std::size_t i = 0; i < m; ++i) {
      const uint32_t slot = counts[(keys[i] >> shift) & 0xFF]++;
      out[slot] = tmp[i];
      keysOut[slot] = keys[i];
    }
    std::copy(out, out + m, tmp.begin());
    keys.swap(keysOut);
  }
  std::copy(tmp.begin(), tmp.begin() + static_cast<std::ptrdiff_t>(m), out);
}

// Sorts the indices 0..m-1 stably by keys[i] into out[0..m), the same order as sortByKey on
// the items 0..m-1 with key i -> keys[i], without an array of items: the first pass numbers
// them, and keys[] serves as one of the radix sort's key buffers. Changes `out`, `scratch`
// and `keys` (left in an unspecified state).
inline void sortIndicesByKey(uint32_t* keys, std::size_t m, uint32_t* out,
                             KeySortScratch& scratch) {
  if (m == 0) return;
  uint32_t kmin = UINT32_MAX, kmax = 0;
  bool ordered = true;
  for (std::size_t i = 0; i < m; ++i) {
    kmin = std::min(kmin, keys[i]);
    kmax = std::max(kmax, keys[i]);
    ordered &= i == 0 || keys[i - 1] <= keys[i];
  }
  if (ordered) {
    for (std::size_t i = 0; i < m; ++i) out[i] = static_cast<uint32_t>(i);
    return;
  }
  const uint64_t range = uint64_t{kmax} - kmin + 1;
  auto& counts = scratch.counts;
  if (range <= 4 * m + 256) {
    counts.assign(range + 1, 0);
    for (std::size_t i = 0; i < m; ++i) ++counts[keys[i] - kmin + 1];
    for (std::size_t b = 1; b <= range; ++b) counts[b] += counts[b - 1];
    for (std::size_t i = 0; i < m; ++i) out[counts[keys[i] - kmin]++] = static_cast<uint32_t>(i);
    return;
  }
  // LSD radix sort on (key - kmin), 8 bits a pass, passes only over the digits in use. The
  // items and keys go back and forth between (out, keysOut) and (items, keys).
  scratch.items.resize(m);
  scratch.keysOut.resize(m);
  for (std::size_t i = 0; i < m; ++i) keys[i] -= kmin;
  const uint32_t spread = kmax - kmin;
  counts.resize(257);
  const uint32_t* fromItems = nullptr;  // the first pass numbers the items
  uint32_t* fromKeys = keys;
  uint32_t* toItems = out;
  uint32_t* toKeys = scratch.keysOut.data();
  for (int shift = 0; shift < 32 && (spread >> shift) != 0; shift += 8) {
    std::fill(counts.begin(), counts.end(), 0u);
    for (std::size_t i = 0; i < m; ++i) ++counts[((fromKeys[i] >> shift) & 0xFF) + 1];
    for (int b = 1; b <= 256; ++b) counts[b] += counts[b - 1];
    for (std::size_t i = 0; i < m; ++i) {
      const uint32_t slot = counts[(fromKeys[i] >> shift) & 0xFF]++;
      toItems[slot] = fromItems ? fromItems[i] : static_cast<uint32_t>(i);
      toKeys[slot] = fromKeys[i];
    }
    uint32_t* const freeItems = toItems == out ? scratch.items.data() : out;
    uint32_t* const freeKeys = toKeys == keys ? scratch.keysOut.data() : keys;
    fromItems = toItems;
    fromKeys = toKeys;
    toItems = freeItems;
    toKeys = freeKeys;
  }
  if (fromItems != out) std::copy(fromItems, fromItems + m, out);
}

}  // namespace demlab::search
