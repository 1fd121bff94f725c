// Platform YAML: fields over defaults, and errors that name the file, line and key.
#include "arch/platform/platform.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <tuple>

#include "arch/cost/resource_report.hpp"
#include "tests/arch/backend/backend_test_support.hpp"
#include "tests/support/temp_dir.hpp"

namespace edx::arch {
namespace {

using ::testing::HasSubstr;

std::string error_of(const std::string& yaml) {
  try {
    Platform::parse(yaml, "p.yaml");
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "no error";
}

TEST(Platform, ReadsFieldsOverTheDefaults) {
  const Platform p = Platform::parse(
      "name: car\nhost:\n  frontend_suite_ms: 2.5\n  provenance: calibrated\n"
      "  backend_suite_ms: 4\nfrontend:\n"
      "  clock_mhz: 200\n  pipeline_fe_sm: false\n  units: {MO: {comparators: 8}}\n",
      "p.yaml");
  EXPECT_EQ(p.name, "car");
  EXPECT_EQ(p.host->params_json()["frontend_suite_ms"], 2.5);
  EXPECT_EQ(p.host->params_json()["provenance"], "calibrated");
  EXPECT_DOUBLE_EQ(p.frontend.clock_mhz, 200);
  EXPECT_FALSE(p.frontend.pipeline_fe_sm);
  EXPECT_EQ(p.frontend.to_json()["units"]["MO"]["comparators"], 8);
  EXPECT_EQ(p.frontend.to_json()["units"]["MO"]["kind"], "hamming");  // the default's, kept
  EXPECT_EQ(p.frontend.fd_stencil, FrontendConfig{}.fd_stencil);
  EXPECT_EQ(p.to_json()["frontend"]["clock_mhz"], 200.0);
}

TEST(Platform, BadInputNamesFileLineAndKey) {
  EXPECT_EQ(error_of("name: car\nfrontend:\n  clock_mhz: fast\n"),
            "p.yaml:3: frontend.clock_mhz: expected a number in [0.001, 1000], got 'fast'");
  EXPECT_EQ(error_of("name: car\nfrontend:\n  clok_mhz: 100\n"),
            "p.yaml:3: frontend.clok_mhz: unknown key");
  EXPECT_EQ(error_of("name: car\nfrontend:\n  fd_stencil: 4\n"),
            "p.yaml:3: frontend.fd_stencil: expected an odd integer in [3, 255], got '4'");
  EXPECT_EQ(error_of("name: car\nhost: 3\n"), "p.yaml:2: platform.host: expected a map of keys");
  EXPECT_EQ(error_of("name: car\nbackend:\n  units:\n    gemm: {block: ~}\n"),
            "p.yaml:4: backend.units.gemm.block: expected an integer in [1, 256], got 'nothing (~ "
            "or an empty value)'");
  EXPECT_EQ(error_of("name: car\nbackend_units: {}\n"),
            "p.yaml:2: platform.backend_units: unknown key");
  EXPECT_THAT(error_of("frontend: {}\n"), HasSubstr("platform.name: required"));
  EXPECT_EQ(error_of("name: car\ndevice: virtex\n"),
            "p.yaml:2: platform.device: expected xc7v690t, zu9eg or zu9cg, got 'virtex'");
  EXPECT_THAT(error_of("name: [unclosed\n"), HasSubstr("p.yaml:"));
  EXPECT_THAT(error_of("name: car\nfrontend:\n  units:\n    MO: {comparators: 0}\n"),
              HasSubstr("p.yaml:4: frontend.units.MO.comparators: expected an integer >= 1"));
  EXPECT_THAT(error_of("name: car\nfrontend:\n  mo_comparators: 8\n"),
              HasSubstr("p.yaml:3: frontend.mo_comparators: moved: now frontend.units.MO."
                        "comparators"));
  EXPECT_THAT(error_of("name: car\nfrontend:\n  units:\n    XX: {kind: fast}\n"),
              HasSubstr("p.yaml:4: frontend.units.XX: expected a task of the graph"));
  EXPECT_THAT(error_of("name: car\nfrontend:\n  units:\n    FD: {kind: hamming}\n"),
              HasSubstr("frontend.units.FD.kind: expected a kind that runs FD, got 'hamming'"));
}

// Issue 45: values inside a key's old range that the model cannot take are refused at the key,
// each at the edge its range now has (arch/common/bounds.hpp, docs/RELIABILITY.md).
TEST(Platform, ValuesTheModelCannotTakeAreRefusedAtTheirKey) {
  EXPECT_EQ(error_of("name: car\nfrontend:\n  clock_mhz: 1e-300\n"),
            "p.yaml:3: frontend.clock_mhz: expected a number in [0.001, 1000], got '1e-300'");
  EXPECT_EQ(error_of("name: car\nfrontend:\n  fe_pixels_per_cycle: 1e-9\n"),
            "p.yaml:3: frontend.fe_pixels_per_cycle: expected a number in [0.0009765625, 1024], "
            "got '1e-9'");
  EXPECT_EQ(error_of("name: car\nfrontend:\n  units: {FD: {clock_mhz: 0.0005}}\n"),
            "p.yaml:3: frontend.units.FD.clock_mhz: expected 0 (the section's clock_mhz) or a "
            "number in [0.001, 1000], got '0.0005'");
  EXPECT_EQ(error_of("name: car\nsystem:\n  sensor_fps: 1e-7\n"),
            "p.yaml:3: system.sensor_fps: expected 0 (frames back to back) or a rate in [0.001, "
            "1e+06] frames/s, got '1e-07'");
  EXPECT_EQ(error_of("name: car\nhost:\n  frontend_suite_ms: 1e308\n  backend_suite_ms: 1\n"),
            "p.yaml:3: host.frontend_suite_ms: expected a number in [0, 100000], got '1e308'");
  EXPECT_EQ(error_of("name: car\nbackend:\n  spm_bytes: 9223372036854775807\n"),
            "p.yaml:3: backend.spm_bytes: expected an integer in [1, 1073741824], got "
            "'9223372036854775807'");
  EXPECT_EQ(error_of("name: car\nlink:\n  dma: {max_outstanding: 2000}\n"),
            "p.yaml:3: link.dma.max_outstanding: expected an integer in [1, 1024], got '2000'");
  EXPECT_EQ(error_of("name: car\npower:\n  int8_op_pj: 1e308\n"),
            "p.yaml:3: power.int8_op_pj: expected a number in [0, 1000000], got '1e308'");
  // Inside the ranges (the edges themselves) a platform is read.
  EXPECT_NO_THROW(Platform::parse(
      "name: car\nfrontend:\n  clock_mhz: 0.001\n  fe_pixels_per_cycle: 0.0009765625\n"
      "system:\n  sensor_fps: 0.001\n",
      "p.yaml"));
}

// An error found while simulating (a product of in-range values the model cannot hold) names
// the file and line of its key, through the platform's origins.
TEST(Platform, LocatePlacesALaterErrorAtItsKeysFileAndLine) {
  const edx::testing::TempDir dir;
  std::ofstream(dir.path() / "base.yaml") << "name: base\nsystem:\n  queue_depth: 3\n";
  std::ofstream(dir.path() / "p.yaml") << "extends: base.yaml\nname: p\nsystem:\n"
                                          "  sensor_fps: 0.001\n";
  const Platform p = Platform::load(dir.path() / "p.yaml");
  const std::string file = (dir.path() / "p.yaml").string();
  const std::string base = (dir.path() / "base.yaml").string();
  EXPECT_EQ(std::string(p.locate(InputError({}, "system.sensor_fps", "too slow")).what()),
            file + ":4: system.sensor_fps: too slow");
  EXPECT_EQ(std::string(p.locate(InputError({}, "system.queue_depth", "x")).what()),
            base + ":3: system.queue_depth: x");
  // A key no file wrote (a default): the platform's file; an error already placed: unchanged.
  EXPECT_EQ(std::string(p.locate(InputError({}, "frontend.fd_stencil", "y")).what()),
            file + ": frontend.fd_stencil: y");
  EXPECT_EQ(std::string(p.locate(InputError({"t.db", 2}, "k", "z")).what()), "t.db:2: k: z");
}

TEST(Platform, ReadsBackendCostPowerSchedulerAndHostBackendScale) {
  const Platform p = Platform::parse(
      "name: car\nhost:\n  frontend_suite_ms: 3\n  backend_suite_ms: 1.5\n"
      "  backend_provenance: measured\n"
      "backend:\n  units: {gemm: {block: 8}}\ncost:\n  ns_modes: 2\npower:\n  fpga_static_w: 2\n"
      "scheduler:\n  policy: oracle\n  training_fraction: 0.5\n",
      "p.yaml");
  EXPECT_EQ(p.host->params_json()["backend_suite_ms"], 1.5);
  EXPECT_EQ(p.host->params_json()["backend_provenance"], "measured");
  EXPECT_EQ(testing::fpga_config(*p.backend).units[0].unit->tile(), 8);
  EXPECT_EQ(testing::fpga_config(*p.backend).units[1].to_json(),
            BackendConfig{}.units[1].to_json());
  EXPECT_EQ(p.cost.ns_modes, 2);
  EXPECT_DOUBLE_EQ(p.power.fpga_static_w, 2);
  EXPECT_EQ(p.scheduler.policy, OffloadPolicy::kOracle);
  EXPECT_DOUBLE_EQ(p.scheduler.training_fraction, 0.5);
  EXPECT_EQ(p.to_json()["scheduler"]["policy"], "oracle");
  EXPECT_EQ(p.to_json()["backend"]["units"]["gemm"]["block"], 8);
}

TEST(Platform, BadKeysOfTheNewSectionsNameFileLineAndKey) {
  EXPECT_EQ(error_of("name: car\nbackend:\n  spm_byte: 4\n"),
            "p.yaml:3: backend.spm_byte: unknown key");
  EXPECT_THAT(error_of("name: car\nbackend:\n  units:\n    gemm:\n      block: big\n"),
              HasSubstr("p.yaml:5: backend.units.gemm.block: expected an integer"));
  EXPECT_EQ(error_of("name: car\ncost:\n  colour: red\n"), "p.yaml:3: cost.colour: unknown key");
  EXPECT_THAT(error_of("name: car\npower:\n  fpga_static_w: hot\n"),
              HasSubstr("p.yaml:3: power.fpga_static_w: expected a number"));
  EXPECT_THAT(
      error_of("name: car\nscheduler:\n  policy: sometimes\n"),
      HasSubstr("p.yaml:3: scheduler.policy: expected never, always, regression or oracle"));
  EXPECT_THAT(
      error_of("name: car\nscheduler:\n  training_fraction: 1.5\n"),
      HasSubstr("p.yaml:3: scheduler.training_fraction: expected a number in [0, 1), got '1.5'"));
  EXPECT_EQ(error_of("name: car\nscheduler:\n  polcy: never\n"),
            "p.yaml:3: scheduler.polcy: unknown key");
  EXPECT_THAT(
      error_of("name: car\nhost:\n  backend_suite_ms: -1\n"),
      HasSubstr("p.yaml:3: host.backend_suite_ms: expected a number in [0, 100000], got '-1'"));
  EXPECT_THAT(error_of("name: car\nhost:\n  frontend_suite_ms: 5\n"),
              HasSubstr("host.backend_suite_ms: expected both suite times or neither"));
  EXPECT_THAT(
      error_of("name: car\nhost:\n  suite: 0\n"),
      HasSubstr(
          "p.yaml:3: host.suite: expected 1 (the reference-suite version edx host-speed measures), "
          "got '0'"));
  EXPECT_EQ(error_of("name: car\npower: 3\n"), "p.yaml:2: platform.power: expected a map of keys");
}

// configs/fp32: each fp64 platform with its backend in single precision, within the fp64
// backend's DSP budget (docs/MODEL.md "Precision"): Car 267 of 269, Drone 97 of 101.
TEST(Platform, Fp32ConfigsFitTheirFp64BackendsDspBudget) {
  const auto backend_dsp = [](const Platform& p) {
    return cost::build_resource_report(p.frontend, *p.backend, p.cost, *p.memory, {},
                                       Device::by_name(p.device), p.scheduler.offload)
        .backend.shared.dsp;
  };
  const std::string dir = std::string(EDX_SOURCE_DIR) + "/configs/";
  for (const auto& [fp64, fp32, dsp64, dsp32] :
       {std::tuple{"edx_car.yaml", "fp32/edx_car_fp32.yaml", 269.0, 267.0},
        std::tuple{"edx_drone.yaml", "fp32/edx_drone_fp32.yaml", 101.0, 97.0}}) {
    const Platform a = Platform::load(dir + fp64), b = Platform::load(dir + fp32);
    EXPECT_EQ(a.backend->precision(), trace::Precision::kFp64);
    EXPECT_EQ(b.backend->precision(), trace::Precision::kFp32);
    EXPECT_EQ(b.backend->matrix_format().scalar_bytes, 4);
    EXPECT_DOUBLE_EQ(backend_dsp(a), dsp64) << fp64;
    EXPECT_DOUBLE_EQ(backend_dsp(b), dsp32) << fp32;
  }
}

TEST(Platform, ShippedConfigsLoad) {
  for (const char* name : {"edx_car.yaml", "edx_drone.yaml"}) {
    const Platform p = Platform::load(std::string(EDX_SOURCE_DIR) + "/configs/" + name);
    EXPECT_EQ(p.scheduler.policy, OffloadPolicy::kRegression) << name;
    EXPECT_DOUBLE_EQ(p.scheduler.training_fraction, 0.25) << name;
  }
  const Platform car = Platform::load(std::string(EDX_SOURCE_DIR) + "/configs/edx_car.yaml");
  const Platform drone = Platform::load(std::string(EDX_SOURCE_DIR) + "/configs/edx_drone.yaml");
  // The Table III DSP budget on Edx-Car; a smaller array and SPM on Edx-Drone.
  const auto unit = [](const Platform& p, const char* name) {
    return p.backend->params_json()["units"][name];
  };
  EXPECT_EQ(unit(car, "gemm")["block"], 4);
  EXPECT_EQ(unit(car, "decomposition")["block"], 1);
  EXPECT_LT(unit(drone, "gemm")["block"], unit(car, "gemm")["block"]);
  EXPECT_LT(testing::fpga_config(*drone.backend).spm_bytes,
            testing::fpga_config(*car.backend).spm_bytes);
  // The same unit design on both (Sec. VII-A: "almost the same" implementations).
  for (const Platform* p : {&car, &drone}) {
    EXPECT_EQ(testing::fpga_config(*p->backend).units.size(), 5u) << p->name;
    EXPECT_EQ(unit(*p, "gemm")["overlap_tiles"], true) << p->name;
    EXPECT_EQ(unit(*p, "decomposition")["blocked"], true) << p->name;
    EXPECT_EQ(unit(*p, "substitution")["blocked"], true) << p->name;
  }
  // The hosts are datasheet processors (docs/MODEL.md, Host CPU): the car's Kaby Lake is the
  // anchor (suite times of this build's suite); the drone's accelerated system runs on the
  // ZU9CG's Cortex-A53 and its baseline on the TX1's Cortex-A57, both predicted from it.
  EXPECT_EQ(car.host->kind(), "datasheet");
  EXPECT_EQ(car.host->params_json()["processor"], "kaby_lake_4c");
  EXPECT_EQ(car.host->params_json()["suite"], trace::kHostSpeedSuite);
  EXPECT_GT(car.host->params_json()["frontend_suite_ms"].get<double>(), 0.0);
  EXPECT_EQ(car.baseline_host, nullptr);
  EXPECT_EQ(drone.host->params_json()["processor"], "cortex_a53_zu9cg");
  ASSERT_NE(drone.baseline_host, nullptr);
  EXPECT_EQ(drone.baseline_host->params_json()["processor"], "cortex_a57_tx1");
  for (const HostProcessor* h : {drone.host.get(), drone.baseline_host.get()}) {
    EXPECT_EQ(h->params_json()["reference"], "kaby_lake_4c");
    EXPECT_EQ(h->cores(), 4);
  }
}

TEST(Platform, MissingFileIsNamed) {
  try {
    Platform::load("/nonexistent/edx_car.yaml");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("/nonexistent/edx_car.yaml"));
  }
}

}  // namespace
}  // namespace edx::arch

