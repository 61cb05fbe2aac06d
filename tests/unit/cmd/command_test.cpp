// Tests of the command system (src/cmd): option matching, the CommandLine parse, the pipes of
// the check phase, the ArgStack and PipeLine destinations, and the Registry's dispatch, help,
// completion and Markdown, all on commands declared here.
#include <gtest/gtest.h>

#include <random>

#include "cmd/registry.hpp"
#include "cmd/words.hpp"

namespace demlab::cmd {
namespace command_test {

struct Ctx : Context {
  int dim = 3;
  bool scene = true;
  bool spread = false;  // the scene is distributed over MPI ranks
  int dimension() const override { return dim; }
  bool distributed() const override { return spread; }
  void requireScene() const override {
    if (!scene) throw Error("no simulation: use \"sim new\" first", {"STATE", "NOSIM"});
  }
};

struct BallDef {
  double radius = 0;
  float density = 0;
  int count = 0;
  std::string material;
  std::vector<double> velocity;
  bool fixed = false;
};

// Returns the error code of the demlab::Error f throws, joined by spaces, or "none".
template <class F>
std::string codeOf(F&& f, std::string* message = nullptr) {
  try {
    f();
  } catch (const Error& e) {
    if (message) *message = e.what();
    std::string s;
    for (const auto& w : e.code()) s += (s.empty() ? "" : " ") + w;
    return s;
  }
  return "none";
}

class RegistryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    reg.describe("ball", "Balls.");
    Command& add = reg.add("ball add", "Adds a ball.");
    add.arg("material", name("material"), "its material").to(&BallDef::material);
    add.option("radius", real().positive().withUnit("m"), "radius").require().to(&BallDef::radius);
    add.option("density", real().positive().withUnit("kg/m^3"), "density")
        .byDefault("2500")
        .to(&BallDef::density);
    add.option("restitution", real().range(0, 1), "restitution").byDefault("0.5");
    add.option("count", integer().min(1), "how many").byDefault("1").to(&BallDef::count);
    add.option("velocity", vector(), "velocity").byDefault("0 0 0").to(&BallDef::velocity);
    add.option("law", choice({"linear", "hertz"}), "contact law").byDefault("hertz");
    add.flag("fixed", "never moves").to(&BallDef::fixed);
    add.run([this](Call& c) {
      BallDef d;
      c.fill(d);
      balls.push_back(d);
      return Value(int(balls.size()));
    });
    Command& get = reg.add("ball get", "Reads a ball.");
    get.variadicArg("id", integer().min(0), "ids");
    get.flag("radius", "radius");
    get.flag("velocity", "velocity");
    get.changesScene = false;
    get.onRanks = OnRanks::Collective;
    get.run([](Call& c) {
      List l;
      for (auto id : c.all<std::int64_t>("id")) l.push_back(Value(id));
      for (const auto& f : c.flagOrder()) l.push_back(Value(f));
      return Value(l);
    });
    Command& run = reg.add("ball run", "Runs.");
    run.option("steps", integer().min(0), "steps");
    run.option("time", real().positive(), "time");
    run.oneOf({"steps", "time"}, true);
    run.run([](Call& c) {
      return c.given("steps") ? Value(c.integer("steps")) : Value(c.real("time"));
    });
    Command& h = reg.add("help", "Help.");
    h.needsScene = false;
    h.onRanks = OnRanks::Alike;
    h.variadicArg("topic", text(), "topic").optional = true;
  }
  Value call(std::vector<std::string> w) { return reg.invoke(w, ctx); }
  std::string code(std::vector<std::string> w, std::string* msg = nullptr) {
    return codeOf([&] { call(w); }, msg);
  }
  Registry reg;
  Ctx ctx;
  std::vector<BallDef> balls;
};

