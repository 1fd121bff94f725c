#include "workloads/datasets/dataset.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <stdexcept>

#include "workloads/datasets/euroc_dataset.hpp"
#include "workloads/datasets/kitti_dataset.hpp"
#include "workloads/datasets/text_table.hpp"

namespace edx::datasets {

DatasetFormat parse_dataset_format(std::string_view text) {
  if (text == "euroc") return DatasetFormat::kEuroc;
  if (text == "kitti") return DatasetFormat::kKitti;
  throw std::runtime_error(
      fmt::format("dataset format '{}' is not known (expected one of: euroc, kitti)", text));
}

std::string_view to_string(DatasetFormat format) {
  switch (format) {
    case DatasetFormat::kEuroc:
      return "euroc";
    case DatasetFormat::kKitti:
      return "kitti";
  }
  return "unknown";
}

cv::Size parse_resolution(std::string_view text) {
  const auto x = text.find('x');
  std::int64_t width = 0, height = 0;
  if (x == std::string_view::npos || !parse_integer(text.substr(0, x), width) ||
      !parse_integer(text.substr(x + 1), height) || width <= 0 || height <= 0 || width > 65536 ||
      height > 65536) {
    throw std::runtime_error(fmt::format(
        "resolution '{}' is not valid (expected WIDTHxHEIGHT in pixels, e.g. 640x480)", text));
  }
  return {static_cast<int>(width), static_cast<int>(height)};
}

std::unique_ptr<Dataset> open_dataset(const std::filesystem::path& path, DatasetFormat format,
                                      const DatasetOptions& options) {
  switch (format) {
    case DatasetFormat::kEuroc:
      return std::make_unique<EurocDataset>(path, options);
    case DatasetFormat::kKitti:
      return std::make_unique<KittiDataset>(path, options);
  }
  throw std::logic_error("open_dataset: unhandled dataset format");
}

std::optional<GroundTruthPose> interpolate_ground_truth(
    const std::vector<GroundTruthPose>& ground_truth, TimestampNs t_ns, TimestampNs max_gap_ns) {
  if (ground_truth.empty() || t_ns < ground_truth.front().t_ns || t_ns > ground_truth.back().t_ns) {
    return std::nullopt;
  }
  const auto after =
      std::lower_bound(ground_truth.begin(), ground_truth.end(), t_ns,
                       [](const GroundTruthPose& pose, TimestampNs t) { return pose.t_ns < t; });
  if (after->t_ns == t_ns) return *after;
  const auto before = std::prev(after);
  const TimestampNs gap = after->t_ns - before->t_ns;
  if (gap > max_gap_ns) return std::nullopt;

  // a = (t - t0) / (t1 - t0); p = (1-a) p0 + a p1; q = slerp(q0, q1, a).
  const double a = static_cast<double>(t_ns - before->t_ns) / static_cast<double>(gap);
  const auto lerp = [a](const std::optional<Eigen::Vector3d>& v0,
                        const std::optional<Eigen::Vector3d>& v1) {
    return v0 && v1 ? std::optional<Eigen::Vector3d>((1 - a) * *v0 + a * *v1) : std::nullopt;
  };
  GroundTruthPose pose;
  pose.t_ns = t_ns;
  const Eigen::Quaterniond q0(before->T_world_body.rotation());
  const Eigen::Quaterniond q1(after->T_world_body.rotation());
  pose.T_world_body.linear() = q0.slerp(a, q1).toRotationMatrix();
  pose.T_world_body.translation() =
      (1 - a) * before->T_world_body.translation() + a * after->T_world_body.translation();
  pose.velocity_m_s = lerp(before->velocity_m_s, after->velocity_m_s);
  pose.gyro_bias_rad_s = lerp(before->gyro_bias_rad_s, after->gyro_bias_rad_s);
  pose.accel_bias_m_s2 = lerp(before->accel_bias_m_s2, after->accel_bias_m_s2);
  return pose;
}

}  // namespace edx::datasets
