#include "common/temporary_files.hpp"

#include <unistd.h>

#include <array>
#include <atomic>
#include <csignal>
#include <cstring>
#include <mutex>
#include <string>

namespace edx::common {
namespace {

constexpr std::size_t kSlots = 64;
constexpr std::array<int, 3> kSignals = {SIGINT, SIGTERM, SIGHUP};
constexpr std::array<const char*, 4> kSuffixes = {"", "-journal", "-wal", "-shm"};

constexpr std::size_t kPathBytes = 4096;

/// The registered paths, read by the signal handler: fixed buffers and lock-free atomics, so the
/// handler does only async-signal-safe work (loads, copies, unlink(2)). A slot is free (0),
/// being written (1) or holds a path (2); the last byte of a buffer is never written, so a path
/// read while its slot is reused is still terminated.
struct Slot {
  std::atomic<int> state{0};
  char path[kPathBytes] = {};
};
std::array<Slot, kSlots> registered;
std::array<struct sigaction, kSignals.size()> previous{};

/// Unlinks every registered file and its companions, then ends the process as the signal
/// would have without this handler.
void on_signal(int signal) {
  char name[kPathBytes + 16];
  for (Slot& slot : registered) {
    if (slot.state.load() != 2) continue;
    const std::size_t length = ::strnlen(slot.path, kPathBytes - 1);
    for (const char* suffix : kSuffixes) {
      std::memcpy(name, slot.path, length);
      std::memcpy(name + length, suffix, std::strlen(suffix) + 1);
      ::unlink(name);
    }
  }
  for (std::size_t i = 0; i < kSignals.size(); ++i) {
    if (kSignals[i] == signal) ::sigaction(signal, &previous[i], nullptr);
  }
  ::raise(signal);
}

void install_handlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    for (std::size_t i = 0; i < kSignals.size(); ++i) {
      struct sigaction action = {};
      action.sa_handler = on_signal;
      ::sigemptyset(&action.sa_mask);
      ::sigaction(kSignals[i], &action, &previous[i]);
      // A signal the process was started to ignore (nohup) stays ignored.
      if (previous[i].sa_handler == SIG_IGN) ::sigaction(kSignals[i], &previous[i], nullptr);
    }
  });
}

}  // namespace

TemporaryFileGuard::TemporaryFileGuard(const std::filesystem::path& path) {
  install_handlers();
  const std::string& text = path.native();
  if (text.size() >= kPathBytes) return;
  for (std::size_t i = 0; i < kSlots; ++i) {
    int expected = 0;
    if (!registered[i].state.compare_exchange_strong(expected, 1)) continue;
    std::memcpy(registered[i].path, text.c_str(), text.size() + 1);
    registered[i].state.store(2);
    slot_ = static_cast<int>(i);
    return;
  }
}

TemporaryFileGuard::~TemporaryFileGuard() {
  if (slot_ >= 0) registered[static_cast<std::size_t>(slot_)].state.store(0);
}

}  // namespace edx::common
