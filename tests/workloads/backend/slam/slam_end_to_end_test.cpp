// End-to-end accuracy of the SLAM backend: frontend + SLAM over a synthetic indoor sequence
// (edx gen, warehouse, drone, IMU) and the real KITTI 01 excerpt (visual-only), run through
// the pipeline runner (`edx trace`) and measured against the ground truth.
//
// The full-size figures (200 synthetic frames at 752x480, all 51 KITTI frames) are measured by
// the DISABLED_ tests (run with --gtest_also_run_disabled_tests); docs/SLAM.md reports them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "tests/support/temp_dir.hpp"
#include "workloads/backend/slam/marginalizer.hpp"
#include "workloads/backend/slam/slam_backend.hpp"
#include "workloads/datasets/synthetic/generator.hpp"
#include "workloads/eval/metrics.hpp"
#include "workloads/modes/trace_runner.hpp"
#include "workloads/trace/reader.hpp"

namespace edx::backend::slam {
namespace {

namespace fs = std::filesystem;

struct RunFigures {
  modes::TraceRunSummary summary;
  double ate_rmse_m = 0;
  double final_drift_pct = 0;  ///< |t(E)| / path length over the whole run (KITTI segment form)
  double marginalization_share = 0;
  int keyframes = 0, marginalizations = 0, tracking_failures = 0;
  double disparity_offset_px = 0;  ///< the backend's final estimate
  /// The marginalization system of the final window (linearize_marginalization).
  struct {
    int m = -1, d = 0;
    double landmark_block_off_diagonal = -1;   ///< max |H_ll(i, j)|, i != j
    double landmark_speed_bias_coupling = -1;  ///< max |H(landmark, removed v/b_a/b_g)|
  } final_window;
};

double final_drift_pct(const fs::path& trace_file);

/// Runs a SLAM backend; when the runner destroys it, copies its statistics out and saves its map.
class StatisticsKeeper : public Backend {
 public:
  StatisticsKeeper(std::unique_ptr<Backend> slam, SlamStatistics& out, RunFigures& figures,
                   fs::path map_file)
      : slam_(std::move(slam)), out_(out), figures_(figures), map_file_(std::move(map_file)) {}
  ~StatisticsKeeper() override {
    const auto& slam = static_cast<const SlamBackend&>(*slam_);
    out_ = slam.statistics();
    if (!map_file_.empty()) slam.save_map(map_file_);
    if (slam.window().keyframes.size() < 2) return;
    const MarginalizationSystem sys = linearize_marginalization(slam.window(), slam.options());
    auto& w = figures_.final_window;
    w.m = sys.m;
    w.d = sys.d;
    Eigen::MatrixXd landmarks = sys.H.topLeftCorner(sys.m, sys.m);
    landmarks.diagonal().setZero();
    w.landmark_block_off_diagonal = sys.m > 0 ? landmarks.cwiseAbs().maxCoeff() : 0.0;
    w.landmark_speed_bias_coupling =
        sys.d == 15 && sys.m > 0 ? sys.H.block(0, sys.m + 6, sys.m, 9).cwiseAbs().maxCoeff() : 0.0;
  }
  trace::BackendMode mode() const override { return slam_->mode(); }
  BackendOutput process(const BackendInput& input) override { return slam_->process(input); }

