#pragma once
// Writing output files all-or-nothing.
#include <filesystem>
#include <string_view>

namespace edx::common {

/// Writes `contents` to a temporary file beside `path` and renames it onto `path`, so readers
/// never see a half-written file. A `path` that exists and is not a regular file (a character
/// device such as /dev/null or /dev/stdout, a FIFO; symbolic links followed) is written in
/// place instead, never replaced; a directory is refused. Throws std::runtime_error naming the
/// file on failure (the temporary is removed).
void write_file_atomically(const std::filesystem::path& path, std::string_view contents);

/// Refuses (std::runtime_error naming it) an output path that exists and is not a regular file,
/// for outputs that must be files (SQLite databases): "x: not a regular file (a <what> is a
/// file)".
void require_regular_output(const std::filesystem::path& path, std::string_view what);

}  // namespace edx::common
