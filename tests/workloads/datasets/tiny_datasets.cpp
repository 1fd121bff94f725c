#include "tests/workloads/datasets/tiny_datasets.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

namespace edx::datasets::testing {
namespace fs = std::filesystem;

TempFolder::TempFolder(const std::string& name)
    : path_(fs::temp_directory_path() / fmt::format("edx_datasets_{}_{}", name, getpid())) {
  fs::remove_all(path_);
  fs::create_directories(path_);
}

TempFolder::~TempFolder() {
  std::error_code error;
  fs::remove_all(path_, error);
}

void write_text(const fs::path& file, const std::string& text) {
  fs::create_directories(file.parent_path());
  std::ofstream stream(file, std::ios::binary | std::ios::trunc);
  stream << text;
  ASSERT_TRUE(stream.good()) << file;
}

std::string read_text(const fs::path& file) {
  std::ifstream stream(file, std::ios::binary);
  std::ostringstream text;
  text << stream.rdbuf();
  return text.str();
}

void replace_in_file(const fs::path& file, const std::string& from, const std::string& to) {
  std::string text = read_text(file);
  const auto at = text.find(from);
  ASSERT_NE(at, std::string::npos) << from << " not in " << file;
  text.replace(at, from.size(), to);
  write_text(file, text);
}

namespace {

std::string camera_yaml(double x_offset_m) {
  return fmt::format(R"(%YAML:1.0
sensor_type: camera
comment: tiny test camera
T_BS:
  cols: 4
  rows: 4
  data: [1.0, 0.0, 0.0, {},
         0.0, 1.0, 0.0, 0.0,
         0.0, 0.0, 1.0, 0.0,
         0.0, 0.0, 0.0, 1.0]
rate_hz: 20
resolution: [{}, {}]
camera_model: pinhole
intrinsics: [50.0, 50.0, 31.5, 23.5] #fu, fv, cu, cv
distortion_model: radial-tangential
distortion_coefficients: [0.0, 0.0, 0.0, 0.0]
)",
                     x_offset_m, kTinyWidth, kTinyHeight);
}

constexpr const char* kImuYaml = R"(%YAML:1.0
sensor_type: imu
T_BS:
  cols: 4
  rows: 4
  data: [1.0, 0.0, 0.0, 0.0,
         0.0, 1.0, 0.0, 0.0,
         0.0, 0.0, 1.0, 0.0,
         0.0, 0.0, 0.0, 1.0]
rate_hz: 200
gyroscope_noise_density: 1.0e-4
gyroscope_random_walk: 2.0e-5
accelerometer_noise_density: 3.0e-3
accelerometer_random_walk: 4.0e-3
)";

}  // namespace

fs::path tiny_euroc_image(const fs::path& root, const std::string& camera, int frame) {
  return root / "mav0" / camera / "data" /
         fmt::format("{}.png", kTinyStartNs + frame * kTinyFrameStepNs);
}

void write_tiny_euroc(const fs::path& root) {
  const fs::path mav0 = root / "mav0";
  for (const std::string camera : {"cam0", "cam1"}) {
    fs::create_directories(mav0 / camera / "data");
    write_text(mav0 / camera / "sensor.yaml", camera_yaml(camera == "cam0" ? 0.0 : 0.1));
    std::string csv = "#timestamp [ns],filename\n";
    for (int i = 0; i < kTinyFrames; ++i) {
      const TimestampNs t = kTinyStartNs + i * kTinyFrameStepNs;
      csv += fmt::format("{},{}.png\n", t, t);
      const cv::Mat image(kTinyHeight, kTinyWidth, CV_8UC1, cv::Scalar(tiny_frame_intensity(i)));
      ASSERT_TRUE(cv::imwrite(tiny_euroc_image(root, camera, i).string(), image));
    }
    write_text(mav0 / camera / "data.csv", csv);
  }
  std::string imu = "#timestamp [ns],w_x,w_y,w_z,a_x,a_y,a_z\n";
  for (int i = 0; i < 60; ++i) {
    imu += fmt::format("{},0.01,-0.02,0.03,0.1,0.2,9.81\n", kTinyStartNs + i * 5'000'000);
  }
  write_text(mav0 / "imu0" / "data.csv", imu);
  write_text(mav0 / "imu0" / "sensor.yaml", kImuYaml);
  std::string gt =
      "#timestamp,p_x,p_y,p_z,q_w,q_x,q_y,q_z,v_x,v_y,v_z,bw_x,bw_y,bw_z,ba_x,ba_y,ba_z\n";
  for (int i = 0; i < kTinyFrames; ++i) {
    gt += fmt::format("{},{},0,1,1,0,0,0,2,0,0,0.001,0.002,0.003,0.01,0.02,0.03\n",
                      kTinyStartNs + i * kTinyFrameStepNs, 0.1 * i);
  }
  write_text(mav0 / "state_groundtruth_estimate0" / "data.csv", gt);
  write_text(mav0 / "gps0" / "data.csv",
             fmt::format("#timestamp [ns],p_x [m],p_y [m],p_z [m],sigma [m]\n"
                         "{},0.05,-0.1,1.2,1.5\n{},0.35,0.1,0.9,2.5\n",
                         kTinyStartNs, kTinyStartNs + 3 * kTinyFrameStepNs));
}

void write_tiny_kitti(const fs::path& root) {
  const fs::path sequence = root / "sequences" / "07";
  write_text(sequence / "calib.txt",
             "P0: 100 0 20 0 0 100 15 0 0 0 1 0\n"
             "P1: 100 0 20 -50 0 100 15 0 0 0 1 0\n"
             "P2: 100 0 20 5 0 100 15 0 0 0 1 0\n");
  write_text(sequence / "times.txt", "0.000000e+00\n1.000000e-01\n2.000000e-01\n");
  write_text(root / "poses" / "07.txt",
             "1 0 0 0 0 1 0 0 0 0 1 0\n"
             "1 0 0 0.1 0 1 0 0 0 0 1 1.0\n"
             "1 0 0 0.2 0 1 0 0 0 0 1 2.0\n");
  for (const std::string camera : {"image_0", "image_1"}) {
    fs::create_directories(sequence / camera);
    for (int i = 0; i < 3; ++i) {
      const cv::Mat image(30, 40, CV_8UC1, cv::Scalar(50 + 60 * i));
      ASSERT_TRUE(cv::imwrite((sequence / camera / fmt::format("{:06d}.png", i)).string(), image));
    }
  }
}

}  // namespace edx::datasets::testing