TEST_F(RegistryTest, ADistributedSceneRefusesWhatIsNotDeclaredForRanksBeforeAnyChange) {
  // (ball get is declared collective, help alike, ball add not: refused.)
  ctx.spread = true;
  std::string msg;
  // Refused before its check phase: a bad word is not what it reports, and nothing changed.
  EXPECT_EQ(code({"ball", "add", "glass", "-radius", "-1"}, &msg), "DEMLAB MPI UNSUPPORTED");
  EXPECT_NE(msg.find("\"ball add\" is not available once the scene is distributed"),
            std::string::npos)
      << msg;
  EXPECT_TRUE(balls.empty());
  EXPECT_EQ(ctx.changes, 0u);
  EXPECT_EQ(toString(call({"ball", "get", "3", "-radius"})), "3 radius");
  EXPECT_EQ(code({"help"}), "none");
  // The same commands in a serial scene: all of them run.
  ctx.spread = false;
  EXPECT_EQ(toString(call({"ball", "add", "glass", "-radius", "1"})), "1");
  // The reference lists them by what they do, from the declarations.
  const std::string md = reg.markdown();
  const size_t section = md.find("## Distributed runs");
  ASSERT_NE(section, std::string::npos);
  EXPECT_NE(md.find("act alike on every rank: `help`", section), std::string::npos);
  EXPECT_NE(md.find("collective, every rank gets the whole scene's answer (element lists in the "
                    "order of the ids, a tag's in the tag's order): `ball get`",
                    section),
            std::string::npos);
  EXPECT_NE(toString(reg.declarations({"ball", "add"})).find("onranks refused"), std::string::npos);
  EXPECT_NE(toString(reg.declarations({"ball", "get"})).find("onranks collective"),
            std::string::npos);
}

TEST_F(RegistryTest, FillsDefsThroughPipeDestsWithDefaultsAndPrefixes) {
  Value v =
      call({"ball", "a", "glass", "-rad", "0.5", "-dens", "1000", "-velocity", "1 2 3", "-fixed"});
  EXPECT_EQ(toString(v), "1");
  ASSERT_EQ(balls.size(), 1u);
  EXPECT_EQ(balls[0].material, "glass");
  EXPECT_EQ(balls[0].radius, 0.5);
  EXPECT_EQ(balls[0].density, 1000.0f);
  EXPECT_EQ(balls[0].count, 1);
  EXPECT_EQ(balls[0].velocity, (std::vector<double>{1, 2, 3}));
  EXPECT_TRUE(balls[0].fixed);
  call({"ball", "add", "x", "-radius", "2", "-radius", "3"});  // the last repeat wins, as in Tcl
  EXPECT_EQ(balls[1].radius, 3);
  EXPECT_FALSE(balls[1].fixed);
  EXPECT_EQ(balls[1].velocity, (std::vector<double>{0, 0, 0}));
}

