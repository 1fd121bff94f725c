// The trace runner end to end on the real excerpts (EuRoC V1_01 micro, KITTI 01) and on a small
// synthetic sequence: what the trace says reads back, and bad input leaves nothing behind.
#include "workloads/modes/trace_runner.hpp"

#include <SQLiteCpp/Database.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <thread>

#include "tests/support/sanitizers.hpp"
#include "tests/support/temp_dir.hpp"
#include "workloads/backend/kernel_recorder.hpp"
#include "workloads/datasets/synthetic/generator.hpp"
#include "workloads/trace/host_speed.hpp"
#include "workloads/trace/reader.hpp"
#include "workloads/trace/schema.hpp"

namespace edx::modes {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::StartsWith;
using trace::Image;
using trace::Task;

const fs::path kData = EDX_SHARED_DATA_DIR;
const fs::path kEuroc = kData / "euroc_v101_micro";
const fs::path kKitti = kData / "kitti_odometry_excerpt" / "sequences" / "01";

TraceRunOptions euroc_options(const fs::path& out, std::size_t frames) {
  TraceRunOptions options;
  options.dataset_path = kEuroc;
  options.format = datasets::DatasetFormat::kEuroc;
  options.max_frames = frames;
  options.out = out;
  return options;
}

/// Checks the rows every frontend trace has: ten tasks per frame in the fixed order, frames in
/// time order, and the per-frame counts against the bounds given.
void expect_frontend_trace(const std::vector<trace::FrameTrace>& frames, int min_left,
                           int min_stereo_frames) {
  const std::vector<std::pair<Task, Image>> layout = {
      {Task::FD, Image::Left},  {Task::IF, Image::Left},  {Task::FD, Image::Right},
      {Task::IF, Image::Right}, {Task::DC, Image::Left},  {Task::LSS, Image::Left},
      {Task::FC, Image::Left},  {Task::FC, Image::Right}, {Task::MO, Image::Stereo},
      {Task::DR, Image::Stereo}};
  int frames_with_stereo = 0;
  for (std::size_t n = 0; n < frames.size(); ++n) {
    const trace::FrameTrace& f = frames[n];
    EXPECT_EQ(f.frame.frame_id, static_cast<std::int64_t>(n));
    EXPECT_EQ(f.frame.mode, trace::BackendMode::None);
    EXPECT_FALSE(f.frame.estimated_pose.has_value());
    EXPECT_GT(f.frame.frontend_host_ns, 0);
    EXPECT_EQ(f.frame.backend_host_ns, 0);
    EXPECT_TRUE(f.kernels.empty());
    if (n > 0) {
      EXPECT_GT(f.frame.timestamp_ns, frames[n - 1].frame.timestamp_ns);
    }
    ASSERT_EQ(f.tasks.size(), layout.size());
    for (std::size_t i = 0; i < layout.size(); ++i) {
      EXPECT_EQ(f.tasks[i].task, layout[i].first);
      EXPECT_EQ(f.tasks[i].image, layout[i].second);
    }
    const std::int64_t left = f.tasks[6].descriptors;  // FC L: every left feature
    EXPECT_LE(left, 1000);
    EXPECT_GE(left, min_left) << "frame " << n;
    EXPECT_LE(f.tasks[7].descriptors, 2000);
    EXPECT_GT(f.tasks[0].candidates, f.tasks[0].keypoints);
    if (f.tasks[9].windows > 100) ++frames_with_stereo;
    if (n > 0) {
      EXPECT_GT(f.tasks[5].points, left / 2) << "frame " << n << ": tracks should persist";
      EXPECT_GT(f.tasks[5].iterations, f.tasks[5].points);
      EXPECT_LT(f.tasks[0].keypoints, left) << "frame " << n << ": most features are tracks";
    }
  }
  EXPECT_GE(frames_with_stereo, min_stereo_frames);
}

TEST(TraceRunner, EurocExcerptTenFrames) {
  const testing::TempDir dir;
  const TraceRunSummary summary = run_trace(euroc_options(dir.path() / "euroc.db", 10));
  EXPECT_EQ(summary.frames, 10u);
  EXPECT_EQ(summary.ground_truth_frames, 10u);
  EXPECT_EQ(summary.sequence, "euroc:euroc_v101_micro");
  EXPECT_EQ(summary.resolution, "752x480");
  EXPECT_EQ(summary.scenario, "indoor_unknown");
  ASSERT_EQ(summary.tasks.size(), 10u);
  EXPECT_GT(summary.left_keypoints.mean, 500);
  EXPECT_GT(summary.stereo_matches.mean, 100);
  EXPECT_GT(summary.tracked.mean, 400);

  const trace::TraceReader reader(dir.path() / "euroc.db");
  EXPECT_EQ(reader.frame_count(), 10u);
  const trace::TraceMeta& meta = reader.meta();
  for (const auto& key : trace::kRequiredMetaKeys) {
    EXPECT_FALSE(meta.at(std::string(key)).empty()) << key;
  }
  EXPECT_THAT(meta.at("dataset"), StartsWith("euroc:"));
  EXPECT_EQ(meta.at("resolution"), "752x480");
  EXPECT_THAT(meta.at("camera_model"), StartsWith("pinhole-rectified fx="));
  EXPECT_THAT(meta.at("compiler_flags"), HasSubstr("-std=c++20"));
  EXPECT_EQ(std::stoi(meta.at("host_cores")),
            static_cast<int>(std::thread::hardware_concurrency()));
  // The reference suite sampled before, every 25 frames and after: 3 + 0 + 2 samples here.
  const trace::HostSpeed speed = trace::host_speed_of(meta, "euroc.db");
  EXPECT_EQ(speed.suite, trace::kHostSpeedSuite);
  EXPECT_EQ(speed.samples, 5);
  // The frontend suite is the slower one on this machine's Release build (sanitizers slow the
  // Eigen-heavy backend suite more: tests/support/sanitizers.hpp).
  if (!edx::testing::kSanitizedBuild) {
    EXPECT_GT(speed.frontend_ms, speed.backend_ms);
  }
  const nlohmann::json params = nlohmann::json::parse(meta.at("pipeline_params"));
  EXPECT_EQ(params.at("frontend").at("features_per_image"), 1000);
  EXPECT_EQ(params.at("frontend").at("count_lk_iterations"), true);
  EXPECT_EQ(params.at("frontend").at("parallel_images"), false);
  EXPECT_EQ(params.at("backend_mode"), "none");

  const std::vector<trace::FrameTrace> frames = reader.read_all();
  expect_frontend_trace(frames, 500, 8);
  for (const trace::FrameTrace& f : frames) {
    EXPECT_EQ(f.frame.sequence, "euroc:euroc_v101_micro");
    EXPECT_EQ(f.frame.scenario, trace::Scenario::IndoorUnknown);
    EXPECT_FALSE(f.frame.gps_available);
    ASSERT_TRUE(f.frame.ground_truth_pose.has_value());
  }
  // The first EuRoC left image is taken at 1403715273262142976 ns (cam0/data.csv).
  EXPECT_EQ(frames.front().frame.timestamp_ns, 1403715273262142976);
}

TEST(TraceRunner, KittiExcerptTenFrames) {
  const testing::TempDir dir;
  TraceRunOptions options;
  options.dataset_path = kKitti;
  options.format = datasets::DatasetFormat::kKitti;
  options.max_frames = 10;
  options.out = dir.path() / "kitti.db";
  const TraceRunSummary summary = run_trace(options);
  EXPECT_EQ(summary.sequence, "kitti:01");
  EXPECT_EQ(summary.resolution, "1241x376");
  EXPECT_EQ(summary.scenario, "outdoor_unknown");
  EXPECT_GT(summary.left_keypoints.mean, 900);
  EXPECT_GT(summary.stereo_matches.mean, 150);
  const trace::TraceReader reader(options.out);
  const std::vector<trace::FrameTrace> frames = reader.read_all();
  ASSERT_EQ(frames.size(), 10u);
  expect_frontend_trace(frames, 900, 8);
  EXPECT_EQ(frames[1].frame.timestamp_ns - frames[0].frame.timestamp_ns, 100'000'000);  // times.txt
}

TEST(TraceRunner, ResolutionOptionResizesTheFrames) {
  const testing::TempDir dir;
  TraceRunOptions options = euroc_options(dir.path() / "small.db", 3);
  options.dataset.resize = cv::Size(376, 240);
  options.scenario = trace::Scenario::IndoorKnown;
  const TraceRunSummary summary = run_trace(options);
  EXPECT_EQ(summary.resolution, "376x240");
  const trace::TraceReader reader(options.out);
  EXPECT_EQ(reader.meta().at("resolution"), "376x240");
  const std::vector<trace::FrameTrace> frames = reader.read_all();
  EXPECT_EQ(frames[0].frame.scenario, trace::Scenario::IndoorKnown);
  EXPECT_EQ(frames[0].tasks[1].per_level.at(0).pixels, 376 * 240);  // IF on the resized image
  EXPECT_EQ(frames[0].tasks[4].per_level.at(0).width, 376);         // DC too
}

/// A small synthetic EuRoC-layout sequence (`edx gen`) in `dir`.
fs::path generate_synthetic(const fs::path& dir, int frames) {
  synthetic::GenerateOptions options;
  options.scenario = synthetic::Scenario::kIndoorUnknown;
  options.frames = frames;
  options.resolution = synthetic::Resolution{376, 240};
  options.seed = 3;
  options.out = dir / "synthetic";
  synthetic::generate_dataset(options);
  return options.out;
}

TEST(TraceRunner, SyntheticSequence) {
  const testing::TempDir dir;
  TraceRunOptions options;
  options.dataset_path = generate_synthetic(dir.path(), 6);
  options.format = datasets::DatasetFormat::kEuroc;
  options.out = dir.path() / "synthetic.db";
  const TraceRunSummary summary = run_trace(options);
  EXPECT_EQ(summary.frames, 6u);
  EXPECT_EQ(summary.ground_truth_frames, 6u);
  EXPECT_EQ(summary.sequence, "euroc:synthetic");
  EXPECT_EQ(summary.resolution, "376x240");
  const std::vector<trace::FrameTrace> frames = trace::TraceReader(options.out).read_all();
  ASSERT_EQ(frames.size(), 6u);
  expect_frontend_trace(frames, 150, 0);
  for (const auto& f : frames) EXPECT_GT(f.tasks[9].windows, 30);
}

std::string run_error(const TraceRunOptions& options) {
  try {
    run_trace(options);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(TraceRunner, ExistingOutputIsRefusedUnlessOverwriting) {
  const testing::TempDir dir;
  const fs::path out = dir.path() / "trace.db";
  { std::ofstream(out) << "not a trace"; }
  TraceRunOptions options = euroc_options(out, 2);
  EXPECT_THAT(run_error(options), HasSubstr("output exists (refusing to overwrite; use --force)"));
  EXPECT_EQ(testing::read_file(out), "not a trace");
  options.overwrite = true;
  EXPECT_EQ(run_error(options), "");
  EXPECT_EQ(trace::TraceReader(out).frame_count(), 2u);
}

TEST(TraceRunner, MissingDatasetLeavesNothing) {
  const testing::TempDir dir;
  TraceRunOptions options = euroc_options(dir.path() / "trace.db", 2);
  options.dataset_path = dir.path() / "no_such_dataset";
  EXPECT_THAT(run_error(options), HasSubstr("no_such_dataset"));
  EXPECT_TRUE(testing::entries(dir.path()).empty());
}

TEST(TraceRunner, UnreadableImageMidSequenceLeavesNothing) {
  const testing::TempDir dir;
  const fs::path dataset = generate_synthetic(dir.path(), 5);
  // Overwrite the fourth left image with bytes that are not a PNG.
  std::vector<fs::path> images;
  for (const auto& e : fs::directory_iterator(dataset / "mav0" / "cam0" / "data")) {
    images.push_back(e.path());
  }
  std::sort(images.begin(), images.end());
  ASSERT_EQ(images.size(), 5u);
  { std::ofstream(images[3], std::ios::trunc) << "garbage"; }
  TraceRunOptions options;
  options.dataset_path = dataset;
  options.out = dir.path() / "out" / "trace.db";
  fs::create_directories(options.out.parent_path());
  EXPECT_THAT(run_error(options), HasSubstr(images[3].filename().string()));
  EXPECT_TRUE(testing::entries(options.out.parent_path()).empty());
}

TEST(TraceRunner, ImageSizeChangeMidSequenceLeavesNothing) {
  const testing::TempDir dir;
  const fs::path dataset = generate_synthetic(dir.path(), 5);
  std::vector<fs::path> images;
  for (const auto& e : fs::directory_iterator(dataset / "mav0" / "cam1" / "data")) {
    images.push_back(e.path());
  }
  std::sort(images.begin(), images.end());
  ASSERT_EQ(images.size(), 5u);
  cv::imwrite(images[2].string(), cv::Mat(120, 188, CV_8U, cv::Scalar(90)));
  TraceRunOptions options;
  options.dataset_path = dataset;
  options.out = dir.path() / "out" / "trace.db";
  fs::create_directories(options.out.parent_path());
  const std::string error = run_error(options);
  EXPECT_THAT(error, HasSubstr(images[2].filename().string()));
  EXPECT_THAT(error, HasSubstr("188x120"));
  EXPECT_TRUE(testing::entries(options.out.parent_path()).empty());
}

TEST(TraceRunner, ATraceOfAnotherSchemaVersionIsRefusedByTheReader) {
  const testing::TempDir dir;
  const fs::path out = dir.path() / "trace.db";
  run_trace(euroc_options(out, 1));
  {
    SQLite::Database db(out.string(), SQLite::OPEN_READWRITE);
    db.exec("UPDATE meta SET value = '999' WHERE key = 'schema_version'");
  }
  try {
    trace::TraceReader reader(out);
    FAIL() << "a trace of schema version 999 was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("999"));
  }
}

TEST(TraceRunner, SequenceNames) {
  const datasets::DatasetOptions none;
  EXPECT_EQ(sequence_name(kEuroc, datasets::DatasetFormat::kEuroc, none), "euroc:euroc_v101_micro");
  EXPECT_EQ(sequence_name(kEuroc / "mav0", datasets::DatasetFormat::kEuroc, none),
            "euroc:euroc_v101_micro");
  EXPECT_EQ(sequence_name(kKitti, datasets::DatasetFormat::kKitti, none), "kitti:01");
  datasets::DatasetOptions root;
  root.kitti_sequence = "01";
  EXPECT_EQ(sequence_name(kData / "kitti_odometry_excerpt", datasets::DatasetFormat::kKitti, root),
            "kitti:01");
}

TEST(TraceRunner, SummaryAsTextAndJson) {
  const testing::TempDir dir;
  const TraceRunSummary summary = run_trace(euroc_options(dir.path() / "t.db", 3));
  const nlohmann::json j = to_json(summary);
  EXPECT_EQ(j.at("frames"), 3);
  EXPECT_EQ(j.at("task_ms").size(), 10u);
  EXPECT_GT(j.at("task_ms").at("FD/L").at("mean").get<double>(), 0);
  EXPECT_GT(j.at("per_frame").at("left_keypoints").at("mean").get<double>(), 300);
  const std::string text = format_summary(summary);
  EXPECT_THAT(text, HasSubstr("LSS/L"));
  EXPECT_THAT(text, HasSubstr("frames     3"));
}

}  // namespace
}  // namespace edx::modes

namespace edx::modes {
namespace {

/// A backend that reports the ground-truth pose shifted by a known offset, counts the IMU
/// samples it is handed, and records one kernel with one op per frame.
class ProbeBackend : public backend::Backend {
 public:
  ProbeBackend(const datasets::Dataset& dataset, std::size_t* imu_seen)
      : dataset_(dataset), imu_seen_(imu_seen) {}
  trace::BackendMode mode() const override { return trace::BackendMode::Vio; }
  backend::BackendOutput process(const backend::BackendInput& input) override {
    backend::BackendOutput out;
    for (const datasets::ImuSample& s : input.imu) {
      EXPECT_GT(s.t_ns, last_t_ns_);
      EXPECT_LE(s.t_ns, input.t_ns);
    }
    last_t_ns_ = input.t_ns;
    *imu_seen_ += input.imu.size();
    {
      auto kernel = recorder_.kernel("kalman_gain", true);
      kernel.record().m = static_cast<std::int64_t>(input.frontend->features.size());
      recorder_.op(trace::Op::Potrf, 6, 6, 0, trace::op_flags::kSymmetric, [] { return 0; });
    }
    out.kernels = recorder_.take();
    const auto truth = datasets::interpolate_ground_truth(dataset_.ground_truth(), input.t_ns);
    if (!truth) {
      out.status = "no_truth";
      return out;
    }
    Eigen::Isometry3d pose = truth->T_world_body;
    pose.translation().x() += 0.5;  // ATE under position+yaw alignment: 0
    out.T_world_body = pose;
    return out;
  }

