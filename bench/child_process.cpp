#include "bench/child_process.hpp"

#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <exception>
#include <stdexcept>

namespace edx::bench {
namespace {

constexpr char kOk = 'O';
constexpr char kFailed = 'E';

void write_all(int fd, const std::string& bytes) {
  std::size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + written, bytes.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;  // the parent reports the short message
    written += static_cast<std::size_t>(n);
  }
}

std::string read_all(int fd) {
  std::string bytes;
  char buffer[4096];
  for (;;) {
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    bytes.append(buffer, static_cast<std::size_t>(n));
  }
  return bytes;
}

[[noreturn]] void run_child(pid_t parent, int write_fd, const std::function<std::string()>& work) {
  // Do not outlive an interrupted benchmark (also if the parent died before prctl took effect).
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (::getppid() != parent) ::_exit(1);
  ::dup2(STDERR_FILENO, STDOUT_FILENO);  // keep the parent's stdout clean
  std::string message;
  try {
    message = kOk + work();
  } catch (const std::exception& e) {
    message = kFailed + std::string(e.what());
  } catch (...) {
    message = kFailed + std::string("unknown exception");
  }
  write_all(write_fd, message);
  ::close(write_fd);
  std::fflush(nullptr);
  ::_exit(0);
}

}  // namespace

std::string run_in_child_process_bytes(const std::string& label,
                                       const std::function<std::string()>& work) {
  int fds[2];
  if (::pipe(fds) != 0) throw std::runtime_error(label + ": cannot create a pipe");
  std::fflush(nullptr);  // nothing buffered may be printed twice
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    throw std::runtime_error(label + ": cannot fork a child process");
  }
  if (pid == 0) {
    ::close(fds[0]);
    run_child(parent, fds[1], work);
  }
  ::close(fds[1]);
  const std::string message = read_all(fds[0]);
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFSIGNALED(status)) {
    throw std::runtime_error(label + ": child process killed by signal " +
                             std::to_string(WTERMSIG(status)));
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || message.empty()) {
    throw std::runtime_error(label + ": child process exited without a result");
  }
  if (message.front() == kFailed) throw std::runtime_error(label + ": " + message.substr(1));
  return message.substr(1);
}

}  // namespace edx::bench
