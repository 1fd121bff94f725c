#pragma once
// The MSCKF measurement update from feature tracks (Mourikis & Roumeliotis 2007, msckf_vio):
// per track, triangulation of the point from the clone cameras, the stereo measurement Jacobians
// with respect to the clones (and extrinsics) and the point, projection onto the left null space
// of the point's Jacobian (which removes the point from the problem), a chi-square gate; then the
// stacked rows go through the EKF update of Eq. 1 (ekf_update.hpp).
//
// Per observation in clone j (p_C = R_IC^T (R_WIj^T (p_W - p_WIj) - p_IC), d = p_W - p_WIj,
// q = p_I - p_IC, J = dz/dp_C of feature_track.hpp):
//   dz/dtheta_WIj = J R_IC^T R_WIj^T [d]x      dz/dp_WIj = -J R_IC^T R_WIj^T
//   dz/dtheta_IC  = J R_IC^T [q]x              dz/dp_IC  = -J R_IC^T
//   dz/dp_W       =  J R_IC^T R_WIj^T
// Null space: H_f = Q [R1; 0] (Householder QR), rows 3.. of Q^T [H_x | r] no longer depend on
// the point. Compression (an option, off by default), when the rows outnumber the c state
// columns H touches: on those columns H = Q1 T (thin QR), H <- T (c rows), r <- Q1^T r (the
// noise stays sigma^2 I). Without it the stacked rows update in groups of whole features of at
// most max_gain_rows rows, one after the other at the same linearization point.
#include <Eigen/Core>
#include <vector>

#include "workloads/backend/kernel_recorder.hpp"
#include "workloads/backend/vio/feature_track.hpp"
#include "workloads/backend/vio/vio_options.hpp"
#include "workloads/backend/vio/vio_state.hpp"

namespace edx::backend::vio {

struct UpdateReport {
  int tracks = 0;        ///< tracks handed in
  int triangulated = 0;  ///< of them triangulated
  int accepted = 0;      ///< of them passing the chi-square gate
  int rows = 0;          ///< rows of H before compression
  int rows_used = 0;     ///< rows of H in the EKF update
  int gains = 0;         ///< Kalman gains (groups of rows) applied, at most max_gain_rows each
  /// Sum of the accepted features' normalized innovations gamma and of their dof: the ratio is
  /// about 1 when the measurement noise model fits.
  double gamma_sum = 0;
  int gamma_dof = 0;
  bool updated = false;
};

/// A track's observations in the window and its rows during one update (msckf_updater.cpp).
struct FeatureRows;

class MsckfUpdater {
 public:
  /// baseline_m: stereo baseline; focal_px: to turn the pixel sigma into normalized units.
  MsckfUpdater(const VioOptions& options, double baseline_m, double focal_px);

  /// Updates `state` with the tracks (observations of clones not in the window are ignored).
  UpdateReport update(VioState& state, const std::vector<const FeatureTrack*>& tracks,
                      KernelRecorder& recorder);

  double sigma_normalized() const { return sigma_; }

 private:
  /// The accepted features' rows stacked (H, r), and the rows of each feature in H's order.
  struct StackedRows {
    Eigen::MatrixXd H;
    Eigen::VectorXd r;
    std::vector<Eigen::Index> feature_rows;
  };

  double chi2_threshold(int dof);
  /// Kernel "triangulation": the tracks with at least min_track_length observations in the
  /// window whose point triangulates from the clone cameras.
  std::vector<FeatureRows> triangulate_tracks(const VioState& state,
                                              const std::vector<const FeatureTrack*>& tracks,
                                              KernelRecorder& recorder) const;
  /// Kernel "jacobians": every feature's H_x, H_f and r (whitened with kRandomWalk).
  void measurement_jacobians(const VioState& state, std::vector<FeatureRows>& features,
                             KernelRecorder& recorder) const;
  /// Kernel "nullspace_projection": the point projected out of every feature's rows, the
  /// chi-square gate, the accepted rows stacked (gate figures into `report`).
  StackedRows project_out_points(const VioState& state, std::vector<FeatureRows>& features,
                                 UpdateReport& report, KernelRecorder& recorder);
  /// Kernel "compression" when the rows outnumber the state columns H touches: H <- T,
  /// r <- Q1^T r (thin QR on those columns). False (rows unchanged, no kernel) otherwise.
  bool compress(StackedRows& rows, int state_dim, KernelRecorder& recorder) const;
  /// Kernels "kalman_gain" and "covariance_update" per group of rows, all at the state's
  /// linearization point; the state corrected when at least one gain applied.
  void sequential_update(VioState& state, const StackedRows& rows,
                         const std::vector<Eigen::Index>& group_rows, UpdateReport& report,
                         KernelRecorder& recorder) const;

  VioOptions options_;
  double baseline_m_;
  double focal_px_;
  double sigma_;       ///< the update's measurement sigma (effective_pixel_sigma), normalized units
  double gate_sigma_;  ///< the chi-square gate's white sigma (pixel_sigma), normalized units
  /// kRandomWalk: rows whitened by the track's covariance, so unit variance at the gate and the
  /// inflation (1 + rho) / (1 - rho) in the update (sigma_^2 / gate_sigma_^2).
  bool whiten_;
  double update_variance_;  ///< per row in the EKF update
  double gate_variance_;    ///< per row at the chi-square gate
  std::vector<double> chi2_table_;
};

}  // namespace edx::backend::vio
