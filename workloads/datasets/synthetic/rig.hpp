#pragma once
// Rectified stereo rigs of the synthetic datasets: an EuRoC-like drone rig (752x480, fx 458,
// baseline 0.11 m) and a car rig (1280x720, fx 700, baseline 0.54 m). Both cameras share one
// rotation; the right camera sits one baseline along the left camera's x axis, so the pair is
// rectified by construction (no distortion).
#include <Eigen/Geometry>
#include <string>
#include <string_view>

namespace edx::synthetic {

enum class RigKind { kEuroc, kCar };

struct Resolution {
  int width = 0;
  int height = 0;
  bool operator==(const Resolution&) const = default;
};

/// Parses "WxH" (e.g. "752x480"); throws std::runtime_error naming the text otherwise.
Resolution parse_resolution(std::string_view text);
/// Parses "euroc" or "car".
RigKind parse_rig(std::string_view text);
std::string_view to_string(RigKind kind);
Resolution native_resolution(RigKind kind);

struct StereoRig {
  RigKind kind = RigKind::kEuroc;
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  double baseline_m = 0;
  /// Left camera in the body (IMU) frame: p_body = T_body_left * p_left.
  Eigen::Isometry3d T_body_left = Eigen::Isometry3d::Identity();

  /// T_body_left * Translation(baseline, 0, 0).
  Eigen::Isometry3d T_body_right() const;
};

/// The rig of `kind` at `resolution`. Other resolutions than the native one scale the focal
/// length by sx = width / native width (square pixels, same horizontal field of view) and the
/// principal point as cv::resize moves pixel centres: c' = (c + 0.5) s - 0.5 with sx, sy.
/// Throws on sizes outside [32, 8192].
StereoRig make_rig(RigKind kind, Resolution resolution);

}  // namespace edx::synthetic
