#pragma once
// Helpers of the synthetic-world tests: temporary folders, a plain CSV reader, camera
// calibration from sensor.yaml (read with cv::FileStorage, independently of the EuRoC reader)
// and content hashes of a folder tree.
#include <Eigen/Geometry>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace edx::synthetic::testing {

/// A fresh empty folder under the test temp dir, removed with the object.
class TempDir {
 public:
  explicit TempDir(const std::string& name);
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

/// Rows of a CSV file, skipping lines that start with '#'; fields split at commas.
std::vector<std::vector<std::string>> read_csv(const std::filesystem::path& file);
/// The first line of a file.
std::string first_line(const std::filesystem::path& file);

/// Rows of a CSV as numbers (every field parsed with std::stod).
std::vector<std::vector<double>> read_numeric_csv(const std::filesystem::path& file);

struct CameraFile {
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  std::vector<double> distortion;
  Eigen::Isometry3d T_BS = Eigen::Isometry3d::Identity();
};
CameraFile read_camera_yaml(const std::filesystem::path& file);

/// Ground-truth row of state_groundtruth_estimate0/data.csv.
struct GroundTruthRow {
  std::int64_t t_ns = 0;
  Eigen::Vector3d p, v, bg, ba;
  Eigen::Quaterniond q;
};
std::vector<GroundTruthRow> read_ground_truth(const std::filesystem::path& mav0);

/// Relative path -> 64-bit FNV-1a hash of the content, for every regular file under root.
std::map<std::string, std::uint64_t> hash_tree(const std::filesystem::path& root);

}  // namespace edx::synthetic::testing
