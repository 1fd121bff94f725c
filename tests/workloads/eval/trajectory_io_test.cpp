// Readers of KITTI, TUM and EuRoC trajectory files: what they read, and a one-line "file:line:"
// error for every defect of a file.
#include "workloads/eval/trajectory_io.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "tests/workloads/eval/eval_test_support.hpp"

namespace edx::eval {
namespace {

using ::testing::HasSubstr;
using testing::ScratchDir;

const std::string kIdentityRow = "1 0 0 0 0 1 0 0 0 0 1 0\n";

/// The message of the std::runtime_error `read_trajectory` throws for `text` (fails if none).
std::string read_error(const std::string& name, const std::string& text, TrajectoryFormat format) {
  ScratchDir dir("io");
  const std::string path = dir.write(name, text);
  try {
    read_trajectory(path, format);
  } catch (const std::runtime_error& error) {
    const std::string message = error.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << "not one line: " << message;
    EXPECT_THAT(message, HasSubstr(path)) << "does not name the file";
    return message.substr(path.size());  // ":LINE: what"
  }
  ADD_FAILURE() << "no error for " << name;
  return {};
}

TEST(TrajectoryIo, ReadsKittiRowsKeyedByLineOrdinal) {
  ScratchDir dir("io");
  const std::string path =
      dir.write("gt.txt", kIdentityRow + "\n" + "0 -1 0 1.5 1 0 0 2.5 0 0 1 -3.25\n");
  const Trajectory trajectory = read_trajectory(path, TrajectoryFormat::kKitti);
  ASSERT_EQ(trajectory.poses.size(), 2u);
  EXPECT_EQ(trajectory.stamp_kind, StampKind::kFrameIndex);
  EXPECT_EQ(trajectory.poses[1].frame_index, 1);  // the blank line is not a pose
  EXPECT_EQ(trajectory.poses[1].line, 3u);
  EXPECT_EQ(trajectory.poses[1].pose.translation(), Eigen::Vector3d(1.5, 2.5, -3.25));
  EXPECT_EQ(trajectory.poses[1].pose.linear()(0, 1), -1.0);  // row-major: r12
  EXPECT_EQ(trajectory.poses[1].pose.linear()(1, 0), 1.0);   // r21
}

TEST(TrajectoryIo, ReadsKittiRowsWithFrameIndex) {
  ScratchDir dir("io");
  const std::string path = dir.write("est.txt", "2 " + kIdentityRow + "7.0 " + kIdentityRow);
  const Trajectory trajectory = read_trajectory(path, TrajectoryFormat::kKitti);
  ASSERT_EQ(trajectory.poses.size(), 2u);
  EXPECT_EQ(trajectory.poses[0].frame_index, 2);
  EXPECT_EQ(trajectory.poses[1].frame_index, 7);
}

TEST(TrajectoryIo, ReadsTumRowsAndComments) {
  ScratchDir dir("io");
  // A 90 degree turn about z: q = (w, x, y, z) = (cos 45, 0, 0, sin 45).
  const std::string path =
      dir.write("est.tum",
                "# timestamp tx ty tz qx qy qz qw\n1.5 1 2 3 0 0 0.70710678118654752 "
                "0.70710678118654752\n1.75 0 0 0 0 0 0 1\n");
  const Trajectory trajectory = read_trajectory(path, TrajectoryFormat::kTum);
  ASSERT_EQ(trajectory.poses.size(), 2u);
  EXPECT_EQ(trajectory.stamp_kind, StampKind::kSeconds);
  EXPECT_DOUBLE_EQ(trajectory.poses[0].time_s, 1.5);
  EXPECT_EQ(trajectory.poses[0].line, 2u);
  EXPECT_EQ(trajectory.poses[0].pose.translation(), Eigen::Vector3d(1, 2, 3));
  EXPECT_NEAR(trajectory.poses[0].pose.linear()(1, 0), 1.0, 1e-12);  // x axis -> y axis
}

TEST(TrajectoryIo, ReadsTheRealEurocGroundTruth) {
  const std::string path = std::string(EDX_SHARED_DATA_DIR) +
                           "/euroc_v101_micro/mav0/state_groundtruth_estimate0/data.csv";
  const Trajectory trajectory = read_trajectory(path, TrajectoryFormat::kEuroc);
  ASSERT_EQ(trajectory.poses.size(), 2895u);  // 2896 lines, one header
  // First row: 1403715273262142976, 0.878895, 2.1834, 0.948427, qw 0.069433, qx -0.824237, ...
  EXPECT_DOUBLE_EQ(trajectory.poses[0].time_s, 1403715273262142976 * 1e-9);
  EXPECT_EQ(trajectory.poses[0].line, 2u);
  EXPECT_EQ(trajectory.poses[0].pose.translation(), Eigen::Vector3d(0.878895, 2.1834, 0.948427));
  const Eigen::Quaterniond q =
      Eigen::Quaterniond(0.069433, -0.824237, -0.106942, -0.551702).normalized();
  EXPECT_TRUE(trajectory.poses[0].pose.linear().isApprox(q.toRotationMatrix(), 1e-12));
}

TEST(TrajectoryIo, ParsesFromAStream) {
  std::istringstream in("0 0 0 0 0 0 0 1\n");
  const Trajectory trajectory = parse_trajectory(in, "memory", TrajectoryFormat::kTum);
  EXPECT_EQ(trajectory.source, "memory");
  EXPECT_EQ(trajectory.poses.size(), 1u);
}

TEST(TrajectoryIo, FormatNames) {
  EXPECT_EQ(parse_trajectory_format("euroc"), TrajectoryFormat::kEuroc);
  EXPECT_EQ(trajectory_format_name(TrajectoryFormat::kTum), "tum");
  EXPECT_THROW(parse_trajectory_format("csv"), std::runtime_error);
}

// ---- bad files: one line, "file:line: what was expected" ----

TEST(TrajectoryIoErrors, KittiShortRow) {
  EXPECT_EQ(
      read_error("est.txt", kIdentityRow + "1 0 0 0 0 1 0 0 0 0 1\n", TrajectoryFormat::kKitti),
      ":2: expected 12 or 13 numbers, got 11");
}

TEST(TrajectoryIoErrors, KittiRowsMustKeepTheirWidth) {
  EXPECT_EQ(read_error("est.txt", "0 " + kIdentityRow + kIdentityRow, TrajectoryFormat::kKitti),
            ":2: expected 13 numbers as on the first pose line, got 12");
}

TEST(TrajectoryIoErrors, NonNumericToken) {
  EXPECT_EQ(read_error("est.txt", "1 0 0 0 0 1 0 x 0 0 1 0\n", TrajectoryFormat::kKitti),
            ":1: 'x' is not a number (column 8)");
  EXPECT_EQ(read_error("est.tum", "0.1 1 2 3abc 0 0 0 1\n", TrajectoryFormat::kTum),
            ":1: '3abc' is not a number (column 4)");
}

TEST(TrajectoryIoErrors, NanAndInf) {
  EXPECT_EQ(read_error("est.txt", "1 0 0 nan 0 1 0 0 0 0 1 0\n", TrajectoryFormat::kKitti),
            ":1: non-finite value 'nan' (column 4)");
  EXPECT_EQ(
      read_error("est.tum", "0.1 1 2 3 0 0 0 1\n0.2 inf 2 3 0 0 0 1\n", TrajectoryFormat::kTum),
      ":2: non-finite value 'inf' (column 2)");
}

TEST(TrajectoryIoErrors, PositionsBeyondABillionMetresAreRefused) {
  // 1e9 m is read, anything beyond is refused in each format at its column (before: 1e155 gave
  // an ATE of inf).
  ScratchDir dir("io");
  EXPECT_EQ(read_trajectory(dir.write("edge.txt", "1 0 0 1e9 0 1 0 -1e9 0 0 1 0\n"),
                            TrajectoryFormat::kKitti)
                .poses.size(),
            1u);
  EXPECT_EQ(read_error("est.txt", "1 0 0 0 0 1 0 1.5e155 0 0 1 0\n", TrajectoryFormat::kKitti),
            ":1: position 1.5e155 m is beyond the 1e+09 m edx evaluates (column 8)");
  EXPECT_EQ(read_error("est.tum", "0.1 1 2 -1000000001 0 0 0 1\n", TrajectoryFormat::kTum),
            ":1: position -1000000001 m is beyond the 1e+09 m edx evaluates (column 4)");
  EXPECT_EQ(read_error("est.csv", "100,2e9,0,0,1,0,0,0\n", TrajectoryFormat::kEuroc),
            ":1: position 2e9 m is beyond the 1e+09 m edx evaluates (column 2)");
}

TEST(TrajectoryIoErrors, FrameIndexMustBeANonNegativeInteger) {
  EXPECT_EQ(read_error("est.txt", "2.5 " + kIdentityRow, TrajectoryFormat::kKitti),
            ":1: frame index '2.5' is not a non-negative integer");
}

TEST(TrajectoryIoErrors, UnsortedAndDuplicateFrameIndices) {
  EXPECT_EQ(
      read_error("est.txt", "3 " + kIdentityRow + "2 " + kIdentityRow, TrajectoryFormat::kKitti),
      ":2: frame index 2 comes after frame index 3 on line 1: poses must be sorted");
  EXPECT_EQ(
      read_error("est.txt", "3 " + kIdentityRow + "3 " + kIdentityRow, TrajectoryFormat::kKitti),
      ":2: duplicate frame index 3 (also on line 1)");
}

TEST(TrajectoryIoErrors, UnsortedAndDuplicateTumTimestamps) {
  const std::string pose = " 0 0 0 0 0 0 1\n";
  EXPECT_EQ(read_error("est.tum", "0.2" + pose + "0.1" + pose, TrajectoryFormat::kTum),
            ":2: timestamp 0.1 s comes after timestamp 0.2 s on line 1: poses must be sorted");
  // Repeated stamps (as in the TUM RGB-D ground truth): the first pose of a stamp is kept.
  std::istringstream repeated(
      "0.1 1 0 0 0 0 0 1\n# comment\n0.1 2 0 0 0 0 0 1\n0.1 3 0 0 0 0 0 1\n"
      "0.2 4 0 0 0 0 0 1\n");
  const Trajectory t = parse_trajectory(repeated, "gt.tum", TrajectoryFormat::kTum);
  ASSERT_EQ(t.poses.size(), 2u);
  EXPECT_DOUBLE_EQ(t.poses[0].pose.translation().x(), 1.0);
  EXPECT_DOUBLE_EQ(t.poses[1].pose.translation().x(), 4.0);
  EXPECT_EQ(t.repeated_stamps_dropped, 2u);
  EXPECT_EQ(t.first_repeated_line, 3u);
}

TEST(TrajectoryIoErrors, UnsortedAndDuplicateEurocTimestamps) {
  const std::string header = "#timestamp, p_x, p_y, p_z, q_w, q_x, q_y, q_z\n";
  // Two stamps 1 ns apart stay distinct (compared as integers, not as seconds).
  EXPECT_EQ(read_error("gt.csv",
                       header + "1403715273262142977,0,0,0,1,0,0,0\n" +
                           "1403715273262142976,0,0,0,1,0,0,0\n",
                       TrajectoryFormat::kEuroc),
            ":3: timestamp 1403715273262142976 ns comes after timestamp 1403715273262142977 ns "
            "on line 2: poses must be sorted");
  std::istringstream repeated(header + "100,0,0,0,1,0,0,0\n100,5,0,0,1,0,0,0\n");
  const Trajectory t = parse_trajectory(repeated, "gt.csv", TrajectoryFormat::kEuroc);
  EXPECT_EQ(t.poses.size(), 1u);
  EXPECT_EQ(t.repeated_stamps_dropped, 1u);
  EXPECT_EQ(t.first_repeated_line, 3u);
}

TEST(TrajectoryIoErrors, ADirectoryIsNamedAsSuch) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path();
  try {
    read_trajectory(dir, TrajectoryFormat::kTum);
    FAIL() << "a directory was read as a trajectory";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              dir.string() + ": is a directory (expected a trajectory file)");
  }
}

