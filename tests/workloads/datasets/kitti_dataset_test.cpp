// The KITTI odometry reader on the real excerpt of sequence 01 (../shared/data).
#include "workloads/datasets/kitti_dataset.hpp"

#include <gtest/gtest.h>

#include <iostream>

#include "tests/workloads/datasets/rectification_check.hpp"
#include "workloads/datasets/dataset.hpp"

namespace edx::datasets {
namespace {

const std::filesystem::path kKittiRoot =
    std::filesystem::path(EDX_SHARED_DATA_DIR) / "kitti_odometry_excerpt";
const std::filesystem::path kSequence = kKittiRoot / "sequences" / "01";

TEST(KittiReader, FramesCalibrationTimesAndGroundTruthOfSequence01) {
  const auto dataset = open_dataset(kSequence, DatasetFormat::kKitti);
  EXPECT_EQ(dataset->format(), DatasetFormat::kKitti);
  ASSERT_EQ(dataset->frame_count(), 51u);
  EXPECT_TRUE(dataset->load_report().warnings.empty());

  // calib.txt: P0 = [718.856 0 607.1928 0; 0 718.856 185.2157 0; 0 0 1 0], P1(0,3) = -386.1448.
  const StereoCalibration& calibration = dataset->calibration();
  EXPECT_DOUBLE_EQ(calibration.rectified.fx, 718.856);
  EXPECT_DOUBLE_EQ(calibration.rectified.fy, 718.856);
  EXPECT_DOUBLE_EQ(calibration.rectified.cx, 607.1928);
  EXPECT_DOUBLE_EQ(calibration.rectified.cy, 185.2157);
  EXPECT_EQ(calibration.rectified.width, 1241);
  EXPECT_EQ(calibration.rectified.height, 376);
  EXPECT_DOUBLE_EQ(calibration.baseline_m, 386.1448 / 718.856);
  EXPECT_NEAR(calibration.baseline_m, 0.537, 0.001);
  EXPECT_TRUE(calibration.T_body_left.isApprox(Eigen::Isometry3d::Identity()));
  EXPECT_NEAR(calibration.frame_rate_hz, 10.0, 1e-9);

  // times.txt line 11 is 1.000000e+00 s.
  EXPECT_EQ(dataset->frame_time(0), 0);
  EXPECT_EQ(dataset->frame_time(10), 1'000'000'000);
  EXPECT_EQ(dataset->frame_time(50), 5'000'000'000);

  const auto& gt = dataset->ground_truth();
  ASSERT_EQ(gt.size(), 51u);
  EXPECT_TRUE(gt[0].T_world_body.isApprox(Eigen::Isometry3d::Identity(), 1e-6));
  EXPECT_TRUE(gt[1].T_world_body.translation().isApprox(
      Eigen::Vector3d(5.154656e-02, -2.424883e-02, 1.000725e+00)));
  EXPECT_FALSE(gt[1].velocity_m_s.has_value());
  EXPECT_EQ(gt[10].t_ns, dataset->frame_time(10));

  EXPECT_TRUE(dataset->imu().empty());
  EXPECT_FALSE(dataset->imu_noise().has_value());
  EXPECT_TRUE(dataset->gps().empty());
}

TEST(KittiReader, RootPlusSequenceIdOpensTheSameSequence) {
  DatasetOptions options;
  options.kitti_sequence = "01";
  const auto from_root = open_dataset(kKittiRoot, DatasetFormat::kKitti, options);
  const auto from_folder = open_dataset(kSequence, DatasetFormat::kKitti, options);
  EXPECT_EQ(from_root->frame_count(), from_folder->frame_count());
  EXPECT_EQ(from_root->ground_truth().size(), 51u);
  EXPECT_TRUE(from_root->ground_truth()[30].T_world_body.isApprox(
      from_folder->ground_truth()[30].T_world_body));
}

TEST(KittiReader, FramesAreRowAlignedAndResizable) {
  const auto dataset = open_dataset(kSequence, DatasetFormat::kKitti);
  const StereoFrame frame = dataset->load_frame(25);
  EXPECT_EQ(frame.left.size(), cv::Size(1241, 376));
  EXPECT_EQ(frame.t_ns, 2'500'000'000);
  const auto alignment = testing::measure_row_alignment(frame.left, frame.right, 200);
  std::cout << "[ figures  ] KITTI frame 25: " << alignment.matches
            << " ORB matches, median |dy| = " << alignment.median_abs_dy_px << " px\n";
  EXPECT_GE(alignment.matches, 100u);
  EXPECT_LT(alignment.median_abs_dy_px, 1.0);

  DatasetOptions options;
  options.resize = cv::Size(640, 480);
  const auto resized = open_dataset(kSequence, DatasetFormat::kKitti, options);
  const CameraIntrinsics& k = resized->calibration().rectified;
  EXPECT_DOUBLE_EQ(k.fx, 718.856 * 640 / 1241);
  EXPECT_DOUBLE_EQ(k.fy, 718.856 * 480 / 376);
  EXPECT_DOUBLE_EQ(k.cy, (185.2157 + 0.5) * 480 / 376 - 0.5);
  EXPECT_EQ(resized->calibration().raw_left.fx, 718.856);
  const StereoFrame small = resized->load_frame(50);
  EXPECT_EQ(small.left.size(), cv::Size(640, 480));
  EXPECT_EQ(small.right.size(), cv::Size(640, 480));
}

}  // namespace
}  // namespace edx::datasets
