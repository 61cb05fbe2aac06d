#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <set>
#include <type_traits>
#include <vector>

#include "core/handle.hpp"

namespace demlab {
namespace core_handle_test {

struct ElementKind;
struct WallKind;
using Grain = Handle<ElementKind>;
using Pool = HandlePool<ElementKind>;

static_assert(!std::is_convertible_v<Handle<ElementKind>, Handle<WallKind>>);
static_assert(sizeof(Grain) == 8);

void expectError(auto&& f, const std::string& message, std::vector<std::string> code) {
  try {
    f();
    FAIL() << "expected an error: " << message;
  } catch (const Error& e) {
    EXPECT_EQ(e.what(), message);
    code.insert(code.begin(), "DEMLAB");
    EXPECT_EQ(e.code(), code);
  }
}

TEST(Handle, NullHandleAndBits) {
  Grain h;
  EXPECT_TRUE(h.isNull());
  const Grain g{17, 3};
  EXPECT_FALSE(g.isNull());
  EXPECT_EQ(g.bits(), (uint64_t{3} << 32) | 17);
  EXPECT_EQ(Grain::fromBits(g.bits()), g);
  EXPECT_EQ(toString(g), std::to_string((uint64_t{1} << 32) | 17));  // its script id
  EXPECT_EQ(toString(Grain{}), "0:0");
  EXPECT_LT((Grain{4, 3}), (Grain{5, 1}));  // slot order, then generation
}

TEST(HandlePool, AllocatesDistinctLiveHandlesInDenseOrder) {
  Pool pool("grain");
  std::vector<Grain> hs;
  for (int i = 0; i < 5; ++i) hs.push_back(pool.allocate());
  EXPECT_EQ(pool.size(), 5u);
  for (uint32_t i = 0; i < 5; ++i) {
    EXPECT_TRUE(pool.valid(hs[i]));
    EXPECT_EQ(pool.denseIndex(hs[i]), i);
    EXPECT_EQ(pool.handleAt(i), hs[i]);
    EXPECT_EQ(hs[i].generation % 2, 1u);
  }
  EXPECT_FALSE(pool.valid(Grain{}));
  EXPECT_TRUE(std::equal(pool.begin(), pool.end(), hs.begin(), hs.end()));
}

TEST(HandlePool, FreedHandleIsStaleAndItsSlotIsReusedWithANewGeneration) {
  Pool pool("grain");
  const Grain a = pool.allocate();
  const Grain b = pool.allocate();
  pool.free(a);
  EXPECT_FALSE(pool.valid(a));
  EXPECT_TRUE(pool.valid(b));
  const Grain c = pool.allocate();
  EXPECT_EQ(c.index, a.index);            // the slot is recycled...
  EXPECT_NE(c.generation, a.generation);  // ...under a new generation
  EXPECT_FALSE(pool.valid(a));
  EXPECT_TRUE(pool.valid(c));
  expectError([&] { pool.denseIndex(a); }, "invalid grain id \"0\": the grain was removed",
              {"LOOKUP", "HANDLE"});
  expectError([&] { pool.free(a); }, "invalid grain id \"0\": the grain was removed",
              {"LOOKUP", "HANDLE"});
  expectError(
      [&] {
        pool.denseIndex(Grain{9, 1});
      },
      "invalid grain id \"9\": no such grain", {"LOOKUP", "HANDLE"});
  expectError(
      [&] {
        pool.denseIndex(Grain{0, 7});
      },
      "invalid grain id \"12884901888\": no such grain", {"LOOKUP", "HANDLE"});
  expectError([&] { pool.free(Grain{}); }, "invalid grain id \"0:0\": no such grain",
              {"LOOKUP", "HANDLE"});
  EXPECT_EQ(pool.size(), 2u);  // the failed calls changed nothing
  EXPECT_EQ(pool.findDense(a), Pool::kNpos);
}

TEST(HandlePool, SwapRemoveKeepsParallelDenseArraysConsistent) {
  // Payload arrays mirror the pool through the SwapRemove moves; an ordered map is the oracle.
  Pool pool("grain");
  std::vector<int> payload;
  std::vector<double> other;
  std::map<uint64_t, int> oracle;
  std::set<uint64_t> everIssued;
  std::mt19937 rng(42);
  int next = 0;
  for (int step = 0; step < 20000; ++step) {
    const bool grow = oracle.empty() || rng() % 100 < 55;
    if (grow) {
      const Grain h = pool.allocate();
      EXPECT_TRUE(everIssued.insert(h.bits()).second) << "handle issued twice";
      ASSERT_EQ(pool.denseIndex(h), payload.size());
      payload.push_back(next);
      other.push_back(next * 0.5);
      oracle[h.bits()] = next++;
    } else {
      auto it = oracle.begin();
      std::advance(it, rng() % oracle.size());
      const Grain h = Grain::fromBits(it->first);
      const SwapRemove m = pool.free(h);
      ASSERT_EQ(m.from, payload.size() - 1);
      applySwapRemove(payload, m);
      applySwapRemove(other, m);
      oracle.erase(it);
      EXPECT_FALSE(pool.valid(h));
    }
    if (step % 97 == 0 || step > 19900) {
      ASSERT_EQ(pool.size(), oracle.size());
      for (auto [bits, value] : oracle) {
        const uint32_t d = pool.denseIndex(Grain::fromBits(bits));
        ASSERT_EQ(payload[d], value);
        ASSERT_EQ(other[d], value * 0.5);
      }
      std::set<uint64_t> iterated;
      for (Grain h : pool.handles()) iterated.insert(h.bits());
      ASSERT_EQ(iterated.size(), oracle.size());
      for (auto [bits, value] : oracle) ASSERT_TRUE(iterated.contains(bits));
    }
  }
}

TEST(HandlePool, ClearLeavesEveryOldHandleStale) {
  Pool pool;
  const Grain a = pool.allocate(), b = pool.allocate();
  pool.clear();
  EXPECT_TRUE(pool.empty());
  EXPECT_FALSE(pool.valid(a));
  EXPECT_FALSE(pool.valid(b));
  const Grain c = pool.allocate(), d = pool.allocate();
  EXPECT_NE(c, a);
  EXPECT_NE(c, b);
  EXPECT_NE(d, a);
  EXPECT_NE(d, b);
}

TEST(HandlePool, RestoredStateContinuesWithTheSameHandles) {
  Pool pool;
  std::vector<Grain> live;
  for (int i = 0; i < 10; ++i) live.push_back(pool.allocate());
  pool.free(live[3]);
  pool.free(live[7]);
  pool.free(live[0]);
  const Pool::State saved = pool.saveState();
  Pool copy;
  copy.restoreState(saved);
  for (int i = 0; i < 5; ++i) {
    const Grain x = pool.allocate(), y = copy.allocate();
    EXPECT_EQ(x, y);
    EXPECT_EQ(pool.denseIndex(x), copy.denseIndex(y));
  }
  EXPECT_TRUE(std::equal(pool.begin(), pool.end(), copy.begin(), copy.end()));
}

TEST(HandlePool, RestoreRejectsAnInconsistentStateAndChangesNothing) {
  Pool pool("grain");
  const Grain a = pool.allocate();
  Pool::State st = pool.saveState();
  st.generations.push_back(2);  // a free slot missing from the free list
  expectError([&] { pool.restoreState(st); },
              "bad grain handle state: slot 1 is neither in use nor free", {"VALUE", "HANDLE"});
  st = pool.saveState();
  st.dense.push_back(st.dense[0]);
  expectError([&] { pool.restoreState(st); },
              "bad grain handle state: dense entry 1 is not a live slot listed once",
              {"VALUE", "HANDLE"});
  st = pool.saveState();
  st.freeSlots.push_back(0);
  expectError([&] { pool.restoreState(st); },
              "bad grain handle state: free slot 0 is live, retired or listed twice",
              {"VALUE", "HANDLE"});
  EXPECT_TRUE(pool.valid(a));
  EXPECT_EQ(pool.size(), 1u);
}

TEST(HandlePool, ASlotRetiresInsteadOfRepeatingAGeneration) {
  // Put slot 0 at its last odd generation through a restored state, then free it.
  Pool pool;
  pool.restoreState({{0xFFFFFFFFu}, {}, {Grain{0, 0xFFFFFFFFu}}});
  const Grain old{0, 0xFFFFFFFFu};
  ASSERT_TRUE(pool.valid(old));
  pool.free(old);
  EXPECT_FALSE(pool.valid(old));
  const Grain fresh = pool.allocate();
  EXPECT_EQ(fresh.index, 1u);  // slot 0 is not recycled
  EXPECT_EQ(fresh.generation, 1u);
  EXPECT_FALSE(pool.valid(Grain{0, 1}));  // its first generation does not come back to life
  EXPECT_EQ(pool.slotCount(), 2u);
}

}  // namespace core_handle_test
}  // namespace demlab
