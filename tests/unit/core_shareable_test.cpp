#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/shareable.hpp"

namespace demlab {
namespace core_shareable_test {

// A component that counts its copies and its live instances.
struct Material {
  static inline int copies = 0;
  static inline int alive = 0;
  double density = 2500;
  std::string name = "glass";
  Material() { ++alive; }
  Material(double d, std::string n) : density(d), name(std::move(n)) { ++alive; }
  Material(const Material& o) : density(o.density), name(o.name) {
    ++copies;
    ++alive;
  }
  Material& operator=(const Material&) = default;
  ~Material() { --alive; }
};

struct Geometry {
  virtual ~Geometry() = default;
  virtual std::string kind() const = 0;
  double scale = 1;
};
struct Sphere : Geometry {
  explicit Sphere(double r) : radius(r) {}
  std::string kind() const override { return "sphere"; }
  double radius;
};

class ShareableTest : public ::testing::Test {
 protected:
  void SetUp() override { Material::copies = 0; }
  void TearDown() override { EXPECT_EQ(Material::alive, 0) << "a Material leaked"; }
};

TEST_F(ShareableTest, ShallowCopiesShareOneValue) {
  auto glass = Shareable<Material>::make(2500.0, "glass");
  std::vector<Shareable<Material>> grains(1000, glass);
  EXPECT_EQ(Material::alive, 1);
  EXPECT_EQ(Material::copies, 0);
  EXPECT_EQ(glass.useCount(), 1001);
  EXPECT_TRUE(grains[999].sharesWith(glass));
  EXPECT_EQ(grains[5]->density, 2500);
  const auto shallow = glass.clone(CloneDepth::kShallow);
  EXPECT_TRUE(shallow.sharesWith(glass));
  EXPECT_EQ(Material::copies, 0);
}

TEST_F(ShareableTest, MakeUniqueCopiesOnlyWhenShared) {
  auto glass = Shareable<Material>::make(2500.0, "glass");
  auto grain = glass;
  grain.makeUnique().density = 1000;  // changing one grain's material...
  EXPECT_EQ(glass->density, 2500);    // ...leaves the others' alone
  EXPECT_EQ(grain->density, 1000);
  EXPECT_FALSE(grain.sharesWith(glass));
  EXPECT_EQ(Material::copies, 1);
  EXPECT_EQ(Material::alive, 2);
  const Material* before = grain.get();
  grain.makeUnique().name = "rubber";  // already unique: no copy, same object
  EXPECT_EQ(grain.get(), before);
  EXPECT_EQ(Material::copies, 1);
  EXPECT_FALSE(glass.isShared());
  EXPECT_EQ(glass.useCount(), 1);
}

TEST_F(ShareableTest, DeepCloneOwnsAFreshCopy) {
  auto glass = Shareable<Material>::make(2500.0, "glass");
  auto copy = glass.clone(CloneDepth::kDeep);
  EXPECT_FALSE(copy.sharesWith(glass));
  EXPECT_EQ(Material::copies, 1);
  EXPECT_EQ(copy->name, "glass");
  copy.makeUnique().name = "steel";  // a deep clone is unique already: no further copy
  EXPECT_EQ(Material::copies, 1);
  EXPECT_EQ(glass->name, "glass");
}

TEST_F(ShareableTest, EmptyShareable) {
  Shareable<Material> none;
  EXPECT_FALSE(none);
  EXPECT_EQ(none.get(), nullptr);
  EXPECT_EQ(none.useCount(), 0);
  EXPECT_FALSE(none.sharesWith(Shareable<Material>()));
  EXPECT_FALSE(none.clone(CloneDepth::kDeep));
  none = Shareable<Material>::make();
  EXPECT_TRUE(none);
  EXPECT_EQ(none->density, 2500);
}

TEST_F(ShareableTest, ClonesKeepTheDynamicTypeWithoutAVirtualClone) {
  auto ball = Shareable<Geometry>::make<Sphere>(0.25);
  auto deep = ball.clone(CloneDepth::kDeep);
  ASSERT_NE(dynamic_cast<const Sphere*>(deep.get()), nullptr);
  EXPECT_EQ(static_cast<const Sphere&>(*deep).radius, 0.25);
  auto shared = ball;
  shared.makeUnique().scale = 2;
  EXPECT_EQ(shared->kind(), "sphere");
  EXPECT_EQ(static_cast<const Sphere&>(*shared).radius, 0.25);
  EXPECT_EQ(ball->scale, 1);
  EXPECT_EQ(shared->scale, 2);
}

}  // namespace core_shareable_test
}  // namespace demlab
