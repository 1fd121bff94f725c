// The ATE of a run per mode (workloads/eval/segment_ate.hpp, trace_accuracy.hpp) on hand-built
// traces whose errors are known: each (segment, mode) aligned on its own, pooled by pairs.
#include "workloads/eval/trace_accuracy.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace edx::eval {
namespace {

using trace::BackendMode;

/// A frame on a straight line along x at 1 m/s (10 Hz), its estimate off by `dz` in z and, when
/// `frame_offset`, by a rigid offset the alignment removes (a yaw of 0.5 rad and a translation).
trace::FrameTrace frame(std::int64_t id, std::int64_t t_ns, BackendMode mode, double dz,
                        const std::string& sequence = "s") {
  trace::FrameTrace f;
  f.frame.frame_id = id;
  f.frame.timestamp_ns = t_ns;
  f.frame.sequence = sequence;
  f.frame.mode = mode;
  const double x = static_cast<double>(t_ns) * 1e-9, y = 0.1 * x * x;
  f.frame.ground_truth_pose = trace::PoseArray{x, y, 0, 1, 0, 0, 0};
  // Estimate: R_z(0.5) * (p + dz e_z) + (3, -2, 0): the yaw and translation align away, dz stays.
  const double c = std::cos(0.5), s = std::sin(0.5);
  f.frame.estimated_pose = trace::PoseArray{
      c * x - s * y + 3, s * x + c * y - 2, dz, std::cos(0.25), 0, 0, std::sin(0.25)};
  return f;
}

/// `n` frames of `mode` from frame `first`, errors alternating +d, -d (mean zero: the alignment
/// keeps them, the RMSE is d).
void add(std::vector<trace::FrameTrace>& frames, int n, BackendMode mode, double d,
         std::int64_t t0 = 0) {
  for (int i = 0; i < n; ++i) {
    const auto id = static_cast<std::int64_t>(frames.size());
    frames.push_back(frame(id, t0 + 100'000'000LL * (i + 1), mode, i % 2 ? -d : d));
  }
}

TEST(SegmentAte, AKnownErrorAfterAYawAndTranslationIsItsRmse) {
  std::vector<trace::FrameTrace> frames;
  add(frames, 10, BackendMode::Vio, 0.1);
  const TraceAccuracy a = trace_accuracy(frames, {});
  EXPECT_EQ(a.alignment, AlignmentMethod::kPosYaw);
  EXPECT_EQ(a.segments, 1u);
  ASSERT_TRUE(a.modes.at("vio").rmse());
  EXPECT_NEAR(*a.modes.at("vio").rmse(), 0.1, 1e-9);
  EXPECT_EQ(a.modes.at("vio").pairs, 10u);
}

TEST(TraceAccuracy, SegmentsAlignedOnTheirOwnAndPooledByPairs) {
  // Segment 1: 10 VIO frames with 0.1 m errors, 4 SLAM frames with 0.2 m. Segment 2 (time starts
  // again): 10 VIO frames with 0.3 m.
  std::vector<trace::FrameTrace> frames;
  add(frames, 10, BackendMode::Vio, 0.1);
  add(frames, 4, BackendMode::Slam, 0.2, 2'000'000'000);
  add(frames, 10, BackendMode::Vio, 0.3);
  const TraceAccuracy a = trace_accuracy(frames, {});
  EXPECT_EQ(a.segments, 2u);
  // sqrt((10 * 0.1^2 + 10 * 0.3^2) / 20) = sqrt(0.05)
  EXPECT_NEAR(*a.modes.at("vio").rmse(), std::sqrt(0.05), 1e-9);
  EXPECT_NEAR(*a.modes.at("slam").rmse(), 0.2, 1e-9);
  // All: sqrt((0.1 + 0.16 + 0.9) / 24)
  EXPECT_NEAR(*a.all.rmse(), std::sqrt(1.16 / 24), 1e-9);
  const nlohmann::json j = a.to_json();
  EXPECT_EQ(j.at("alignment"), "posyaw");
  EXPECT_EQ(j.at("vio").at("pairs"), 20);
  EXPECT_FALSE(j.contains("registration"));
}

TEST(TraceAccuracy, AMixTracesSegmentsComeFromItsMeta) {
  // Two segments of 6 frames by the meta, although time never restarts.
  std::vector<trace::FrameTrace> frames;
  add(frames, 6, BackendMode::Vio, 0.1);
  add(frames, 6, BackendMode::Vio, 0.1, 1'000'000'000);
  const trace::TraceMeta meta = {
      {"pipeline_params",
       R"({"segments": [{"name": "a", "frames": 6}, {"name": "b", "frames": 6}]})"}};
  EXPECT_EQ(trace_accuracy(frames, meta).segments, 2u);
  EXPECT_EQ(trace_accuracy(frames, {}).segments, 1u);
  // Frame counts that do not add up to the trace: cut where time or sequence jumps instead.
  const trace::TraceMeta wrong = {{"pipeline_params", R"({"segments": [{"frames": 5}]})"}};
  EXPECT_EQ(trace_accuracy(frames, wrong).segments, 1u);
}

TEST(TraceAccuracy, KittiTracesAlignInSe3AndTooFewEstimatesGiveNoRmse) {
  EXPECT_EQ(trace_alignment({{"dataset", "kitti:/data/01"}}), AlignmentMethod::kSe3);
  EXPECT_EQ(trace_alignment({{"dataset", "euroc:/data/mav0"}}), AlignmentMethod::kPosYaw);
  std::vector<trace::FrameTrace> frames;
  add(frames, 1, BackendMode::Registration, 0.1);  // one pair: posyaw needs 2
  frames.push_back(frame(1, 300'000'000, BackendMode::Vio, 0.0));
  frames.back().frame.estimated_pose.reset();  // VIO ran without an estimate
  const TraceAccuracy a = trace_accuracy(frames, {});
  EXPECT_FALSE(a.modes.at("registration").rmse());
  EXPECT_FALSE(a.modes.at("vio").rmse());
  EXPECT_FALSE(a.all.rmse());
  EXPECT_TRUE(a.to_json().at("vio").at("ate_rmse_m").is_null());
}

}  // namespace
}  // namespace edx::eval
