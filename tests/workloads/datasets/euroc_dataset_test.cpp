// The EuRoC reader on the real V1_01_easy excerpt (../shared/data/euroc_v101_micro).
#include "workloads/datasets/euroc_dataset.hpp"

#include <gtest/gtest.h>

#include <iostream>
#include <opencv2/imgcodecs.hpp>

#include "tests/workloads/datasets/rectification_check.hpp"
#include "workloads/datasets/dataset.hpp"

namespace edx::datasets {
namespace {

const std::filesystem::path kEuroc =
    std::filesystem::path(EDX_SHARED_DATA_DIR) / "euroc_v101_micro";

/// The dataset is opened once for the whole suite (IMU and ground-truth parsing).
class EurocExcerpt : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { dataset_ = open_dataset(kEuroc, DatasetFormat::kEuroc).release(); }
  static void TearDownTestSuite() {
    delete dataset_;
    dataset_ = nullptr;
  }
  static const Dataset& dataset() { return *dataset_; }

 private:
  static inline Dataset* dataset_ = nullptr;
};

TEST_F(EurocExcerpt, PairsTheNinetyFiveFramesAndReportsTheFourMissingCam1Images) {
  EXPECT_EQ(dataset().format(), DatasetFormat::kEuroc);
  EXPECT_EQ(dataset().frame_count(), 95u);
  const LoadReport& report = dataset().load_report();
  EXPECT_EQ(report.left_rows, 95u);
  EXPECT_EQ(report.right_rows, 99u);
  EXPECT_EQ(report.left_missing_images, 0u);
  EXPECT_EQ(report.right_missing_images, 4u);
  EXPECT_EQ(report.left_unpaired, 0u);
  EXPECT_EQ(report.right_unpaired, 0u);
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_NE(report.warnings[0].find("cam1"), std::string::npos) << report.warnings[0];
  EXPECT_NE(report.warnings[0].find("4 of 99"), std::string::npos) << report.warnings[0];
  // First and last rows of cam0/data.csv; 50 ms apart throughout (20 Hz).
  EXPECT_EQ(dataset().frame_time(0), 1403715273262142976);
  EXPECT_EQ(dataset().frame_time(94), 1403715277962142976);
  for (std::size_t i = 1; i < dataset().frame_count(); ++i) {
    EXPECT_NEAR(dataset().frame_time(i) - dataset().frame_time(i - 1), 50'000'000, 1000);
  }
}

TEST_F(EurocExcerpt, RawCalibrationEqualsTheSensorYamlNumbers) {
  const StereoCalibration& calibration = dataset().calibration();
  EXPECT_EQ(calibration.raw_left.width, 752);
  EXPECT_EQ(calibration.raw_left.height, 480);
  EXPECT_DOUBLE_EQ(calibration.raw_left.fx, 458.654);
  EXPECT_DOUBLE_EQ(calibration.raw_left.fy, 457.296);
  EXPECT_DOUBLE_EQ(calibration.raw_left.cx, 367.215);
  EXPECT_DOUBLE_EQ(calibration.raw_left.cy, 248.375);
  EXPECT_EQ(calibration.raw_left.distortion,
            (std::vector<double>{-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05}));
  EXPECT_DOUBLE_EQ(calibration.raw_right.fx, 457.587);
  EXPECT_DOUBLE_EQ(calibration.raw_right.cy, 255.238);
  EXPECT_EQ(calibration.raw_right.distortion,
            (std::vector<double>{-0.28368365, 0.07451284, -0.00010473, -3.55590700e-05}));
  EXPECT_DOUBLE_EQ(calibration.frame_rate_hz, 20.0);
  EXPECT_NEAR(calibration.T_body_raw_left.matrix()(0, 3), -0.0216401454975, 1e-12);
  EXPECT_NEAR(calibration.T_body_raw_left.matrix()(1, 0), 0.999557249008, 1e-9);
  EXPECT_NEAR(calibration.T_body_raw_right.matrix()(1, 3), 0.0453689425024, 1e-12);
}

TEST_F(EurocExcerpt, RectifiedBaselineAndLeftPoseFollowFromTheTwoTbs) {
  const StereoCalibration& calibration = dataset().calibration();
  // Translations of T_BS of cam0 and cam1, as written in their sensor.yaml.
  const Eigen::Vector3d t_body_cam0(-0.0216401454975, -0.064676986768, 0.00981073058949);
  const Eigen::Vector3d t_body_cam1(-0.0198435579556, 0.0453689425024, 0.00786212447038);
  const double expected_baseline = (t_body_cam1 - t_body_cam0).norm();  // |t| of T_cam0_cam1
  EXPECT_NEAR(expected_baseline, 0.110, 0.001);
  EXPECT_NEAR(calibration.baseline_m, expected_baseline, 1e-9);
  // The rectified left camera sits at cam0's centre; the rectified right one, B along its x
  // axis, lands on cam1's centre.
  EXPECT_LT((calibration.T_body_left.translation() - t_body_cam0).norm(), 1e-12);
  const Eigen::Vector3d right_centre =
      calibration.T_body_left * Eigen::Vector3d(calibration.baseline_m, 0, 0);
  EXPECT_LT((right_centre - t_body_cam1).norm(), 1e-9);
  // Rectification only slightly turns cam0: the optical axes stay within a few degrees.
  const Eigen::Vector3d rect_axis = calibration.T_body_left.rotation().col(2);
  const Eigen::Vector3d raw_axis = calibration.T_body_raw_left.rotation().col(2);
  EXPECT_GT(rect_axis.dot(raw_axis), std::cos(3.0 * M_PI / 180));
  const CameraIntrinsics& rectified = calibration.rectified;
  EXPECT_EQ(rectified.width, 752);
  EXPECT_EQ(rectified.height, 480);
  EXPECT_DOUBLE_EQ(rectified.fx, rectified.fy);
  EXPECT_TRUE(rectified.distortion.empty());
  EXPECT_GT(rectified.fx, 300);
  EXPECT_LT(rectified.fx, 500);
  std::cout << "[ figures  ] EuRoC rectified fx=" << rectified.fx << " cx=" << rectified.cx
            << " cy=" << rectified.cy << " baseline=" << calibration.baseline_m << " m\n";
}

TEST_F(EurocExcerpt, RectifiedFeaturesLieOnTheSameRow) {
  double worst_rectified = 0;
  for (const std::size_t index : {0u, 47u, 94u}) {
    const StereoFrame frame = dataset().load_frame(index);
    ASSERT_EQ(frame.left.type(), CV_8UC1);
    const auto rectified = testing::measure_row_alignment(frame.left, frame.right, 120);
    ASSERT_GE(rectified.matches, 100u) << "frame " << index;
    EXPECT_LT(rectified.median_abs_dy_px, 1.0) << "frame " << index;
    worst_rectified = std::max(worst_rectified, rectified.median_abs_dy_px);
    std::cout << "[ figures  ] EuRoC frame " << index << ": " << rectified.matches
              << " ORB matches, median |dy| = " << rectified.median_abs_dy_px << " px";
    if (index == 0) {  // the same measure on the raw images, for comparison
      const auto file = [](const char* camera) {
        return (kEuroc / "mav0" / camera / "data" / "1403715273262142976.png").string();
      };
      const auto raw =
          testing::measure_row_alignment(cv::imread(file("cam0"), cv::IMREAD_GRAYSCALE),
                                         cv::imread(file("cam1"), cv::IMREAD_GRAYSCALE), 120);
      std::cout << " (raw: " << raw.matches << " matches, median |dy| = " << raw.median_abs_dy_px
                << " px)";
    }
    std::cout << "\n";
  }
  EXPECT_LT(worst_rectified, 1.0);
}

TEST_F(EurocExcerpt, EveryFrameLoadsAtTheCalibratedSize) {
  for (std::size_t i = 0; i < dataset().frame_count(); ++i) {
    const StereoFrame frame = dataset().load_frame(i);
    EXPECT_EQ(frame.index, i);
    EXPECT_EQ(frame.t_ns, dataset().frame_time(i));
    EXPECT_EQ(frame.left.size(), cv::Size(752, 480));
    EXPECT_EQ(frame.right.size(), cv::Size(752, 480));
  }
  EXPECT_THROW(dataset().load_frame(95), std::out_of_range);
}

TEST_F(EurocExcerpt, ImuSamplesAndNoiseModel) {
  const auto& imu = dataset().imu();
  ASSERT_EQ(imu.size(), 29120u);
  for (std::size_t i = 1; i < imu.size(); ++i) ASSERT_GT(imu[i].t_ns, imu[i - 1].t_ns) << i;
  EXPECT_EQ(imu.front().t_ns, 1403715273262142976);
  EXPECT_DOUBLE_EQ(imu.front().gyro_rad_s.x(), -0.0020943951023931952);
  EXPECT_DOUBLE_EQ(imu.front().accel_m_s2.z(), -3.6938381666666662);
  EXPECT_EQ(imu.back().t_ns, 1403715418857143040);
  // Standing still: |a| near g.
  EXPECT_NEAR(imu.front().accel_m_s2.norm(), 9.81, 0.2);
  const auto noise = dataset().imu_noise();
  ASSERT_TRUE(noise.has_value());
  EXPECT_DOUBLE_EQ(noise->gyro_noise_density, 1.6968e-04);
  EXPECT_DOUBLE_EQ(noise->gyro_random_walk, 1.9393e-05);
  EXPECT_DOUBLE_EQ(noise->accel_noise_density, 2.0e-3);
  EXPECT_DOUBLE_EQ(noise->accel_random_walk, 3.0e-3);
  EXPECT_DOUBLE_EQ(noise->rate_hz, 200);
  EXPECT_TRUE(dataset().gps().empty());
}

TEST_F(EurocExcerpt, GroundTruthRowsAndFirstPose) {
  const auto& gt = dataset().ground_truth();
  ASSERT_EQ(gt.size(), 2895u);
  const GroundTruthPose& first = gt.front();
  EXPECT_EQ(first.t_ns, 1403715273262142976);
  EXPECT_TRUE(
      first.T_world_body.translation().isApprox(Eigen::Vector3d(0.878895, 2.1834, 0.948427)));
  const Eigen::Quaterniond q =
      Eigen::Quaterniond(0.069433, -0.824237, -0.106942, -0.551702).normalized();
  EXPECT_TRUE(first.T_world_body.rotation().isApprox(q.toRotationMatrix(), 1e-12));
  ASSERT_TRUE(first.velocity_m_s.has_value());
  EXPECT_TRUE(first.velocity_m_s->isApprox(Eigen::Vector3d(0.00157587, 0.00179383, -0.00231615)));
  ASSERT_TRUE(first.accel_bias_m_s2.has_value());
  EXPECT_DOUBLE_EQ(first.accel_bias_m_s2->y(), 0.0659796);
  EXPECT_EQ(gt.back().t_ns, 1403715417962142976);
  // Ground truth at a frame time (the frames are stamped on the ground-truth clock).
  const auto at_frame = interpolate_ground_truth(gt, dataset().frame_time(10));
  ASSERT_TRUE(at_frame.has_value());
  EXPECT_EQ(at_frame->t_ns, dataset().frame_time(10));
}

TEST(EurocReader, ResizedFramesCarryScaledIntrinsics) {
  DatasetOptions options;
  options.resize = cv::Size(640, 480);
  const auto native = open_dataset(kEuroc / "mav0", DatasetFormat::kEuroc);
  const auto resized = open_dataset(kEuroc, DatasetFormat::kEuroc, options);
  const CameraIntrinsics& k = native->calibration().rectified;
  const CameraIntrinsics& k2 = resized->calibration().rectified;
  const double sx = 640.0 / 752.0;
  EXPECT_EQ(k2.width, 640);
  EXPECT_EQ(k2.height, 480);
  EXPECT_DOUBLE_EQ(k2.fx, k.fx * sx);
  EXPECT_DOUBLE_EQ(k2.fy, k.fy);
  EXPECT_DOUBLE_EQ(k2.cx, (k.cx + 0.5) * sx - 0.5);
  EXPECT_DOUBLE_EQ(k2.cy, k.cy);
  EXPECT_DOUBLE_EQ(resized->calibration().baseline_m, native->calibration().baseline_m);
  const StereoFrame frame = resized->load_frame(20);
  EXPECT_EQ(frame.left.size(), cv::Size(640, 480));
  EXPECT_EQ(frame.right.size(), cv::Size(640, 480));
  const auto alignment = testing::measure_row_alignment(frame.left, frame.right, 100);
  EXPECT_GE(alignment.matches, 100u);
  EXPECT_LT(alignment.median_abs_dy_px, 1.0);
}

}  // namespace
}  // namespace edx::datasets
