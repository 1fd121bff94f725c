#pragma once
// Reads a trace database, checking the schema version, the table layout and every row it hands
// over (docs/TRACE.md). Errors are one line: "<file>: <table> row <key>: <what is wrong>".
#include <filesystem>
#include <vector>

#include "workloads/trace/records.hpp"

namespace edx::trace {

class TraceReader {
 public:
  /// Opens read-only and checks version, tables and required metadata.
  explicit TraceReader(std::filesystem::path path);

  const TraceMeta& meta() const { return meta_; }
  std::size_t frame_count() const { return frame_count_; }
  /// The file's schema version (an older readable one is upgraded in memory).
  int schema_version() const { return schema_version_; }
  /// All frames in order with their tasks, kernels and ops, each validated.
  std::vector<FrameTrace> read_all() const;

 private:
  std::filesystem::path path_;
  TraceMeta meta_;
  std::size_t frame_count_ = 0;
  int schema_version_ = 0;
};

}  // namespace edx::trace
