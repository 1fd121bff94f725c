#pragma once
// Files a process writes under a temporary name before renaming them into place (traces, new
// results databases, atomically written text files) are removed when the process is stopped by
// SIGINT, SIGTERM or SIGHUP before the rename (docs/RELIABILITY.md, "Outputs"): nothing of an
// interrupted run is left beside its target. SIGKILL cannot be caught; what it leaves in a trace
// store is swept at the store's next opening (arch/sweep/sweep_engine.hpp, open_trace_store).
#include <filesystem>

namespace edx::common {

/// Registers `path` for removal on SIGINT, SIGTERM and SIGHUP while the guard lives (also its
/// SQLite companions `-journal`, `-wal`, `-shm`). The handlers are installed at the first guard;
/// after removing the registered files they restore the handler found before and raise the
/// signal again, so the process ends as it would have. The guard itself removes nothing: the
/// writer renames or removes its file as before. At most 64 files are registered at once
/// (more are simply not guarded).
class TemporaryFileGuard {
 public:
  explicit TemporaryFileGuard(const std::filesystem::path& path);
  ~TemporaryFileGuard();
  TemporaryFileGuard(const TemporaryFileGuard&) = delete;
  TemporaryFileGuard& operator=(const TemporaryFileGuard&) = delete;

 private:
  int slot_ = -1;  ///< index in the registry, -1 when it was full
};

}  // namespace edx::common
