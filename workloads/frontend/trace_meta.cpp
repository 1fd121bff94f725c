#include "workloads/frontend/trace_meta.hpp"

#include <fmt/core.h>

#include <ctime>
#include <fstream>
#include <thread>

#include "edx_revision.hpp"

// Filled in by workloads/frontend/CMakeLists.txt.
#ifndef EDX_COMPILER_DESCRIPTION
#error "EDX_COMPILER_DESCRIPTION must be defined by the build"
#endif

namespace edx::frontend {

std::string cpu_model(const std::filesystem::path& cpuinfo) {
  std::ifstream in(cpuinfo);
  std::string line;
  for (const char* key : {"model name", "Hardware", "cpu model"}) {
    in.clear();
    in.seekg(0);
    while (std::getline(in, line)) {
      const auto colon = line.find(':');
      if (colon == std::string::npos) continue;
      std::string name = line.substr(0, colon);
      while (!name.empty() && (name.back() == ' ' || name.back() == '\t')) name.pop_back();
      if (name != key) continue;
      std::string value = line.substr(colon + 1);
      const auto first = value.find_first_not_of(" \t");
      if (first == std::string::npos) continue;
      value = value.substr(first);
      while (!value.empty() && (value.back() == ' ' || value.back() == '\r')) value.pop_back();
      if (!value.empty()) return value;
    }
  }
  return "unknown";
}

std::string compiler_description() { return EDX_COMPILER_DESCRIPTION; }

std::string source_revision() { return kSourceRevision; }

std::string iso8601_utc(std::chrono::system_clock::time_point time) {
  const std::time_t t = std::chrono::system_clock::to_time_t(time);
  std::tm utc{};
  gmtime_r(&t, &utc);
  return fmt::format("{:04}-{:02}-{:02}T{:02}:{:02}:{:02}Z", utc.tm_year + 1900, utc.tm_mon + 1,
                     utc.tm_mday, utc.tm_hour, utc.tm_min, utc.tm_sec);
}

trace::TraceMeta host_and_build_meta() {
  trace::TraceMeta meta;
  meta["host_cpu"] = cpu_model();
  meta["host_cores"] = std::to_string(std::thread::hardware_concurrency());
  meta["compiler_flags"] = compiler_description();
  meta["source_revision"] = source_revision();
  meta["created_utc"] = iso8601_utc(std::chrono::system_clock::now());
  return meta;
}

}  // namespace edx::frontend
