#include "common/resources.hpp"

#include <cstdlib>
#include <stdexcept>
#include <system_error>

// EDX_DATA_FROM_BIN: the data folder relative to the binary's folder ("../share/edx", from
// GNUInstallDirs) or absolute; EDX_BUILD_SOURCE_DIR: the source tree of this build.
#ifndef EDX_DATA_FROM_BIN
#error "EDX_DATA_FROM_BIN must be defined (common/CMakeLists.txt)"
#endif
#ifndef EDX_BUILD_SOURCE_DIR
#error "EDX_BUILD_SOURCE_DIR must be defined (common/CMakeLists.txt)"
#endif

namespace edx::common {
namespace {

namespace fs = std::filesystem;

bool is_folder(const fs::path& path) {
  std::error_code ignored;
  return fs::is_directory(path, ignored);
}

}  // namespace

DataRoot data_root() {
  if (const char* env = std::getenv("EDX_DATA_DIR"); env != nullptr && *env != '\0') {
    return {fs::path(env), "set by EDX_DATA_DIR"};
  }
  std::error_code error;
  const fs::path exe = fs::read_symlink("/proc/self/exe", error);
  fs::path installed;
  if (!error) {
    installed = (exe.parent_path() / EDX_DATA_FROM_BIN).lexically_normal();
    if (is_folder(installed)) return {installed, "installed beside " + exe.string()};
  }
  const fs::path source(EDX_BUILD_SOURCE_DIR);
  if (is_folder(source)) return {source, "the source tree this edx was built from"};
  return {fs::path(), "none, neither " +
                          (installed.empty() ? std::string("<bindir>/") + EDX_DATA_FROM_BIN
                                             : installed.string()) +
                          " nor the source tree " + source.string() + " exists"};
}

fs::path find_resource(const fs::path& relative) {
  const DataRoot root = data_root();
  if (root.path.empty()) {
    throw std::runtime_error("cannot find edx's " + relative.string() +
                             " (data folder: " + root.how + "; set EDX_DATA_DIR)");
  }
  fs::path path = root.path / relative;
  std::error_code ignored;
  if (!fs::exists(path, ignored)) {
    const bool from_env = root.how.find("EDX_DATA_DIR") != std::string::npos;
    throw std::runtime_error("cannot find edx's " + relative.string() + ": no " + path.string() +
                             " (data folder: " + root.how +
                             (from_env ? ")" : "; EDX_DATA_DIR overrides it)"));
  }
  return path;
}

}  // namespace edx::common
