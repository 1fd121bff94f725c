#pragma once
// Keyframe selection (VINS-Fusion style): a frame becomes a keyframe when
//   - the mean parallax of the tracks it shares with the last keyframe,
//       mean_i |u_i(frame) - u_i(keyframe)|  (left image, px),
//     reaches keyframe_parallax_px, or
//   - the tracked-feature ratio, (landmarks of the last keyframe still seen) / (landmarks it
//     saw), falls below keyframe_tracked_ratio, or
//   - keyframe_max_interval_s has passed since the last keyframe (bounds the IMU interval).
#include <string>
#include <vector>

#include "workloads/backend/slam/slam_options.hpp"
#include "workloads/backend/slam/window.hpp"

namespace edx::backend::slam {

struct KeyframeDecision {
  bool is_keyframe = false;
  double parallax_px = 0;
  double tracked_ratio = 0;
  int shared_tracks = 0;
  std::string reason;  ///< "parallax", "tracked_ratio", "interval" or "" (not a keyframe)
};

KeyframeDecision select_keyframe(const Window& window,
                                 const std::vector<frontend::Feature>& features, std::int64_t t_ns,
                                 const SlamOptions& options);

}  // namespace edx::backend::slam
