#include "common/atomic_file.hpp"

#include <fcntl.h>
#include <fmt/core.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
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
  const auto fail = [&](const std::string& what, int error) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw std::runtime_error(fmt::format("{}: {} ({})", path.string(), what, std::strerror(error)));
  };
  // POSIX calls rather than a stream, so that a failure carries the system's reason.
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) fail(fmt::format("cannot open '{}' for writing", temporary.string()), errno);
  for (std::size_t done = 0; done < contents.size();) {
    const ssize_t n = ::write(fd, contents.data() + done, contents.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const int error = errno;
      ::close(fd);
      fail("write failed", error);
    }
    done += static_cast<std::size_t>(n);  // a short write (a filling disk): the rest next
  }
  if (::fsync(fd) != 0) {
    const int error = errno;
    ::close(fd);
    fail("write failed: cannot flush it to the disk", error);
  }
  if (::close(fd) != 0) fail("write failed", errno);
  if (::rename(temporary.c_str(), path.c_str()) != 0) {
    fail("cannot rename temporary file into place", errno);
  }
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
