#include "workloads/eval/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

namespace edx::eval {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

void require_same_size(std::size_t gt, std::size_t est, const char* what) {
  if (gt != est) throw std::invalid_argument(std::string(what) + ": gt and est differ in size");
}

}  // namespace

ErrorStats summarize_errors(std::vector<double> values) {
  ErrorStats stats;
  stats.count = values.size();
  if (values.empty()) return stats;
  double sum = 0.0, sum_sq = 0.0;
  for (const double v : values) {
    sum += v;
    sum_sq += v * v;
    stats.max = std::max(stats.max, v);
  }
  const auto n = static_cast<double>(values.size());
  stats.mean = sum / n;
  stats.rmse = std::sqrt(sum_sq / n);
  std::sort(values.begin(), values.end());
  const std::size_t mid = values.size() / 2;
  stats.median = values.size() % 2 == 1 ? values[mid] : 0.5 * (values[mid - 1] + values[mid]);
  return stats;
}

double rotation_angle_rad(const Eigen::Matrix3d& rotation) {
  const double d = 0.5 * (rotation(0, 0) + rotation(1, 1) + rotation(2, 2) - 1.0);
  return std::acos(std::clamp(d, -1.0, 1.0));
}

std::vector<double> position_errors(const std::vector<Pose>& gt, const std::vector<Pose>& est) {
  require_same_size(gt.size(), est.size(), "position_errors");
  std::vector<double> errors(gt.size());
  for (std::size_t i = 0; i < gt.size(); ++i) {
    errors[i] = (gt[i].translation() - est[i].translation()).norm();
  }
  return errors;
}

std::vector<double> path_distances(const std::vector<Pose>& poses) {
  std::vector<double> distances(poses.size(), 0.0);
  for (std::size_t i = 1; i < poses.size(); ++i) {
    distances[i] = distances[i - 1] + (poses[i].translation() - poses[i - 1].translation()).norm();
  }
  return distances;
}

std::vector<FramePair> consecutive_pairs(std::size_t count) {
  std::vector<FramePair> pairs;
  for (std::size_t i = 0; i + 1 < count; ++i) pairs.push_back({i, i + 1});
  return pairs;
}

std::vector<FramePair> pairs_at_distance(const std::vector<double>& distances, double delta_m) {
  std::vector<FramePair> pairs;
  for (std::size_t i = 0; i < distances.size(); ++i) {
    // Distances never decrease, so the first d_j > d_i + delta is an upper bound search.
    const auto it = std::upper_bound(distances.begin() + static_cast<std::ptrdiff_t>(i),
                                     distances.end(), distances[i] + delta_m);
    if (it == distances.end()) break;  // later starts cannot reach further
    pairs.push_back({i, static_cast<std::size_t>(it - distances.begin())});
  }
  return pairs;
}

PoseError relative_pose_error(const Pose& gt_a, const Pose& gt_b, const Pose& est_a,
                              const Pose& est_b) {
  const Pose gt_motion = gt_a.inverse() * gt_b;
  const Pose est_motion = est_a.inverse() * est_b;
  const Pose error = gt_motion.inverse() * est_motion;
  return {error.translation().norm(), rotation_angle_rad(error.linear())};
}

RelativeErrors relative_errors(const std::vector<Pose>& gt, const std::vector<Pose>& est,
                               const std::vector<FramePair>& pairs) {
  require_same_size(gt.size(), est.size(), "relative_errors");
  std::vector<double> translation, rotation;
  translation.reserve(pairs.size());
  rotation.reserve(pairs.size());
  for (const auto& [a, b] : pairs) {
    const PoseError error = relative_pose_error(gt.at(a), gt.at(b), est.at(a), est.at(b));
    translation.push_back(error.translation_m);
    rotation.push_back(error.rotation_rad * kDegPerRad);
  }
  return {summarize_errors(std::move(translation)), summarize_errors(std::move(rotation))};
}

std::vector<KittiSegmentError> kitti_segment_errors(const std::vector<Pose>& gt,
                                                    const std::vector<std::optional<Pose>>& est,
                                                    const KittiSegmentOptions& options) {
  require_same_size(gt.size(), est.size(), "kitti_segment_errors");
  if (options.start_step == 0) throw std::invalid_argument("kitti_segment_errors: start_step 0");
  const std::vector<double> distances = path_distances(gt);
  std::vector<KittiSegmentError> segments;
  for (std::size_t first = 0; first < gt.size(); first += options.start_step) {
    for (const double length : options.lengths_m) {
      const auto it = std::upper_bound(distances.begin() + static_cast<std::ptrdiff_t>(first),
                                       distances.end(), distances[first] + length);
      if (it == distances.end()) continue;  // the sequence is not long enough
      const auto last = static_cast<std::size_t>(it - distances.begin());
      if (!est[first] || !est[last]) continue;
      // The devkit's order: E = (E_first^-1 E_last)^-1 (G_first^-1 G_last).
      const Pose gt_motion = gt[first].inverse() * gt[last];
      const Pose est_motion = est[first]->inverse() * *est[last];
      const Pose error = est_motion.inverse() * gt_motion;
      segments.push_back({first, last, length, error.translation().norm() / length,
                          rotation_angle_rad(error.linear()) / length});
    }
  }
  return segments;
}

KittiSummary summarize_kitti_segments(const std::vector<KittiSegmentError>& segments,
                                      const KittiSegmentOptions& options) {
  KittiSummary summary;
  summary.segments = segments.size();
  const auto summarize = [](std::size_t count, double t_sum, double r_sum) {
    const auto n = static_cast<double>(count);
    return std::pair{100.0 * t_sum / n, 100.0 * kDegPerRad * r_sum / n};
  };
  double t_sum = 0.0, r_sum = 0.0;
  for (const auto& segment : segments) {
    t_sum += segment.t_err_per_m;
    r_sum += segment.r_err_rad_per_m;
  }
  if (!segments.empty()) {
    const auto [t_pct, r_deg] = summarize(segments.size(), t_sum, r_sum);
    summary.t_err_pct = t_pct;
    summary.r_err_deg_per_100m = r_deg;
  }
  for (const double length : options.lengths_m) {
    std::size_t count = 0;
    double t_len = 0.0, r_len = 0.0;
    for (const auto& segment : segments) {
      if (segment.length_m != length) continue;
      ++count;
      t_len += segment.t_err_per_m;
      r_len += segment.r_err_rad_per_m;
    }
    if (count == 0) continue;
    const auto [t_pct, r_deg] = summarize(count, t_len, r_len);
    summary.by_length.push_back({length, count, t_pct, r_deg});
  }
  return summary;
}

}  // namespace edx::eval
