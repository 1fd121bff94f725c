#pragma once
// The VIO backend (paper Sec. IV-A, "Filtering" and "Fusion"): an MSCKF over the stereo
// frontend's feature tracks and the IMU, with loosely coupled GPS fusion.
//
// Per frame: IMU propagation to the image time (imu_propagation), stochastic cloning (cloning),
// the update from the tracks that ended and, when the window is full, from those seen in the
// oldest clone (triangulation, jacobians, nullspace_projection, compression, kalman_gain,
// covariance_update), marginalization of the oldest clone (clone_marginalization), and GPS
// fusion (gps_fusion) when fixes arrived.
#include <map>
#include <memory>
#include <optional>

#include "workloads/backend/backend.hpp"
#include "workloads/backend/kernel_recorder.hpp"
#include "workloads/backend/vio/gps_fusion.hpp"
#include "workloads/backend/vio/imu_propagator.hpp"
#include "workloads/backend/vio/initializer.hpp"
#include "workloads/backend/vio/msckf_updater.hpp"
#include "workloads/backend/vio/vio_options.hpp"
#include "workloads/backend/vio/vio_state.hpp"

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
  UpdateReport last_update_;
  GpsReport last_gps_;
};

/// The VIO backend for a dataset: its rectified camera and IMU noise (the EuRoC ADIS16448 values
/// when the dataset states none). Throws std::runtime_error when the dataset has no IMU.
std::unique_ptr<Backend> make_vio_backend(const datasets::Dataset& dataset,
                                          const VioOptions& options);

}  // namespace edx::backend::vio
