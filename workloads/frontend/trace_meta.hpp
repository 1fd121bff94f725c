#pragma once
// The trace metadata that describes the host and the build (docs/TRACE.md, meta table):
// host_cpu, host_cores, compiler_flags, source_revision, created_utc.
#include <chrono>
#include <filesystem>
#include <string>

#include "workloads/trace/records.hpp"

namespace edx::frontend {

/// CPU model of the first processor in a /proc/cpuinfo-format file ("model name", or
/// "Hardware" / "cpu model" on CPUs that name themselves so); "unknown" when absent or
/// unreadable.
std::string cpu_model(const std::filesystem::path& cpuinfo = "/proc/cpuinfo");

/// Compiler id, version, flags and build type of this build, e.g.
/// "GNU 12.2.0 -O3 -DNDEBUG -Wall -Wextra -Werror -std=c++20 (Release)".
std::string compiler_description();

/// `git describe` of the source this binary was built from (configure time).
std::string source_revision();

/// ISO 8601 UTC time with seconds, e.g. "2024-05-01T12:00:00Z".
std::string iso8601_utc(std::chrono::system_clock::time_point time);

/// host_cpu, host_cores, compiler_flags, source_revision and created_utc (now).
trace::TraceMeta host_and_build_meta();

}  // namespace edx::frontend
