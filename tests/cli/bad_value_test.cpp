// Bad values that used to be accepted silently (issue 21, class 6): each is now a one-line error
// naming the option, file or key, with a non-zero exit and no output created.
#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "tests/support/run_command.hpp"
#include "tests/support/temp_dir.hpp"

namespace edx::testing {
namespace {

namespace fs = std::filesystem;

std::string edx() { return fmt::format("'{}'", built_binary("edx")); }

TEST(BadValue, OptionsNegativeSeedsAndEmptyPathsAreRefused) {
  const TempDir dir;
  const CommandResult seed =
      run_command(fmt::format("{} gen --scenario indoor_unknown --frames 2 --seed -1 --out '{}'",
                              edx(), (dir.path() / "g").string()));
  EXPECT_EQ(seed.exit_code, 2);
  EXPECT_EQ(seed.err, "edx: --seed: expected a non-negative integer, got '-1' (see edx --help)\n");
  EXPECT_FALSE(fs::exists(dir.path() / "g"));
  const CommandResult out = run_command(fmt::format(
      "{} simulate --config '{}/configs/edx_car.yaml' --trace '{}/tests/data/golden/golden_mix.db' "
      "--out ''",
      edx(), EDX_SOURCE_DIR, EDX_SOURCE_DIR));
  EXPECT_EQ(out.exit_code, 2);
  EXPECT_EQ(out.err, "edx: --out: expected a path, got '' (see edx --help)\n");
}

TEST(BadValue, ATimelinePastTheTraceAndAKeyWrittenTwiceAreErrors) {
  const TempDir dir;
  const std::string trace = fmt::format("{}/tests/data/golden/golden_mix.db", EDX_SOURCE_DIR);
  const fs::path timeline = dir.path() / "tl.json";
  const CommandResult late = run_command(
      fmt::format("{} simulate --config '{}/configs/edx_car.yaml' --trace '{}' --timeline '{}' "
                  "--timeline-first 100000",
                  edx(), EDX_SOURCE_DIR, trace, timeline.string()));
  EXPECT_EQ(late.exit_code, 1);
  EXPECT_EQ(late.err, "edx: error: " + trace +
                          ": the timeline's first frame 100000 is past the trace's last (240 "
                          "frames)\n");
  EXPECT_FALSE(fs::exists(timeline));
  const fs::path config = dir.path() / "dup.yaml";
  std::ofstream(config) << "name: a\nbackend:\n  spm_bytes: 4\n  spm_bytes: 8\n";
  const CommandResult twice = run_command(
      fmt::format("{} simulate --config '{}' --trace '{}'", edx(), config.string(), trace));
  EXPECT_EQ(twice.exit_code, 1);
  EXPECT_EQ(twice.err, "edx: error: " + config.string() +
                           ":4: backend.spm_bytes: written twice (also on "
                           "line 3)\n");
}

TEST(BadValue, SystemModelAndMemoryOptionsAreOneLineErrors) {
  const TempDir dir;
  const std::string trace = fmt::format("{}/tests/data/golden/golden_mix.db", EDX_SOURCE_DIR);
  const CommandResult model = run_command(
      fmt::format("{} simulate --config '{}/configs/edx_car.yaml' --trace '{}' --model fast", edx(),
                  EDX_SOURCE_DIR, trace));
  EXPECT_EQ(model.exit_code, 2);
  EXPECT_EQ(model.err, "edx: --model: fast not in {des,analytical} (see edx --help)\n");
  for (const char* jobs : {"0", "257", "two"}) {
    const CommandResult threads =
        run_command(fmt::format("{} simulate --config '{}/configs/edx_car.yaml' --trace '{}' -j {}",
                                edx(), EDX_SOURCE_DIR, trace, jobs));
    EXPECT_EQ(threads.exit_code, 2) << jobs;
    EXPECT_EQ(threads.err, fmt::format("edx: --jobs: Value {} not in range 1 to 256 (see edx "
                                       "--help)\n",
                                       jobs));
  }
  const fs::path config = dir.path() / "p.yaml";
  std::ofstream(config) << "name: p\nsystem:\n  drop: sometimes\n";
  const CommandResult drop = run_command(
      fmt::format("{} simulate --config '{}' --trace '{}'", edx(), config.string(), trace));
  EXPECT_EQ(drop.exit_code, 1);
  EXPECT_EQ(drop.err, "edx: error: " + config.string() +
                          ":3: system.drop: expected oldest, newest or none, got 'sometimes'\n");
  std::ofstream(config) << "name: p\nfrontend:\n  input_buffering: sram\n";
  const CommandResult buffering = run_command(
      fmt::format("{} simulate --config '{}' --trace '{}'", edx(), config.string(), trace));
  EXPECT_EQ(buffering.exit_code, 1);
  EXPECT_EQ(buffering.err,
            "edx: error: " + config.string() +
                ":3: frontend.input_buffering: expected on_chip_double or dram, got 'sram'\n");
}

TEST(BadValue, CharacterizeAndCheckJobsAreOneLineErrors) {
  const TempDir dir;
  const fs::path out = dir.path() / "c";
  for (const char* jobs : {"0", "257", "two"}) {
    const CommandResult characterize = run_command(fmt::format(
        "{} characterize --seeds 1 --frames 8 --out '{}' -j {}", edx(), out.string(), jobs));
    EXPECT_EQ(characterize.exit_code, 2) << jobs;
    EXPECT_EQ(characterize.err,
              fmt::format("edx: --jobs: Value {} not in range 1 to 256 (see edx --help)\n", jobs));
    const CommandResult check =
        run_command(fmt::format("{} check --config '{}/configs/edx_car.yaml' --trace "
                                "'{}/tests/data/golden/golden_mix.db' --jobs {}",
                                edx(), EDX_SOURCE_DIR, EDX_SOURCE_DIR, jobs));
    EXPECT_EQ(check.exit_code, 2) << jobs;
    EXPECT_EQ(check.err,
              fmt::format("edx: --jobs: Value {} not in range 1 to 256 (see edx --help)\n", jobs));
  }
  EXPECT_FALSE(fs::exists(out));  // nothing traced, nothing written
}

TEST(BadValue, FilesThatAreNotDatabasesAreNamedAndLeftAlone) {
  const TempDir dir;
  const fs::path junk = dir.path() / "junk.db";
  std::ofstream(junk) << "hello\n";
  const fs::path spec = dir.path() / "s.yaml";
  std::ofstream(spec) << "base: " << EDX_SOURCE_DIR
                      << "/configs/edx_car.yaml\ntrace: " << EDX_SOURCE_DIR
                      << "/tests/data/golden/golden_mix.db\n"
                      << "parameters:\n  backend.units.gemm.block: {values: [2, 4]}\n"
                      << "objectives: [{minimize: dsp}]\n";
  const CommandResult sweep =
      run_command(fmt::format("{} sweep '{}' --db '{}'", edx(), spec.string(), junk.string()));
  EXPECT_EQ(sweep.exit_code, 1);
  EXPECT_EQ(sweep.err, "edx: error: " + junk.string() +
                           ": not a readable SQLite database: file is not a database\n");
  const CommandResult exported =
      run_command(fmt::format("{} export '{}' --table runs --out '{}'", edx(), junk.string(),
                              (dir.path() / "x.csv").string()));
  EXPECT_EQ(exported.exit_code, 1);
  EXPECT_EQ(exported.err, "edx: error: " + junk.string() +
                              ": not a readable edx results database: file is not a database\n");
  EXPECT_FALSE(fs::exists(dir.path() / "x.csv"));
  EXPECT_EQ(read_text_file(junk), "hello\n");
}

}  // namespace
}  // namespace edx::testing
