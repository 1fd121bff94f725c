// One field list per config struct drives parsing, checking, JSON and the reference: each of
// those four against hand-written expectations on a small struct.
#include "common/config_fields.hpp"

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "common/yaml_fields.hpp"

namespace edx {
namespace {

enum class Mode { kFast, kSlow };
std::string mode_name(Mode m) { return m == Mode::kFast ? "fast" : "slow"; }
Mode parse_mode(const std::string& text) { return text == "fast" ? Mode::kFast : Mode::kSlow; }

struct Demo {
  double clock_mhz = 150;
  int stencil = 7;
  std::int64_t bytes = 4096;
  bool enabled = true;
  std::string name = "demo";
  std::string buffering = "dram";
  int word = 8;
  Mode mode = Mode::kFast;

  static const FieldList<Demo>& fields() {
    static const FieldList<Demo> list = {
        field("clock_mhz", &Demo::clock_mhz, "MHz", "clock", Bounds::above(0).at_most(1000)),
        field("stencil", &Demo::stencil, "pixels", "window side", Bounds::at_least(3).odd_only()),
        field("bytes", &Demo::bytes, "bytes", "size", Bounds::at_least(1)),
        field("enabled", &Demo::enabled, "", "on or off"),
        field("name", &Demo::name, "", "free text"),
        choice_field("buffering", &Demo::buffering, "", {"on_chip", "dram"}, "where"),
        choice_field("word", &Demo::word, "bytes", {"4", "8"}, "element size"),
        enum_field("mode", &Demo::mode, {"fast", "slow"}, mode_name, parse_mode, "speed"),
    };
    return list;
  }
};

Demo parse(const std::string& text) {
  Demo d;
  YamlFields f(YAML::Load(text), "demo.yaml", "demo");
  parse_fields(f, d, Demo::fields());
  f.finish();
  return d;
}

std::string parse_error(const std::string& text) {
  try {
    parse(text);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "no error";
}

TEST(Bounds, DescribeAndContain) {
  EXPECT_EQ(Bounds::above(0).at_most(1000).describe(false), "a number in (0, 1000]");
  EXPECT_EQ(Bounds::at_least(1).describe(true), "an integer >= 1");
  EXPECT_EQ(Bounds::at_least(3).odd_only().describe(true), "an odd integer >= 3");
  EXPECT_EQ(Bounds::at_least(0).below(1).describe(false), "a number in [0, 1)");
  EXPECT_EQ(Bounds::any().describe(false), "a number");
  EXPECT_TRUE(Bounds::above(0).contains(1e-9));
  EXPECT_FALSE(Bounds::above(0).contains(0));
  EXPECT_TRUE(Bounds::at_least(0).below(1).contains(0));
  EXPECT_FALSE(Bounds::at_least(0).below(1).contains(1));
  EXPECT_FALSE(Bounds::at_least(3).odd_only().contains(4));
  EXPECT_TRUE(Bounds::at_least(3).odd_only().contains(5));
  EXPECT_FALSE(Bounds::any().contains(std::numeric_limits<double>::quiet_NaN()));
}

TEST(ConfigFields, ReadsEveryKindOverTheDefaults) {
  const Demo d = parse(
      "clock_mhz: 200\nstencil: 5\nbytes: 3000000000\nenabled: false\nname: x y\n"
      "buffering: on_chip\nword: 4\nmode: slow\n");
  EXPECT_DOUBLE_EQ(d.clock_mhz, 200);
  EXPECT_EQ(d.stencil, 5);
  EXPECT_EQ(d.bytes, 3000000000);  // beyond an int: an int64 member keeps it
  EXPECT_FALSE(d.enabled);
  EXPECT_EQ(d.name, "x y");
  EXPECT_EQ(d.buffering, "on_chip");
  EXPECT_EQ(d.word, 4);
  EXPECT_EQ(d.mode, Mode::kSlow);
  const Demo defaults = parse("{}");
  EXPECT_EQ(defaults.stencil, 7);
  EXPECT_EQ(defaults.mode, Mode::kFast);
  // An absent section (a null node, as a missing map key gives) leaves every default.
  Demo absent;
  YamlFields f(YAML::Node(), "demo.yaml", "demo");
  parse_fields(f, absent, Demo::fields());
  EXPECT_EQ(absent.name, "demo");
  EXPECT_DOUBLE_EQ(absent.clock_mhz, 150);
}

TEST(ConfigFields, ErrorsNameFileLineKeyAndWhatIsAccepted) {
  EXPECT_EQ(parse_error("stencil: 5\nclock_mhz: 0\n"),
            "demo.yaml:2: demo.clock_mhz: expected a number in (0, 1000], got '0'");
  EXPECT_EQ(parse_error("stencil: 4\n"),
            "demo.yaml:1: demo.stencil: expected an odd integer >= 3, got '4'");
  EXPECT_EQ(parse_error("stencil: 3000000001\n"),
            "demo.yaml:1: demo.stencil: expected an odd integer >= 3, got '3000000001'");
  EXPECT_EQ(parse_error("stencil: 2.5\n"),
            "demo.yaml:1: demo.stencil: expected an odd integer >= 3, got '2.5'");
  EXPECT_EQ(parse_error("enabled: maybe\n"),
            "demo.yaml:1: demo.enabled: expected true or false, got 'maybe'");
  EXPECT_EQ(parse_error("buffering: sram\n"),
            "demo.yaml:1: demo.buffering: expected on_chip or dram, got 'sram'");
  EXPECT_EQ(parse_error("word: 6\n"), "demo.yaml:1: demo.word: expected 4 or 8, got '6'");
  EXPECT_EQ(parse_error("mode: [1]\n"),
            "demo.yaml:1: demo.mode: expected fast or slow, got 'a list'");
  EXPECT_EQ(parse_error("clock_mhz: .nan\n"),
            "demo.yaml:1: demo.clock_mhz: expected a number in (0, 1000], got '.nan'");
  EXPECT_EQ(parse_error("clockmhz: 1\n"), "demo.yaml:1: demo.clockmhz: unknown key");
}

TEST(ConfigFields, CheckFieldsFindsWhatCodeSetWrong) {
  Demo d;
  EXPECT_NO_THROW(check_fields(d, "demo", Demo::fields()));
  d.word = 2;
  try {
    check_fields(d, "demo", Demo::fields());
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "demo.word: expected 4 or 8, got '2'");
  }
}

TEST(ConfigFields, ValidateAtReportsARuleAtTheKeysLine) {
  YamlFields f(YAML::Load("name: a\nbytes: 10\n"), "demo.yaml", "demo");
  try {
    validate_at(f, [] { require_field(false, "demo", "bytes", "at least the name's size"); });
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "demo.yaml:2: demo.bytes: expected at least the name's size");
  }
}

TEST(ConfigFields, JsonHasEveryKeyWithItsValue) {
  const nlohmann::json j = fields_to_json(Demo{}, Demo::fields());
  EXPECT_EQ(j.size(), Demo::fields().size());
  EXPECT_EQ(j["clock_mhz"], 150.0);
  EXPECT_EQ(j["bytes"], 4096);
  EXPECT_EQ(j["enabled"], true);
  EXPECT_EQ(j["mode"], "fast");
  EXPECT_EQ(j["word"], 8);
}

TEST(ConfigFields, ReferenceRowsAndMarkdown) {
  const std::vector<ReferenceRow> rows = reference_rows("demo", Demo::fields());
  ASSERT_EQ(rows.size(), Demo::fields().size());
  EXPECT_EQ(rows[0].key, "demo.clock_mhz");
  EXPECT_EQ(rows[0].type, "number");
  EXPECT_EQ(rows[0].unit, "MHz");
  EXPECT_EQ(rows[0].value, "150");
  EXPECT_EQ(rows[0].accepted, "(0, 1000]");
  EXPECT_EQ(rows[1].accepted, ">= 3, odd");
  EXPECT_EQ(rows[3].type, "true/false");
  EXPECT_EQ(rows[3].accepted, "");
  EXPECT_EQ(rows[6].accepted, "4 or 8");
  EXPECT_EQ(rows[7].accepted, "fast or slow");
  const std::string md = render_reference(rows);
  EXPECT_NE(md.find("## `demo:`"), std::string::npos);
  EXPECT_NE(md.find("| `demo.stencil` | integer | pixels | 7 | >= 3, odd | window side |"),
            std::string::npos)
      << md;
}

// ---- the structured error ----

TEST(InputError, OneLineOfWhatIsKnown) {
  EXPECT_STREQ(InputError({"a.yaml", 3}, "x.y", "unknown key").what(),
               "a.yaml:3: x.y: unknown key");
  EXPECT_STREQ(InputError({"a.yaml"}, "x", "required").what(), "a.yaml: x: required");
  EXPECT_STREQ(InputError({"a.yaml"}, "", "cannot read").what(), "a.yaml: cannot read");
  EXPECT_STREQ(InputError({"s.yaml", 4, "parameters.k = 2"}, "k", "bad").what(),
               "s.yaml:4 (parameters.k = 2): k: bad");
  const InputError e = InputError::expected("frames", "an integer >= 8", "3");
  EXPECT_STREQ(e.what(), "frames: expected an integer >= 8, got '3'");
  EXPECT_EQ(e.expected(), "an integer >= 8");
  EXPECT_EQ(e.got(), "3");
  // Re-placed and re-keyed as data, not by editing the text.
  const InputError placed = e.with_key("workload.frames").at({"w.yaml", 2});
  EXPECT_STREQ(placed.what(), "w.yaml:2: workload.frames: expected an integer >= 8, got '3'");
  EXPECT_EQ(placed.file(), "w.yaml");
  EXPECT_EQ(placed.line(), 2);
  EXPECT_EQ(placed.key(), "workload.frames");
  EXPECT_EQ(placed.expected(), "an integer >= 8");
  EXPECT_STREQ(InputError::expected("x", "true or false").what(), "x: expected true or false");
}

// ---- what the field lists gained for the other input files and the options ----

struct Inner {
  double gain = 2;
  static const FieldList<Inner>& fields() {
    static const FieldList<Inner> list = {
        field("gain", &Inner::gain, "", "a gain", Bounds::above(0)),
    };
    return list;
  }
};

struct Rich {
  std::optional<int> frames;
  std::vector<double> costs = {1, 2};
  std::vector<std::string> names = {"a"};
  int population = 8;
  int samples = 1;
  std::string base;
  Inner inner;