 private:
  const datasets::Dataset& dataset_;
  std::size_t* imu_seen_;
  std::int64_t last_t_ns_ = std::numeric_limits<std::int64_t>::min();
  backend::KernelRecorder recorder_;
};

TEST(TraceRunner, RunsTheBackendOnEveryFrameAndMeasuresItsEstimate) {
  testing::TempDir dir;
  TraceRunOptions options = euroc_options(dir.path() / "probe.db", 12);
  std::size_t imu_seen = 0;
  options.make_backend = [&imu_seen](const datasets::Dataset& dataset) {
    return std::make_unique<ProbeBackend>(dataset, &imu_seen);
  };
  const TraceRunSummary summary = run_trace(options);
  EXPECT_EQ(summary.backend_mode, "vio");

  // Every IMU sample up to the last frame is handed over exactly once.
  const auto dataset = datasets::open_dataset(kEuroc, datasets::DatasetFormat::kEuroc);
  const std::int64_t last_t = dataset->frame_time(11);
  const auto expected =
      std::count_if(dataset->imu().begin(), dataset->imu().end(),
                    [&](const datasets::ImuSample& s) { return s.t_ns <= last_t; });
  EXPECT_EQ(imu_seen, static_cast<std::size_t>(expected));
  EXPECT_GT(imu_seen, 12u * 5);  // EuRoC: 200 Hz IMU, 20 Hz camera

  ASSERT_TRUE(summary.accuracy.has_value());
  EXPECT_EQ(summary.accuracy->alignment, eval::AlignmentMethod::kPosYaw);
  EXPECT_EQ(summary.accuracy->pairs, summary.estimated_frames);
  EXPECT_NEAR(summary.accuracy->ate_m.rmse, 0.0, 1e-6);
  ASSERT_EQ(summary.kernel_ms.size(), 1u);
  EXPECT_EQ(summary.kernel_ms[0].first, "kalman_gain");
  EXPECT_EQ(summary.backend_ms.count, 12u);

  const std::vector<trace::FrameTrace> frames = trace::TraceReader(options.out).read_all();
  ASSERT_EQ(frames.size(), 12u);
  for (const trace::FrameTrace& f : frames) {
    EXPECT_EQ(f.frame.mode, trace::BackendMode::Vio);
    ASSERT_EQ(f.kernels.size(), 1u);
    EXPECT_EQ(f.kernels[0].kernel, "kalman_gain");
    EXPECT_EQ(f.kernels[0].m, f.tasks[6].descriptors);  // every left feature
    ASSERT_EQ(f.kernels[0].ops.size(), 1u);
    EXPECT_EQ(f.kernels[0].ops[0].op, trace::Op::Potrf);
    EXPECT_GE(f.frame.backend_host_ns, f.kernels[0].host_ns);
    EXPECT_EQ(f.frame.estimated_pose.has_value(), f.frame.backend_status == "ok");
    if (f.frame.estimated_pose && f.frame.ground_truth_pose) {
      EXPECT_NEAR((*f.frame.estimated_pose)[0] - (*f.frame.ground_truth_pose)[0], 0.5, 1e-9);
    }
  }
  EXPECT_NE(trace::TraceReader(options.out).meta().at("pipeline_params").find("\"vio\""),
            std::string::npos);
}

}  // namespace
}  // namespace edx::modes
