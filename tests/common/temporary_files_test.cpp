// Temporary files are removed when a signal stops the process (common/temporary_files.hpp): in a
// forked child that registers files and then raises the signal.
#include "common/temporary_files.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <fstream>
#include <optional>

#include "tests/support/temp_dir.hpp"

namespace edx::common {
namespace {

namespace fs = std::filesystem;

/// Runs `body` in a forked child and returns the signal that ended it (nullopt if it exited).
template <typename Body>
std::optional<int> signal_ending(Body body) {
  const pid_t child = ::fork();
  if (child == 0) {
    body();
    ::_exit(0);
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  if (WIFSIGNALED(status)) return WTERMSIG(status);
  return std::nullopt;
}

TEST(TemporaryFiles, ASignalRemovesTheGuardedFilesAndEndsTheProcessAsItWould) {
  for (const int signal : {SIGINT, SIGTERM, SIGHUP}) {
    const testing::TempDir dir;
    const fs::path guarded = dir.path() / "t.db.tmp-1";
    const fs::path released = dir.path() / "done.tmp";
    const fs::path other = dir.path() / "other.txt";
    const auto ended = signal_ending([&] {
      { const TemporaryFileGuard finished(released); }  // renamed into place: no longer guarded
      const TemporaryFileGuard guard(guarded);
      for (const fs::path& p :
           {guarded, fs::path(guarded.string() + "-journal"), released, other}) {
        std::ofstream(p) << "partial";
      }
      ::raise(signal);
    });
    EXPECT_EQ(ended, signal);
    EXPECT_FALSE(fs::exists(guarded)) << signal;
    EXPECT_FALSE(fs::exists(guarded.string() + "-journal")) << signal;
    EXPECT_TRUE(fs::exists(released)) << signal;
    EXPECT_TRUE(fs::exists(other)) << signal;
  }
}

TEST(TemporaryFiles, AnIgnoredSignalStaysIgnored) {
  const testing::TempDir dir;
  const fs::path guarded = dir.path() / "kept.tmp";
  const auto ended = signal_ending([&] {
    ::signal(SIGHUP, SIG_IGN);  // as under nohup
    const TemporaryFileGuard guard(guarded);
    std::ofstream(guarded) << "partial";
    ::raise(SIGHUP);
  });
  EXPECT_EQ(ended, std::nullopt);
  EXPECT_TRUE(fs::exists(guarded));
}

}  // namespace
}  // namespace edx::common
