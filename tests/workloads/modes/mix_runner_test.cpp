// The mixed-sequence runner end to end (workloads/modes/mix_runner.hpp): the paper mix on small
// synthetic worlds, the modes the switch picks per segment, the map handed from SLAM to
// registration, and the trace it writes.
#include "workloads/modes/mix_runner.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <stdexcept>

#include "tests/support/temp_dir.hpp"
#include "tests/support/trace_rows.hpp"
#include "workloads/backend/registration/bow/training.hpp"
#include "workloads/datasets/dataset.hpp"
#include "workloads/datasets/synthetic/generator.hpp"
#include "workloads/modes/characterization.hpp"
#include "workloads/trace/reader.hpp"

namespace edx::modes {
namespace {

TEST(MixRunner, PaperMixSwitchesModesByScenario) {
  const edx::testing::TempDir dir;
  MixRunOptions options;
  options.plan = make_mix("paper", 64, {376, 240}, 1);
  options.data_dir = dir.path() / "data";
  options.out = dir.path() / "mix.db";
  const MixRunSummary summary = run_mix(options);
  std::cout << format_summary(summary);
  ASSERT_EQ(summary.segments.size(), 3u);
  EXPECT_EQ(summary.frames, 64u);
  // Outdoors: VIO once the receiver has 5 fixes in a second (0.4 s: the first 8 frames run SLAM).
  EXPECT_EQ(summary.segments[0].frames_by_mode.at("slam"), 8u);
  EXPECT_EQ(summary.segments[0].frames_by_mode.at("vio"), 24u);
  // The indoor mapping run has no GPS and no map yet: SLAM throughout, its map saved.
  EXPECT_EQ(summary.segments[1].frames_by_mode.at("slam"), 16u);
  ASSERT_TRUE(summary.segments[1].map_saved);
  EXPECT_TRUE(std::filesystem::exists(*summary.segments[1].map_saved));
  // The later run through the same warehouse registers in that map.
  EXPECT_EQ(summary.segments[2].frames_by_mode.at("registration"), 16u);
  EXPECT_LE(summary.segments[2].registration_failures, 2u);
  for (const ModeRunSummary& m : summary.modes) {
    EXPECT_GT(m.estimated_frames, 0u) << m.mode;  // VIO: after its 20 initialization frames
    if (m.mode == "registration") {
      ASSERT_TRUE(m.ate_rmse_m);
      EXPECT_LT(*m.ate_rmse_m, 0.15);
    }
  }

  // The vocabulary's world: only the 25 frames its training reads (0, 4, ..., 96 of 100).
  const auto vocabulary_world = datasets::open_dataset(
      options.data_dir / "vocabulary-world-376x240-s2-every4", datasets::DatasetFormat::kEuroc);
  EXPECT_EQ(vocabulary_world->frame_count(), 25u);

  const trace::TraceReader reader(options.out);
  EXPECT_EQ(reader.frame_count(), 64u);
  const std::vector<trace::FrameTrace> frames = reader.read_all();
  EXPECT_EQ(frames[0].frame.scenario, trace::Scenario::OutdoorUnknown);
  EXPECT_EQ(frames[10].frame.mode, trace::BackendMode::Vio);
  EXPECT_EQ(frames[40].frame.mode, trace::BackendMode::Slam);
  EXPECT_EQ(frames[63].frame.scenario, trace::Scenario::IndoorKnown);
  EXPECT_EQ(frames[63].frame.mode, trace::BackendMode::Registration);
  EXPECT_TRUE(frames[63].frame.map_available);
  EXPECT_FALSE(frames[40].frame.map_available);
}

using edx::testing::without_host_times;

/// The characterization's known-scenario runs share their mapping segment (SegmentCache): the
/// registration run that replays the vio run's mapping segment writes the same rows and measures
/// the same as the registration run that traces it itself; its mapping frames are the vio run's
/// records (their host times too: replayed, not traced again). Another workload (other SLAM
/// options) does not take the entry. The replay leaves the mapping's map in the data folder, as
/// tracing it does (a SLAM measured run in between saved its own there).
TEST(MixRunner, AReplayedMappingSegmentGivesTheSameTraceAsTracingIt) {
  const edx::testing::TempDir dir;
  const synthetic::Resolution resolution{376, 240};
  const auto options_for = [&](trace::BackendMode backend, const char* out) {
    MixRunOptions options;
    options.plan = characterization_plan({synthetic::Scenario::kIndoorKnown, backend}, 12,
                                         resolution, kCharacterizationFirstSeed);
    options.data_dir = dir.path() / "data";
    options.out = dir.path() / out;
    return options;
  };
  const MixRunSummary traced = run_mix(options_for(trace::BackendMode::Registration, "a.db"));
  ASSERT_TRUE(traced.segments[0].map_saved);
  const std::filesystem::path map_file = *traced.segments[0].map_saved;
  const std::string mapping_map = edx::testing::read_file(map_file);

  const std::shared_ptr<SegmentCache> cache = make_segment_cache();
  MixRunOptions vio = options_for(trace::BackendMode::Vio, "vio.db");
  vio.segment_cache = cache;
  run_mix(vio);
  // The slam run replays the mapping segment too; its measured segment (SLAM in the same world)
  // then saves its own map over the mapping's.
  MixRunOptions slam = options_for(trace::BackendMode::Slam, "slam.db");
  slam.segment_cache = cache;
  run_mix(slam);
  ASSERT_NE(edx::testing::read_file(map_file), mapping_map);
  MixRunOptions registration = options_for(trace::BackendMode::Registration, "b.db");
  registration.segment_cache = cache;
  const MixRunSummary replayed = run_mix(registration);

  const std::vector<trace::FrameTrace> a = trace::TraceReader(dir.path() / "a.db").read_all();
  const std::vector<trace::FrameTrace> b = trace::TraceReader(dir.path() / "b.db").read_all();
  const std::vector<trace::FrameTrace> v = trace::TraceReader(dir.path() / "vio.db").read_all();
  ASSERT_EQ(a.size(), 24u);
  EXPECT_EQ(without_host_times(a), without_host_times(b));
  // The mapping frames (SLAM, 0..11) are the vio run's records, host times included.
  EXPECT_EQ(std::vector(b.begin(), b.begin() + 12), std::vector(v.begin(), v.begin() + 12));
  EXPECT_EQ(b[0].frame.mode, trace::BackendMode::Slam);
  EXPECT_EQ(b[12].frame.mode, trace::BackendMode::Registration);
  EXPECT_TRUE(b[12].frame.map_available);
  // The replay saved the mapping's map again, as tracing it does.
  EXPECT_EQ(edx::testing::read_file(map_file), mapping_map);
  // The same segments' and modes' figures (ATE, estimates, frames by mode).
  ASSERT_EQ(replayed.segments.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(replayed.segments[i].ate_rmse_m, traced.segments[i].ate_rmse_m) << i;
    EXPECT_EQ(replayed.segments[i].ate_pairs, traced.segments[i].ate_pairs) << i;
    EXPECT_EQ(replayed.segments[i].frames_by_mode, traced.segments[i].frames_by_mode) << i;
    EXPECT_EQ(replayed.segments[i].registration_failures, traced.segments[i].registration_failures);
    EXPECT_EQ(replayed.segments[i].map_saved, traced.segments[i].map_saved) << i;
  }
  EXPECT_EQ(replayed.segments[0].frames_by_mode.at("slam"), 12u);
  ASSERT_TRUE(replayed.segments[1].ate_rmse_m.count("registration"));
  ASSERT_EQ(replayed.modes.size(), traced.modes.size());
  for (std::size_t i = 0; i < replayed.modes.size(); ++i) {
    EXPECT_EQ(replayed.modes[i].mode, traced.modes[i].mode);
    EXPECT_EQ(replayed.modes[i].frames, traced.modes[i].frames);
    EXPECT_EQ(replayed.modes[i].estimated_frames, traced.modes[i].estimated_frames);
    EXPECT_EQ(replayed.modes[i].ate_rmse_m, traced.modes[i].ate_rmse_m);
    EXPECT_EQ(replayed.modes[i].ate_pairs, traced.modes[i].ate_pairs);
  }

  // Other SLAM options: another workload, its mapping segment traced (its own host times).
  MixRunOptions other = options_for(trace::BackendMode::Slam, "c.db");
  other.segment_cache = cache;
  other.slam.window_size += 1;
  run_mix(other);
  const std::vector<trace::FrameTrace> c = trace::TraceReader(dir.path() / "c.db").read_all();
  EXPECT_NE(std::vector(c.begin(), c.begin() + 12), std::vector(v.begin(), v.begin() + 12));
}

/// What the mix runner relies on for its vocabulary: training on every frame of a world generated
/// with frame_stride n gives the same vocabulary, byte for byte, as training on every n-th frame
/// of the full world.
TEST(MixRunner, AStridedWorldTrainsTheSameVocabularyAsTheFullOne) {
  const edx::testing::TempDir dir;
  synthetic::GenerateOptions world;
  world.scenario = synthetic::Scenario::kIndoorUnknown;
  world.frames = 11;
  world.resolution = synthetic::Resolution{376, 240};
  world.seed = 5;
  world.out = dir.path() / "full";
  synthetic::generate_dataset(world);
  world.out = dir.path() / "strided";
  world.frame_stride = 4;
  synthetic::generate_dataset(world);

  bow::TrainingOptions training;
  training.vocabulary.depth = 3;
  training.vocabulary.seed = 5;
  training.datasets = {{dir.path() / "full", datasets::DatasetFormat::kEuroc, {}}};
  training.frame_stride = 4;
  const bow::TrainedVocabulary full = bow::train_vocabulary(training);
  training.datasets = {{dir.path() / "strided", datasets::DatasetFormat::kEuroc, {}}};
  training.frame_stride = 1;
  const bow::TrainedVocabulary strided = bow::train_vocabulary(training);
  EXPECT_EQ(full.summary.images, 3u);  // frames 0, 4, 8
  EXPECT_EQ(strided.summary.images, 3u);
  EXPECT_GT(full.summary.descriptors, 100u);
  EXPECT_EQ(strided.summary.descriptors, full.summary.descriptors);
  full.vocabulary.save(dir.path() / "full.bin");
  strided.vocabulary.save(dir.path() / "strided.bin");
  EXPECT_EQ(edx::testing::read_file(dir.path() / "full.bin"),
            edx::testing::read_file(dir.path() / "strided.bin"));
}

/// A run refused after it generated its worlds (here by a vocabulary file that is not one)
/// removes the data folder it created and writes no trace; a folder that was there stays.
TEST(MixRunner, ARefusedRunLeavesNoDataFolderItCreated) {
  const edx::testing::TempDir dir;
  const std::filesystem::path vocabulary = dir.path() / "bad.bin";
  std::ofstream(vocabulary) << "garbage\n";
  MixRunOptions options;
  options.plan = make_mix("paper", 8, {160, 120}, 1);
  options.vocabulary = vocabulary;
  options.out = dir.path() / "mix.db";
  options.data_dir = dir.path() / "new-data";
  EXPECT_THROW(run_mix(options), std::runtime_error);
  EXPECT_FALSE(std::filesystem::exists(options.data_dir));
  EXPECT_FALSE(std::filesystem::exists(options.out));

  options.data_dir = dir.path() / "old-data";
  std::filesystem::create_directories(options.data_dir);
  EXPECT_THROW(run_mix(options), std::runtime_error);
  // The worlds generated into an existing folder stay: it is a cache across runs.
  EXPECT_TRUE(std::filesystem::exists(
      segment_mav0(options.plan, options.plan.segments[0], options.data_dir)));
  EXPECT_FALSE(std::filesystem::exists(options.out));
}

}  // namespace
}  // namespace edx::modes
