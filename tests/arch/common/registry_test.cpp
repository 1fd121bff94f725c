// The component registry (arch/common/registry.hpp) on a kind of its own: registration, a
// one-component section's parsing (kind optional, unknown kinds and keys refused at their line),
// its JSON and reference, and a kind that reads its own parameters (presets).
#include "arch/common/registry.hpp"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <stdexcept>

namespace edx::arch {
namespace {

/// A toy component kind: something with a rate.
class Pump : public Component {
 public:
  static constexpr const char* kKindName = "pump";
  virtual double litres_per_s() const = 0;
};

class Piston final : public Pump {
 public:
  struct Params {
    double stroke_l = 0.5;
    double strokes_per_s = 2.0;
    static const FieldList<Params>& fields() {
      static const FieldList<Params> list = {
          field("stroke_l", &Params::stroke_l, "L", "litres a stroke", Bounds::above(0)),
          field("strokes_per_s", &Params::strokes_per_s, "1/s", "strokes a second",
                Bounds::above(0))};
      return list;
    }
    void validate() const { check_fields(*this, "pump", fields()); }
  };
  explicit Piston(const Params& params) : params_(params) {}
  std::string_view kind() const override { return "piston"; }
  nlohmann::json params_json() const override { return params_to_json(params_); }
  double litres_per_s() const override { return params_.stroke_l * params_.strokes_per_s; }

 private:
  Params params_;
};
EDX_REGISTER_COMPONENT(Pump, Piston, "piston", "a piston pump");

/// A kind with presets: `preset: small|large` sets the defaults its other keys override.
class Turbine final : public Pump {
 public:
  struct Params {
    double litres_per_s = 10.0;
    static const FieldList<Params>& fields() {
      static const FieldList<Params> list = {
          field("litres_per_s", &Params::litres_per_s, "L/s", "throughput", Bounds::above(0))};
      return list;
    }
    void validate() const { check_fields(*this, "pump", fields()); }
    static Params parse(YamlFields& fields) {
      Params params;
      if (const YAML::Node preset = fields.take("preset")) {
        if (preset.Scalar() == "large") {
          params.litres_per_s = 100.0;
        } else if (preset.Scalar() != "small") {
          fields.fail("preset", "expected small or large, got '" + preset.Scalar() + "'");
        }
      }
      parse_fields(fields, params, Params::fields());
      return params;
    }
  };
  explicit Turbine(const Params& params) : params_(params) {}
  std::string_view kind() const override { return "turbine"; }
  nlohmann::json params_json() const override { return params_to_json(params_); }
  double litres_per_s() const override { return params_.litres_per_s; }

 private:
  Params params_;
};
EDX_REGISTER_COMPONENT(Pump, Turbine, "turbine", "a turbine pump, with presets");

std::shared_ptr<const Pump> parse(const std::string& text) {
  const YAML::Node root = YAML::Load(text);
  YamlFields fields(root["pump"], "plant.yaml", "pump");
  return parse_component<Pump>(fields, "piston");
}

std::string error_of(const std::string& text) {
  try {
    parse(text);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(ComponentRegistry, ListsItsKindsByName) {
  auto& registry = ComponentRegistry<Pump>::instance();
  EXPECT_EQ(registry.names(), "piston or turbine");
  EXPECT_EQ(registry.make("turbine")->litres_per_s(), 10.0);
  EXPECT_THROW(registry.add(component_entry<Pump, Piston>("piston", "again")), std::logic_error);
}

TEST(ParseComponent, TheKindIsOptionalAndItsKeysOverrideItsDefaults) {
  EXPECT_EQ(parse("pump: {strokes_per_s: 4}")->litres_per_s(), 2.0);  // 0.5 L x 4 /s
  EXPECT_EQ(parse("pump: {kind: turbine}")->litres_per_s(), 10.0);
  EXPECT_EQ(parse("pump: {kind: turbine, preset: large}")->litres_per_s(), 100.0);
  EXPECT_EQ(parse("pump: {kind: turbine, preset: large, litres_per_s: 7}")->litres_per_s(), 7.0);
  EXPECT_EQ(parse("other: 1")->kind(), "piston");  // no section: the default kind's defaults
}

TEST(ParseComponent, ErrorsNameTheFileLineAndKey) {
  EXPECT_EQ(error_of("pump:\n  kind: gear\n"),
            "plant.yaml:2: pump.kind: expected one of piston or turbine, got 'gear'");
  EXPECT_EQ(error_of("pump:\n  kind: turbine\n  stroke_l: 1\n"),
            "plant.yaml:3: pump.stroke_l: unknown key");
  EXPECT_EQ(error_of("pump:\n  kind: turbine\n  preset: huge\n"),
            "plant.yaml:3: pump.preset: expected small or large, got 'huge'");
  EXPECT_NE(error_of("pump:\n  stroke_l: -1\n").find("plant.yaml:2: pump.stroke_l"),
            std::string::npos);
}

TEST(ParseComponent, JsonAndReferenceCarryTheKindAndItsParameters) {
  const nlohmann::json j = component_json(*parse("pump: {kind: turbine, litres_per_s: 3}"));
  EXPECT_EQ(j.at("kind"), "turbine");
  EXPECT_EQ(j.at("litres_per_s"), 3.0);
  const std::vector<ReferenceRow> rows = component_reference<Pump>("pump", "piston");
  ASSERT_EQ(rows.size(), 4u);  // kind, then piston's two keys, then turbine's one
  EXPECT_EQ(rows[0].key, "pump.kind");
  EXPECT_EQ(rows[1].key, "pump.stroke_l");
  EXPECT_EQ(rows[3].key, "pump.litres_per_s");
}

}  // namespace
}  // namespace edx::arch
