#pragma once
// Runs a shell command for end-to-end tests and captures its exit code, stdout and stderr.
#include <sys/wait.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace edx::testing {

struct CommandResult {
  int exit_code = -1;
  std::string out;  ///< standard output
  std::string err;  ///< standard error
};

inline std::string read_text_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// Runs `command` through /bin/sh with stdout and stderr redirected to temporary files.
inline CommandResult run_command(const std::string& command) {
  namespace fs = std::filesystem;
  const fs::path dir =
      fs::temp_directory_path() / ("edx-cmd-" + std::to_string(::getpid()) + "-" +
                                   std::to_string(reinterpret_cast<std::uintptr_t>(&command)));
  fs::create_directories(dir);
  const fs::path out = dir / "stdout", err = dir / "stderr";
  const std::string full = command + " >" + out.string() + " 2>" + err.string() + " </dev/null";
  const int status = std::system(full.c_str());
  CommandResult result;
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  result.out = read_text_file(out);
  result.err = read_text_file(err);
  fs::remove_all(dir);
  return result;
}

/// Path of a binary built by this project (e.g. "edx").
inline std::string built_binary(const std::string& name) {
  return std::string(EDX_BIN_DIR) + "/" + name;
}

}  // namespace edx::testing
