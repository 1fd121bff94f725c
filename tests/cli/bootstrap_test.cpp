// The bootstrap script ./edx (issue 20): while it builds, stdout carries nothing but the edx
// command's own output (--json stays clean); stderr tells the build's progress, as one updating
// "[n/N]" line on a terminal or one line otherwise, and nothing when there was nothing to build;
// a failed build shows its log and exits 1. The build is a stub `cmake` (first on PATH) printing
// ninja's lines, the built edx a stub printing its arguments: seconds, no compiler.
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
using ::testing::Not;

void write_executable(const fs::path& path, const std::string& text) {
  std::ofstream(path) << text;
  fs::permissions(path, fs::perms::owner_all, fs::perm_options::add);
}

class Bootstrap : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::create_directories(dir_.path() / "stub");
    fs::create_directories(build() / "bin");
    std::ofstream(build() / "build.ninja") << "";  // configured: ./edx skips cmake -S -B
    // STUB_BUILD: "work" (a few steps), "none" (only the revision header), "fail".
    write_executable(dir_.path() / "stub" / "cmake", R"(#!/bin/sh
echo "[1/4] Source revision"
[ "$STUB_BUILD" = none ] && exit 0
echo "[2/4] Building CXX object cli/CMakeFiles/edx.dir/main.cpp.o"
echo "cli/main.cpp:1:1: warning: a compiler's message"
echo "[3/4] Building CXX object common/CMakeFiles/edx_common.dir/resources.cpp.o"
[ "$STUB_BUILD" = fail ] && { echo "common/resources.cpp:9:1: error: stub failure" >&2; exit 1; }
echo "[4/4] Linking CXX executable bin/edx"
)");
    write_executable(build() / "bin" / "edx", "#!/bin/sh\necho \"{\\\"args\\\": \\\"$*\\\"}\"\n");
  }

  fs::path build() const { return dir_.path() / "build"; }

  /// The environment and command line of ./edx with the stubs.
  std::string edx(const std::string& stub_build, const std::string& args) const {
    return fmt::format(
        "env -u NINJA_STATUS PATH='{}':\"$PATH\" EDX_BUILD_DIR='{}' STUB_BUILD={} '{}/edx' {}",
        (dir_.path() / "stub").string(), build().string(), stub_build, EDX_SOURCE_DIR, args);
  }

  TempDir dir_;
};

TEST_F(Bootstrap, StdoutHoldsOnlyTheCommandsOutputAndStderrOneLineOfProgress) {
  const CommandResult r = run_command(edx("work", "--version --json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, "{\"args\": \"--version --json\"}\n");
  EXPECT_EQ(r.err, fmt::format("edx: building: 4 steps (log: {0}/last-build.log)\nedx: built edx\n",
                               build().string()));
  const std::string log = read_text_file(build() / "last-build.log");
  EXPECT_THAT(log, HasSubstr("warning: a compiler's message"));
  EXPECT_THAT(log, HasSubstr("[4/4] Linking CXX executable bin/edx"));
}

TEST_F(Bootstrap, NothingToBuildSaysNothing) {
  const CommandResult r = run_command(edx("none", "simulate --json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, "{\"args\": \"simulate --json\"}\n");
  EXPECT_EQ(r.err, "");
}

TEST_F(Bootstrap, AFailedBuildShowsItsLogOnStderrAndExitsOne) {
  const CommandResult r = run_command(edx("fail", "--version --json"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.out, "");
  EXPECT_THAT(r.err, HasSubstr("common/resources.cpp:9:1: error: stub failure"));
  EXPECT_THAT(r.err, HasSubstr("warning: a compiler's message"));
  EXPECT_THAT(r.err, HasSubstr(fmt::format("edx: build failed (log: {}/last-build.log)",
                                           build().string())));
}

TEST_F(Bootstrap, OnATerminalProgressIsOneUpdatingLineOnStderr) {
  if (run_command("command -v script").exit_code != 0) GTEST_SKIP() << "no script(1)";
  // script(1) gives ./edx a terminal on stderr; stdout goes to a file.
  const fs::path out = dir_.path() / "out", typescript = dir_.path() / "typescript";
  std::ofstream(dir_.path() / "run.sh")
      << edx("work", "--version --json") << " >'" << out.string() << "'\n";
  const CommandResult r = run_command(fmt::format(
      "script -qec 'sh {}' '{}'", (dir_.path() / "run.sh").string(), typescript.string()));
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_EQ(read_text_file(out), "{\"args\": \"--version --json\"}\n");
  const std::string terminal = read_text_file(typescript);
  EXPECT_THAT(terminal, HasSubstr("\redx: building [2/4] Building CXX object"));
  EXPECT_THAT(terminal, HasSubstr("\redx: building [4/4] Linking CXX executable bin/edx\033[K"));
  EXPECT_THAT(terminal, HasSubstr("\r\033[Kedx: built edx"));
  EXPECT_THAT(terminal, Not(HasSubstr("warning: a compiler's message")));
  EXPECT_THAT(terminal, Not(HasSubstr("args")));
}

}  // namespace
}  // namespace edx::testing