 private:
  std::unique_ptr<Backend> slam_;
  SlamStatistics& out_;
  RunFigures& figures_;
  fs::path map_file_;
};

/// Runs the pipeline with the SLAM backend; writes its map to map_file when not empty.
RunFigures run(const fs::path& dataset, datasets::DatasetFormat format, const fs::path& out,
               std::optional<std::size_t> max_frames = std::nullopt, const fs::path& map_file = {},
               std::optional<cv::Size> resize = std::nullopt,
               const SlamOptions& slam_options = SlamOptions{}) {
  modes::TraceRunOptions options;
  options.dataset.resize = resize;
  options.dataset_path = dataset;
  options.format = format;
  options.out = out;
  options.max_frames = max_frames;
  RunFigures f;
  SlamStatistics statistics;
  options.make_backend = [&](const datasets::Dataset& d) {
    return std::make_unique<StatisticsKeeper>(make_slam_backend(d, slam_options), statistics, f,
                                              map_file);
  };
  f.summary = modes::run_trace(options);
  f.final_drift_pct = final_drift_pct(out);
  EXPECT_TRUE(f.summary.accuracy.has_value());
  if (!f.summary.accuracy) return f;
  f.ate_rmse_m = f.summary.accuracy->ate_m.rmse;
  double total = 0, marginalization = 0;
  for (const auto& [name, stats] : f.summary.kernel_ms) {
    total += stats.mean;
    if (name == "marginalization") marginalization = stats.mean;
  }
  f.marginalization_share = total > 0 ? marginalization / total : 0;
  f.keyframes = statistics.keyframes;
  f.marginalizations = statistics.marginalizations;
  f.tracking_failures = statistics.tracking_failures;
  f.disparity_offset_px = statistics.disparity_offset_px;
  return f;
}

Eigen::Isometry3d to_isometry(const trace::PoseArray& a) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(a[3], a[4], a[5], a[6]).normalized().toRotationMatrix();
  T.translation() = Eigen::Vector3d(a[0], a[1], a[2]);
  return T;
}

/// Translational drift over the whole run in the KITTI segment form, from the trace's poses:
/// E = (E_0^-1 E_N)^-1 (G_0^-1 G_N), drift = |t(E)| / (ground-truth path length 0..N).
double final_drift_pct(const fs::path& trace_file) {
  const std::vector<trace::FrameTrace> frames = trace::TraceReader(trace_file).read_all();
  std::vector<Eigen::Isometry3d> est, gt;
  for (const trace::FrameTrace& f : frames) {
    if (!f.frame.estimated_pose || !f.frame.ground_truth_pose) continue;
    est.push_back(to_isometry(*f.frame.estimated_pose));
    gt.push_back(to_isometry(*f.frame.ground_truth_pose));
  }
  if (gt.size() < 2) return 1e9;
  double length = 0;
  for (std::size_t i = 1; i < gt.size(); ++i) {
    length += (gt[i].translation() - gt[i - 1].translation()).norm();
  }
  const Eigen::Isometry3d E =
      (est.front().inverse() * est.back()).inverse() * (gt.front().inverse() * gt.back());
  return 100 * E.translation().norm() / length;
}

void print(const char* what, const RunFigures& f) {
  std::printf(
      "%s: %zu frames, ATE RMSE %.3f m over %.1f m, final drift %.2f%%; backend %.2f ms mean, SD "
      "%.2f ms, RSD %.1f%%; "
      "marginalization %.1f%% of kernel time; %d keyframes, %d marginalizations, %d tracking "
      "failures; disparity offset %.3f px\n",
      what, f.summary.frames, f.ate_rmse_m,
      f.summary.accuracy ? f.summary.accuracy->gt_length_m : 0, f.final_drift_pct,
      f.summary.backend_ms.mean, f.summary.backend_ms.sd,
      f.summary.backend_ms.mean > 0 ? 100 * f.summary.backend_ms.sd / f.summary.backend_ms.mean : 0,
      100 * f.marginalization_share, f.keyframes, f.marginalizations, f.tracking_failures,
      f.disparity_offset_px);
  for (const auto& [name, stats] : f.summary.kernel_ms) {
    std::printf("  kernel %-20s mean %.3f ms  sd %.3f ms\n", name.c_str(), stats.mean, stats.sd);
  }
}

fs::path generate_indoor(const fs::path& dir, int frames, std::optional<synthetic::Resolution> res,
                         std::uint64_t seed = 1) {
  synthetic::GenerateOptions options;
  options.scenario = synthetic::Scenario::kIndoorUnknown;
  options.frames = frames;
  options.resolution = res;
  options.seed = seed;
  options.out = dir / "indoor_unknown";
  synthetic::generate_dataset(options);
  return options.out;
}

TEST(SlamEndToEnd, SyntheticIndoorUnknownSmall) {
  const testing::TempDir dir;
  const fs::path data = generate_indoor(dir.path(), 60, synthetic::Resolution{376, 240});
  const RunFigures f = run(data, datasets::DatasetFormat::kEuroc, dir.path() / "trace.db");
  print("synthetic indoor_unknown 60 frames 376x240", f);
  EXPECT_EQ(f.summary.estimated_frames, 60u);
  EXPECT_GT(f.marginalizations, 0);
  EXPECT_EQ(f.tracking_failures, 0);
  EXPECT_LT(f.ate_rmse_m, 0.19);
  // The synthetic rig is calibrated exactly: no disparity offset to find.
  EXPECT_LT(std::abs(f.disparity_offset_px), 0.2);
  // With the IMU the removed keyframe's velocity and biases are eliminated first (a 9x9 LDLT),
  // then the inverse of A_mm (flagged diagonal + 6x6 block); the trace carries the IMU
  // preintegration kernel.
  // Each linearization is followed by its normal equations over the same terms, recorded as
  // batched products: 2 syrk 6x6 of 4 a cross term, at least 2 gemm 1x1x4 a term, one JᵀWJ
  // (gemm 30x30x15) an IMU factor; each solve factors the C x C reduced system.
  int marginalizations = 0, preintegrations = 0, normal_equations = 0;
  const std::vector<trace::FrameTrace> frames =
      trace::TraceReader(dir.path() / "trace.db").read_all();
  for (const trace::FrameTrace& frame : frames) {
    for (std::size_t i = 0; i < frame.kernels.size(); ++i) {
      const trace::KernelRecord& k = frame.kernels[i];
      const auto batch_of = [&](trace::Op op, std::int64_t m, std::int64_t n, std::int64_t kk) {
        std::int64_t b = 0;
        for (const trace::OpRecord& o : k.ops) {
          if (o.op == op && o.m == m && o.n == n && o.k == kk) b += o.batch;
        }
        return b;
      };
      if (k.kernel == "normal_equations") {
        ++normal_equations;
        ASSERT_GT(i, 0u);
        EXPECT_EQ(frame.kernels[i - 1].kernel, "linearization");
        EXPECT_EQ(frame.kernels[i - 1].m, k.m);
        EXPECT_GT(k.k, 0);
        EXPECT_EQ(batch_of(trace::Op::Syrk, 6, 6, 4), 2 * k.k);
        EXPECT_GE(batch_of(trace::Op::Gemm, 1, 1, 4), 2 * k.m);
        const auto detail = nlohmann::json::parse(k.detail_json);
        EXPECT_GT(detail.at("imu_factors").get<std::int64_t>(), 0);
        EXPECT_EQ(batch_of(trace::Op::Gemm, 30, 30, 15),
                  detail.at("imu_factors").get<std::int64_t>());
      }
      if (k.kernel == "solve") {
        ASSERT_FALSE(k.ops.empty());
        EXPECT_EQ(k.ops[0].op, trace::Op::Ldlt);
        EXPECT_EQ(k.ops[0].m, k.m);
      }
      preintegrations += k.kernel == "preintegration" ? 1 : 0;
      if (k.kernel != "marginalization") continue;
      ++marginalizations;
      ASSERT_GE(k.ops.size(), 6u);
      EXPECT_EQ(k.k, 15);
      EXPECT_EQ(k.ops[0].op, trace::Op::Ldlt);
      EXPECT_EQ(k.ops[0].m, 9);
      const trace::OpRecord& inverse = k.ops[5];
      EXPECT_EQ(inverse.op, trace::Op::Inverse);
      EXPECT_EQ(inverse.m, k.m + 6);
      EXPECT_EQ(inverse.flags, trace::op_flags::kDiagonalBlock | trace::op_flags::kBlock6x6 |
                                   trace::op_flags::kSymmetric);
      EXPECT_EQ(k.n % 15, 1);  // kept keyframes (15 each) and the disparity offset
    }
  }
  EXPECT_EQ(marginalizations, f.marginalizations);
  EXPECT_GE(preintegrations, 59);
  EXPECT_GT(normal_equations, 0);
  // A_mm of the paper's Sec. VI on a real window: the landmark block A is diagonal (landmarks
  // couple only through poses) and no landmark couples to the removed keyframe's velocity and
  // biases, so once those 9 are eliminated D is the 6x6 pose block.
  EXPECT_EQ(f.final_window.d, 15);
  EXPECT_GT(f.final_window.m, 0);
  EXPECT_EQ(f.final_window.landmark_block_off_diagonal, 0.0);
  EXPECT_EQ(f.final_window.landmark_speed_bias_coupling, 0.0);
}

fs::path kitti_excerpt() {
  return fs::path(EDX_SHARED_DATA_DIR) / "kitti_odometry_excerpt" / "sequences" / "01";
}

// The target is <= 2 % translational drift over the 52 m; the backend reaches 1.7 %
// (3.8 % before the disparity offset was estimated, 2.6 % with it conditioned away at each
// marginalization; docs/SLAM.md). KITTI's rectified disparities measure ~1.1 px short of the
// calibration's geometry (checked against ground-truth motion in docs/SLAM.md): the estimated
// offset must come out positive and about that size.
TEST(SlamEndToEnd, KittiExcerptVisualOnly) {
  const testing::TempDir dir;
  const RunFigures f = run(kitti_excerpt(), datasets::DatasetFormat::kKitti,
                           dir.path() / "trace.db", std::nullopt, dir.path() / "map.json");
  print("KITTI 01 excerpt", f);
  EXPECT_EQ(f.summary.estimated_frames, f.summary.frames);
  EXPECT_EQ(f.tracking_failures, 0);
  EXPECT_LT(f.final_drift_pct, 2.0);
  EXPECT_LT(f.ate_rmse_m, 0.3);
  EXPECT_GT(f.disparity_offset_px, 0.4);
  EXPECT_LT(f.disparity_offset_px, 1.6);

  // Every marginalization in the trace is the accelerable kernel with the structured inverse
  // of Sec. VI first: visual-only, so the pose block D is 6x6.
  int marginalizations = 0;
  for (const trace::FrameTrace& frame : trace::TraceReader(dir.path() / "trace.db").read_all()) {
    for (const trace::KernelRecord& k : frame.kernels) {
      if (k.kernel != "marginalization") continue;
      ++marginalizations;
      EXPECT_TRUE(k.accelerable);
      ASSERT_FALSE(k.ops.empty());
      EXPECT_EQ(k.ops.front().op, trace::Op::Inverse);
      EXPECT_EQ(k.ops.front().m, k.m + 6);
      EXPECT_EQ(k.ops.front().flags, trace::op_flags::kDiagonalBlock | trace::op_flags::kBlock6x6 |
                                         trace::op_flags::kSymmetric);
      EXPECT_EQ(k.n % 6, 1);  // kept keyframes (6 each) and the disparity offset
    }
  }
  EXPECT_EQ(marginalizations, f.marginalizations);

  // The map: every keyframe, landmarks with valid references, positions in front of the camera
  // that observed them.
  const Map map = load_map(dir.path() / "map.json");
  EXPECT_EQ(static_cast<int>(map.keyframes.size()), f.keyframes);
  EXPECT_GT(map.landmarks.size(), 1000u);
  std::map<std::int64_t, const MapKeyframe*> keyframes;
  for (const MapKeyframe& kf : map.keyframes) keyframes[kf.id] = &kf;
  int in_front = 0;
  for (const MapLandmark& l : map.landmarks) {
    const MapKeyframe& kf = *keyframes.at(l.observations.front().keyframe_id);
    in_front += (kf.T_world_body.inverse() * l.position).z() > 0 ? 1 : 0;
    EXPECT_EQ(kf.keypoints[l.observations.front().keypoint_index].track_id, l.track_id);
  }
  EXPECT_EQ(in_front, static_cast<int>(map.landmarks.size()));
}

// The car input size of the paper (aspect ratio changes: fx, fy scale apart). By hand.
TEST(SlamEndToEnd, DISABLED_KittiExcerpt1280x720) {
  const testing::TempDir dir;
  const RunFigures f = run(kitti_excerpt(), datasets::DatasetFormat::kKitti,
                           dir.path() / "trace.db", std::nullopt, {}, cv::Size(1280, 720));
  print("KITTI 01 excerpt 1280x720", f);
  EXPECT_EQ(f.tracking_failures, 0);
  EXPECT_LT(f.final_drift_pct, 5.0);
}

// Sensitivity of the KITTI figures to the zero-mean prior on the disparity offset (default 2 px,
// only there to keep it bounded). By hand.
TEST(SlamEndToEnd, DISABLED_KittiOffsetPriorSensitivity) {
  for (const double sigma : {0.5, 20.0}) {
    const testing::TempDir dir;
    SlamOptions options;
    options.disparity_offset_sigma_px = sigma;
    const RunFigures f = run(kitti_excerpt(), datasets::DatasetFormat::kKitti,
                             dir.path() / "trace.db", std::nullopt, {}, std::nullopt, options);
    std::printf("disparity_offset_sigma_px %.1f: ", sigma);
    print("KITTI 01 excerpt", f);
    EXPECT_LT(f.final_drift_pct, 5.0);
  }
}

TEST(SlamEndToEnd, SameInputGivesTheSameEstimate) {
  const testing::TempDir dir;
  run(kitti_excerpt(), datasets::DatasetFormat::kKitti, dir.path() / "a.db", 15);
  run(kitti_excerpt(), datasets::DatasetFormat::kKitti, dir.path() / "b.db", 15);
  const auto a = trace::TraceReader(dir.path() / "a.db").read_all();
  const auto b = trace::TraceReader(dir.path() / "b.db").read_all();
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_TRUE(a[i].frame.estimated_pose.has_value());
    EXPECT_EQ(a[i].frame.estimated_pose, b[i].frame.estimated_pose) << "frame " << i;
    ASSERT_EQ(a[i].kernels.size(), b[i].kernels.size());
  }
}

// Full size, by hand: 200 frames at the generator's default resolution on the seeds of
// $EDX_SLAM_SEEDS (default 1; issue 16's check on seeds nobody tuned on: "11 12 13").
TEST(SlamEndToEnd, DISABLED_SyntheticIndoorUnknownFullSize) {
  const char* env = std::getenv("EDX_SLAM_SEEDS");
  std::istringstream seeds(env ? env : "1");
  for (std::uint64_t seed; seeds >> seed;) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const testing::TempDir dir;
    const fs::path data = generate_indoor(dir.path(), 200, std::nullopt, seed);
    const RunFigures f = run(data, datasets::DatasetFormat::kEuroc, dir.path() / "trace.db");
    print(("synthetic indoor_unknown 200 frames native, seed " + std::to_string(seed)).c_str(), f);
    EXPECT_LT(f.ate_rmse_m, 0.19);
  }
}

}  // namespace
}  // namespace edx::backend::slam