namespace edx::arch {
namespace {

TEST(RosTransport, AFramesMessagesCostTheirCountAndBytesByHand) {
  trace::FrameTrace frame;
  frame.frame.gps_available = true;
  trace::TaskRecord fc;
  fc.task = trace::Task::FC;
  fc.image = trace::Image::Left;
  fc.keypoints = fc.descriptors = 100;
  frame.tasks = {fc};
  RosTransport ros;
  const FrameTransferConfig transfers;  // 14 B features, 10 IMU samples of 56 B, 1 GPS of 32 B
  EXPECT_EQ(ros.frame_cost(frame, transfers, 640, 480).frontend_ms, 0.0);  // off by default
  ros.enabled = true;
  ros.message_ms = 0.1;
  ros.byte_ns = 2;
  const RosTransport::FrameCost c = ros.frame_cost(frame, transfers, 640, 480);
  // Two images of 307 200 B: 2 x (0.1 + 0.6144) ms.
  EXPECT_NEAR(c.frontend_ms, 2 * (0.1 + 307200 * 2e-6), 1e-12);
  // Features 100 x 14 B, a pose of 80 B (stamp, 7 doubles, 16-B frame id), 10 IMU samples of
  // 56 B, a GPS fix of 32 B.
  const double bytes = 1400 + 80 + 10 * 56 + 32;
  EXPECT_NEAR(c.backend_ms, 13 * 0.1 + bytes * 2e-6, 1e-12);
  frame.frame.gps_available = false;
  EXPECT_NEAR(ros.frame_cost(frame, transfers, 640, 480).backend_ms, 12 * 0.1 + (bytes - 32) * 2e-6,
              1e-12);
}

TEST(RosTransport, IsReadFromItsSectionAndOnlyThenInTheJson) {
  const Platform off = Platform::parse("name: p\n", "p.yaml");
  EXPECT_FALSE(off.ros.enabled);
  EXPECT_FALSE(off.to_json().contains("ros"));
  const Platform on = Platform::parse("name: p\nros: {enabled: true, message_ms: 0.2}\n", "p.yaml");
  EXPECT_TRUE(on.ros.enabled);
  EXPECT_EQ(on.to_json()["ros"]["message_ms"], 0.2);
  try {
    Platform::parse("name: p\nros:\n  byte_ns: -1\n", "p.yaml");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "p.yaml:3: ros.byte_ns: expected a number in [0, 1000000], got '-1'");
  }
}

}  // namespace
}  // namespace edx::arch
