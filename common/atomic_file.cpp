#include "common/atomic_file.hpp"

#include <fcntl.h>
#include <fmt/core.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <string>
#include <system_error>

#include "common/temporary_files.hpp"

namespace edx::common {
namespace {

/// Writes `contents` to `file` (opened with `flags`), then fsyncs it when `sync`; throws
/// std::runtime_error "<name>: <what> (<the system's reason>)". POSIX calls rather than a
/// stream, so that a failure carries its reason.
void write_contents(const std::filesystem::path& file, int flags, std::string_view contents,
                    bool sync, const std::filesystem::path& name) {
  const auto fail = [&](const std::string& what, int error) {
    throw std::runtime_error(fmt::format("{}: {} ({})", name.string(), what, std::strerror(error)));
  };
  const int fd = ::open(file.c_str(), flags | O_WRONLY | O_CLOEXEC, 0644);
  if (fd < 0) {
    fail(file == name ? std::string("cannot open for writing")
                      : fmt::format("cannot open '{}' for writing", file.string()),
         errno);
  }
  const auto fail_open = [&](const std::string& what) {
    const int error = errno;
    ::close(fd);
    fail(what, error);
  };
  for (std::size_t done = 0; done < contents.size();) {
    const ssize_t n = ::write(fd, contents.data() + done, contents.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) fail_open("write failed");
    done += static_cast<std::size_t>(n);  // a short write (a filling disk): the rest next
  }
  if (sync && ::fsync(fd) != 0) fail_open("write failed: cannot flush it to the disk");
  if (::close(fd) != 0) fail("write failed", errno);
}

}  // namespace

void write_file_atomically(const std::filesystem::path& path, std::string_view contents) {
  std::error_code status_error;
  const std::filesystem::file_status status = std::filesystem::status(path, status_error);
  if (std::filesystem::is_directory(status)) {
    throw std::runtime_error(path.string() + ": is a directory (expected a file to write)");
  }
  if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status)) {
    // A device or FIFO: write in place (renaming would replace it with a regular file).
    write_contents(path, 0, contents, false, path);
    return;
  }
  std::filesystem::path temporary = path;
  temporary += ".tmp." + std::to_string(::getpid());
  const TemporaryFileGuard guard(temporary);
  try {
    write_contents(temporary, O_CREAT | O_TRUNC, contents, true, path);
    if (::rename(temporary.c_str(), path.c_str()) != 0) {
      throw std::runtime_error(fmt::format("{}: cannot rename temporary file into place ({})",
                                           path.string(), std::strerror(errno)));
    }
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw;
  }
}

void write_file(const std::filesystem::path& path, std::string_view contents) {
  write_contents(path, O_CREAT | O_TRUNC, contents, false, path);
}

void sync_file(const std::filesystem::path& path, const std::filesystem::path& name) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0 || ::fsync(fd) != 0) {
    const int error = errno;
    if (fd >= 0) ::close(fd);
    throw std::runtime_error(fmt::format("{}: cannot flush '{}' to the disk ({})", name.string(),
                                         path.string(), std::strerror(error)));
  }
  ::close(fd);
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
