// An LD_PRELOAD library that makes writes, syncs and renames fail as a full or broken disk would
// (issue 45, point 6; docs/RELIABILITY.md, "I/O faults"). It wraps the libc entry points edx and
// the libraries it uses reach through the dynamic linker: write, pwrite, pwrite64 and writev
// (std::ofstream, SQLite's pager and journal), fsync and fdatasync (SQLite's commits), rename,
// renameat, renameat2, link and linkat (std::filesystem's renames and hard links into place). Calls
// made inside libc itself (stdio's fwrite) do not pass through the dynamic linker and are not seen.
//
// Environment (read once, when the library is loaded):
//   EDX_FAULT_PATH=DIR     only files under DIR (the path of /proc/self/fd/FD, or a rename's or
//                          link's either argument) are counted or failed; unset: nothing is.
//   EDX_FAULT_OPS=LIST     the operation classes that fail, comma-separated: write (write, pwrite,
//                          pwrite64, writev), fsync (fsync, fdatasync), rename (rename, renameat,
//                          renameat2, link, linkat); unset or empty: none fail, the calls are only
//                          counted.
//   EDX_FAULT_BYTES=N      writes: the write that would take the bytes written so far past N
//                          writes up to N (a short write, as a filling disk does) and the next
//                          write fails; a write starting at N fails. Default: never.
//   EDX_FAULT_CALL=K       fsync, rename: the K-th call (1-based, per class) fails. Default: never.
//   EDX_FAULT_ERRNO=E      ENOSPC (default), EIO or EDQUOT, or a number.
//   EDX_FAULT_REPORT=FILE  one line is appended to FILE at the first fault of a process
//                          ("fault pid=P op=OP errno=E path=PATH") and one at its exit
//                          ("exit pid=P bytes=B writes=W fsyncs=S renames=R faults=F"); unset:
//                          the same lines go to standard error.
//
// A fault is sticky: once one fired, every later call of a failing class on a matching file
// fails with the same errno (a full disk stays full, a broken one stays broken), so the code
// that runs after the first failure (rollbacks, removals of temporaries) runs on the same disk.
// Removing files (unlink, rmdir) is never failed: that is how a full disk is cleaned up.
#include <dlfcn.h>
#include <fcntl.h>
#include <pthread.h>
#include <sys/syscall.h>
#include <sys/uio.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace {

enum Class { kWrite = 1, kFsync = 2, kRename = 4 };

struct State {
  std::string root;  ///< EDX_FAULT_PATH, canonical, without a trailing '/'
  int failing = 0;   ///< Class bits of EDX_FAULT_OPS
  unsigned long long byte_limit = ~0ull;
  unsigned long long call_limit = ~0ull;
  int error = ENOSPC;
  std::string report;
  // Counts over matching files.
  unsigned long long bytes = 0, writes = 0, fsyncs = 0, renames = 0, faults = 0;
  bool fired = false;
};

State* state = nullptr;
pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
pthread_once_t once = PTHREAD_ONCE_INIT;

template <typename F>
F next(const char* name) {
  return reinterpret_cast<F>(dlsym(RTLD_NEXT, name));
}

/// libc's own entry points, resolved when the library is loaded (before any thread or fork of
/// the process): a wrapper called in the child of a multi-threaded fork (mpirun starting its
/// ranks) must take neither the dynamic linker's lock (dlsym) nor a static's guard, which another
/// thread of the parent may have held at the fork. A call before the load (another library's
/// constructor) resolves its entry itself.
struct Real {
  ssize_t (*write)(int, const void*, size_t) = nullptr;
  ssize_t (*pwrite)(int, const void*, size_t, off_t) = nullptr;
  ssize_t (*pwrite64)(int, const void*, size_t, off64_t) = nullptr;
  ssize_t (*writev)(int, const struct iovec*, int) = nullptr;
  int (*fsync)(int) = nullptr;
  int (*fdatasync)(int) = nullptr;
  int (*rename)(const char*, const char*) = nullptr;
  int (*renameat)(int, const char*, int, const char*) = nullptr;
  int (*renameat2)(int, const char*, int, const char*, unsigned) = nullptr;
  int (*link)(const char*, const char*) = nullptr;
  int (*linkat)(int, const char*, int, const char*, int) = nullptr;
};
Real real;

