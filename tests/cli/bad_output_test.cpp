// Outputs edx must not damage or silently lose (issue 21, classes 2, 3 and 5): special files are
// written in place or refused, never replaced by a regular file; a trace is never written into
// as a results database; output that cannot reach standard output fails the command.
#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "tests/support/run_command.hpp"
#include "tests/support/temp_dir.hpp"

namespace edx::testing {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const fs::path kSource = EDX_SOURCE_DIR;

std::string edx() { return fmt::format("'{}'", built_binary("edx")); }

bool is_character_device(const fs::path& path) {
  return fs::is_character_file(fs::symlink_status(path));
}

TEST(BadOutput, SpecialFilesAreWrittenInPlaceOrRefusedNeverReplaced) {
  const TempDir dir;
  fs::copy_file(kSource / "tests/data/golden/golden_mix.db", dir.path() / "t.db");
  const std::string simulate = edx() + " simulate --config '" +
                               (kSource / "configs/edx_car.yaml").string() + "' --trace '" +
                               (dir.path() / "t.db").string() + "'";
  // A text output (the timeline) goes into the device.
  const CommandResult timeline = run_command(simulate + " --timeline /dev/null");
  EXPECT_EQ(timeline.exit_code, 0) << timeline.err;
  // A database output must be a file: refused, naming it.
  const CommandResult results = run_command(simulate + " --out /dev/null");
  EXPECT_EQ(results.exit_code, 1);
  EXPECT_EQ(results.err,
            "edx: error: /dev/null: not a regular file (a results database is a file; give a "
            "file path)\n");
  const CommandResult trace =
      run_command(edx() + " trace --dataset /nonexistent --format euroc --out /dev/null --force");
  EXPECT_EQ(trace.exit_code, 1);
  EXPECT_EQ(trace.err,
            "edx: error: /dev/null: not a regular file (a trace is a SQLite file; give a file "
            "path)\n");
  EXPECT_TRUE(is_character_device("/dev/null"));
  // A FIFO receives the export in place and stays a FIFO.
  const fs::path fifo = dir.path() / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const fs::path received = dir.path() / "received.csv";
  const CommandResult exported = run_command(
      "(cat '" + fifo.string() + "' > '" + received.string() + "' &) ; " + simulate + " --out '" +
      (dir.path() / "r.db").string() + "' > /dev/null && " + edx() + " export '" +
      (dir.path() / "r.db").string() + "' --table runs --out '" + fifo.string() + "'; sleep 0.3");
  EXPECT_EQ(exported.exit_code, 0) << exported.err;
  EXPECT_TRUE(fs::is_fifo(fs::symlink_status(fifo)));
  EXPECT_THAT(read_text_file(received), HasSubstr("run_id"));
}

TEST(BadOutput, ATraceIsNeverWrittenIntoAsAResultsDatabase) {
  const TempDir dir;
  const fs::path trace = dir.path() / "t.db";
  fs::copy_file(kSource / "tests/data/golden/golden_mix.db", trace);
  const std::string before = read_text_file(trace);
  const std::string config = (kSource / "configs/edx_car.yaml").string();
  const CommandResult simulate =
      run_command(edx() + " simulate --config '" + config + "' --trace '" + trace.string() +
                  "' --out '" + trace.string() + "'");
  EXPECT_EQ(simulate.exit_code, 1);
  EXPECT_EQ(simulate.err, "edx: error: " + trace.string() +
                              ": is an edx trace (schema version 4), not a results database\n");
  std::ofstream(dir.path() / "s.yaml")
      << "base: " << config << "\ntrace: t.db\n"
      << "parameters:\n  backend.units.gemm.block: {values: [2, 4]}\n"
      << "objectives: [{minimize: dsp}]\n";
  const CommandResult sweep = run_command(edx() + " sweep '" + (dir.path() / "s.yaml").string() +
                                          "' --db '" + trace.string() + "'");
  EXPECT_EQ(sweep.exit_code, 1);
  EXPECT_THAT(sweep.err, HasSubstr(trace.string() + ": is an edx trace (schema version 4)"));
  EXPECT_EQ(read_text_file(trace), before);  // not a byte changed
  EXPECT_FALSE(fs::exists(trace.string() + "-wal"));
}

TEST(BadOutput, OutputThatCannotReachStandardOutputFailsTheCommand) {
  const TempDir dir;
  fs::copy_file(kSource / "tests/data/golden/golden_mix.db", dir.path() / "t.db");
  for (const std::string& command :
       {edx() + " host-speed --samples 1",
        edx() + " simulate --json --config '" + (kSource / "configs/edx_car.yaml").string() +
            "' --trace '" + (dir.path() / "t.db").string() + "'"}) {
    const CommandResult r = run_command("sh -c \"" + command + " > /dev/full\"");
    EXPECT_EQ(r.exit_code, 1) << command;
    EXPECT_EQ(r.err, "edx: error: standard output: write failed (No space left on device)\n")
        << command;
  }
}

}  // namespace
}  // namespace edx::testing
