#include "common/atomic_file.hpp"

#include <unistd.h>

#include <fstream>
#include <stdexcept>
#include <string>
#include <system_error>

#include "common/temporary_files.hpp"

namespace edx::common {

void write_file_atomically(const std::filesystem::path& path, std::string_view contents) {
  std::error_code status_error;
  const std::filesystem::file_status status = std::filesystem::status(path, status_error);
  if (std::filesystem::is_directory(status)) {
    throw std::runtime_error(path.string() + ": is a directory (expected a file to write)");
  }
  if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status)) {
    // A device or FIFO: write in place (renaming would replace it with a regular file).
    std::ofstream out(path, std::ios::binary);
    if (!out) throw std::runtime_error(path.string() + ": cannot open for writing");
    out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
    out.flush();
    if (!out) throw std::runtime_error(path.string() + ": write failed");
    return;
  }
  std::filesystem::path temporary = path;
  temporary += ".tmp." + std::to_string(::getpid());
  const TemporaryFileGuard guard(temporary);
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) {
      throw std::runtime_error(path.string() + ": cannot open '" + temporary.string() +
                               "' for writing");
    }
    out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
    out.close();
    if (!out) {
      std::error_code ignored;
      std::filesystem::remove(temporary, ignored);
      throw std::runtime_error(path.string() + ": write failed");
    }
  }
  std::error_code error;
  std::filesystem::rename(temporary, path, error);
  if (error) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw std::runtime_error(path.string() +
                             ": cannot rename temporary file into place: " + error.message());
  }
}

void require_regular_output(const std::filesystem::path& path, std::string_view what) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);
  if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status)) {
    throw std::runtime_error(path.string() + ": not a regular file (a " + std::string(what) +
                             " is a file; give a file path)");
  }
}

}  // namespace edx::common
