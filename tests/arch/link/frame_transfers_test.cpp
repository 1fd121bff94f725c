// The three host <-> FPGA transfers per frame (paper Sec. VII-A), hand-computed sizes.
#include "arch/link/frame_transfers.hpp"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <stdexcept>
#include <string>

namespace edx::arch {
namespace {

trace::FrameTrace frontend_only_frame(std::int64_t left_features, bool gps) {
  trace::FrameTrace f;
  f.frame.frame_id = 7;
  f.frame.gps_available = gps;
  trace::TaskRecord fc_left;
  fc_left.task = trace::Task::FC;
  fc_left.image = trace::Image::Left;
  fc_left.keypoints = left_features;
  fc_left.descriptors = left_features;
  trace::TaskRecord fc_right = fc_left;
  fc_right.image = trace::Image::Right;
  fc_right.keypoints = 3 * left_features;
  trace::TaskRecord mo;
  mo.task = trace::Task::MO;
  mo.image = trace::Image::Stereo;
  mo.keypoints = left_features / 2;
  f.tasks = {fc_right, fc_left, mo};
  return f;
}

/// Doubles, 6 pose parameters, 3 per landmark (x, y, z) where the trace does not say.
const KernelMatrixFormat kFormat{8, 6, 3};

trace::KernelRecord kernel(const std::string& name, std::int64_t m, std::int64_t n,
                           bool accelerable = true) {
  trace::KernelRecord k;
  k.kernel = name;
  k.accelerable = accelerable;
  k.m = m;
  k.n = n;
  return k;
}

TEST(FrameTransfers, FrontendOnlyFrame) {
  const FrameTransferConfig c;
  EXPECT_EQ(c.feature_record_bytes(), 14);  // id 4 + 4 coordinates x 2 + disparity 2
  const FrameTransfers t = frame_transfers(frontend_only_frame(200, false), c, kFormat);
  EXPECT_EQ(t.frame_id, 7);
  EXPECT_EQ(t.features, 200);  // the left FC row, not the right one nor MO
  EXPECT_EQ(t.frontend_bytes, 2800);
  EXPECT_EQ(t.imu_bytes, 560);  // 10 x 56
  EXPECT_EQ(t.gps_bytes, 0);    // no GPS on this frame
  EXPECT_EQ(t.frontend_to_host(), 3360);
  EXPECT_EQ(t.kernel_inputs_to_fpga(), 0);
  EXPECT_EQ(t.kernel_results_to_host(), 0);
  EXPECT_EQ(t.total(), 3360);

  const FrameTransfers with_gps = frame_transfers(frontend_only_frame(200, true), c, kFormat);
  EXPECT_EQ(with_gps.gps_bytes, 32);
  EXPECT_EQ(with_gps.frontend_to_host(), 3392);

  FrameTransferConfig descriptors = c;
  descriptors.descriptor_bytes = 32;
  EXPECT_EQ(frame_transfers(frontend_only_frame(100, false), descriptors, kFormat).frontend_bytes,
            4600);
}

TEST(FrameTransfers, FallsBackToMatchedFeaturesWithoutAnFcRow) {
  trace::FrameTrace f = frontend_only_frame(200, false);
  f.tasks.erase(f.tasks.begin() + 1);  // drop FC L
  EXPECT_EQ(frame_transfers(f, {}, kFormat).features, 100);
}

TEST(FrameTransfers, Projection) {
  // C 3x4 + X 4x1000 in, 2x1000 out, doubles.
  const KernelTransfer t = kernel_transfer(kernel("projection", 1000, 0), {}, kFormat);
  EXPECT_EQ(t.input_bytes, (12 + 4000) * 8);
  EXPECT_EQ(t.output_bytes, 2000 * 8);
  EXPECT_EQ(t.parts["inputs"]["camera_matrix"], 96);
}

TEST(FrameTransfers, KalmanGain) {
  // H 4x3 (12) + P 3x3 (9) + R diag (4) = 25 doubles in; K 3x4 = 12 out.
  const KernelTransfer t = kernel_transfer(kernel("kalman_gain", 4, 3), {}, kFormat);
  EXPECT_EQ(t.input_bytes, 200);
  EXPECT_EQ(t.output_bytes, 96);
  FrameTransferConfig packed;
  packed.pack_symmetric = true;  // P as 6 scalars
  EXPECT_EQ(kernel_transfer(kernel("kalman_gain", 4, 3), packed, kFormat).input_bytes, 176);
  EXPECT_EQ(kernel_transfer(kernel("kalman_gain", 4, 3), {}, {4, 6, 3}).input_bytes, 100);
}

TEST(FrameTransfers, Marginalization) {
  // 2 landmarks of 3 parameters, 12 kept: d_l = 6, d_m = 12.
  // A 2 x 9 = 18, B 6 x 6 = 36, D 36, A_mr 12 x 12 = 144, A_rr 144, b_m 12, b_r 12 = 402
  // doubles in; prior 144 + 12 = 156 out.
  const KernelTransfer t = kernel_transfer(kernel("marginalization", 2, 12), {}, kFormat);
  EXPECT_EQ(t.input_bytes, 402 * 8);
  EXPECT_EQ(t.output_bytes, 156 * 8);

  // Inverse-depth landmarks from the detail: d_l = 2, d_m = 8:
  // A 2 + B 12 + D 36 + A_mr 96 + A_rr 144 + b_m 8 + b_r 12 = 310.
  trace::KernelRecord detail = kernel("marginalization", 2, 12);
  detail.detail_json = R"({"landmark_dim": 1})";
  EXPECT_EQ(kernel_transfer(detail, {}, kFormat).input_bytes, 310 * 8);

  // The A_mm inverse of size 10 = 2 l + 6 gives l = 2: d_l = 4, d_m = 10:
  // A 8 + B 24 + D 36 + A_mr 120 + A_rr 144 + b_m 10 + b_r 12 = 354.
  trace::KernelRecord ops = kernel("marginalization", 2, 12);
  ops.ops.push_back({trace::Op::Inverse, 10, 10, 0, trace::op_flags::kDiagonalBlock, 0});
  EXPECT_EQ(kernel_transfer(ops, {}, kFormat).input_bytes, 354 * 8);

  trace::KernelRecord bad = kernel("marginalization", 2, 12);
  bad.detail_json = R"({"landmark_dim": 0})";
  EXPECT_THROW(kernel_transfer(bad, {}, kFormat), std::runtime_error);
}

TEST(FrameTransfers, SumsAccelerableKernelsAndIgnoresHostOnlyOnes) {
  trace::FrameTrace f = frontend_only_frame(150, false);
  f.kernels = {kernel("imu_propagation", 0, 15, false), kernel("kalman_gain", 4, 3),
               kernel("projection", 1000, 0)};
  const FrameTransfers t = frame_transfers(f, {}, kFormat);
  ASSERT_EQ(t.kernels.size(), 2u);
  EXPECT_EQ(t.kernel_inputs_to_fpga(), 200 + 32096);
  EXPECT_EQ(t.kernel_results_to_host(), 96 + 16000);
  EXPECT_EQ(t.frontend_to_host(), 150 * 14 + 560);
  EXPECT_EQ(t.total(), 2100 + 560 + 32296 + 16096);
  EXPECT_EQ(t.to_json()["kernel_inputs_to_fpga"], 32296);
}

TEST(FrameTransfers, RejectsUnknownAcceleratedKernels) {
  trace::FrameTrace f = frontend_only_frame(10, false);
  f.kernels = {kernel("bundle_adjustment", 5, 5)};
  try {
    frame_transfers(f, {}, kFormat);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("frame 7"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("bundle_adjustment"), std::string::npos);
  }
  EXPECT_THROW(kernel_transfer(kernel("projection", -1, 0), {}, kFormat), std::runtime_error);
}

TEST(FrameTransfers, ConfigFromYaml) {
  const FrameTransferConfig c = FrameTransferConfig::from_yaml(
      YAML::Load("imu_samples_per_frame: 20\npack_symmetric: true\n"), "car.yaml");
  EXPECT_EQ(c.imu_samples_per_frame, 20);
  EXPECT_TRUE(c.pack_symmetric);
  const auto error_of = [](const std::string& text) {
    try {
      FrameTransferConfig::from_yaml(YAML::Load(text), "car.yaml");
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(error_of("pack_symmetric: true\nimu_sample_bytes: -1\n"),
            "car.yaml:2: transfers.imu_sample_bytes: expected an integer >= 0, got '-1'");
  // The element size has one home, backend.scalar_bytes.
  EXPECT_EQ(error_of("scalar_bytes: 4\n"), "car.yaml:1: transfers.scalar_bytes: unknown key");
  EXPECT_THROW(FrameTransferConfig::from_yaml(YAML::Load("imu_rate: 2\n"), "car.yaml"),
               std::runtime_error);
}

}  // namespace
}  // namespace edx::arch

namespace edx::arch {
namespace {

TEST(FrameTransferTimes, EachTransferIsOneDmaTransfer) {
  // AXI4 at 1.2 GB/s with no setup or latency: 1200 B take 1 us.
  LinkSpec axi = LinkSpec::axi4();
  axi.link.latency_ns = 0;
  axi.dma.setup_ns = 0;
  trace::FrameTrace f = frontend_only_frame(0, false);
  f.kernels = {kernel("projection", 297, 0)};  // in (12 + 1188) x 8 = 9600 B, out 4752 B
  FrameTransferConfig c;
  c.imu_samples_per_frame = 20;
  c.imu_sample_bytes = 60;  // 1200 B of IMU samples, nothing else on (1)
  const FrameTransfers t = frame_transfers(f, c, kFormat);
  ASSERT_EQ(t.frontend_to_host(), 1200);
  ASSERT_EQ(t.kernel_inputs_to_fpga(), 9600);
  ASSERT_EQ(t.kernel_results_to_host(), 4752);
  const FrameTransferTimes times = frame_transfer_times(axi, t);
  EXPECT_EQ(times.frontend_to_host, sim::us(1));
  EXPECT_EQ(times.kernel_inputs_to_fpga, sim::us(8));
  EXPECT_EQ(times.kernel_results_to_host, sim::ns(3960));
  EXPECT_EQ(times.total(), sim::ns(12960));
  EXPECT_EQ(kernel_transfer_time(axi, t.kernels[0]), sim::ns(11960));
}

}  // namespace
}  // namespace edx::arch
