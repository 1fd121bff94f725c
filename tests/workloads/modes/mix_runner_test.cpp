// The mixed-sequence runner end to end (workloads/modes/mix_runner.hpp): the paper mix on small
// synthetic worlds, the modes the switch picks per segment, the map handed from SLAM to
// registration, and the trace it writes.
#include "workloads/modes/mix_runner.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <stdexcept>

#include "tests/support/temp_dir.hpp"
#include "workloads/backend/registration/bow/training.hpp"
#include "workloads/datasets/dataset.hpp"
#include "workloads/datasets/synthetic/generator.hpp"
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
