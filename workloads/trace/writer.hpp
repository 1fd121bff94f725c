#pragma once
// Writes a trace database. Frames are appended in order inside batched transactions into a
// temporary file next to the target, which is flushed to the disk and renamed onto the target by
// finish(): a trace that was not finished (error, crash, a full disk) leaves nothing behind under
// the target name, nor its temporary. Write errors name the target (`t.db: cannot write the
// trace: database or disk is full`).
#include <SQLiteCpp/Database.h>
#include <SQLiteCpp/Statement.h>

#include <filesystem>
#include <memory>
#include <stdexcept>

#include "common/temporary_files.hpp"
#include "workloads/trace/records.hpp"

namespace edx::trace {

struct TraceWriterOptions {
  bool overwrite = false;  ///< replace an existing file (edx trace --force)
  int frames_per_transaction = 64;
};

class TraceWriter {
 public:
  /// Creates the temporary database; throws std::runtime_error if `path` exists and overwrite
  /// is off, or if `meta` lacks a required key (schema.hpp).
  TraceWriter(std::filesystem::path path, TraceMeta meta, TraceWriterOptions options = {});
  ~TraceWriter();
  /// The output checks of the constructor, for runners to make before any work: an empty path,
  /// an existing path that is not a regular file, an existing file without `overwrite`.
  static void check_output(const std::filesystem::path& path, bool overwrite);
  TraceWriter(const TraceWriter&) = delete;
  TraceWriter& operator=(const TraceWriter&) = delete;

  /// Validates and appends one frame; frame ids must run 0, 1, 2, ...
  void append(const FrameTrace& frame);
  /// Replaces the value of meta `key` (one measured over the run, e.g. host_speed). Before
  /// finish() only; a required key may not be emptied.
  void set_meta(const std::string& key, const std::string& value);
  /// Commits, closes and moves the database onto the target path.
  void finish();
  std::size_t frames_written() const { return frames_written_; }

 private:
  void insert_frame(const FrameTrace& frame);
  /// A SQLite error as one naming the trace.
  std::runtime_error write_error(const std::exception& e) const;
  /// Closes the database and removes the temporary file.
  void discard() noexcept;

  std::filesystem::path path_;
  std::filesystem::path temp_path_;
  /// Removes temp_path_ if a signal stops the process before finish() renames it.
  std::unique_ptr<common::TemporaryFileGuard> temp_guard_;
  TraceWriterOptions options_;
  std::unique_ptr<SQLite::Database> db_;
  std::unique_ptr<SQLite::Statement> insert_frame_, insert_task_, insert_kernel_, insert_op_;
  std::size_t frames_written_ = 0;
  bool in_transaction_ = false;
  bool finished_ = false;
};

}  // namespace edx::trace
