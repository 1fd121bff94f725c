// Writing files all-or-nothing: the new contents or the old file, never a half-written one; a
// special file (a FIFO, /dev/null) written in place, never replaced; a directory refused.
#include "common/atomic_file.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "tests/support/temp_dir.hpp"

namespace edx::common {
namespace {

namespace fs = std::filesystem;

std::string read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(AtomicFile, WritesAndReplacesAndLeavesNoTemporary) {
  testing::TempDir dir;
  const fs::path file = dir.path() / "out.json";
  write_file_atomically(file, "first");
  EXPECT_EQ(read(file), "first");
  write_file_atomically(file, "second, longer");
  EXPECT_EQ(read(file), "second, longer");
  std::size_t entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir.path())) ++entries;
  EXPECT_EQ(entries, 1u);  // the temporary was renamed onto the file
}

TEST(AtomicFile, SpecialFilesAreWrittenInPlaceDirectoriesRefused) {
  testing::TempDir dir;
  write_file_atomically("/dev/null", "discarded");
  EXPECT_TRUE(fs::is_character_file("/dev/null"));  // still the device
  try {
    write_file_atomically(dir.path(), "x");
    FAIL() << "wrote onto a directory";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("is a directory"), std::string::npos) << e.what();
  }
  const fs::path missing_dir = dir.path() / "no" / "such" / "out.txt";
  EXPECT_THROW(write_file_atomically(missing_dir, "x"), std::runtime_error);
  EXPECT_FALSE(fs::exists(missing_dir));
}

TEST(AtomicFile, AFailedWriteNamesTheFileAndTheReason) {
  // /dev/full fails every write with ENOSPC, as a full disk does (special files are written in
  // place); tests/faults/ fails the temporary's write, sync and rename (IoFaults.QuickSweep).
  for (const auto& write : {write_file_atomically, write_file}) {
    try {
      write("/dev/full", "lost");
      FAIL() << "a write to /dev/full succeeded";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "/dev/full: write failed (No space left on device)");
    }
  }
  testing::TempDir dir;
  const fs::path missing = dir.path() / "no" / "out.csv";
  try {
    write_file(missing, "x");
    FAIL() << "wrote into a missing folder";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              missing.string() + ": cannot open for writing (No such file or directory)");
  }
  write_file(dir.path() / "plain.dat", "1 2\n");
  EXPECT_EQ(read(dir.path() / "plain.dat"), "1 2\n");
}

TEST(AtomicFile, RegularOutputCheckRefusesSpecialFiles) {
  testing::TempDir dir;
  EXPECT_NO_THROW(require_regular_output(dir.path() / "new.db", "results database"));
  const fs::path fifo = dir.path() / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  try {
    require_regular_output(fifo, "results database");
    FAIL() << "accepted a FIFO";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(fifo.string()), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace edx::common
