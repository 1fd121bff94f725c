#pragma once
// Test helper: runs the stereo frontend and the VIO backend over a dataset and measures the
// estimate against the ground truth (ATE, final drift, NEES), and the backend's host times.
#include <Eigen/Geometry>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "workloads/backend/vio/vio_backend.hpp"
#include "workloads/datasets/dataset.hpp"
#include "workloads/eval/evaluate.hpp"
#include "workloads/trace/records.hpp"

namespace edx::backend::vio::testing {

struct VioRun {
  std::size_t frames = 0;
  std::size_t estimated = 0;                 ///< frames with a pose
  std::optional<eval::EvalResult> accuracy;  ///< posyaw-aligned ATE over the estimated frames
  double distance_m = 0;                     ///< ground-truth path length over the estimated frames
  /// |p_est - p_gt| at the last frame, ground truth brought into the filter frame by the 4-DoF
  /// gauge (yaw, position) of the initialization frame.
  double final_drift_m = 0;
  double mean_nees = 0;       ///< 6-DoF pose NEES averaged over frames (filter frame)
  double nees_in_bounds = 0;  ///< fraction of frames with NEES in the 95% chi2(6) interval
  std::vector<double> nees;   ///< per estimated frame with ground truth
  std::vector<double> backend_ms;
  std::map<std::string, double> kernel_ms_total;
  std::vector<std::vector<trace::KernelRecord>> kernels;  ///< per frame
  int visual_updates = 0;                                 ///< frames whose MSCKF update was applied
  int gps_fused = 0;
  double gamma_per_dof = 0;  ///< accepted features' sum gamma / sum dof (about 1: noise fits)
  bool gps_aligned = false;
  /// The GPS-fused output in the GPS frame, p_G = Rz(yaw_GV) p_W + t_GV, R_G = Rz(yaw_GV) R_WI,
  /// over the frames after the alignment (the synthetic worlds' GPS frame is their ground-truth
  /// frame): ATE posyaw-aligned and without alignment, and the filter-frame ATE over the same
  /// frames for comparison.
  std::optional<eval::EvalResult> global_accuracy, global_unaligned, filter_accuracy_aligned_frames;
};

/// Runs `frames` frames (0: all) of the EuRoC-layout dataset at `path`. use_gps=false hides the
/// fixes from the backend.
VioRun run_vio(const std::filesystem::path& path, const VioOptions& options, std::size_t frames,
               bool collect_kernels = false);

/// The number in environment variable `name` (a diagnostic's setting), at least `min`; a
/// one-line std::invalid_argument naming the variable when it is unset, not a number or smaller.
double env_number(const char* name, double min);

/// Mean and SD of a series.
std::pair<double, double> mean_sd(const std::vector<double>& values);

}  // namespace edx::backend::vio::testing