  static const FieldList<Rich>& fields() {
    static const FieldList<Rich> list = joined<Rich>({
        {
            optional_field("frames", &Rich::frames, "", "frames", Bounds::at_least(2),
                           Unset{"default", nullptr}),
            field("costs", &Rich::costs, "ns", "costs", Bounds::at_least(0)),
            field("names", &Rich::names, "", "names"),
            field("population", &Rich::population, "", "designs",
                  Bounds::at_least(8).at_most(16).multiple_of(4)),
            field("samples", &Rich::samples, "", "draws", Bounds::at_least(1).at_most(1e6))
                .expects("an integer from 1 to 10^6"),
            field("base", &Rich::base, "", "a file").required(),
        },
        nested_fields("inner", &Rich::inner, Inner::fields()),
    });
    return list;
  }
};

Rich parse_rich(const std::string& text) {
  Rich r;
  YamlFields f(YAML::Load(text), "rich.yaml", "");
  f.refuse_unknown(field_keys(Rich::fields()), "expected one of the keys");
  parse_fields(f, r, Rich::fields());
  return r;
}

std::string rich_error(const std::string& text) {
  try {
    parse_rich(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(ConfigFields, OptionalListsRequiredAndOwnWordings) {
  Rich r = parse_rich("base: b\nframes: 12\ncosts: [0.5, 3]\nnames: [x, y]\npopulation: 12\n");
  EXPECT_EQ(r.frames, 12);
  EXPECT_EQ(r.costs, (std::vector<double>{0.5, 3}));
  EXPECT_EQ(r.names, (std::vector<std::string>{"x", "y"}));
  EXPECT_EQ(r.population, 12);
  for (const char* unset : {"~", "default", "null"}) {
    EXPECT_FALSE(parse_rich(std::string("base: b\nframes: ") + unset + "\n").frames) << unset;
  }
  // A file's top level (prefix ""): keys bare.
  EXPECT_EQ(rich_error("frames: 12\n"), "rich.yaml:1: base: required");
  EXPECT_EQ(rich_error("base: b\nframes: 1\n"),
            "rich.yaml:2: frames: expected an integer >= 2 or default, got '1'");
  EXPECT_EQ(rich_error("base: b\ncosts: [1, -2]\n"),
            "rich.yaml:2: costs: expected a list of numbers >= 0, got '-2'");
  EXPECT_EQ(rich_error("base: b\ncosts: 3\n"),
            "rich.yaml:2: costs: expected a list of numbers >= 0, got '3'");
  EXPECT_EQ(rich_error("base: b\npopulation: 10\n"),
            "rich.yaml:2: population: expected a multiple of 4 in [8, 16], got '10'");
  EXPECT_EQ(rich_error("base: b\nsamples: 0\n"),
            "rich.yaml:2: samples: expected an integer from 1 to 10^6, got '0'");
  EXPECT_EQ(rich_error("base: b\nsampels: 0\n"),
            "rich.yaml:2: sampels: unknown key (expected one of the keys)");
}

TEST(ConfigFields, NestedFieldsAreDottedKeysAndNestedJson) {
  Rich r;
  r.frames.reset();
  r.inner.gain = 0;
  const nlohmann::json j = fields_to_json(r, Rich::fields());
  EXPECT_EQ(j.at("frames"), nullptr);  // unset: its Unset json
  EXPECT_EQ(j.at("costs"), nlohmann::json({1.0, 2.0}));
  EXPECT_EQ(j.at("inner").at("gain"), 0.0);
  try {
    check_fields(r, "rich", Rich::fields());
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "rich.inner.gain: expected a number > 0, got '0'");
    EXPECT_EQ(e.key(), "rich.inner.gain");
  }
  const std::vector<ReferenceRow> rows = reference_rows("rich", Rich::fields());
  EXPECT_EQ(rows.front().value, "default");
  EXPECT_EQ(rows.front().accepted, ">= 2 or default");
  EXPECT_EQ(rows[1].type, "list of numbers");
  EXPECT_EQ(rows[1].value, "[1, 2]");
  EXPECT_EQ(rows.back().key, "rich.inner.gain");
}

TEST(ConfigFields, ValuesBuiltInCodeReadAsAFilesMap) {
  Rich r;
  YamlFields f(yaml_of_json({{"base", "b"}, {"frames", 40}, {"costs", {1, 2.5}}}), "", "");
  parse_fields(f, r, Rich::fields());
  EXPECT_EQ(r.frames, 40);
  EXPECT_EQ(r.costs, (std::vector<double>{1, 2.5}));
  YamlFields unset(yaml_of_json({{"base", "b"}, {"frames", nullptr}}), "", "");
  parse_fields(unset, r, Rich::fields());
  EXPECT_FALSE(r.frames);
}

TEST(ConfigFields, ValidateAtPlacesTheRuleOfAKeyBelowTheMap) {
  YamlFields f(YAML::Load("a: 1\nunits:\n  gemm: {block: 2}\n"), "p.yaml", "backend");
  try {
    validate_at(f, [] { throw InputError({}, "backend.units.gemm", "no unit kind"); });
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "p.yaml:3: backend.units.gemm: no unit kind");
  }
  // A kind's own section ("systolic_array.block") names the key of this map.
  try {
    validate_at(f, [] { require_field(false, "systolic_array", "a", "more", "1"); });
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "p.yaml:1: backend.a: expected more, got '1'");
  }
}

}  // namespace
}  // namespace edx

