#include <gtest/gtest.h>

#include <memory>

#include <algorithm>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "core/handle.hpp"
#include "core/name_lookup.hpp"

namespace demlab {
namespace core_lookup_test {

struct ElementKind;
using Element = Handle<ElementKind>;
using Names = NameLookup<Element>;
using Tags = TagTable<ElementKind>;
using SV = std::vector<std::string_view>;

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

TEST(NameLookup, NamesAndHandlesBothWays) {
  Names names("element");
  const Element a{0, 1}, b{1, 1};
  names.add("foo", a);
  names.add("bar", b);
  EXPECT_EQ(names.get("foo"), a);
  EXPECT_EQ(names.find("bar"), b);
  EXPECT_EQ(names.find("baz"), std::nullopt);
  EXPECT_EQ(names.nameOf(a), "foo");
  EXPECT_EQ(names.nameOf(Element{2, 1}), std::nullopt);
  EXPECT_EQ(names.names(), (SV{"bar", "foo"}));  // sorted
  EXPECT_EQ(names.size(), 2u);
}

TEST(NameLookup, CopiesAreIndependentOfTheirSource) {
  const Element a{0, 1}, b{1, 1};
  auto source = std::make_unique<Names>("element");
  source->add("foo", a);
  Names copy(*source);
  Names assigned("element");
  assigned.add("bar", b);
  assigned = *source;
  source.reset();  // a copy that pointed into the source would now read freed memory
  EXPECT_EQ(copy.nameOf(a), "foo");
  EXPECT_EQ(assigned.nameOf(a), "foo");
  EXPECT_EQ(assigned.find("bar"), std::nullopt);
  EXPECT_EQ(assigned.nameOf(b), std::nullopt);
  Names moved(std::move(copy));
  EXPECT_EQ(moved.nameOf(a), "foo");
}

TEST(NameLookup, ErrorsUseTclWordingAndChangeNothing) {
  Names names("element");
  const Element a{0, 1}, b{1, 1};
  names.add("foo", a);
  expectError([&] { names.add("foo", b); }, "element \"foo\" already exists", {"EXISTS", "NAME"});
  expectError([&] { names.get("nope"); }, "no element named \"nope\"", {"LOOKUP", "NAME"});
  expectError([&] { names.add("other", a); },
              "can't name element \"other\": it is already named \"foo\"", {"EXISTS", "NAME"});
  for (const char* bad : {"", "3x", "-radius", " x", "17"}) {
    expectError([&] { names.add(bad, b); },
                "bad element name \"" + std::string(bad) + "\": must start with a letter or \"_\"",
                {"VALUE", "NAME"});
  }
  EXPECT_EQ(names.names(), (SV{"foo"}));
  EXPECT_EQ(names.nameOf(b), std::nullopt);
  names.add("_x9", b);
  names.add("\xCE\xB1", Element{2, 1});  // "α": non-ASCII letters are letters
  EXPECT_EQ(names.size(), 3u);
}

TEST(NameLookup, RenameMovesTheNameOrFailsWhole) {
  Names names("element");
  const Element a{0, 1}, b{1, 1};
  names.add("foo", a);
  names.add("bar", b);
  names.rename("foo", "zed");
  EXPECT_EQ(names.get("zed"), a);
  EXPECT_EQ(names.nameOf(a), "zed");
  EXPECT_EQ(names.find("foo"), std::nullopt);
  names.rename("zed", "zed");  // a no-op, not a clash with itself
  EXPECT_EQ(names.get("zed"), a);
  expectError([&] { names.rename("zed", "bar"); }, "element \"bar\" already exists",
              {"EXISTS", "NAME"});
  expectError([&] { names.rename("foo", "qux"); }, "no element named \"foo\"", {"LOOKUP", "NAME"});
  expectError([&] { names.rename("zed", "9"); },
              "bad element name \"9\": must start with a letter or \"_\"", {"VALUE", "NAME"});
  EXPECT_EQ(names.names(), (SV{"bar", "zed"}));
  EXPECT_EQ(names.nameOf(a), "zed");
  EXPECT_EQ(names.nameOf(b), "bar");
}

TEST(NameLookup, RemoveFreesTheNameForReuse) {
  Names names("wall");
  const Element a{0, 1}, c{0, 3};
  names.add("lid", a);
  EXPECT_TRUE(names.remove(a));
  EXPECT_FALSE(names.remove(a));
  EXPECT_EQ(names.find("lid"), std::nullopt);
  names.add("lid", c);  // the slot's next object may take the name
  EXPECT_EQ(names.get("lid"), c);
  std::vector<std::string> seen;
  names.forEach([&](std::string_view n, Element h) {
    seen.emplace_back(n);
    EXPECT_EQ(h, c);
  });
  EXPECT_EQ(seen, (std::vector<std::string>{"lid"}));
  names.clear();
  EXPECT_EQ(names.size(), 0u);
}

TEST(TagTable, TagsBothWaysInHistoryOrder) {
  Tags tags;
  const Element a{0, 1}, b{1, 1}, c{2, 1};
  EXPECT_TRUE(tags.add(b, "bed"));
  EXPECT_TRUE(tags.add(a, "bed"));
  EXPECT_TRUE(tags.add(a, "top"));
  EXPECT_TRUE(tags.add(c, "bed"));
  EXPECT_FALSE(tags.add(a, "bed"));  // idempotent, and keeps the first position
  EXPECT_EQ(tags.objects("bed"), (std::vector<Element>{b, a, c}));
  EXPECT_EQ(tags.tagsOf(a), (SV{"bed", "top"}));
  EXPECT_EQ(tags.count("bed"), 3u);
  EXPECT_TRUE(tags.has(a, "top"));
  EXPECT_FALSE(tags.has(b, "top"));
  EXPECT_TRUE(tags.objects("nothing").empty());  // an unknown tag is empty, not an error
  EXPECT_EQ(tags.count("nothing"), 0u);
  EXPECT_EQ(tags.tags(), (SV{"bed", "top"}));
}

TEST(TagTable, RemovingTagsAndObjects) {
  Tags tags;
  const Element a{0, 1}, b{1, 1}, c{2, 1};
  for (Element h : {a, b, c}) tags.add(h, "bed");
  tags.add(b, "red");
  tags.add(b, "blue");
  EXPECT_TRUE(tags.remove(b, "red"));
  EXPECT_FALSE(tags.remove(b, "red"));
  EXPECT_FALSE(tags.remove(b, "unknown"));
  EXPECT_EQ(tags.tagsOf(b), (SV{"bed", "blue"}));
  EXPECT_EQ(tags.tags(), (SV{"bed", "blue"}));  // "red" has no objects left
  EXPECT_EQ(tags.removeObject(b), 2u);
  EXPECT_EQ(tags.removeObject(b), 0u);
  EXPECT_TRUE(tags.tagsOf(b).empty());
  EXPECT_EQ(tags.objects("bed"), (std::vector<Element>{a, c}));
  EXPECT_TRUE(tags.objects("blue").empty());
}

TEST(TagTable, BadTagsAreRefused) {
  Tags tags;
  for (const char* bad : {"", "12", "-all"}) {
    expectError(
        [&] {
          tags.add(Element{0, 1}, bad);
        },
        "bad tag \"" + std::string(bad) + "\": must start with a letter or \"_\"",
        {"VALUE", "TAG"});
  }
  EXPECT_TRUE(tags.tagsOf(Element{0, 1}).empty());
  EXPECT_TRUE(tags.tags().empty());
}

TEST(TagTable, ANewObjectInAReusedSlotDoesNotInheritTags) {
  Tags tags;
  const Element old{4, 1}, reused{4, 3};
  tags.add(old, "bed");
  tags.add(Element{5, 1}, "bed");
  EXPECT_TRUE(tags.tagsOf(reused).empty());
  EXPECT_FALSE(tags.has(reused, "bed"));
  tags.add(reused, "lid");  // the old object's tags, never removed, are dropped now
  EXPECT_EQ(tags.objects("bed"), (std::vector<Element>{Element{5, 1}}));
  EXPECT_TRUE(tags.tagsOf(old).empty());
  EXPECT_EQ(tags.tagsOf(reused), (SV{"lid"}));
}

TEST(TagTable, CompactionKeepsOrderAndBoundsStorage) {
  Tags tags;
  std::vector<Element> all;
  for (uint32_t i = 0; i < 1000; ++i) {
    all.push_back(Element{i, 1});
    tags.add(all.back(), "bed");
    if (i % 3 == 0) tags.add(all.back(), "third");
  }
  std::vector<Element> kept;
  for (uint32_t i = 0; i < 1000; ++i) {
    if (i % 10 == 7) {
      kept.push_back(all[i]);
    } else {
      tags.removeObject(all[i]);
    }
    EXPECT_LE(tags.storedMembers("bed"), 2 * tags.count("bed") + 16);
  }
  EXPECT_EQ(tags.objects("bed"), kept);
  for (Element h : kept) {
    // Positions recorded for each object were fixed up: removing by tag still works.
    EXPECT_TRUE(tags.remove(h, "bed"));
  }
  EXPECT_EQ(tags.count("bed"), 0u);
  EXPECT_EQ(tags.storedMembers("bed"), 0u);
  EXPECT_EQ(tags.tags(), (SV{"third"}));
}

TEST(TagTable, MatchesAnOrderedListOracleUnderRandomOperations) {
  Tags tags;
  const std::vector<std::string> names = {"a", "b", "c", "d"};
  std::map<std::string, std::vector<Element>> oracle;  // tag -> objects in tagging order
  std::vector<uint32_t> generation(64, 1);
  std::mt19937 rng(3);
  for (int step = 0; step < 30000; ++step) {
    const uint32_t slot = rng() % 64;
    const Element h{slot, generation[slot]};
    const std::string& tag = names[rng() % names.size()];
    auto& list = oracle[tag];
    const auto pos = std::find(list.begin(), list.end(), h);
    switch (rng() % 4) {
      case 0:
      case 1:
        EXPECT_EQ(tags.add(h, tag), pos == list.end());
        if (pos == list.end()) list.push_back(h);
        break;
      case 2:
        EXPECT_EQ(tags.remove(h, tag), pos != list.end());
        if (pos != list.end()) list.erase(pos);
        break;
      default:
        if (rng() % 8 == 0) {  // the object dies; its slot gets a new generation
          tags.removeObject(h);
          for (auto& [t, l] : oracle) std::erase(l, h);
          generation[slot] += 2;
        }
    }
    if (step % 101 == 0) {
      for (const auto& [t, l] : oracle) ASSERT_EQ(tags.objects(t), l) << "tag " << t;
      for (uint32_t s = 0; s < 64; ++s) {
        const Element e{s, generation[s]};
        std::vector<std::string_view> expect;
        for (const auto& [t, l] : oracle) {
          if (std::find(l.begin(), l.end(), e) != l.end()) expect.push_back(t);
        }
        SV got = tags.tagsOf(e);
        std::sort(got.begin(), got.end());
        ASSERT_EQ(got, expect);
      }
    }
  }
}

}  // namespace core_lookup_test
}  // namespace demlab
