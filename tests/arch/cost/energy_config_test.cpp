// Energy per frame on hand numbers, and the `cost:` / `power:` YAML sections.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <stdexcept>

#include "arch/cost/cost_config.hpp"
#include "arch/cost/energy.hpp"

namespace edx::arch::cost {
namespace {

using ::testing::HasSubstr;

TEST(FrameEnergy, HandComputedFrame) {
  PowerConfig p;
  p.fpga_static_w = 1.0;
  const HostPower host{10.0, 2.0};
  p.double_mac_pj = 20.0;
  p.int8_op_pj = 0.1;
  p.fpga_energy_factor = 10.0;
  p.dram_pj_per_byte = 100.0;
  const ByteEnergies bytes{/*on_chip_pj_per_byte=*/1.0, /*link_pj_per_byte=*/50.0};
  FrameActivity a;
  a.frame_s = 0.05;
  a.host_busy_s = 0.02;
  a.double_macs = 1e6;
  a.int8_ops = 1e8;
  a.dram_bytes = 2e6;
  a.bram_bytes = 1e7;
  a.link_bytes = 1e5;
  const FrameEnergy e = frame_energy(a, p, host, bytes);
  EXPECT_DOUBLE_EQ(e.fpga_static_j, 0.05);                               // 1 W x 50 ms
  EXPECT_DOUBLE_EQ(e.host_j, 10 * 0.02 + 2 * 0.03);                      // busy 20 ms, idle 30 ms
  EXPECT_NEAR(e.compute_j, 10 * (1e6 * 20 + 1e8 * 0.1) * 1e-12, 1e-15);  // 3e-4 J
  EXPECT_NEAR(e.memory_j, (2e6 * 100 + 1e7 * 1) * 1e-12, 1e-15);         // 2.1e-4 J
  EXPECT_NEAR(e.link_j, 1e5 * 50 * 1e-12, 1e-15);
  EXPECT_NEAR(e.total_j, 0.05 + 0.26 + 3e-4 + 2.1e-4 + 5e-6, 1e-12);
}

TEST(FrameEnergy, NoFpgaNoStaticAndScalesApply) {
  PowerConfig p;
  p.host_power_scale = 0.5;
  FrameActivity cpu;
  cpu.frame_s = 0.1;
  cpu.host_busy_s = 0.1;
  cpu.fpga_present = false;
  const FrameEnergy e = frame_energy(cpu, p, HostPower{16.0, 16.0}, {});
  EXPECT_DOUBLE_EQ(e.fpga_static_j, 0);
  EXPECT_DOUBLE_EQ(e.total_j, 0.5 * 16 * 0.1);
}

TEST(FrameEnergy, RejectsAHostBusierThanTheFrame) {
  FrameActivity a;
  a.frame_s = 0.01;
  a.host_busy_s = 0.02;
  EXPECT_THROW(frame_energy(a, {}, {}, {}), std::runtime_error);
}

TEST(CostYaml, ReadsFieldsOverDefaults) {
  const YAML::Node n =
      YAML::Load("ns_modes: 2\nfrontend_lut_overhead: 1.5\nns_fe_per_camera: false\n");
  const CostConfig c = CostConfig::from_yaml(n, "car.yaml");
  EXPECT_EQ(c.ns_modes, 2);
  EXPECT_DOUBLE_EQ(c.frontend_lut_overhead, 1.5);
  EXPECT_FALSE(c.ns_fe_per_camera);
  EXPECT_EQ(c.to_json()["ns_modes"], 2);
  EXPECT_EQ(CostConfig::from_yaml(YAML::Node(), "x").to_json(), CostConfig{}.to_json());
}

void expect_error(const std::string& yaml, bool power, const std::string& message) {
  try {
    const YAML::Node n = YAML::Load(yaml)["s"];
    if (power) {
      PowerConfig::from_yaml(n, "car.yaml");
    } else {
      CostConfig::from_yaml(n, "car.yaml");
    }
    FAIL() << "expected an error for " << yaml;
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr(message));
  }
}

TEST(CostYaml, ErrorsNameFileLineAndKey) {
  expect_error("s:\n  ns_modes: 0\n", false,
               "car.yaml:2: cost.ns_modes: expected an integer >= 1, got '0'");
  expect_error("s:\n  bogus: 1\n", false, "car.yaml:2: cost.bogus: unknown key");
  expect_error("s:\n  ns_fe_per_camera: maybe\n", false, "car.yaml:2: cost.ns_fe_per_camera");
  // The keys that became the frontend units' own name where they went.
  expect_error("s:\n  if_separable: true\n", false,
               "car.yaml:2: cost.if_separable: moved: now frontend.units.IF.separable");
  // The backend's precision has one home, backend.precision.
  expect_error("s:\n  ns_modes: 2\n  backend_precision: single\n", false,
               "car.yaml:3: cost.backend_precision: unknown key");
  expect_error("s:\n  frontend_arithmetic: single\n", false,
               "cost.frontend_arithmetic: moved: now frontend.units.IF.arithmetic and "
               "frontend.units.LSS.arithmetic");
  expect_error("s:\n  fpga_static_w: -1\n", true, "car.yaml:2: power.fpga_static_w");
  // The host's power is the host processor's own (host.active_w, host.idle_w).
  expect_error("s:\n  fpga_static_w: 1\n  host_active_w: 5\n", true,
               "car.yaml:3: power.host_active_w: moved: now host.active_w (docs/CONFIG.md)");
  expect_error("s:\n  host_idle_w: 1\n", true,
               "car.yaml:2: power.host_idle_w: moved: now host.idle_w (docs/CONFIG.md)");
  expect_error(
      "s:\n  fpga_energy_factor: [1]\n", true,
      "car.yaml:2: power.fpga_energy_factor: expected a number in (0, 1000], got 'a list'");
  expect_error("s:\n  fpga_idle_fraction: 1.5\n", true,
               "car.yaml:2: power.fpga_idle_fraction: expected a number in [0, 1], got '1.5'");
  // The keys that became the memory's and the link's kinds' own name where they went.
  expect_error("s:\n  ns_modes: 2\n  allow_bram18: false\n", false,
               "car.yaml:3: cost.allow_bram18: moved: now memory.allow_bram18 of the bram memory "
               "kind (docs/CONFIG.md)");
  expect_error(
      "s:\n  memory_read_muxes: false\n", false,
      "car.yaml:2: cost.memory_read_muxes: moved: now memory.read_muxes of the bram memory "
      "kind (docs/CONFIG.md)");
  expect_error("s:\n  bram_pj_per_byte: 1.25\n", true,
               "car.yaml:2: power.bram_pj_per_byte: moved: now memory.pj_per_byte of the memory "
               "kind (docs/CONFIG.md)");
  expect_error("s:\n  link_pj_per_byte: 80\n", true,
               "car.yaml:2: power.link_pj_per_byte: moved: now link.pj_per_byte of the link kind "
               "(docs/CONFIG.md)");
}

TEST(ResourceEnergy, BusyAndIdleTimesTimesTheirPowers) {
  PowerConfig p;
  p.fpga_idle_fraction = 0.25;
  // 2 mJ of work in 4 ms of a 10 ms run: 0.5 W busy, 0.125 W idle for 6 ms.
  const ResourceEnergy e = unit_energy("backend.multiply", 0.004, 0.010, 0.002, p);
  EXPECT_EQ(e.name, "backend.multiply");
  EXPECT_DOUBLE_EQ(e.active_w, 0.5);
  EXPECT_DOUBLE_EQ(e.idle_w, 0.125);
  EXPECT_DOUBLE_EQ(e.idle_s, 0.006);
  EXPECT_NEAR(e.energy_j, 0.002 + 0.125 * 0.006, 1e-15);
  // Default (no idle power): the work energy alone.
  EXPECT_NEAR(unit_energy("u", 0.004, 0.010, 0.002, PowerConfig{}).energy_j, 0.002, 1e-15);
  // Never busy: no power either way.
  EXPECT_EQ(unit_energy("u", 0.0, 0.010, 0.0, p).energy_j, 0.0);
  // dynamic_energy_j is frame_energy's work part: 1000 double MACs x 18.4 pJ x 10 + 8 on-chip
  // bytes x 1.25 pJ.
  FrameActivity a;
  a.double_macs = 1000;
  a.bram_bytes = 8;
  EXPECT_NEAR(dynamic_energy_j(a, PowerConfig{}, {1.25, 0.0}), 1e-12 * (184000 + 10), 1e-18);
}

TEST(PowerYaml, ReadsFieldsAndPrintsThem) {
  const PowerConfig p =
      PowerConfig::from_yaml(YAML::Load("fpga_static_w: 0.5\ndram_pj_per_byte: 120"), "d.yaml");
  EXPECT_DOUBLE_EQ(p.fpga_static_w, 0.5);
  EXPECT_DOUBLE_EQ(p.dram_pj_per_byte, 120);
  EXPECT_DOUBLE_EQ(p.to_json()["dram_pj_per_byte"].get<double>(), 120);
}

}  // namespace
}  // namespace edx::arch::cost