/// Set while this thread runs a wrapper's own code. A signal handler that writes (OpenMPI's and
/// libevent's handlers write to a pipe; mpirun catches SIGCHLD as its ranks end) and interrupts a
/// wrapper of its thread goes straight to libc: it must not wait for the lock its own thread
/// holds, nor allocate while the thread may be inside malloc (mpirun hung so once, 2026-11-29).
__attribute__((tls_model("initial-exec"))) thread_local bool inside = false;

/// Marks the wrapper's code of this thread (see `inside`).
struct Inside {
  Inside() { inside = true; }
  ~Inside() { inside = false; }
  Inside(const Inside&) = delete;
  Inside& operator=(const Inside&) = delete;
};

template <typename F>
F resolved(F& slot, const char* name) {
  if (!slot) slot = next<F>(name);
  return slot;
}

int parse_errno(const char* text) {
  if (!text || !*text || std::strcmp(text, "ENOSPC") == 0) return ENOSPC;
  if (std::strcmp(text, "EIO") == 0) return EIO;
  if (std::strcmp(text, "EDQUOT") == 0) return EDQUOT;
  const int value = std::atoi(text);
  return value > 0 ? value : ENOSPC;
}

void init() {
  state = new State;
  if (const char* root = std::getenv("EDX_FAULT_PATH"); root && *root) {
    char resolved[4096];
    state->root = ::realpath(root, resolved) ? resolved : root;
    while (state->root.size() > 1 && state->root.back() == '/') state->root.pop_back();
  }
  if (const char* ops = std::getenv("EDX_FAULT_OPS")) {
    const std::string list = std::string(",") + ops + ",";
    if (list.find(",write,") != std::string::npos) state->failing |= kWrite;
    if (list.find(",fsync,") != std::string::npos) state->failing |= kFsync;
    if (list.find(",rename,") != std::string::npos) state->failing |= kRename;
  }
  if (const char* n = std::getenv("EDX_FAULT_BYTES"); n && *n) {
    state->byte_limit = std::strtoull(n, nullptr, 10);
  }
  if (const char* k = std::getenv("EDX_FAULT_CALL"); k && *k) {
    state->call_limit = std::strtoull(k, nullptr, 10);
  }
  state->error = parse_errno(std::getenv("EDX_FAULT_ERRNO"));
  if (const char* report = std::getenv("EDX_FAULT_REPORT")) state->report = report;
}

State& get() {
  pthread_once(&once, init);
  return *state;
}

/// At load: the environment read and libc's entry points resolved while the process has one
/// thread, and `lock` held across fork (taken before, released after in parent and child), so
/// that a child never starts with the lock another thread held (a write of the child would wait
/// for it forever: the clean MPI sweep's one hang, 2026-11-29).
__attribute__((constructor)) void load() {
  get();
  resolved(real.write, "write");
  resolved(real.pwrite, "pwrite");
  resolved(real.pwrite64, "pwrite64");
  resolved(real.writev, "writev");
  resolved(real.fsync, "fsync");
  resolved(real.fdatasync, "fdatasync");
  resolved(real.rename, "rename");
  resolved(real.renameat, "renameat");
  resolved(real.renameat2, "renameat2");
  resolved(real.link, "link");
  resolved(real.linkat, "linkat");
  pthread_atfork([] { pthread_mutex_lock(&lock); }, [] { pthread_mutex_unlock(&lock); },
                 [] { pthread_mutex_unlock(&lock); });
}

/// Appends one line to the report (or stderr), bypassing the wrappers.
void report_line(const char* format, ...) {
  char line[4400];
  va_list args;
  va_start(args, format);
  const int n = std::vsnprintf(line, sizeof line, format, args);
  va_end(args);
  if (n <= 0) return;
  const std::size_t size = std::min<std::size_t>(static_cast<std::size_t>(n), sizeof line - 1);
  State& s = get();
  int fd = STDERR_FILENO;
  if (!s.report.empty()) {
    fd = ::open(s.report.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) return;
  }
  const long ignored = ::syscall(SYS_write, fd, line, size);
  (void)ignored;
  if (fd != STDERR_FILENO) ::close(fd);
}

