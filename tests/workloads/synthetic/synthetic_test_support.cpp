#include "tests/workloads/synthetic/synthetic_test_support.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <iterator>
#include <opencv2/core.hpp>
#include <sstream>
#include <stdexcept>

namespace edx::synthetic::testing {

namespace fs = std::filesystem;

TempDir::TempDir(const std::string& name) {
  path_ =
      fs::path(::testing::TempDir()) / ("edx_synthetic_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(path_);
  fs::create_directories(path_);
}

TempDir::~TempDir() {
  std::error_code ec;
  fs::remove_all(path_, ec);
}

std::vector<std::vector<std::string>> read_csv(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error("cannot open " + file.string());
  std::vector<std::vector<std::string>> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> fields;
    std::stringstream ss(line);
    std::string field;
    while (std::getline(ss, field, ',')) fields.push_back(field);
    rows.push_back(fields);
  }
  return rows;
}

std::string first_line(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  return line;
}

std::vector<std::vector<double>> read_numeric_csv(const fs::path& file) {
  std::vector<std::vector<double>> out;
  for (const auto& row : read_csv(file)) {
    std::vector<double> values;
    for (const auto& f : row) values.push_back(std::stod(f));
    out.push_back(values);
  }
  return out;
}

CameraFile read_camera_yaml(const fs::path& file) {
  cv::FileStorage fs(file.string(), cv::FileStorage::READ);
  if (!fs.isOpened()) throw std::runtime_error("cannot parse " + file.string());
  CameraFile c;
  std::vector<int> resolution;
  fs["resolution"] >> resolution;
  std::vector<double> intrinsics;
  fs["intrinsics"] >> intrinsics;
  fs["distortion_coefficients"] >> c.distortion;
  std::vector<double> data;
  fs["T_BS"]["data"] >> data;
  if (resolution.size() != 2 || intrinsics.size() != 4 || data.size() != 16) {
    throw std::runtime_error("incomplete camera file " + file.string());
  }
  c.width = resolution[0];
  c.height = resolution[1];
  c.fx = intrinsics[0];
  c.fy = intrinsics[1];
  c.cx = intrinsics[2];
  c.cy = intrinsics[3];
  Eigen::Matrix4d M;
  for (int i = 0; i < 16; ++i) M(i / 4, i % 4) = data[static_cast<std::size_t>(i)];
  c.T_BS.matrix() = M;
  return c;
}

std::vector<GroundTruthRow> read_ground_truth(const fs::path& mav0) {
  std::vector<GroundTruthRow> rows;
  for (const auto& r : read_csv(mav0 / "state_groundtruth_estimate0" / "data.csv")) {
    if (r.size() != 17)
      throw std::runtime_error("ground truth row with " + std::to_string(r.size()) + " fields");
    GroundTruthRow g;
    g.t_ns = std::stoll(r[0]);
    auto num = [&](int i) { return std::stod(r[static_cast<std::size_t>(i)]); };
    g.p = {num(1), num(2), num(3)};
    g.q = Eigen::Quaterniond(num(4), num(5), num(6), num(7)).normalized();
    g.v = {num(8), num(9), num(10)};
    g.bg = {num(11), num(12), num(13)};
    g.ba = {num(14), num(15), num(16)};
    rows.push_back(g);
  }
  return rows;
}

std::map<std::string, std::uint64_t> hash_tree(const fs::path& root) {
  std::map<std::string, std::uint64_t> out;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    if (!entry.is_regular_file()) continue;
    std::ifstream in(entry.path(), std::ios::binary);
    std::uint64_t h = 0xCBF29CE484222325ull;
    for (std::istreambuf_iterator<char> it(in), end; it != end; ++it) {
      h = (h ^ static_cast<unsigned char>(*it)) * 0x100000001B3ull;
    }
    out[fs::relative(entry.path(), root).generic_string()] = h;
  }
  return out;
}

}  // namespace edx::synthetic::testing
