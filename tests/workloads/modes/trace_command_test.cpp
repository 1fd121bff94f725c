// `edx trace` end to end: JSON and text summaries, refusal of an existing output, bad command
// lines (exit 2) and bad input (exit 1, one line, nothing written).
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "tests/support/run_command.hpp"
#include "tests/support/temp_dir.hpp"
#include "workloads/trace/reader.hpp"

namespace edx::modes {
namespace {

namespace fs = std::filesystem;
using edx::testing::built_binary;
using edx::testing::run_command;
using ::testing::HasSubstr;
using ::testing::StartsWith;

const std::string kEuroc = std::string(EDX_SHARED_DATA_DIR) + "/euroc_v101_micro";

std::string trace_command(const std::string& arguments) {
  return built_binary("edx") + " trace " + arguments;
}

long lines(const std::string& text) { return std::count(text.begin(), text.end(), '\n'); }

TEST(TraceCommand, JsonSummaryOnlyOnStdout) {
  const testing::TempDir dir;
  const fs::path out = dir.path() / "t.db";
  const auto r = run_command(trace_command(
      "--dataset " + kEuroc + " --format euroc --frames 3 --out " + out.string() + " --json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);  // throws if anything else is on stdout
  EXPECT_EQ(j.at("frames"), 3);
  EXPECT_EQ(j.at("sequence"), "euroc:euroc_v101_micro");
  EXPECT_EQ(j.at("task_ms").size(), 10u);
  EXPECT_GT(j.at("per_frame").at("stereo_matches").at("mean").get<double>(), 50);
  EXPECT_EQ(trace::TraceReader(out).frame_count(), 3u);
}

TEST(TraceCommand, TextSummaryAndForce) {
  const testing::TempDir dir;
  const fs::path out = dir.path() / "t.db";
  const std::string args = "--dataset " + kEuroc +
                           " --format euroc --frames 2 --features 400 "
                           "--resolution 376x240 --out " +
                           out.string();
  const auto first = run_command(trace_command(args));
  ASSERT_EQ(first.exit_code, 0) << first.err;
  EXPECT_THAT(first.out, HasSubstr("FD/L"));
  EXPECT_THAT(first.out, HasSubstr("376x240"));
  EXPECT_THAT(trace::TraceReader(out).meta().at("pipeline_params"),
              HasSubstr("\"features_per_image\":400"));

  const auto again = run_command(trace_command(args));
  EXPECT_EQ(again.exit_code, 1);
  EXPECT_EQ(lines(again.err), 1) << again.err;
  EXPECT_THAT(again.err, StartsWith("edx: error: "));
  EXPECT_THAT(again.err, HasSubstr("output exists"));
  EXPECT_TRUE(again.out.empty());

  const auto forced = run_command(trace_command(args + " --force"));
  EXPECT_EQ(forced.exit_code, 0) << forced.err;
}

TEST(TraceCommand, AnInterruptedTraceLeavesNothingAndARerunCompletes) {
  // SIGINT (Ctrl-C) and SIGTERM while the trace is written under its temporary name: the process
  // ends by the signal, nothing is left beside the target, and the same command then completes.
  for (const int signal : {SIGINT, SIGTERM}) {
    const testing::TempDir dir;
    const fs::path out = dir.path() / "t.db";
    const std::string command =
        trace_command("--dataset " + kEuroc + " --format euroc --out " + out.string());
    const pid_t child = ::fork();
    if (child == 0) {
      ::execl("/bin/sh", "sh", "-c", ("exec " + command + " >/dev/null 2>&1").c_str(), nullptr);
      ::_exit(127);
    }
    ASSERT_GT(child, 0);
    bool writing = false;  // the temporary trace exists
    for (int i = 0; i < 6000 && !writing; ++i) {
      for (const auto& entry : fs::directory_iterator(dir.path())) {
        writing = writing || entry.path().filename().string().starts_with("t.db.tmp-");
      }
      if (!writing) ::usleep(10'000);
    }
    ASSERT_TRUE(writing) << "the trace never started";
    ::kill(child, signal);
    int status = 0;
    ::waitpid(child, &status, 0);
    ASSERT_TRUE(WIFSIGNALED(status)) << signal;
    EXPECT_EQ(WTERMSIG(status), signal);
    EXPECT_TRUE(testing::entries(dir.path()).empty())
        << signal << ": left " << ::testing::PrintToString(testing::entries(dir.path()));
    const auto rerun = run_command(built_binary("edx") + " trace --dataset " + kEuroc +
                                   " --format euroc --frames 3 --out " + out.string());
    EXPECT_EQ(rerun.exit_code, 0) << rerun.err;
  }
}

TEST(TraceCommand, BadCommandLinesExitTwo) {
  const testing::TempDir dir;
  const std::string out = " --out " + (dir.path() / "t.db").string();
  for (const std::string& args :
       {"--dataset " + kEuroc + " --format tum" + out,
        "--dataset " + kEuroc + " --format euroc --resolution 640by480" + out,
        "--dataset " + kEuroc + " --format euroc --frames 0" + out,
        "--dataset " + kEuroc + " --format euroc", "--format euroc" + out,
        "--dataset " + kEuroc + " --format euroc --scenario underwater" + out}) {
    const auto r = run_command(trace_command(args));
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_EQ(lines(r.err), 1) << args << "\n" << r.err;
  }
  EXPECT_TRUE(testing::entries(dir.path()).empty());
}

TEST(TraceCommand, BadDatasetExitsOneAndWritesNothing) {
  const testing::TempDir dir;
  const auto r =
      run_command(trace_command("--dataset " + (dir.path() / "nothing").string() +
                                " --format kitti --out " + (dir.path() / "t.db").string()));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(lines(r.err), 1) << r.err;
  EXPECT_THAT(r.err, StartsWith("edx: error: "));
  EXPECT_THAT(r.err, HasSubstr("nothing"));
  EXPECT_TRUE(testing::entries(dir.path()).empty());
}

TEST(TraceCommand, HelpListsTheOptions) {
  const auto r = run_command(trace_command("--help"));
  EXPECT_EQ(r.exit_code, 0);
  for (const char* option : {"--dataset", "--format", "--frames", "--resolution", "--out",
                             "--force", "--json", "--scenario", "--features"}) {
    EXPECT_THAT(r.out, HasSubstr(option));
  }
}

}  // namespace
}  // namespace edx::modes