TEST_F(RegistryTest, ErrorsUseTclWordingAndCodesAndChangeNothing) {
  std::string m;
  EXPECT_EQ(code({"ball", "add", "g", "-radus", "1"}, &m), "DEMLAB OPTION");
  EXPECT_EQ(m,
            "bad option \"-radus\": must be -radius, -density, -restitution, -count, -velocity, "
            "-law, or -fixed");
  EXPECT_EQ(code({"ball", "add", "g", "-r", "1"}, &m), "DEMLAB OPTION");
  EXPECT_EQ(m,
            "ambiguous option \"-r\": must be -radius, -density, -restitution, -count, -velocity, "
            "-law, or -fixed");
  EXPECT_EQ(code({"ball", "add", "g", "-radius", "abc"}, &m), "DEMLAB VALUE RADIUS");
  EXPECT_EQ(m, "bad radius \"abc\": expected floating-point number");
  EXPECT_EQ(code({"ball", "add", "g", "-radius", "-1"}, &m), "DEMLAB VALUE RADIUS");
  EXPECT_EQ(m, "bad radius \"-1\": must be a positive number");
  EXPECT_EQ(code({"ball", "add", "g", "-radius", "1", "-restitution", "1.5"}, &m),
            "DEMLAB VALUE RESTITUTION");
  EXPECT_EQ(m, "bad restitution \"1.5\": must be between 0 and 1");
  EXPECT_EQ(code({"ball", "add", "g", "-radius", "1", "-count", "0"}, &m), "DEMLAB VALUE COUNT");
  EXPECT_EQ(m, "bad count \"0\": must be >= 1");
  EXPECT_EQ(code({"ball", "add", "g", "-radius", "1", "-count", "1.5"}, &m), "DEMLAB VALUE COUNT");
  EXPECT_EQ(m, "bad count \"1.5\": expected integer");
  EXPECT_EQ(code({"ball", "add", "g", "-radius", "1", "-velocity", "1 2"}, &m),
            "DEMLAB VALUE VELOCITY");
  EXPECT_EQ(m, "bad velocity \"1 2\": expected a vector of 3 numbers but got 2");
  EXPECT_EQ(code({"ball", "add", "g", "-radius", "1", "-velocity", "{1 2"}, &m),
            "DEMLAB VALUE VELOCITY");
  EXPECT_EQ(m, "bad velocity \"{1 2\": unmatched open brace in list");  // the word is named
  EXPECT_EQ(code({"ball", "add", "g", "-radius", "1", "-law", "h"}, &m), "none");
  EXPECT_EQ(code({"ball", "add", "g", "-radius", "1", "-law", "x"}, &m), "DEMLAB VALUE LAW");
  EXPECT_EQ(m, "bad law \"x\": must be linear or hertz");
  EXPECT_EQ(code({"ball", "add", "9g", "-radius", "1"}, &m), "DEMLAB VALUE MATERIAL");
  EXPECT_EQ(code({"ball", "add"}, &m), "DEMLAB ARGS");
  EXPECT_EQ(m, "wrong # args: should be \"ball add material -radius radius ?-option value ...?\"");
  EXPECT_EQ(code({"ball", "add", "g"}, &m), "DEMLAB ARGS");
  EXPECT_EQ(m,
            "missing required option -radius: should be \"ball add material -radius radius "
            "?-option value ...?\"");
  EXPECT_EQ(code({"ball", "add", "g", "-radius"}, &m), "DEMLAB ARGS");
  EXPECT_EQ(m, "value for \"-radius\" missing");
  EXPECT_EQ(code({"ball", "add", "g", "stray"}, &m), "DEMLAB OPTION");
  EXPECT_EQ(code({"ball", "frob"}, &m), "DEMLAB LOOKUP SUBCOMMAND");
  EXPECT_EQ(m, "unknown or ambiguous subcommand \"frob\": must be add, get, or run");
  EXPECT_EQ(code({"ball"}, &m), "DEMLAB ARGS");
  EXPECT_EQ(m, "wrong # args: should be \"ball subcommand ?arg ...?\"");
  EXPECT_EQ(code({"nope"}, &m), "DEMLAB LOOKUP COMMAND");
  EXPECT_EQ(code({"ball", "run"}, &m), "DEMLAB ARGS");
  EXPECT_EQ(m,
            "wrong # args: should be \"ball run -steps steps | -time time ?-option value ...?\"");
  EXPECT_EQ(code({"ball", "run", "-steps", "1", "-time", "2"}, &m), "DEMLAB ARGS");
  EXPECT_EQ(m, "conflicting options -steps and -time: give at most one of -steps or -time");
  EXPECT_EQ(code({"ball", "get"}, &m), "DEMLAB ARGS");
  ctx.scene = false;
  EXPECT_EQ(code({"ball", "add", "g", "-radius", "1"}, &m), "DEMLAB STATE NOSIM");
  EXPECT_EQ(code({"help"}, &m), "none");
  EXPECT_TRUE(balls.size() == 1u);  // only the one call that succeeded added a ball
}

