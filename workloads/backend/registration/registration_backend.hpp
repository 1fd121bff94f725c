#pragma once
// The registration backend (paper Sec. IV-A, registration mode, the indoor_known and
// outdoor_known scenarios): localizes every frame in a prebuilt map (the SLAM backend's map,
// map.hpp) without changing it. At load, every map keyframe's descriptors are turned into a
// bag-of-words vector and added to a keyframe database (bow::Database), and the map points are
// stacked as the 4xM homogeneous matrix X of the projection kernel.
//
// Per frame (kernel names in docs/REGISTRATION.md and docs/TRACE.md):
//   tracking (after a registered frame): predict the pose by constant velocity; `local_map`:
//     the current map, ORB-SLAM's local map around the points the previous frame matched
//     (covisibility.hpp; or the whole map); `projection` Y = C X of its M points (C = K [R|t],
//     accelerable, one gemm 3x4 by 4xM);
//     `projection_matching` of the frame's features in a window around each projection by
//     descriptor distance; `pose_refinement` (robust Gauss-Newton, pose_solver.hpp). Too few
//     inliers: the window is doubled once, then relocalization.
//   relocalization (first frame, after a failure): `bow_query` of the frame's BoW vector in the
//     keyframe database; `matching` of the frame's features to the best candidates' keypoints
//     on map points (same vocabulary node, distance and ratio tests); `pnp` (RANSAC) per
//     candidate, the best kept; `pose_refinement`; then `local_map` around its inliers,
//     `projection`, `projection_matching` and `pose_refinement` as in tracking.
// A frame is registered when the last refinement keeps options.min_inliers inliers; otherwise
// BackendOutput has no pose and status "registration_failed: REASON" (no_features,
// no_candidates, few_matches, pnp_failed, few_inliers), which a mode switch can act on.
// Deterministic: no threads, RANSAC with OpenCV's fixed seed.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "workloads/backend/backend.hpp"
#include "workloads/backend/kernel_recorder.hpp"
#include "workloads/backend/registration/bow/database.hpp"
#include "workloads/backend/registration/bow/vocabulary.hpp"
#include "workloads/backend/registration/covisibility.hpp"
#include "workloads/backend/registration/pose_solver.hpp"
#include "workloads/backend/registration/registration_options.hpp"
#include "workloads/backend/slam/map.hpp"

namespace edx::backend::registration {

/// Counters of a run (for reports and tests).
struct RegistrationStatistics {
  int frames = 0;
  int registered = 0;
  int tracked = 0;      ///< registered by tracking from the previous pose
  int relocalized = 0;  ///< registered by BoW relocalization
  int failures = 0;
  int relocalization_attempts = 0;
};

class RegistrationBackend : public Backend {
 public:
  /// Throws std::runtime_error on invalid options, a null or empty map (no keyframes or no
  /// landmarks) or an empty vocabulary.
  RegistrationBackend(const BackendCamera& camera, const RegistrationOptions& options,
                      std::shared_ptr<const slam::Map> map,
                      std::shared_ptr<const bow::Vocabulary> vocabulary);

  trace::BackendMode mode() const override { return trace::BackendMode::Registration; }
  BackendOutput process(const BackendInput& input) override;

  const RegistrationStatistics& statistics() const { return statistics_; }
  std::size_t map_points() const { return static_cast<std::size_t>(points_.cols()); }
  std::size_t keyframes() const { return database_.size(); }
  const RegistrationOptions& options() const { return options_; }

 private:
  struct Attempt {
    bool ok = false;
    std::string reason;  ///< why it failed
    Eigen::Isometry3d T_cam_world = Eigen::Isometry3d::Identity();
    int inliers = 0;
    std::vector<std::size_t> inlier_points;  ///< map points of the inlier matches
  };

  /// The map points to project around the anchors (the points the previous frame matched):
  /// kernel `local_map`; every point when options.local_map is off.
  std::vector<std::size_t> current_map(const std::vector<std::size_t>& anchor_points);
  /// projection + projection_matching + pose_refinement from a pose guess, over `points`.
  Attempt track_by_projection(const std::vector<frontend::Feature>& features,
                              const Eigen::Isometry3d& T_cam_world_guess, double radius_px,
                              const std::vector<std::size_t>& points);
  /// bow_query + matching + pnp + pose_refinement, then track_by_projection.
  Attempt relocalize(const std::vector<frontend::Feature>& features);
  /// Correspondences of the given map points, projected with the pose, to features within
  /// radius_px.
  std::vector<Correspondence> match_by_projection(const std::vector<frontend::Feature>& features,
                                                  const Eigen::Isometry3d& T_cam_world,
                                                  double radius_px,
                                                  const std::vector<std::size_t>& points);
  /// Records a pose_refinement kernel around refine_pose.
  RefinementResult refine(const std::vector<Correspondence>& correspondences,
                          const Eigen::Isometry3d& T_cam_world);
  double sigma_px(int octave) const;

  BackendCamera camera_;
  RegistrationOptions options_;
  std::shared_ptr<const slam::Map> map_;
  std::shared_ptr<const bow::Vocabulary> vocabulary_;
  bow::Database database_;
  Eigen::Matrix4Xd points_;  ///< X: homogeneous map points, 4 x M
  std::vector<bow::PackedDescriptor> point_descriptors_;
  /// Per database image (= map keyframe in order): keypoint index -> map point index or -1.
  std::vector<std::vector<std::ptrdiff_t>> keypoint_points_;
  std::vector<std::vector<bow::PackedDescriptor>> keypoint_descriptors_;
  std::unique_ptr<CovisibilityGraph> covisibility_;

  KernelRecorder recorder_;
  RegistrationStatistics statistics_;
  std::optional<Eigen::Isometry3d> last_T_cam_world_, previous_T_cam_world_;
  std::vector<std::size_t> last_inlier_points_;  ///< map points the last frame matched
};

/// The backend for a dataset's camera (BackendCamera::from its calibration).
std::unique_ptr<Backend> make_registration_backend(
    const datasets::Dataset& dataset, const RegistrationOptions& options,
    std::shared_ptr<const slam::Map> map, std::shared_ptr<const bow::Vocabulary> vocabulary);

}  // namespace edx::backend::registration
