#include "workloads/eval/trace_accuracy.hpp"

#include <Eigen/Geometry>

namespace edx::eval {
namespace {

Pose from_pose_array(const trace::PoseArray& p) {
  Pose pose = Pose::Identity();
  pose.linear() = Eigen::Quaterniond(p[3], p[4], p[5], p[6]).normalized().toRotationMatrix();
  pose.translation() = Eigen::Vector3d(p[0], p[1], p[2]);
  return pose;
}

StampedPose stamped(const trace::FrameRecord& f, const trace::PoseArray& p) {
  StampedPose s;
  s.time_s = static_cast<double>(f.timestamp_ns) * 1e-9;
  s.frame_index = f.frame_id;
  s.pose = from_pose_array(p);
  return s;
}

/// The first frame (index into `frames`) of each segment.
std::vector<std::size_t> segment_starts(const std::vector<trace::FrameTrace>& frames,
                                        const trace::TraceMeta& meta) {
  const auto params = meta.find("pipeline_params");
  if (params != meta.end()) {
    const nlohmann::json j = nlohmann::json::parse(params->second, nullptr, false);
    if (j.is_object() && j.contains("segments") && j["segments"].is_array()) {
      std::vector<std::size_t> starts;
      std::size_t at = 0;
      for (const nlohmann::json& s : j["segments"]) {
        if (!s.is_object() || !s.contains("frames") || !s["frames"].is_number_unsigned()) break;
        starts.push_back(at);
        at += s["frames"].get<std::size_t>();
      }
      if (at == frames.size() && !starts.empty()) return starts;
    }
  }
  std::vector<std::size_t> starts;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    if (i == 0 || frames[i].frame.sequence != frames[i - 1].frame.sequence ||
        frames[i].frame.timestamp_ns <= frames[i - 1].frame.timestamp_ns) {
      starts.push_back(i);
    }
  }
  return starts;
}

}  // namespace

AlignmentMethod trace_alignment(const trace::TraceMeta& meta) {
  const auto dataset = meta.find("dataset");
  return segment_alignment(dataset == meta.end() || !dataset->second.starts_with("kitti:"));
}

TraceAccuracy trace_accuracy(const std::vector<trace::FrameTrace>& frames,
                             const trace::TraceMeta& meta) {
  TraceAccuracy out;
  out.alignment = trace_alignment(meta);
  std::vector<std::size_t> starts = segment_starts(frames, meta);
  out.segments = starts.size();
  starts.push_back(frames.size());
  for (std::size_t s = 0; s + 1 < starts.size(); ++s) {
    std::map<trace::BackendMode, std::pair<Trajectory, Trajectory>> poses;  // truth, estimate
    for (std::size_t i = starts[s]; i < starts[s + 1]; ++i) {
      const trace::FrameRecord& f = frames[i].frame;
      if (f.mode == trace::BackendMode::None) continue;
      auto& [truth, estimate] = poses[f.mode];
      if (!f.estimated_pose || !f.ground_truth_pose) continue;
      truth.poses.push_back(stamped(f, *f.ground_truth_pose));
      estimate.poses.push_back(stamped(f, *f.estimated_pose));
    }
    for (auto& [mode, pair] : poses) {
      PooledAte& pooled = out.modes[trace::to_string(mode)];
      pair.first.stamp_kind = pair.second.stamp_kind = StampKind::kSeconds;
      pair.first.source = "trace ground truth";
      pair.second.source = "trace estimate";
      if (const std::optional<EvalResult> r = segment_ate(pair.first, pair.second, out.alignment)) {
        pooled.add(*r);
        out.all.add(*r);
      }
    }
  }
  return out;
}

nlohmann::json TraceAccuracy::to_json() const {
  const auto pooled = [](const PooledAte& p) {
    const std::optional<double> rmse = p.rmse();
    return nlohmann::json{{"ate_rmse_m", rmse ? nlohmann::json(*rmse) : nlohmann::json()},
                          {"pairs", p.pairs}};
  };
  nlohmann::json j = {{"alignment", std::string(alignment_method_name(alignment))},
                      {"segments", segments},
                      {"all", pooled(all)}};
  for (const auto& [mode, p] : modes) j[mode] = pooled(p);
  return j;
}

}  // namespace edx::eval
