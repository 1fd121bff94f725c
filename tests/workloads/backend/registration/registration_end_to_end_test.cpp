// Registration end to end on a small synthetic indoor_known dataset, as a user runs it:
//   edx gen --scenario indoor_known                      (map run and loc run re-traversing it)
//   edx trace --backend slam --save-map map.json          (on the map run)
//   edx vocab (the map run's frames)                      (a small vocabulary)
//   edx trace --backend registration --map --vocab        (on the loc run)
// through the same library calls, at 376x240. Asserts the ATE of the registered poses, the
// fraction of frames registered, the trace's kernels and the one-line errors of bad --map and
// --vocab arguments. The full-size figures of docs/REGISTRATION.md come from the DISABLED_ test.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include "tests/support/temp_dir.hpp"
#include "workloads/backend/registration/bow/training.hpp"
#include "workloads/backend/registration/registration_backend.hpp"
#include "workloads/backend/slam/map.hpp"
#include "workloads/datasets/synthetic/generator.hpp"
#include "workloads/modes/backend_registry.hpp"
#include "workloads/modes/trace_runner.hpp"
#include "workloads/trace/reader.hpp"

namespace edx::backend::registration {
namespace {

namespace fs = std::filesystem;

struct Figures {
  modes::TraceRunSummary map, loc;
  double registered_fraction = 0;
  double projection_share = 0;
};

/// Localizes the loc run of the generated data in dir (map.json, vocab.bin) into `out`.
modes::TraceRunSummary localize(const fs::path& dir, const fs::path& out,
                                const RegistrationOptions& options) {
  auto map = std::make_shared<const slam::Map>(slam::load_map(dir / "map.json"));
  auto vocabulary =
      std::make_shared<const bow::Vocabulary>(bow::Vocabulary::load(dir / "vocab.bin"));
  modes::TraceRunOptions r;
  r.dataset_path = dir / "data" / "loc";
  r.out = out;
  r.make_backend = [=](const datasets::Dataset& d) {
    return make_registration_backend(d, options, map, vocabulary);
  };
  return modes::run_trace(r);
}

/// The projection kernel's M of every frame of a trace.
std::vector<std::int64_t> projection_sizes(const fs::path& trace_file) {
  std::vector<std::int64_t> sizes;
  for (const trace::FrameTrace& frame : trace::TraceReader(trace_file).read_all()) {
    for (const trace::KernelRecord& k : frame.kernels) {
      if (k.kernel == "projection") sizes.push_back(k.m);
    }
  }
  return sizes;
}

Figures map_and_localize(const fs::path& dir, int frames, std::optional<synthetic::Resolution> res,
                         int vocabulary_depth, std::uint64_t seed = 1) {
  synthetic::GenerateOptions g;
  g.scenario = synthetic::Scenario::kIndoorKnown;
  g.frames = frames;
  g.resolution = res;
  g.seed = seed;
  g.out = dir / "data";
  synthetic::generate_dataset(g);

  Figures f;
  modes::TraceRunOptions m;
  m.dataset_path = dir / "data" / "map";
  m.out = dir / "map.db";
  m.make_backend = modes::backend_factory("slam");
  m.map_out = dir / "map.json";
  f.map = modes::run_trace(m);

  bow::TrainingOptions t;
  t.datasets = {{dir / "data" / "map", datasets::DatasetFormat::kEuroc, {}}};
  t.frame_stride = 4;
  t.vocabulary.depth = vocabulary_depth;
  bow::train_vocabulary(t).vocabulary.save(dir / "vocab.bin");

  modes::BackendSettings settings;
  settings.map = dir / "map.json";
  settings.vocabulary = dir / "vocab.bin";
  modes::TraceRunOptions r;
  r.dataset_path = dir / "data" / "loc";
  r.out = dir / "loc.db";
  r.make_backend = modes::backend_factory("registration", settings);
  f.loc = modes::run_trace(r);
  f.registered_fraction =
      static_cast<double>(f.loc.estimated_frames) / static_cast<double>(f.loc.frames);
  double total = 0;
  for (const auto& [name, ms] : f.loc.kernel_ms) {
    total += ms.mean;
    if (name == "projection") f.projection_share = ms.mean;
  }
  f.projection_share = total > 0 ? f.projection_share / total : 0;
  std::printf(
      "map: %zu keyframes, %zu landmarks; loc: %zu of %zu frames registered, ATE %.4f m over "
      "%.1f m; backend %.3f / %.3f ms (mean / SD); projection %.1f %% of kernel time\n",
      f.map.map_keyframes, f.map.map_landmarks, f.loc.estimated_frames, f.loc.frames,
      f.loc.accuracy ? f.loc.accuracy->ate_m.rmse : -1.0,
      f.loc.accuracy ? f.loc.accuracy->gt_length_m : 0.0, f.loc.backend_ms.mean,
      f.loc.backend_ms.sd, 100 * f.projection_share);
  for (const auto& [name, ms] : f.loc.kernel_ms) {
    std::printf("  %-20s %8.3f ms mean %8.3f ms SD\n", name.c_str(), ms.mean, ms.sd);
  }
  return f;
}

TEST(RegistrationEndToEnd, LocalizesTheLocRunInTheMapOfTheMapRun) {
  testing::TempDir dir;
  const Figures f = map_and_localize(dir.path(), 60, synthetic::Resolution{376, 240}, 4);
  EXPECT_GT(f.map.map_keyframes, 5u);
  EXPECT_GT(f.map.map_landmarks, 500u);
  EXPECT_EQ(f.loc.backend_mode, "registration");
  EXPECT_EQ(f.loc.scenario, "indoor_known");
  EXPECT_GE(f.registered_fraction, 0.9);
  ASSERT_TRUE(f.loc.accuracy);
  EXPECT_LE(f.loc.accuracy->ate_m.rmse, 0.15);
  std::set<std::string> kernels;
  for (const auto& [name, ms] : f.loc.kernel_ms) kernels.insert(name);
  for (const char* name : {"bow_query", "matching", "pnp", "pose_refinement", "local_map",
                           "projection", "projection_matching"}) {
    EXPECT_TRUE(kernels.count(name)) << name;
  }
  // The current map (ORB-SLAM's local map): this 3.5 m warehouse is covisible as a whole, so
  // with the default bound (80 keyframes) every frame projects the 15 keyframes' points.
  for (std::int64_t m : projection_sizes(dir.path() / "loc.db")) {
    EXPECT_GT(m, 0);
    EXPECT_LE(m, static_cast<std::int64_t>(f.map.map_landmarks));
  }
  // Bounded to 4 keyframes, the current map follows the frame through the map: M varies over
  // the run (the full-size map of docs/REGISTRATION.md varies with the default bound), and the
  // run still registers.
  RegistrationOptions bounded;
  bounded.local_map_max_keyframes = 4;
  const modes::TraceRunSummary b = localize(dir.path(), dir.path() / "loc_bounded.db", bounded);
  EXPECT_GE(static_cast<double>(b.estimated_frames), 0.9 * static_cast<double>(b.frames));
  const std::vector<std::int64_t> sizes = projection_sizes(dir.path() / "loc_bounded.db");
  const std::set<std::int64_t> distinct(sizes.begin(), sizes.end());
  EXPECT_GE(distinct.size(), 5u);
  EXPECT_LT(*distinct.rbegin(), static_cast<std::int64_t>(f.map.map_landmarks));
}

// Full size, by hand (--gtest_also_run_disabled_tests): the figures of docs/REGISTRATION.md, on
// the seeds of $EDX_REGISTRATION_SEEDS (default 1, the documented run; issue 16's check on seeds
// nobody tuned on: EDX_REGISTRATION_SEEDS="11 12 13"). Every frame registers, ATE <= 0.15 m.
TEST(RegistrationEndToEnd, DISABLED_FullSizeIndoorKnown) {
  const char* env = std::getenv("EDX_REGISTRATION_SEEDS");
  std::istringstream seeds(env ? env : "1");
  for (std::uint64_t seed; seeds >> seed;) {
    SCOPED_TRACE(fmt::format("seed {}", seed));
    testing::TempDir dir;
    std::printf("seed %llu: ", static_cast<unsigned long long>(seed));
    const Figures f = map_and_localize(dir.path(), 200, std::nullopt, 5, seed);
    EXPECT_EQ(f.loc.estimated_frames, f.loc.frames);
    ASSERT_TRUE(f.loc.accuracy);
    EXPECT_LE(f.loc.accuracy->ate_m.rmse, 0.15);
  }
}

std::string error_of(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(RegistrationEndToEnd, BadMapOrVocabularyArgumentsGiveOneLineErrors) {
  testing::TempDir dir;
  modes::BackendSettings settings;
  EXPECT_NE(error_of([&] { modes::backend_factory("registration", settings); }).find("--map"),
            std::string::npos);
  settings.map = dir.path() / "missing.json";
  EXPECT_NE(error_of([&] { modes::backend_factory("registration", settings); }).find("--vocab"),
            std::string::npos);
  settings.vocabulary = dir.path() / "missing.bin";
  std::string message = error_of([&] { modes::backend_factory("registration", settings); });
  EXPECT_NE(message.find("missing.json"), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;

  std::ofstream(dir.path() / "bad.json") << R"({"format": "edx-slam-map", "version": 1})";
  settings.map = dir.path() / "bad.json";
  message = error_of([&] { modes::backend_factory("registration", settings); });
  EXPECT_NE(message.find("bad.json"), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;

  modes::BackendSettings slam_with_vocab;
  slam_with_vocab.vocabulary = dir.path() / "vocab.bin";
  message = error_of([&] { modes::backend_factory("slam", slam_with_vocab); });
  EXPECT_NE(message.find("--vocab"), std::string::npos) << message;
}

}  // namespace
}  // namespace edx::backend::registration
