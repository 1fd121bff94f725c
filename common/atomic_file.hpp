#pragma once
// Writing output files all-or-nothing.
#include <filesystem>
#include <string_view>

namespace edx::common {

/// Writes `contents` to a temporary file beside `path`, flushes it to the disk (fsync) and
/// renames it onto `path`, so readers never see a half-written file, nor a power cut an empty
/// one under the new name. A `path` that exists and is not a regular file (a character device
/// such as /dev/null or /dev/stdout, a FIFO; symbolic links followed) is written in place
/// instead, never replaced; a directory is refused. Throws std::runtime_error naming the file
/// and the system's reason on failure (`r.csv: write failed (No space left on device)`; the
/// temporary is removed).
void write_file_atomically(const std::filesystem::path& path, std::string_view contents);

/// Writes `contents` to `path` in place (created or truncated; not synced): for files inside a
/// folder that is itself renamed into place (a report's plots). Throws std::runtime_error naming
/// the file and the system's reason.
void write_file(const std::filesystem::path& path, std::string_view contents);

/// Flushes the regular file `path` to the disk (fsync), before it is renamed into place; throws
/// std::runtime_error naming `name` (the target the caller writes) and the system's reason.
void sync_file(const std::filesystem::path& path, const std::filesystem::path& name);

/// Refuses (std::runtime_error naming it) an output path that exists and is not a regular file,
/// for outputs that must be files (SQLite databases): "x: not a regular file (a <what> is a
/// file)".
void require_regular_output(const std::filesystem::path& path, std::string_view what);

}  // namespace edx::common
