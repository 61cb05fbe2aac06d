#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "core/type_interaction.hpp"

namespace demlab {
namespace core_type_interaction_test {

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

// Returns "t<i>". (Built with += rather than "t" + to_string(i): the latter trips a false
// -Wrestrict in GCC 12 at -O3, bug 105329.)
std::string typeName(size_t i) {
  std::string s = "t";
  s += std::to_string(i);
  return s;
}

struct Sphere {
  double x, r;
};
struct Plane {
  double x;
};

// Narrow phase routines written for one orientation; each returns the signed gap.
using Gap = double (*)(const void*, const void*);
double sphereSphere(const void* a, const void* b) {
  auto& s = *static_cast<const Sphere*>(a);
  auto& t = *static_cast<const Sphere*>(b);
  return std::abs(t.x - s.x) - s.r - t.r;
}
double spherePlane(const void* a, const void* b) {
  return static_cast<const Sphere*>(a)->x - static_cast<const Sphere*>(a)->r -
         static_cast<const Plane*>(b)->x;
}

TEST(TypeRegistry, DenseIdsByNameAndByClass) {
  TypeRegistry types("geometry type");
  const TypeId s = types.add<Sphere>("sphere");
  const TypeId p = types.add<Plane>("plane");
  const TypeId c = types.add("cylinder");
  EXPECT_EQ(s.value, 0);
  EXPECT_EQ(p.value, 1);
  EXPECT_EQ(c.value, 2);
  EXPECT_EQ(types.id<Plane>(), p);
  EXPECT_EQ(types.get("cylinder"), c);
  EXPECT_EQ(types.find("cone"), std::nullopt);
  EXPECT_EQ(types.name(p), "plane");
  EXPECT_EQ(types.size(), 3u);
  expectError([&] { types.add("sphere"); }, "geometry type \"sphere\" already exists",
              {"EXISTS", "NAME"});
  expectError([&] { types.get("cone"); }, "no geometry type named \"cone\"", {"LOOKUP", "NAME"});
  expectError([&] { types.name(TypeId{9}); }, "unknown geometry type id 9", {"LOOKUP", "TYPE"});
  expectError([&] { types.add<Sphere>("ball"); },
              "C++ class of geometry type \"ball\" is already registered", {"EXISTS", "TYPE"});
  EXPECT_THROW(types.id<int>(), Error);
  EXPECT_EQ(types.size(), 3u);  // failed registrations changed nothing
}

TEST(TypeRegistry, HasALimit) {
  TypeRegistry types;
  for (size_t i = 0; i < TypeRegistry::kMaxTypes; ++i) types.add(typeName(i));
  expectError([&] { types.add("one_more"); }, "too many types: at most 256", {"LIMIT", "TYPE"});
}

TEST(TypeInteractionManager, EachAsymmetricPairIsWrittenOnceAndServesBothOrders) {
  TypeRegistry types("geometry type");
  const TypeId s = types.add("sphere"), p = types.add("plane");
  TypeInteractionManager<Gap> gaps(types, "intersection routine");
  gaps.add(s, s, sphereSphere);
  gaps.add(s, p, spherePlane);
  const Sphere ball{1.0, 0.25};
  const Plane floor{0.5};
  // Both orders reach the one routine, which always sees (sphere, plane).
  EXPECT_DOUBLE_EQ(gaps.dispatch(s, p, &ball, &floor), 0.25);
  EXPECT_DOUBLE_EQ(gaps.dispatch(p, s, &floor, &ball), 0.25);
  EXPECT_FALSE(gaps.get(s, p).swapped());
  EXPECT_TRUE(gaps.get(p, s).swapped());
  EXPECT_FALSE(gaps.get(s, s).swapped());  // a symmetric pair is never swapped
  const Sphere other{2.0, 0.5};
  EXPECT_DOUBLE_EQ(gaps.dispatch(s, s, &ball, &other), 0.25);
  EXPECT_EQ(gaps.get(s, p).fn, gaps.get(p, s).fn);
  EXPECT_FALSE(gaps.has(p, p));
  EXPECT_EQ(gaps.pairs(), (std::vector<std::pair<TypeId, TypeId>>{{s, s}, {s, p}}));
}

TEST(TypeInteractionManager, ErrorsNameBothTypes) {
  TypeRegistry types("geometry type");
  const TypeId s = types.add("sphere"), p = types.add("plane");
  TypeInteractionManager<Gap> gaps(types, "intersection routine");
  gaps.add(s, p, spherePlane);
  expectError([&] { gaps.get(p, p); },
              "no intersection routine for geometry types \"plane\" and \"plane\"",
              {"LOOKUP", "INTERACTION"});
  expectError([&] { gaps.add(p, s, spherePlane); },
              "intersection routine for geometry types \"plane\" and \"sphere\" already exists",
              {"EXISTS", "INTERACTION"});
  expectError([&] { gaps.add(s, TypeId{7}, spherePlane); }, "unknown geometry type id 7",
              {"LOOKUP", "TYPE"});
  expectError([&] { gaps.get(TypeId{7}, s); }, "unknown geometry type id 7", {"LOOKUP", "TYPE"});
  EXPECT_EQ(gaps.find(TypeId{7}, s), nullptr);
  EXPECT_EQ(gaps.pairs().size(), 1u);
  EXPECT_TRUE(gaps.get(p, s).swapped());  // the failed add did not overwrite the mirror
}

TEST(TypeInteractionManager, TypesRegisteredLaterGrowTheTableKeepingEntries) {
  TypeRegistry types;
  const TypeId a = types.add("a"), b = types.add("b");
  // A std::function Fn that records the order its arguments arrive in.
  TypeInteractionManager<std::function<std::string(std::string, std::string, int)>> m(types);
  m.add(a, b, [](std::string x, std::string y, int n) { return x + y + std::to_string(n); });
  std::vector<TypeId> more;
  for (int i = 0; i < 40; ++i) more.push_back(types.add(typeName(i)));
  EXPECT_FALSE(m.has(more[3], a));  // known type, no routine, no error from find()
  m.add(more[39], a, [](std::string x, std::string y, int n) { return y + x + std::to_string(n); });
  EXPECT_EQ(m.dispatch(a, b, "A", "B", 1), "AB1");
  EXPECT_EQ(m.dispatch(b, a, "B", "A", 2), "AB2");
  EXPECT_EQ(m.dispatch(more[39], a, "T", "A", 3), "AT3");
  EXPECT_EQ(m.dispatch(a, more[39], "A", "T", 4), "AT4");
  expectError([&] { m.get(more[0], more[1]); }, "no interaction for types \"t0\" and \"t1\"",
              {"LOOKUP", "INTERACTION"});
}

TEST(TypeInteractionManager, FnMayBeAStructOfRoutines) {
  // A table entry can carry several routines for the pair (intersection and contact law).
  struct Routines {
    int (*intersect)(int, int) = nullptr;
    int (*law)(int) = nullptr;
  };
  TypeRegistry types;
  const TypeId a = types.add("a"), b = types.add("b");
  TypeInteractionManager<Routines> m(types);
  m.add(a, b, Routines{[](int x, int y) { return 10 * x + y; }, [](int o) { return -o; }});
  const auto& e = m.get(b, a);
  ASSERT_TRUE(e.swapped());
  const int x = 2, y = 7;  // objects of types b and a
  EXPECT_EQ(e.swapped() ? e.fn.intersect(y, x) : e.fn.intersect(x, y), 72);
  EXPECT_EQ(e.fn.law(3), -3);
}

}  // namespace core_type_interaction_test
}  // namespace demlab
