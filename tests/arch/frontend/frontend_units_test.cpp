// The frontend units as registered kinds (arch/frontend/frontend_unit.hpp, units/): the paper's
// seven are registered, each runs its task, the default frontend has one per task, and a
// frontend.units map overrides a unit's keys, keeps or changes its kind, and names bad input.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <stdexcept>
#include <string>

#include "arch/frontend/frontend_config.hpp"

namespace edx::arch {
namespace {

using trace::Task;

TEST(FrontendUnits, ThePapersSevenKindsAreRegisteredOnePerTask) {
  const auto& registry = ComponentRegistry<FrontendUnit>::instance();
  const std::pair<const char*, Task> kinds[] = {
      {"fast", Task::FD},      {"gaussian", Task::IF},      {"rbrief", Task::FC},
      {"hamming", Task::MO},   {"sad_disparity", Task::DR}, {"scharr_pyramid", Task::DC},
      {"lk_solver", Task::LSS}};
  for (const auto& [kind, task] : kinds) {
    const auto* entry = registry.find(kind);
    ASSERT_NE(entry, nullptr) << kind;
    EXPECT_EQ(entry->make_default()->task(), task) << kind;
  }
  const FrontendConfig c;
  ASSERT_EQ(c.units.size(), trace::kTasks.size());
  for (Task task : trace::kTasks) {
    EXPECT_EQ(c.unit(task).name, trace::to_string(task));
    EXPECT_EQ(c.unit(task).unit->task(), task);
  }
  EXPECT_NO_THROW(c.validate());
}

TEST(FrontendUnits, TheMapOverridesByTaskAndNamesBadInput) {
  const FrontendConfig c = FrontendConfig::from_yaml(
      YAML::Load("units:\n  FC: {tests_per_cycle: 64}\n  DR: {count: 2, clock_mhz: 300}\n"),
      "fe.yaml");
  EXPECT_EQ(c.to_json()["units"]["FC"]["tests_per_cycle"], 64);
  EXPECT_EQ(c.to_json()["units"]["FC"]["kind"], "rbrief");
  EXPECT_EQ(c.unit(Task::DR).count, 2);
  EXPECT_DOUBLE_EQ(c.clock_of(c.unit(Task::DR)), 300.0);
  EXPECT_DOUBLE_EQ(c.clock_of(c.unit(Task::MO)), c.clock_mhz);  // the frontend's
  const auto error_of = [](const std::string& text) {
    try {
      FrontendConfig::from_yaml(YAML::Load(text), "fe.yaml");
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(
      error_of("units:\n  FC: {tests_per_cycle: 0}\n"),
      "fe.yaml:2: frontend.units.FC.tests_per_cycle: expected an integer in [1, 256], got '0'");
  EXPECT_EQ(error_of("units:\n  DR: {count: 0}\n"),
            "fe.yaml:2: frontend.units.DR.count: expected an integer in [1, 64], got '0'");
  EXPECT_EQ(error_of("units:\n  MO: {kind: lk_solver}\n"),
            "fe.yaml:2: frontend.units.MO.kind: expected a kind that runs MO, got 'lk_solver' "
            "(it runs LSS)");
  EXPECT_EQ(error_of("dr_sad_units: 4\n"),
            "fe.yaml:1: frontend.dr_sad_units: moved: now frontend.units.DR.sad_units "
            "(docs/CONFIG.md)");
}

}  // namespace
}  // namespace edx::arch
