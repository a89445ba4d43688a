#include <gtest/gtest.h>

#include "core/config.hpp"
#include "core/error.hpp"

using namespace biota::core;

namespace {
ConfigSchema make_schema() {
  ConfigSchema s;
  s.add_real("lbm.tau", 0.6, 0.5, 2.0, "-", "relaxation time", true);
  s.add_int("run.steps", std::nullopt, 0, 1'000'000'000'000, "number of steps");
  s.add_string("lbm.lattice", "D3Q19", {"D3Q15", "D3Q19"}, "lattice");
  s.add_bool("coupling.two_way", true, "two-way coupling");
  s.add_real_list("jet.center", std::vector<double>{0.5, 0.5}, 2, "m", "jet centre");
  return s;
}
std::string error_of(const std::string& toml, std::vector<std::string> ov = {}) {
  auto schema = make_schema();
  try {
    Config::from_string(schema, toml, "deck.toml", ov);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(Config, DefaultsAndValues) {
  auto schema = make_schema();
  auto c = Config::from_string(schema, "run.steps = 10\n[lbm]\ntau = 0.8\n", "deck.toml");
  EXPECT_EQ(c.get_int("run.steps"), 10);
  EXPECT_DOUBLE_EQ(c.get_real("lbm.tau"), 0.8);
  EXPECT_EQ(c.get_string("lbm.lattice"), "D3Q19");
  EXPECT_TRUE(c.get_bool("coupling.two_way"));
  EXPECT_EQ(c.get_real_list("jet.center").size(), 2u);
  EXPECT_NE(c.effective_toml().find("tau = 0.8"), std::string::npos);
}

TEST(Config, OverridesWin) {
  auto schema = make_schema();
  auto c = Config::from_string(schema, "run.steps = 10\n", "deck.toml",
                               {"run.steps=20", "lbm.lattice=D3Q15", "jet.center=[0.1, 0.2]"});
  EXPECT_EQ(c.get_int("run.steps"), 20);
  EXPECT_EQ(c.get_string("lbm.lattice"), "D3Q15");
  EXPECT_DOUBLE_EQ(c.get_real_list("jet.center")[1], 0.2);
}

TEST(Config, ErrorsNameFileKeyValueAndRange) {
  std::string e = error_of("run.steps = 10\nlbm.tau = 0.5\n");
  EXPECT_NE(e.find("deck.toml"), std::string::npos) << e;
  EXPECT_NE(e.find("lbm.tau"), std::string::npos) << e;
  EXPECT_NE(e.find("0.5"), std::string::npos) << e;
  EXPECT_NE(e.find("(0.5, 2]"), std::string::npos) << e;
  EXPECT_NE(error_of("run.steps = 10\nlbm.tua = 0.7\n").find("lbm.tua"), std::string::npos);
  EXPECT_NE(error_of("run.steps = 'ten'\n").find("run.steps"), std::string::npos);
  EXPECT_NE(error_of("").find("run.steps"), std::string::npos);
  EXPECT_NE(error_of("run.steps = 1\nlbm.lattice = 'D2Q9'\n").find("D3Q15"), std::string::npos);
  EXPECT_NE(error_of("run.steps = [\n").find("syntax"), std::string::npos);
  EXPECT_NE(error_of("run.steps = 1\njet.center = [1.0]\n").find("jet.center"), std::string::npos);
  EXPECT_NE(error_of("run.steps = 1\n", {"lbm.tau=0.1"}).find("lbm.tau"), std::string::npos);
  EXPECT_NE(error_of("run.steps = 1\n", {"nokey=1"}).find("nokey"), std::string::npos);
}

TEST(Config, ReferenceListsEveryKey) {
  auto md = make_schema().reference_markdown();
  for (const char* k : {"lbm.tau", "run.steps", "lbm.lattice", "coupling.two_way", "jet.center"})
    EXPECT_NE(md.find(k), std::string::npos);
}

TEST(Config, IntegerKeysNeedARange) {
  // An integer without an upper bound overflowed to 0 in an `int` interval (SIGFPE): the schema
  // refuses such a declaration.
  ConfigSchema s;
  KeySpec open;
  open.type = ConfigType::kInt;
  open.default_value = std::int64_t{5};
  open.min = 1;
  EXPECT_THROW(s.add("flock.stats_interval", open), std::logic_error);
  open.max = 1e9;
  EXPECT_NO_THROW(s.add("flock.stats_interval", open));
}

TEST(Config, IntegerBoundsAreExactAbove2To53) {
  ConfigSchema s;
  s.add_int("seed", 1, 0, 1'000'000'000'000'000'000, "seed");
  EXPECT_NO_THROW(Config::from_string(s, "seed = 1000000000000000000\n", "deck.toml"));
  EXPECT_THROW(Config::from_string(s, "seed = 1000000000000000001\n", "deck.toml"), InputError);
}

TEST(Config, OverrideStringValueQuotedOrBare) {
  EXPECT_EQ(override_string_value("\"flock\""), "flock");
  EXPECT_EQ(override_string_value("'flock'"), "flock");
  EXPECT_EQ(override_string_value("flock"), "flock");
  EXPECT_EQ(override_string_value("out/dir name"), "out/dir name");
  EXPECT_EQ(override_string_value("3"), "3");  // not a TOML string: the text as given
}

TEST(Config, ReadDeckTextRejectsADirectoryAndAMissingFile) {
  try {
    read_deck_text(".");
    FAIL() << "a directory was read as a deck";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(".: is a directory, not a deck file"), std::string::npos);
  }
  EXPECT_THROW(read_deck_text("no/such/deck.toml"), InputError);
}

TEST(Config, UnusedGivenKeysAreTheGivenOnesNothingRead) {
  ConfigSchema s;
  s.add_real("a", 1.0, 0.0, 10.0, "", "read");
  s.add_real("b", 1.0, 0.0, 10.0, "", "given, never read");
  s.add_real("c", 1.0, 0.0, 10.0, "", "a default, never read");
  s.add_real("d", 1.0, 0.0, 10.0, "", "given, asked for by has()");
  s.add_real("e", 1.0, 0.0, 10.0, "", "given by --set, never read");
  const auto cfg = Config::from_string(s, "a = 2\nb = 3\nd = 4\n", "deck.toml", {"e=5"});
  EXPECT_EQ(cfg.unused_given_keys(), (std::vector<std::string>{"a", "b", "d", "e"}));
  cfg.get_real("a");
  EXPECT_TRUE(cfg.has("d"));
  EXPECT_EQ(cfg.unused_given_keys(), (std::vector<std::string>{"b", "e"}));
  EXPECT_NE(cfg.effective_toml().find("b = 3"), std::string::npos);  // printing is not a use
  EXPECT_EQ(cfg.unused_given_keys(), (std::vector<std::string>{"b", "e"}));
}