namespace edx {
namespace {

/// load_yaml_map's error on `text` ("" when it is read).
std::string load_error(const std::string& text) {
  try {
    load_yaml_map(text, "in.yaml", "keys");
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(YamlLimits, NodesAndDepthAreCountedWithAliasesExpanded) {
  // Nodes: the root map, its key, the list and N scalars = N + 3; at most 100 000 are read.
  const auto flat_list = [](std::size_t n) {
    std::string text = "a: [";
    for (std::size_t i = 0; i < n; ++i) text += i == 0 ? "0" : ",0";
    return text + "]\n";
  };
  EXPECT_EQ(load_error(flat_list(kMaxYamlNodes - 3)), "");
  EXPECT_EQ(load_error(flat_list(kMaxYamlNodes - 2)),
            "in.yaml:1: more than 100000 YAML nodes with its aliases expanded (nested anchors? "
            "edx reads documents of at most 100000 nodes)");
  // Nine levels of ten aliases each stand for 10^9 nodes: refused, after at most 10^5 visits.
  std::string bomb = "l0: &l0 [x, x, x, x, x, x, x, x, x, x]\n";
  for (int level = 1; level < 9; ++level) {
    bomb += fmt::format("l{}: &l{} [", level, level);
    for (int i = 0; i < 10; ++i) bomb += fmt::format("{}*l{}", i == 0 ? "" : ", ", level - 1);
    bomb += "]\n";
  }
  EXPECT_THAT(load_error(bomb), ::testing::StartsWith("in.yaml:"));
  EXPECT_THAT(load_error(bomb), ::testing::HasSubstr("more than 100000 YAML nodes"));
  // An alias used as meant (one list written twice) is read, each use a copy of the anchor's.
  const YAML::Node root = load_yaml_map("a: &l [1, 2]\nb: *l\n", "in.yaml", "keys");
  EXPECT_EQ(root["b"][1].as<int>(), 2);
  // Depth: the root map and 63 lists within each other are 64 levels; one more is refused.
  const auto nested = [](std::size_t lists) {
    return "a: " + std::string(lists, '[') + std::string(lists, ']') + "\n";
  };
  EXPECT_EQ(load_error(nested(kMaxYamlDepth - 1)), "");
  EXPECT_EQ(load_error(nested(kMaxYamlDepth)), "in.yaml:1: nested deeper than 64 maps and lists");
}

}  // namespace
}  // namespace edx
