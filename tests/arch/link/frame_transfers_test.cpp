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
  const FrameTransfers t = frontend_transfer(frontend_only_frame(200, false), c);
  EXPECT_EQ(t.frame_id, 7);
  EXPECT_EQ(t.features, 200);  // the left FC row, not the right one nor MO
  EXPECT_EQ(t.frontend_bytes, 2800);
  EXPECT_EQ(t.imu_bytes, 560);  // 10 x 56
  EXPECT_EQ(t.gps_bytes, 0);    // no GPS on this frame
  EXPECT_EQ(t.frontend_to_host(), 3360);

  const FrameTransfers with_gps = frontend_transfer(frontend_only_frame(200, true), c);
  EXPECT_EQ(with_gps.gps_bytes, 32);
  EXPECT_EQ(with_gps.frontend_to_host(), 3392);

  FrameTransferConfig descriptors = c;
  descriptors.descriptor_bytes = 32;
  EXPECT_EQ(frontend_transfer(frontend_only_frame(100, false), descriptors).frontend_bytes, 4600);
}

TEST(FrameTransfers, FallsBackToMatchedFeaturesWithoutAnFcRow) {
  trace::FrameTrace f = frontend_only_frame(200, false);
  f.tasks.erase(f.tasks.begin() + 1);  // drop FC L
  EXPECT_EQ(frontend_transfer(f, {}).features, 100);
}

TEST(FrameTransfers, Projection) {
  // C 3x4 + X 4x1000 in, 2x1000 out, doubles.
  const KernelTransfer t = kernel_transfer(kernel("projection", 1000, 0), {}, kFormat);
  EXPECT_EQ(t.input_bytes, (12 + 4000) * 8);
  EXPECT_EQ(t.output_bytes, 2000 * 8);
  // By matrix: the kernel's descriptor lists them (the camera matrix 3x4).
  const KernelOperands operands =
      accelerable_kernel("projection").operands(kernel("projection", 1000, 0), kFormat, false);
  EXPECT_EQ(operands.inputs["camera_matrix"], 96);
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

TEST(FrameTransfers, TheKernelsBeyondThePapersThree) {
  // schur_complement of 3 landmarks, 12 camera columns: H_cc 144 + H_cl 36 + H_ll 3 + b_c 12 +
  // b_l 3 = 198 doubles in; S 144 + s 12 out.
  const KernelTransfer schur = kernel_transfer(kernel("schur_complement", 3, 12), {}, kFormat);
  EXPECT_EQ(schur.input_bytes, 198 * 8);
  EXPECT_EQ(schur.output_bytes, 156 * 8);
  // covariance_update of 4 rows, state 3: P 9 + K 12 + P H^T 12 in, P 9 out.
  const KernelTransfer cov = kernel_transfer(kernel("covariance_update", 4, 3), {}, kFormat);
  EXPECT_EQ(cov.input_bytes, 33 * 8);
  EXPECT_EQ(cov.output_bytes, 9 * 8);
  // gps_fusion of 2 fixes, state 3: P 9 + H 2 x 9 + R 6 in; P 9 + x 3 out.
  const KernelTransfer gps = kernel_transfer(kernel("gps_fusion", 2, 3), {}, kFormat);
  EXPECT_EQ(gps.input_bytes, 33 * 8);
  EXPECT_EQ(gps.output_bytes, 12 * 8);
}

TEST(FrameTransfers, RejectsUnknownAcceleratedKernels) {
  try {
    kernel_transfer(kernel("bundle_adjustment", 5, 5), {}, kFormat);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
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
            "car.yaml:2: transfers.imu_sample_bytes: expected an integer in [0, 1024], got '-1'");
  // The element size has one home, backend.precision.
  EXPECT_EQ(error_of("scalar_bytes: 4\n"), "car.yaml:1: transfers.scalar_bytes: unknown key");
  EXPECT_THROW(FrameTransferConfig::from_yaml(YAML::Load("imu_rate: 2\n"), "car.yaml"),
               std::runtime_error);
}

}  // namespace
}  // namespace edx::arch

namespace edx::arch {
namespace {

TEST(KernelTransferTime, InputsAndResultsAreOneDmaTransferEach) {
  // AXI4 at 1.2 GB/s with no setup or latency: 1200 B take 1 us. A projection of 297 points:
  // in (12 + 1188) x 8 = 9600 B (8 us), out 4752 B (3.96 us).
  const auto axi =
      make_component<Link>("dma", "{preset: axi4, latency_ns: 0, dma: {setup_ns: 0}}", "link");
  const KernelTransfer t = kernel_transfer(kernel("projection", 297, 0), {}, kFormat);
  ASSERT_EQ(t.input_bytes, 9600);
  ASSERT_EQ(t.output_bytes, 4752);
  EXPECT_EQ(kernel_transfer_time(*axi, t), sim::ns(11960));
  EXPECT_EQ(axi->transfer_time(1200), sim::us(1));
}

}  // namespace
}  // namespace edx::arch
