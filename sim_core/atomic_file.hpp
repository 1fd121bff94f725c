#pragma once
// Writing output files all-or-nothing.
#include <filesystem>
#include <string_view>

namespace edx::sim {

/// Writes `contents` to a temporary file beside `path` and renames it onto `path`, so readers
/// never see a half-written file. Throws std::runtime_error naming the file on failure (the
/// temporary is removed).
void write_file_atomically(const std::filesystem::path& path, std::string_view contents);

}  // namespace edx::sim
