#pragma once
// Trajectory error metrics on associated (and already aligned) poses: absolute trajectory error,
// relative pose error over frame pairs, and the KITTI odometry segment errors.
#include <cstddef>
#include <optional>
#include <vector>

#include "workloads/eval/trajectory.hpp"

namespace edx::eval {

/// count, mean, root mean square, median and maximum of a list of non-negative errors (all zero
/// when the list is empty).
struct ErrorStats {
  std::size_t count = 0;
  double mean = 0.0;
  double rmse = 0.0;  ///< sqrt(sum x_i^2 / n)
  double median = 0.0;
  double max = 0.0;
};
ErrorStats summarize_errors(std::vector<double> values);

/// Rotation angle of R (rad): acos(d), d = (trace R - 1) / 2 clipped to [-1, 1] as in the KITTI
/// devkit, so that rounding in nearly-identity matrices gives 0 rather than NaN.
double rotation_angle_rad(const Eigen::Matrix3d& rotation);

/// Absolute position errors |t_gt,i - t_est,i| of poses associated by position in the lists.
std::vector<double> position_errors(const std::vector<Pose>& gt, const std::vector<Pose>& est);

/// Path length along the poses: d_0 = 0, d_i = d_{i-1} + |t_i - t_{i-1}|.
std::vector<double> path_distances(const std::vector<Pose>& poses);

/// Two positions (first < second) in a list of associated poses.
struct FramePair {
  std::size_t first = 0;
  std::size_t second = 0;
};

/// (i, i+1) for i = 0 .. count-2.
std::vector<FramePair> consecutive_pairs(std::size_t count);

/// For every start i, the first j with d_j > d_i + delta_m (the KITTI devkit's rule); starts
/// without such a j are left out.
std::vector<FramePair> pairs_at_distance(const std::vector<double>& distances, double delta_m);

/// Translation and rotation error of one relative motion.
struct PoseError {
  double translation_m = 0.0;
  double rotation_rad = 0.0;
};

/// Relative pose error from a to b: E = (G_a^-1 G_b)^-1 (E_a^-1 E_b); |t(E)| and angle(R(E)).
PoseError relative_pose_error(const Pose& gt_a, const Pose& gt_b, const Pose& est_a,
                              const Pose& est_b);

struct RelativeErrors {
  ErrorStats translation_m;
  ErrorStats rotation_deg;
};
/// relative_pose_error over `pairs` of positions in the associated lists `gt` and `est`.
RelativeErrors relative_errors(const std::vector<Pose>& gt, const std::vector<Pose>& est,
                               const std::vector<FramePair>& pairs);

/// The KITTI odometry benchmark's segments: lengths 100..800 m, a start every 10 frames.
struct KittiSegmentOptions {
  std::vector<double> lengths_m{100, 200, 300, 400, 500, 600, 700, 800};
  std::size_t start_step = 10;
};

/// One segment from `first` to `last` (positions in the track), and its errors per metre.
struct KittiSegmentError {
  std::size_t first = 0;
  std::size_t last = 0;
  double length_m = 0.0;
  double t_err_per_m = 0.0;      ///< |t(E)| / length
  double r_err_rad_per_m = 0.0;  ///< angle(R(E)) / length
};

/// KITTI devkit segment errors. `gt` is the ground-truth track along which distances are measured
/// (d_i as in path_distances); `est` holds the estimated pose at each position of the track, or
/// nullopt where there is none. For first = 0, step, 2 step, ... and each length L, last is the
/// first frame with d_last > d_first + L; the segment counts when both ends have an estimate, with
///   E = (E_first^-1 E_last)^-1 (G_first^-1 G_last),
///   t_err = |t(E)| / L,  r_err = angle(R(E)) / L.
std::vector<KittiSegmentError> kitti_segment_errors(const std::vector<Pose>& gt,
                                                    const std::vector<std::optional<Pose>>& est,
                                                    const KittiSegmentOptions& options = {});

struct KittiLengthSummary {
  double length_m = 0.0;
  std::size_t segments = 0;
  double t_err_pct = 0.0;
  double r_err_deg_per_100m = 0.0;
};

/// Averages over segments (all lengths pooled, as the devkit and kitti-odom-eval report):
///   t_err (%) = 100 mean(t_err_per_m),  r_err (deg/100 m) = 100 (180/pi) mean(r_err_rad_per_m).
/// Empty (nullopt) when there is no segment.
struct KittiSummary {
  std::size_t segments = 0;
  std::optional<double> t_err_pct;
  std::optional<double> r_err_deg_per_100m;
  std::vector<KittiLengthSummary> by_length;  ///< one per length that has segments
};
KittiSummary summarize_kitti_segments(const std::vector<KittiSegmentError>& segments,
                                      const KittiSegmentOptions& options = {});

}  // namespace edx::eval