bool under_root(const State& s, const std::string& path) {
  if (s.root.empty()) return false;
  return path.size() > s.root.size() && path.compare(0, s.root.size(), s.root) == 0 &&
         (path[s.root.size()] == '/' || s.root == "/");
}

std::string fd_path(int fd) {
  char link[64], target[4096];
  std::snprintf(link, sizeof link, "/proc/self/fd/%d", fd);
  const ssize_t n = ::readlink(link, target, sizeof target - 1);
  return n > 0 ? std::string(target, static_cast<std::size_t>(n)) : std::string();
}

/// `path` made absolute against `dirfd` (AT_FDCWD: the working directory), lexically.
std::string absolute(int dirfd, const char* path) {
  if (!path) return {};
  if (path[0] == '/') return path;
  std::string base;
  if (dirfd == AT_FDCWD) {
    char cwd[4096];
    if (::getcwd(cwd, sizeof cwd)) base = cwd;
  } else {
    base = fd_path(dirfd);
  }
  std::string p = path;
  while (p.starts_with("./")) p.erase(0, 2);
  return base + "/" + p;
}

void fire(State& s, const char* op, const std::string& path) {
  ++s.faults;
  if (!s.fired) {
    s.fired = true;
    report_line("fault pid=%d op=%s errno=%s path=%s\n", static_cast<int>(::getpid()), op,
                std::strerror(s.error), path.c_str());
  }
}

/// Decides a write of `size` bytes to `fd`: returns how many bytes may be written (size: all;
/// fewer: a short write; 0 with `fail` set: the call fails). Counts nothing yet.
std::size_t allowed(State& s, int fd, std::size_t size, bool& matching, bool& fail,
                    std::string& path) {
  fail = false;
  path = fd_path(fd);
  matching = under_root(s, path);
  if (!matching || !(s.failing & kWrite) || size == 0) return size;
  if (s.fired || s.bytes >= s.byte_limit) {
    fail = true;
    return 0;
  }
  const unsigned long long room = s.byte_limit - s.bytes;
  return size > room ? static_cast<std::size_t>(room) : size;
}

/// The common body of the write wrappers: `call(n)` writes the first n bytes.
template <typename Call>
ssize_t guarded_write(const char* op, int fd, std::size_t size, Call call) {
  if (inside) return call(size);
  const Inside mark;
  State& s = get();
  pthread_mutex_lock(&lock);
  bool matching = false, fail = false;
  std::string path;
  const std::size_t n = allowed(s, fd, size, matching, fail, path);
  if (fail) {
    fire(s, op, path);
    pthread_mutex_unlock(&lock);
    errno = s.error;
    return -1;
  }
  pthread_mutex_unlock(&lock);
  const ssize_t written = call(n);
  if (matching && written > 0) {
    pthread_mutex_lock(&lock);
    s.bytes += static_cast<unsigned long long>(written);
    ++s.writes;
    pthread_mutex_unlock(&lock);
  }
  return written;
}

/// fsync and rename classes: counts a matching call, returns true when it is to fail.
bool call_fails(int bit, const char* op, const std::string& path_a, const std::string& path_b) {
  State& s = get();
  pthread_mutex_lock(&lock);
  const bool matching = under_root(s, path_a) || under_root(s, path_b);
  bool fail = false;
  if (matching) {
    unsigned long long& count = bit == kFsync ? s.fsyncs : s.renames;
    ++count;
    if (s.failing & bit) {
      fail = s.fired || count >= s.call_limit;
      if (fail) fire(s, op, under_root(s, path_a) ? path_a : path_b);
    }
  }
  pthread_mutex_unlock(&lock);
  if (fail) errno = s.error;
  return fail;
}

__attribute__((destructor)) void report_exit() {
  if (!state) return;
  State& s = *state;
  if (s.root.empty()) return;
  report_line("exit pid=%d bytes=%llu writes=%llu fsyncs=%llu renames=%llu faults=%llu\n",
              static_cast<int>(::getpid()), s.bytes, s.writes, s.fsyncs, s.renames, s.faults);
}

}  // namespace

