#pragma once
// The VIO backend (paper Sec. IV-A, "Filtering" and "Fusion"): an MSCKF over the stereo
// frontend's feature tracks and the IMU, with loosely coupled GPS fusion.
//
// Per frame: the first-window check of every track (track_check, on the host, only with
// VioOptions::first_window_check_px > 0, off by default; it ends the tracks that drifted from
// their first window), IMU propagation to the image time (imu_propagation), stochastic cloning
// (cloning), the update from the tracks that ended and, when the window is full, from those
// seen in the oldest clone (triangulation, jacobians, nullspace_projection, compression,
// kalman_gain, covariance_update), marginalization of the oldest clone (clone_marginalization),
// and GPS fusion (gps_fusion) when fixes arrived.
#include <map>
#include <memory>
#include <optional>
#include <set>

#include "workloads/backend/backend.hpp"
#include "workloads/backend/kernel_recorder.hpp"
#include "workloads/backend/vio/gps_fusion.hpp"
#include "workloads/backend/vio/imu_propagator.hpp"
#include "workloads/backend/vio/initializer.hpp"
#include "workloads/backend/vio/msckf_updater.hpp"
#include "workloads/backend/vio/vio_options.hpp"
#include "workloads/backend/vio/vio_state.hpp"
#include "workloads/frontend/first_window.hpp"

namespace edx::backend::vio {

class VioBackend final : public Backend {
 public:
  /// Throws std::runtime_error on invalid options, camera (fx, baseline not > 0) or noise.
  VioBackend(const BackendCamera& camera, const datasets::ImuNoise& imu_noise,
             const VioOptions& options);

  trace::BackendMode mode() const override { return trace::BackendMode::Vio; }
  BackendOutput process(const BackendInput& input) override;

  /// The bias priors (1 sigma per axis; gyro rad/s, accelerometer m/s^2): the option when set,
  /// else the turn-on bias the IMU file states, else VioOptions' fallbacks.
  struct BiasPriors {
    double gyro = 0, accel = 0;
  };
  static BiasPriors bias_priors(const VioOptions& options, const datasets::ImuNoise& imu_noise);

  bool initialized() const { return initialized_; }
  /// The filter state (valid once initialized), in the filter's world frame.
  const VioState& state() const { return state_; }
  bool gps_aligned() const { return gps_.aligned(); }
  const UpdateReport& last_update() const { return last_update_; }
  const GpsReport& last_gps() const { return last_gps_; }

 private:
  std::vector<FrameFeature> to_frame_features(const frontend::FrontendFrame& frame) const;
  /// The first-window check (VioOptions::first_window_check_px): removes from `features` the
  /// tracks that end here, and every later observation of them.
  void check_first_windows(const frontend::FrontendFrame& frame, const cv::Mat& left_image,
                           std::vector<FrameFeature>& features);
  void start(const InitialState& initial);

  BackendCamera camera_;
  VioOptions options_;
  ImuPropagator propagator_;
  Initializer initializer_;
  MsckfUpdater updater_;
  GpsFusion gps_;
  BiasPriors bias_priors_;
  KernelRecorder recorder_;
  bool initialized_ = false;
  VioState state_;
  std::map<std::int64_t, FeatureTrack> tracks_;
  /// A track's first window and where it was last aligned (the next frame's warm start).
  struct CheckedTrack {
    frontend::FirstWindow window;
    std::optional<frontend::WindowAlignment> last;
    cv::Point2f last_position;
  };
  std::map<std::int64_t, CheckedTrack> first_windows_;  ///< by track id
  std::set<std::int64_t> ended_by_check_;  ///< tracks the check ended that the frontend still has
  UpdateReport last_update_;
  GpsReport last_gps_;
};

/// The VIO backend for a dataset: its rectified camera and IMU noise (the EuRoC ADIS16448 values
/// when the dataset states none). Throws std::runtime_error when the dataset has no IMU.
std::unique_ptr<Backend> make_vio_backend(const datasets::Dataset& dataset,
                                          const VioOptions& options);

}  // namespace edx::backend::vio
