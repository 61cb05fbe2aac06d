// The option table (sim/options.hpp): every option's default is the scene's, the one get/set
// pair checks all settings before storing any, and a checkpoint keeps every option.
#include <gtest/gtest.h>

#include <sstream>

#include "sim/options.hpp"
#include "sim/simulation.hpp"
#include "sim_test_util.hpp"

namespace demlab::sim {
namespace sim_options_test {

using testing::codeOf;
using testing::grain;
using testing::material;
using Code = std::vector<std::string>;

class SimOptions : public ::testing::TestWithParam<int> {};

// Returns a value of o other than its default, within its range.
OptionValue otherValue(const OptionSpec& o) {
  switch (o.type) {
    case OptionType::Boolean:
      return !std::get<bool>(o.def);
    case OptionType::Real:
      return std::get<double>(o.def) + 0.25;
    case OptionType::Choice:
      return std::string(o.choices.back() == std::get<std::string>(o.def) ? o.choices.front()
                                                                          : o.choices.back());
  }
  return o.def;
}

// Returns the bytes of s's checkpoint.
std::string saved(const Simulation& s) {
  std::ostringstream out;
  s.save(out);
  return out.str();
}

TEST_P(SimOptions, DefaultsAreTheScenes) {
  auto s = makeSimulation(GetParam());
  for (const OptionSpec& o : optionSpecs()) {
    EXPECT_EQ(s->option(o.group, o.name), o.def) << o.group << " -" << o.name;
  }
}

TEST_P(SimOptions, BadSettingsChangeNothing) {
  const int d = GetParam();
  auto s = makeSimulation(d);
  s->addMaterial("glass", material(1e8, 0.5, 0.5));
  s->addElement(grain({0, 0, 0}, 0.01, "glass"));
  const uint64_t digest = s->stateDigest();
  // The first setting is good, the second not: neither is stored.
  EXPECT_EQ(codeOf([&] {
              s->setOptions({{"watchdog", "overlap", 0.3}, {"watchdog", "energy", -1.0}});
            }),
            (Code{"VALUE", "ENERGY"}));
  EXPECT_EQ(codeOf([&] {
              s->setOptions({{"touch", "on", false}, {"detection", "skin", INFINITY}});
            }),
            (Code{"VALUE", "SKIN"}));
  EXPECT_EQ(codeOf([&] { s->setOption("rotation", "on", std::string("yes")); }),
            (Code{"VALUE", "ON"}));
  EXPECT_EQ(codeOf([&] { s->setOption("watchdog", "nosuch", 1.0); }), (Code{"VALUE", "OPTION"}));
  EXPECT_EQ(codeOf([&] { (void)s->option("nosuch", "on"); }), (Code{"LOOKUP", "MODULE"}));
  EXPECT_EQ(s->stateDigest(), digest);
  EXPECT_EQ(s->option("watchdog", "overlap"), OptionValue(2.0));
}

// Every option set away from its default comes back from a checkpoint and a clone, and setting
// them all back to the defaults gives the default scene's bytes.
TEST_P(SimOptions, CheckpointsKeepEveryOption) {
  const int d = GetParam();
  auto s = makeSimulation(d);
  s->addMaterial("glass", material(1e8, 0.5, 0.5));
  s->addElement(grain({0, 0, 0}, 0.01, "glass"));
  const std::string plain = saved(*s);
  std::vector<OptionSetting> other;
  for (const OptionSpec& o : optionSpecs()) {
    other.push_back({std::string(o.group), std::string(o.name), otherValue(o)});
  }
  s->setOptions(other);
  std::istringstream in(saved(*s));
  auto t = makeSimulation(d);
  t->load(in);
  const auto c = s->clone();
  for (const OptionSetting& o : other) {
    EXPECT_EQ(t->option(o.group, o.name), o.value) << o.group << " -" << o.name;
    EXPECT_EQ(c->option(o.group, o.name), o.value) << o.group << " -" << o.name;
  }
  for (const OptionSpec& o : optionSpecs()) s->setOption(o.group, o.name, o.def);
  EXPECT_EQ(saved(*s), plain);
}

// An option a later build added (here: a name this build does not know) is refused by name.
TEST_P(SimOptions, AnUnknownOptionIsRefused) {
  const int d = GetParam();
  auto s = makeSimulation(d);
  s->setOption("law", "rolling", std::string("off"));
  std::string bytes = testing::editCheckpoint(saved(*s), [](std::string& b) {
    const size_t at = b.rfind("rolling");
    ASSERT_NE(at, std::string::npos);
    b[at + 6] = 'x';  // "rollinx": the section keeps its length
  });
  std::istringstream in(bytes);
  auto t = makeSimulation(d);
  EXPECT_EQ(codeOf([&] { t->load(in); }), (Code{"LOAD", "SECTION"}));
}

INSTANTIATE_TEST_SUITE_P(Dims, SimOptions, ::testing::Values(2, 3));

}  // namespace sim_options_test
}  // namespace demlab::sim