extern "C" {

ssize_t write(int fd, const void* buffer, size_t size) {
  const auto call = resolved(real.write, "write");
  return guarded_write("write", fd, size, [&](std::size_t n) { return call(fd, buffer, n); });
}

ssize_t pwrite(int fd, const void* buffer, size_t size, off_t offset) {
  const auto call = resolved(real.pwrite, "pwrite");
  return guarded_write("pwrite", fd, size,
                       [&](std::size_t n) { return call(fd, buffer, n, offset); });
}

ssize_t pwrite64(int fd, const void* buffer, size_t size, off64_t offset) {
  const auto call = resolved(real.pwrite64, "pwrite64");
  return guarded_write("pwrite64", fd, size,
                       [&](std::size_t n) { return call(fd, buffer, n, offset); });
}

ssize_t writev(int fd, const struct iovec* iov, int count) {
  const auto call = resolved(real.writev, "writev");
  std::size_t size = 0;
  for (int i = 0; i < count; ++i) size += iov[i].iov_len;
  return guarded_write("writev", fd, size, [&](std::size_t n) -> ssize_t {
    if (n == size) return call(fd, iov, count);
    // A short write: the leading n bytes of the vector.
    struct iovec part[64];
    int parts = 0;
    for (int i = 0; i < count && n > 0 && parts < 64; ++i, ++parts) {
      part[parts] = iov[i];
      if (part[parts].iov_len > n) part[parts].iov_len = n;
      n -= part[parts].iov_len;
    }
    return call(fd, part, parts);
  });
}

int fsync(int fd) {
  const auto call = resolved(real.fsync, "fsync");
  if (inside) return call(fd);
  const Inside mark;
  const std::string path = fd_path(fd);
  if (call_fails(kFsync, "fsync", path, {})) return -1;
  return call(fd);
}

int fdatasync(int fd) {
  const auto call = resolved(real.fdatasync, "fdatasync");
  if (inside) return call(fd);
  const Inside mark;
  const std::string path = fd_path(fd);
  if (call_fails(kFsync, "fdatasync", path, {})) return -1;
  return call(fd);
}

int rename(const char* from, const char* to) {
  const auto call = resolved(real.rename, "rename");
  if (inside) return call(from, to);
  const Inside mark;
  if (call_fails(kRename, "rename", absolute(AT_FDCWD, from), absolute(AT_FDCWD, to))) return -1;
  return call(from, to);
}

int renameat(int from_dir, const char* from, int to_dir, const char* to) {
  const auto call = resolved(real.renameat, "renameat");
  if (inside) return call(from_dir, from, to_dir, to);
  const Inside mark;
  if (call_fails(kRename, "renameat", absolute(from_dir, from), absolute(to_dir, to))) return -1;
  return call(from_dir, from, to_dir, to);
}

int renameat2(int from_dir, const char* from, int to_dir, const char* to, unsigned flags) {
  const auto call = resolved(real.renameat2, "renameat2");
  if (inside) return call(from_dir, from, to_dir, to, flags);
  const Inside mark;
  if (call_fails(kRename, "renameat2", absolute(from_dir, from), absolute(to_dir, to))) return -1;
  return call(from_dir, from, to_dir, to, flags);
}

int link(const char* from, const char* to) {
  const auto call = resolved(real.link, "link");
  if (inside) return call(from, to);
  const Inside mark;
  if (call_fails(kRename, "link", absolute(AT_FDCWD, from), absolute(AT_FDCWD, to))) return -1;
  return call(from, to);
}

int linkat(int from_dir, const char* from, int to_dir, const char* to, int flags) {
  const auto call = resolved(real.linkat, "linkat");
  if (inside) return call(from_dir, from, to_dir, to, flags);
  const Inside mark;
  if (call_fails(kRename, "linkat", absolute(from_dir, from), absolute(to_dir, to))) return -1;
  return call(from_dir, from, to_dir, to, flags);
}

}  // extern "C"
