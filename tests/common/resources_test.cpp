// Finding edx's own files (common/resources.hpp): a binary of the build tree reads the source
// tree, EDX_DATA_DIR overrides, and a missing file is one error naming what and where. The
// installed layout is tested end to end by tests/cli/install_test.cpp.
#include "common/resources.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "tests/support/temp_dir.hpp"

namespace edx::common {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

/// Sets or unsets EDX_DATA_DIR for one test and restores it.
class DataDirEnv {
 public:
  explicit DataDirEnv(const char* value) {
    if (const char* old = std::getenv("EDX_DATA_DIR")) {
      old_ = old;
      had_ = true;
    }
    if (value == nullptr) {
      ::unsetenv("EDX_DATA_DIR");
    } else {
      ::setenv("EDX_DATA_DIR", value, 1);
    }
  }
  ~DataDirEnv() {
    if (had_) {
      ::setenv("EDX_DATA_DIR", old_.c_str(), 1);
    } else {
      ::unsetenv("EDX_DATA_DIR");
    }
  }
  DataDirEnv(const DataDirEnv&) = delete;
  DataDirEnv& operator=(const DataDirEnv&) = delete;

 private:
  std::string old_;
  bool had_ = false;
};

TEST(Resources, ABinaryOfTheBuildTreeReadsTheSourceTree) {
  const DataDirEnv env(nullptr);
  const DataRoot root = data_root();
  EXPECT_EQ(root.path, fs::path(EDX_SOURCE_DIR));
  EXPECT_THAT(root.how, HasSubstr("source tree"));
  EXPECT_EQ(find_resource("reports/paper_targets.yaml"),
            fs::path(EDX_SOURCE_DIR) / "reports" / "paper_targets.yaml");
  EXPECT_TRUE(fs::is_directory(find_resource("configs")));
}

TEST(Resources, EdxDataDirOverridesAndAMissingFileNamesWhatAndWhere) {
  const testing::TempDir dir;
  fs::create_directories(dir.path() / "reports");
  std::ofstream(dir.path() / "reports" / "paper_targets.yaml") << "targets: []\n";
  const DataDirEnv env(dir.path().c_str());
  EXPECT_EQ(data_root().path, dir.path());
  EXPECT_EQ(find_resource("reports/paper_targets.yaml"),
            dir.path() / "reports" / "paper_targets.yaml");
  try {
    find_resource("configs/edx_car.yaml");
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_THAT(message, HasSubstr("configs/edx_car.yaml"));
    EXPECT_THAT(message, HasSubstr((dir.path() / "configs" / "edx_car.yaml").string()));
    EXPECT_THAT(message, HasSubstr("EDX_DATA_DIR"));
    EXPECT_EQ(message.find('\n'), std::string::npos);
  }
}

}  // namespace
}  // namespace edx::common