TEST_F(RegistryTest, VariadicFlagsAndExclusiveGroups) {
  EXPECT_EQ(toString(call({"ball", "get", "3", "4", "-vel", "-radius"})), "3 4 velocity radius");
  EXPECT_EQ(toString(call({"ball", "run", "-time", "0.5"})), "0.5");
  EXPECT_EQ(toString(call({"ball", "run", "-st", "7"})), "7");
  ctx.dim = 2;
  call({"ball", "add", "g", "-radius", "1", "-velocity", "1 2"});
  EXPECT_EQ(balls.back().velocity.size(), 2u);
}

TEST_F(RegistryTest, HelpComesFromTheDeclaration) {
  std::string h = toString(call({"ball", "add", "-help"}));
  EXPECT_NE(h.find("ball add material -radius radius ?-option value ...?"), std::string::npos) << h;
  EXPECT_NE(h.find("-density real"), std::string::npos) << h;
  EXPECT_NE(h.find("[kg/m^3] (> 0); default 2500"), std::string::npos) << h;
  EXPECT_NE(h.find("contact law: linear or hertz"), std::string::npos) << h;
  EXPECT_EQ(reg.help({"ball", "add"}), h);
  EXPECT_EQ(reg.help({"b", "a"}), h);
  std::string g = reg.help({"ball"});
  EXPECT_NE(g.find("ball add"), std::string::npos);
  EXPECT_NE(g.find("Reads a ball."), std::string::npos);
  EXPECT_EQ(toString(call({"ball", "-help"})), g);
  EXPECT_EQ(codeOf([&] { reg.help({"ball", "zzz"}); }), "DEMLAB LOOKUP SUBCOMMAND");
  std::string md = reg.markdown();
  EXPECT_NE(md.find("### `ball add material -radius radius ?-option value ...?`"),
            std::string::npos);
  EXPECT_NE(md.find("| `-density` | real | kg/m^3 | > 0 | `2500` | density |"), std::string::npos)
      << md;
}

TEST_F(RegistryTest, DeclarationsAreTheDeclarationAsData) {
  std::string all = toString(reg.declarations({}));
  std::vector<std::string> commands = splitList(all);
  ASSERT_EQ(commands.size(), 4u);  // ball add, ball get, ball run, help
  std::string add = toString(reg.declarations({"ball", "add"}));
  EXPECT_EQ(splitList(add).size(), 1u);
  EXPECT_EQ(splitList(add)[0], commands[0]);
  EXPECT_NE(add.find("command {ball add}"), std::string::npos) << add;
  EXPECT_NE(add.find("{name radius role option required 1 optional 0 kind real label real unit m "
                     "min 0.0 minopen 1 max {} maxopen 0 length 0 choices {} default {} "
                     "hasdefault 0}"),
            std::string::npos)
      << add;
  EXPECT_NE(add.find("name material role positional required 1"), std::string::npos) << add;
  EXPECT_NE(add.find("kind choice label {linear hertz} unit {} min {} minopen 0 max {} maxopen 0 "
                     "length 0 choices {linear hertz} default hertz hasdefault 1"),
            std::string::npos)
      << add;
  std::string run = toString(reg.declarations({"ball", "run"}));
  EXPECT_NE(run.find("exclusive {{names {steps time} requireone 1}}"), std::string::npos) << run;
  EXPECT_EQ(splitList(toString(reg.declarations({"ball"}))).size(), 3u);
  EXPECT_EQ(codeOf([&] { reg.declarations({"ball", "zzz"}); }), "DEMLAB LOOKUP SUBCOMMAND");
}

