#pragma once
// The SLAM backend (paper Sec. IV-A, SLAM mode; VINS-Fusion-style): per frame, tracking
// estimates the body pose against the latest local map (motion-only, tracker.hpp); when the
// frame is selected as a keyframe (keyframe_selector.hpp), mapping adds it to a sliding window
// of keyframes, creates landmarks from its stereo features, optimizes the window with
// Levenberg-Marquardt (stereo reprojection with Huber loss, IMU preintegration between
// keyframes when there is an IMU, the marginalization prior; lm_solver.hpp) and, when the window
// is full, marginalizes its oldest keyframe (marginalizer.hpp: the accelerable kernel). Every
// kernel goes through KernelRecorder. Keyframes and landmarks that leave the window are kept
// in a map that save_map writes (map.hpp). Deterministic: no threads, no random numbers.
#include <filesystem>
#include <memory>
#include <optional>

#include "workloads/backend/backend.hpp"
#include "workloads/backend/kernel_recorder.hpp"
#include "workloads/backend/slam/map.hpp"
#include "workloads/backend/slam/preintegration.hpp"
#include "workloads/backend/slam/slam_options.hpp"
#include "workloads/backend/slam/window.hpp"

namespace edx::backend::slam {

/// Counters of a run (for reports and tests).
struct SlamStatistics {
  int frames = 0;
  int keyframes = 0;
  int marginalizations = 0;
  int tracking_failures = 0;
  int landmarks_created = 0;
  int outliers_rejected = 0;
  int lm_iterations = 0;
  double disparity_offset_px = 0;  ///< the window's latest estimate (SlamOptions)
};

class SlamBackend : public Backend {
 public:
  /// `imu`: noise densities when the data has an IMU and options.use_imu (else visual-only).
  /// Throws std::runtime_error on invalid options or camera.
  SlamBackend(const BackendCamera& camera, std::optional<ImuNoiseDensities> imu,
              const SlamOptions& options, std::string source = {});

  trace::BackendMode mode() const override { return trace::BackendMode::Slam; }
  BackendOutput process(const BackendInput& input) override;

  /// The map so far: keyframes and landmarks marginalized out plus the current window.
  Map map() const;
  /// Writes map() to a file (map.hpp format).
  void save_map(const std::filesystem::path& path) const { slam::save_map(map(), path); }

  const Window& window() const { return window_; }
  const SlamStatistics& statistics() const { return statistics_; }
  const SlamOptions& options() const { return options_; }

 private:
  void initialize(const BackendInput& input);
  void integrate_imu(const BackendInput& input);
  Eigen::Isometry3d predict_pose() const;
  /// Adds the frame as a keyframe; observations of existing landmarks only for the track ids in
  /// `inlier_tracks` when given (the tracking inliers), else for every feature on a landmark.
  void add_keyframe(const BackendInput& input, const Eigen::Isometry3d& T_world_body,
                    const std::vector<std::int64_t>* inlier_tracks = nullptr);
  void map_window();
  void archive(const KeyframeState& keyframe, const std::vector<Landmark>& landmarks,
               const std::vector<Eigen::Vector3d>& positions, Map& map) const;
  /// Whether a point at this depth gets stereo (right-image) residuals.
  bool is_close(double depth_m) const;
  MapKeyframe to_map_keyframe(const KeyframeState& keyframe) const;

  SlamOptions options_;
  std::optional<ImuNoiseDensities> imu_;
  std::string source_;
  Window window_;
  KernelRecorder recorder_;
  SlamStatistics statistics_;
  Map archive_;  ///< what left the window

  std::int64_t next_keyframe_id_ = 0;
  std::int64_t next_landmark_id_ = 0;
  bool initialized_ = false;
  // IMU since the last keyframe.
  std::optional<Preintegration> imu_since_keyframe_;
  std::int64_t imu_t_ns_ = 0;
  datasets::ImuSample imu_sample_;
  // Pose history for the constant-velocity prediction.
  Eigen::Isometry3d last_pose_ = Eigen::Isometry3d::Identity();
  std::optional<Eigen::Isometry3d> previous_pose_;
};

/// The SLAM backend for a dataset: its rectified camera and, when it has an IMU with known
/// noise and options.use_imu, IMU factors.
std::unique_ptr<Backend> make_slam_backend(const datasets::Dataset& dataset,
                                           const SlamOptions& options);

}  // namespace edx::backend::slam