TEST(TrajectoryIoErrors, TumAndEurocShortRows) {
  EXPECT_EQ(read_error("est.tum", "0.1 1 2 3 0 0 1\n", TrajectoryFormat::kTum),
            ":1: expected 8 numbers (t x y z qx qy qz qw), got 7");
  EXPECT_EQ(read_error("gt.csv", "#header\n100, 1, 2, 3, 1\n", TrajectoryFormat::kEuroc),
            ":2: expected at least 8 comma-separated values (timestamp_ns, px, py, pz, qw, qx, "
            "qy, qz), got 5");
}

TEST(TrajectoryIoErrors, EurocTimestampMustBeIntegerNanoseconds) {
  EXPECT_EQ(read_error("gt.csv", "1.5,0,0,0,1,0,0,0\n", TrajectoryFormat::kEuroc),
            ":1: timestamp '1.5' is not a non-negative integer in ns (column 1)");
}

TEST(TrajectoryIoErrors, RotationNotOrthonormal) {
  EXPECT_EQ(
      read_error("est.txt", kIdentityRow + "1.1 0 0 0 0 1 0 0 0 0 1 0\n", TrajectoryFormat::kKitti),
      ":2: rotation is not orthonormal (max |R^T R - I| = 0.21, tolerance 0.001)");
  EXPECT_EQ(read_error("est.txt", "-1 0 0 0 0 1 0 0 0 0 1 0\n", TrajectoryFormat::kKitti),
            ":1: rotation has a negative determinant (a reflection)");
  EXPECT_EQ(read_error("est.tum", "0.1 1 2 3 0 0 0 0.5\n", TrajectoryFormat::kTum),
            ":1: quaternion norm 0.5 is not 1 (tolerance 0.001)");
}

TEST(TrajectoryIoErrors, KittiRotationsAtSevenDigitsAreAccepted) {
  // A rotation printed with 7 significant digits (as KITTI's ground truth) is within tolerance.
  ScratchDir dir("io");
  const std::string path = dir.write(
      "gt.txt",
      "9.999268e-01 -3.092411e-03 1.169425e-02 2.138869e-02 3.079219e-03 9.999946e-01 "
      "1.146026e-03 -8.456433e-03 -1.169773e-02 -1.109933e-03 9.999310e-01 2.880714e-01\n");
  EXPECT_EQ(read_trajectory(path, TrajectoryFormat::kKitti).poses.size(), 1u);
}

TEST(TrajectoryIoErrors, EmptyAndMissingFiles) {
  EXPECT_EQ(read_error("est.txt", "# only a comment\n\n", TrajectoryFormat::kKitti),
            ": no poses found (expected kitti format)");
  try {
    read_trajectory("/nonexistent/est.txt", TrajectoryFormat::kKitti);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& error) {
    EXPECT_STREQ(error.what(), "/nonexistent/est.txt: cannot open trajectory file");
  }
}

}  // namespace
}  // namespace edx::eval