TEST_F(RegistryTest, CompletionOffersCommandsOptionsAndChoices) {
  using V = std::vector<std::string>;
  EXPECT_EQ(reg.complete({}, "b", ctx), V{"ball"});
  EXPECT_EQ(reg.complete({"ball"}, "", ctx), (V{"add", "get", "run"}));
  EXPECT_EQ(reg.complete({"ball", "add", "g"}, "-r", ctx), (V{"-radius", "-restitution"}));
  EXPECT_EQ(reg.complete({"ball", "add", "g", "-law"}, "", ctx), (V{"linear", "hertz"}));
  EXPECT_EQ(reg.complete({"ball", "add", "g", "-law"}, "l", ctx), (V{"linear"}));
  EXPECT_EQ(reg.complete({"ball", "run"}, "-", ctx), (V{"-steps", "-time", "-help"}));
}

TEST(Words, NumbersAndBooleansReadAsTclReadsThem) {
  double d;
  std::int64_t i;
  bool b;
  EXPECT_TRUE(readReal(" 1.5e3 ", d) && d == 1500);
  EXPECT_TRUE(readReal("0x10", d) && d == 16);
  EXPECT_TRUE(readReal("-.5", d) && d == -0.5);
  EXPECT_FALSE(readReal("1.5x", d));
  EXPECT_FALSE(readReal("", d));
  EXPECT_FALSE(readReal("e5", d));
  EXPECT_TRUE(readInt("-0b101", i) && i == -5);
  EXPECT_TRUE(readInt("9223372036854775807", i) && i == INT64_MAX);
  EXPECT_FALSE(readInt("9223372036854775808", i));
  EXPECT_FALSE(readInt("1.0", i));
  EXPECT_TRUE(readBool("Yes", b) && b);
  EXPECT_TRUE(readBool("of", b) && !b);
  EXPECT_FALSE(readBool("o", b));  // on or off: ambiguous
  EXPECT_TRUE(readBool("off", b) && !b);
  EXPECT_TRUE(readBool("f", b) && !b);
  EXPECT_FALSE(readBool("maybe", b));
  EXPECT_EQ(formatReal(1.0), "1.0");
  EXPECT_EQ(formatReal(0.1), "0.1");
  EXPECT_EQ(formatReal(1e-5), "1e-5");
  EXPECT_EQ(formatReal(1e16), "10000000000000000.0");
  EXPECT_EQ(formatReal(1e17), "1e+17");
  EXPECT_EQ(formatReal(-0.00012), "-0.00012");
  EXPECT_EQ(formatReal(1.5e300), "1.5e+300");
  EXPECT_EQ(formatReal(123.25), "123.25");
  EXPECT_EQ(formatReal(1e15), "1000000000000000.0");
  EXPECT_EQ(formatReal(2.5e20), "2.5e+20");
  EXPECT_EQ(alternatives({"a"}), "a");
  EXPECT_EQ(alternatives({"a", "b"}), "a or b");
  EXPECT_EQ(alternatives({"a", "b", "c"}), "a, b, or c");
}

TEST(Words, ListsRoundTripThroughQuoteAndSplit) {
  EXPECT_EQ(splitList(" a {b c} \"d e\" f\\ g {} "),
            (std::vector<std::string>{"a", "b c", "d e", "f g", ""}));
  EXPECT_EQ(splitList("{a {b}} c"), (std::vector<std::string>{"a {b}", "c"}));
  EXPECT_THROW(splitList("{a"), Error);
  EXPECT_THROW(splitList("\"a"), Error);
  EXPECT_THROW(splitList("{a}b"), Error);
  std::mt19937 rng(7);
  const std::string alphabet = "ab {}\"\\$[];#\t\n";
  for (int trial = 0; trial < 2000; ++trial) {
    std::vector<std::string> elems(rng() % 5);
    for (auto& e : elems) {
      int n = int(rng() % 6);
      for (int k = 0; k < n; ++k) e += alphabet[rng() % alphabet.size()];
    }
    std::string joined = joinList(elems);
    EXPECT_EQ(splitList(joined), elems) << "joined: [" << joined << "]";
  }
}

}  // namespace command_test
}  // namespace demlab::cmd
