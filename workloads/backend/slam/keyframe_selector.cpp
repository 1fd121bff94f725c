#include "workloads/backend/slam/keyframe_selector.hpp"

#include <cmath>
#include <unordered_map>
#include <unordered_set>

namespace edx::backend::slam {

KeyframeDecision select_keyframe(const Window& window,
                                 const std::vector<frontend::Feature>& features, std::int64_t t_ns,
                                 const SlamOptions& options) {
  KeyframeDecision decision;
  if (window.keyframes.empty()) {
    decision.is_keyframe = true;
    decision.reason = "first";
    return decision;
  }
  const KeyframeState& last = window.keyframes.back();
  std::unordered_map<std::int64_t, const frontend::Feature*> current;
  for (const frontend::Feature& f : features) current.emplace(f.id, &f);

  double parallax_sum = 0;
  int landmarks_seen_by_last = 0, landmarks_still_seen = 0;
  for (const frontend::Feature& f : last.features) {
    const auto it = current.find(f.id);
    if (it != current.end()) {
      parallax_sum += std::hypot(it->second->left.x - f.left.x, it->second->left.y - f.left.y);
      ++decision.shared_tracks;
    }
    const auto lm = window.landmarks.find(f.id);
    if (lm == window.landmarks.end()) continue;
    ++landmarks_seen_by_last;
    if (it != current.end()) ++landmarks_still_seen;
  }
  decision.parallax_px = decision.shared_tracks > 0 ? parallax_sum / decision.shared_tracks : 0;
  decision.tracked_ratio = landmarks_seen_by_last > 0
                               ? static_cast<double>(landmarks_still_seen) / landmarks_seen_by_last
                               : 0;
  const double interval_s = static_cast<double>(t_ns - last.t_ns) * 1e-9;
  if (decision.parallax_px >= options.keyframe_parallax_px) {
    decision.reason = "parallax";
  } else if (decision.tracked_ratio < options.keyframe_tracked_ratio) {
    decision.reason = "tracked_ratio";
  } else if (interval_s >= options.keyframe_max_interval_s) {
    decision.reason = "interval";
  }
  decision.is_keyframe = !decision.reason.empty();
  return decision;
}

}  // namespace edx::backend::slam
