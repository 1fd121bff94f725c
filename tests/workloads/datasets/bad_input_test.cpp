// Broken datasets: each test writes a tiny valid folder, breaks one thing and checks the
// one-line error (naming the file and the line or key) or the reported skip.
#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "tests/support/error_of.hpp"
#include "tests/workloads/datasets/tiny_datasets.hpp"
#include "workloads/datasets/dataset.hpp"
#include "workloads/datasets/image_io.hpp"

namespace edx::datasets {
namespace {

namespace fs = std::filesystem;
using testing::TempFolder;

using edx::testing::error_of;

std::string open_error(const fs::path& path, DatasetFormat format = DatasetFormat::kEuroc,
                       const DatasetOptions& options = {}) {
  return error_of([&] { open_dataset(path, format, options); });
}

#define EXPECT_CONTAINS(text, part) \
  EXPECT_NE(std::string(text).find(part), std::string::npos) << "'" << (text) << "'"

class TinyEuroc : public ::testing::Test {
 protected:
  void SetUp() override { testing::write_tiny_euroc(root()); }
  const fs::path& root() const { return folder_.path(); }
  fs::path mav0(const std::string& relative) const { return root() / "mav0" / relative; }

 private:
  TempFolder folder_{"tiny_euroc"};
};

TEST_F(TinyEuroc, ValidFolderReadsEveryStream) {
  const auto dataset = open_dataset(root(), DatasetFormat::kEuroc);
  EXPECT_EQ(dataset->frame_count(), 5u);
  EXPECT_TRUE(dataset->load_report().warnings.empty());
  // An already rectified pair (as `edx gen` writes) passes through: stated intrinsics, the
  // image files' own pixels.
  const StereoCalibration& calibration = dataset->calibration();
  EXPECT_NEAR(calibration.baseline_m, 0.1, 1e-12);
  EXPECT_EQ(calibration.rectified.fx, 50.0);
  EXPECT_EQ(calibration.rectified.cx, 31.5);
  EXPECT_EQ(calibration.rectified.cy, 23.5);
  EXPECT_TRUE(calibration.rectified.distortion.empty());
  EXPECT_TRUE(calibration.T_body_left.isApprox(calibration.T_body_raw_left));
  const StereoFrame frame = dataset->load_frame(2);
  const cv::Mat file =
      cv::imread(testing::tiny_euroc_image(root(), "cam1", 2).string(), cv::IMREAD_GRAYSCALE);
  EXPECT_EQ(cv::norm(frame.right, file, cv::NORM_INF), 0);
  EXPECT_EQ(dataset->imu().size(), 60u);
  EXPECT_DOUBLE_EQ(dataset->imu_noise()->accel_random_walk, 4.0e-3);
  EXPECT_FALSE(dataset->imu_noise()->accel_bias_sigma.has_value());  // EuRoC states none
  ASSERT_EQ(dataset->ground_truth().size(), 5u);
  EXPECT_DOUBLE_EQ(dataset->ground_truth()[3].T_world_body.translation().x(), 0.3);
  EXPECT_DOUBLE_EQ(dataset->ground_truth()[3].velocity_m_s->x(), 2.0);
  // gps0/data.csv: "#timestamp [ns],p_x [m],p_y [m],p_z [m],sigma [m]".
  ASSERT_EQ(dataset->gps().size(), 2u);
  EXPECT_EQ(dataset->gps()[1].t_ns, testing::kTinyStartNs + 3 * testing::kTinyFrameStepNs);
  EXPECT_TRUE(dataset->gps()[1].position_m.isApprox(Eigen::Vector3d(0.35, 0.1, 0.9)));
  EXPECT_DOUBLE_EQ(dataset->gps()[1].sigma_m, 2.5);
}

TEST_F(TinyEuroc, MissingImageIsSkippedAndNeverMispaired) {
  fs::remove(testing::tiny_euroc_image(root(), "cam1", 2));
  const auto dataset = open_dataset(root(), DatasetFormat::kEuroc);
  ASSERT_EQ(dataset->frame_count(), 4u);
  const LoadReport& report = dataset->load_report();
  EXPECT_EQ(report.right_missing_images, 1u);
  EXPECT_EQ(report.left_missing_images, 0u);
  EXPECT_EQ(report.left_unpaired, 1u);  // cam0's frame 2 has lost its partner
  EXPECT_EQ(report.warnings.size(), 2u);
  EXPECT_CONTAINS(report.warnings[0], "cam1");
  const int expected_frames[] = {0, 1, 3, 4};
  for (std::size_t i = 0; i < 4; ++i) {
    const StereoFrame frame = dataset->load_frame(i);
    const int source = expected_frames[i];
    EXPECT_EQ(frame.t_ns, testing::kTinyStartNs + source * testing::kTinyFrameStepNs);
    // Each pixel carries the frame's fingerprint intensity, left and right alike.
    const cv::Point centre(testing::kTinyWidth / 2, testing::kTinyHeight / 2);
    EXPECT_EQ(frame.left.at<std::uint8_t>(centre), testing::tiny_frame_intensity(source));
    EXPECT_EQ(frame.right.at<std::uint8_t>(centre), testing::tiny_frame_intensity(source));
  }
}

TEST_F(TinyEuroc, NoImageAtAllIsAnError) {
  fs::remove_all(mav0("cam0/data"));
  EXPECT_CONTAINS(open_error(root()), "no stereo pair");
}

TEST_F(TinyEuroc, MissingFoldersAndFiles) {
  EXPECT_CONTAINS(open_error(root() / "nowhere"), "nowhere: dataset folder not found");
  fs::remove_all(mav0("cam1"));
  EXPECT_CONTAINS(open_error(root()), "cam1: camera folder not found");
  testing::write_tiny_euroc(root());
  fs::remove(mav0("cam0/data.csv"));
  EXPECT_CONTAINS(open_error(root()), "cam0/data.csv: file not found");
  testing::write_tiny_euroc(root());
  fs::remove(mav0("imu0/data.csv"));
  EXPECT_CONTAINS(open_error(root()), "imu0/data.csv: file not found");
  testing::write_tiny_euroc(root());
  fs::remove(mav0("cam1/sensor.yaml"));
  EXPECT_CONTAINS(open_error(root()), "cam1/sensor.yaml: file not found");
}

TEST_F(TinyEuroc, ShortCsvRowNamesFileAndLine) {
  // Line 1 is the header, line 3 the second sample.
  testing::replace_in_file(mav0("imu0/data.csv"), "1005000000,0.01,-0.02,0.03,0.1,0.2,9.81",
                           "1005000000,0.01,-0.02,0.03");
  const std::string message = open_error(root());
  EXPECT_CONTAINS(message, "imu0/data.csv:3:");
  EXPECT_CONTAINS(message, "expected 7 fields, got 4");
}

TEST_F(TinyEuroc, MalformedNumberNamesFileLineAndField) {
  testing::replace_in_file(mav0("state_groundtruth_estimate0/data.csv"), ",0.2,0,1,", ",0.2x,0,1,");
  const std::string message = open_error(root());
  EXPECT_CONTAINS(message, "state_groundtruth_estimate0/data.csv:4:");
  EXPECT_CONTAINS(message, "'0.2x'");
  testing::write_tiny_euroc(root());
  testing::replace_in_file(mav0("cam0/data.csv"), "1050000000,", "1050000000.5,");
  EXPECT_CONTAINS(open_error(root()),
                  "cam0/data.csv:3: field 1 (timestamp [ns]) must be an integer");
}

TEST_F(TinyEuroc, NonIncreasingTimeStampsNameFileAndLine) {
  testing::replace_in_file(mav0("cam1/data.csv"), "1100000000,", "1000000000,");
  EXPECT_CONTAINS(open_error(root()), "cam1/data.csv:4: time stamp 1000000000 does not increase");
  testing::write_tiny_euroc(root());
  testing::replace_in_file(mav0("gps0/data.csv"), "1150000000,", "1000000000,");
  EXPECT_CONTAINS(open_error(root()), "gps0/data.csv:3: time stamp");
}

TEST_F(TinyEuroc, MissingOrMalformedYamlKeysNameFileAndKey) {
  testing::replace_in_file(mav0("cam0/sensor.yaml"), "intrinsics: [50.0, 50.0, 31.5, 23.5]", "");
  std::string message = open_error(root());
  EXPECT_CONTAINS(message, "cam0/sensor.yaml: missing key 'intrinsics'");

  testing::write_tiny_euroc(root());
  testing::replace_in_file(mav0("cam1/sensor.yaml"), "[50.0, 50.0, 31.5, 23.5]", "[50.0, 50.0]");
  EXPECT_CONTAINS(open_error(root()),
                  "cam1/sensor.yaml: key 'intrinsics': expected a list of 4 numbers");

  testing::write_tiny_euroc(root());
  testing::replace_in_file(mav0("cam0/sensor.yaml"), "radial-tangential", "equidistant");
  EXPECT_CONTAINS(open_error(root()), "key 'distortion_model': 'equidistant' is not supported");

  testing::write_tiny_euroc(root());
  testing::replace_in_file(mav0("cam1/sensor.yaml"), "data: [1.0,", "data: [2.0,");
  EXPECT_CONTAINS(open_error(root()), "cam1/sensor.yaml: key 'T_BS': top-left 3x3 block is not");

  testing::write_tiny_euroc(root());
  testing::replace_in_file(mav0("imu0/sensor.yaml"), "accelerometer_random_walk: 4.0e-3", "");
  EXPECT_CONTAINS(open_error(root()), "imu0/sensor.yaml: missing key 'accelerometer_random_walk'");

  testing::write_tiny_euroc(root());
  testing::replace_in_file(mav0("imu0/sensor.yaml"), "accelerometer_random_walk: 4.0e-3",
                           "accelerometer_random_walk: 4.0e-3\naccelerometer_bias_sigma: -0.02");
  EXPECT_CONTAINS(open_error(root()),
                  "imu0/sensor.yaml: key 'accelerometer_bias_sigma': expected a positive number");

  testing::write_tiny_euroc(root());
  testing::replace_in_file(mav0("cam0/sensor.yaml"), "rate_hz: 20", "rate_hz: [20");
  EXPECT_CONTAINS(open_error(root()), "cam0/sensor.yaml: not valid YAML");
}

TEST_F(TinyEuroc, ImuMustBeTheBodyFrame) {
  testing::replace_in_file(mav0("imu0/sensor.yaml"), "data: [1.0, 0.0, 0.0, 0.0,",
                           "data: [1.0, 0.0, 0.0, 0.5,");
  EXPECT_CONTAINS(open_error(root()), "imu0/sensor.yaml: key 'T_BS': the IMU must be the body");
}

TEST_F(TinyEuroc, VerticalOrSwappedStereoPairIsRejected) {
  testing::replace_in_file(mav0("cam1/sensor.yaml"), "data: [1.0, 0.0, 0.0, 0.1,",
                           "data: [1.0, 0.0, 0.0, -0.1,");
  EXPECT_CONTAINS(open_error(root()), "not horizontal with the right camera on the +x side");
}

TEST_F(TinyEuroc, WrongImageSizeNamesTheFile) {
  const fs::path image = testing::tiny_euroc_image(root(), "cam1", 3);
  ASSERT_TRUE(cv::imwrite(image.string(), cv::Mat(24, 32, CV_8UC1, cv::Scalar(9))));
  const auto dataset = open_dataset(root(), DatasetFormat::kEuroc);  // frame 0 is fine
  const std::string message = error_of([&] { dataset->load_frame(3); });
  EXPECT_CONTAINS(message, image.string() + ": image is 32x24, expected 64x48");
  EXPECT_CONTAINS(message, "cam1/sensor.yaml");
  // A wrong first frame is caught when the dataset is opened.
  ASSERT_TRUE(cv::imwrite(testing::tiny_euroc_image(root(), "cam0", 0).string(),
                          cv::Mat(48, 65, CV_8UC1, cv::Scalar(9))));
  EXPECT_CONTAINS(open_error(root()), "image is 65x48, expected 64x48");
}

TEST_F(TinyEuroc, UnreadableImageNamesTheFile) {
  const fs::path image = testing::tiny_euroc_image(root(), "cam0", 4);
  testing::write_text(image, "this is not a PNG file");
  const auto dataset = open_dataset(root(), DatasetFormat::kEuroc);
  EXPECT_EQ(error_of([&] { dataset->load_frame(4); }),
            image.string() + ": cannot read image: not a PNG file (expected a PNG image)");
  testing::write_text(image, "");
  EXPECT_EQ(error_of([&] { dataset->load_frame(4); }),
            image.string() + ": cannot read image (missing, unreadable or empty)");
}

TEST_F(TinyEuroc, GpsSigmaMustBePositive) {
  testing::replace_in_file(mav0("gps0/data.csv"), ",2.5\n", ",-2.5\n");
  EXPECT_CONTAINS(open_error(root()), "gps0/data.csv:3: field 5 (sigma) must be positive");
}

TEST_F(TinyEuroc, BadOptionsAreErrors) {
  DatasetOptions options;
  options.resize = cv::Size(0, 480);
  EXPECT_CONTAINS(open_error(root(), DatasetFormat::kEuroc, options), "resize target 0x480");
  options.resize.reset();
  options.rectify_alpha = 2;
  EXPECT_CONTAINS(open_error(root(), DatasetFormat::kEuroc, options), "rectify_alpha 2");
}

class TinyKitti : public ::testing::Test {
 protected:
  void SetUp() override { testing::write_tiny_kitti(root()); }
  const fs::path& root() const { return folder_.path(); }
  fs::path sequence() const { return root() / "sequences" / "07"; }

 private:
  TempFolder folder_{"tiny_kitti"};
};

TEST_F(TinyKitti, ValidFolderOpensFromRootOrSequence) {
  DatasetOptions options;
  options.kitti_sequence = "07";
  const auto dataset = open_dataset(root(), DatasetFormat::kKitti, options);
  EXPECT_EQ(dataset->frame_count(), 3u);
  EXPECT_DOUBLE_EQ(dataset->calibration().baseline_m, 0.5);
  EXPECT_EQ(dataset->frame_time(2), 200'000'000);
  EXPECT_DOUBLE_EQ(dataset->ground_truth()[2].T_world_body.translation().z(), 2.0);
  EXPECT_EQ(dataset->load_frame(1).left.at<std::uint8_t>(10, 10), 110);
  EXPECT_EQ(open_dataset(sequence(), DatasetFormat::kKitti)->frame_count(), 3u);
}

TEST_F(TinyKitti, RootWithoutSequenceIdOrWrongIdIsAnError) {
  EXPECT_CONTAINS(open_error(root(), DatasetFormat::kKitti), "needs a sequence id");
  DatasetOptions options;
  options.kitti_sequence = "08";
  EXPECT_CONTAINS(open_error(root(), DatasetFormat::kKitti, options),
                  "08: sequence folder not found");
  EXPECT_CONTAINS(open_error(sequence(), DatasetFormat::kKitti, options),
                  "does not match sequence '08'");
}

TEST_F(TinyKitti, CalibrationErrorsNameFileLineAndKey) {
  testing::replace_in_file(sequence() / "calib.txt", "P1: 100 0 20 -50 0 100 15 0 0 0 1 0\n", "");
  EXPECT_CONTAINS(open_error(sequence(), DatasetFormat::kKitti), "calib.txt: missing key 'P1'");
  testing::write_tiny_kitti(root());
  testing::replace_in_file(sequence() / "calib.txt", "-50 0 100 15 0 0 0 1 0", "-50 0 100 15 0");
  EXPECT_CONTAINS(open_error(sequence(), DatasetFormat::kKitti),
                  "calib.txt:2: key 'P1' expects 12 numbers, got 8");
  testing::write_tiny_kitti(root());
  testing::replace_in_file(sequence() / "calib.txt", "-50", "50");
  EXPECT_CONTAINS(open_error(sequence(), DatasetFormat::kKitti), "right camera on the left");
}

TEST_F(TinyKitti, TimesAndPosesErrors) {
  testing::replace_in_file(sequence() / "times.txt", "2.000000e-01", "1.000000e-01");
  EXPECT_CONTAINS(open_error(sequence(), DatasetFormat::kKitti), "times.txt:3: time");
  testing::write_tiny_kitti(root());
  testing::replace_in_file(root() / "poses" / "07.txt", "1 0 0 0.2 0 1 0 0 0 0 1 2.0\n", "");
  EXPECT_CONTAINS(open_error(sequence(), DatasetFormat::kKitti), "07.txt: 2 poses for 3 time");
  testing::write_tiny_kitti(root());
  testing::replace_in_file(root() / "poses" / "07.txt", "1 0 0 0.1 0 1 0 0 0 0 1 1.0",
                           "1 0 0 0.1 0 1 0 0 0 0 1");
  EXPECT_CONTAINS(open_error(sequence(), DatasetFormat::kKitti),
                  "07.txt:2: expected 12 or 13 numbers, got 11");
}

TEST_F(TinyKitti, MissingRightImageIsSkippedWithAWarning) {
  fs::remove(sequence() / "image_1" / "000001.png");
  const auto dataset = open_dataset(sequence(), DatasetFormat::kKitti);
  EXPECT_EQ(dataset->frame_count(), 2u);
  EXPECT_EQ(dataset->load_report().right_missing_images, 1u);
  EXPECT_EQ(dataset->frame_time(1), 200'000'000);
  EXPECT_EQ(dataset->load_frame(1).right.at<std::uint8_t>(0, 0), 170);
}

TEST(DatasetFormatParsing, AcceptsTheTwoFormatsAndListsThemOtherwise) {
  EXPECT_EQ(parse_dataset_format("euroc"), DatasetFormat::kEuroc);
  EXPECT_EQ(parse_dataset_format("kitti"), DatasetFormat::kKitti);
  EXPECT_EQ(to_string(DatasetFormat::kKitti), "kitti");
  const std::string message = error_of([] { parse_dataset_format("tum"); });
  EXPECT_CONTAINS(message, "'tum'");
  EXPECT_CONTAINS(message, "euroc, kitti");
}

TEST(ResolutionParsing, AcceptsWidthByHeightOnly) {
  EXPECT_EQ(parse_resolution("640x480"), cv::Size(640, 480));
  EXPECT_EQ(parse_resolution("1280x720"), cv::Size(1280, 720));
  for (const char* bad : {"640", "640x", "x480", "640x-480", "0x480", "640X480", "64.0x48"}) {
    EXPECT_CONTAINS(error_of([&] { parse_resolution(bad); }), "expected WIDTHxHEIGHT") << bad;
  }
}

/// A truncated or damaged PNG is our one error naming the file (libpng printed a line of its own
/// before, "libpng error: Read Error"); an intact one decodes as cv::imread decodes it.
TEST(ReadGrayImage, ATruncatedOrDamagedPngIsOneErrorNamingTheFile) {
  const TempFolder folder("png");
  cv::Mat image(48, 64, CV_8U);
  cv::randu(image, 0, 255);
  const fs::path good = folder.path() / "good.png";
  ASSERT_TRUE(cv::imwrite(good.string(), image));
  std::vector<unsigned char> bytes;
  cv::imencode(".png", image, bytes);
  const cv::Mat decoded = read_gray_image(good);
  EXPECT_EQ(cv::norm(decoded, cv::imread(good.string(), cv::IMREAD_GRAYSCALE), cv::NORM_INF), 0);
  EXPECT_EQ(cv::norm(decoded, image, cv::NORM_INF), 0);

  const auto write_bytes = [&](const std::string& name, const std::vector<unsigned char>& b) {
    std::ofstream(folder.path() / name, std::ios::binary)
        .write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
    return folder.path() / name;
  };
  // Cut inside the image data (IDAT), and cut just before the final IEND chunk.
  const fs::path cut = write_bytes("cut.png", {bytes.begin(), bytes.begin() + 100});
  EXPECT_EQ(error_of([&] { read_gray_image(cut); }),
            cut.string() + ": truncated PNG (100 bytes; the chunk at byte 33 declares " +
                std::to_string(bytes.size() - 33 - 12 - 12) + " bytes of data)");
  const fs::path no_end = write_bytes("no_end.png", {bytes.begin(), bytes.end() - 12});
  EXPECT_EQ(error_of([&] { read_gray_image(no_end); }), no_end.string() + ": truncated PNG (" +
                                                            std::to_string(bytes.size() - 12) +
                                                            " bytes, ends before its IEND chunk)");
  // One flipped bit in the image data: its chunk's CRC-32 no longer holds.
  std::vector<unsigned char> flipped = bytes;
  flipped[60] ^= 0x10;
  const fs::path damaged = write_bytes("damaged.png", flipped);
  EXPECT_EQ(error_of([&] { read_gray_image(damaged); }),
            damaged.string() + ": damaged PNG (the IDAT chunk at byte 33 fails its CRC)");
  // Every cut and every flipped byte is refused with one line (error_of checks it); a cut
  // inside the 8-byte signature is not a PNG at all.
  for (std::size_t size = 0; size < bytes.size(); size += 13) {
    const fs::path file = write_bytes("cut_any.png", {bytes.begin(), bytes.begin() + size});
    EXPECT_NE(error_of([&] { read_gray_image(file); }), "") << "cut at " << size;
  }
  for (std::size_t at = 0; at < bytes.size(); at += 11) {
    std::vector<unsigned char> changed = bytes;
    changed[at] ^= 0x01;
    const fs::path file = write_bytes("flip_any.png", changed);
    EXPECT_NE(error_of([&] { read_gray_image(file); }), "") << "flip at " << at;
  }
}

}  // namespace
}  // namespace edx::datasets
