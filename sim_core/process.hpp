#pragma once
// Processes as C++20 coroutines.
//
// `Process` (= Task<void>) is the coroutine type of a simulated process; `Task<T>` is the same
// machinery returning a value. Both are lazy: nothing runs until the coroutine is either
//   - spawned:  `ProcessHandle h = sim.spawn(make_worker(...), "worker");` -- the simulator owns
//     it, starts it at the current time and destroys its frame when it finishes; or
//   - awaited:  `co_await transfer(bytes);` / `int n = co_await count_items();` -- it runs as a
//     subroutine of the awaiting coroutine (symmetric transfer, no event queue round trip) and an
//     exception it throws is rethrown at the co_await.
// An exception escaping a spawned process is rethrown by Simulator::run() / run_until().
#include <coroutine>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include "sim_core/wait_list.hpp"

namespace edx::sim {

namespace detail {

/// Book-keeping of one spawned process; owned (and recycled) by its Simulator.
struct ProcessRecord {
  Simulator* sim = nullptr;
  std::coroutine_handle<> frame;  ///< root coroutine frame; null once finished
  std::uint64_t id = 0;           ///< unique spawn number (1, 2, ...); 0 once finished
  std::string name;
  WaitList joiners;  ///< coroutines blocked in `co_await handle`
};

/// Called by a root coroutine at its final suspend point (defined in simulator.cpp).
void finish_process(ProcessRecord* record, std::exception_ptr error,
                    std::coroutine_handle<> frame) noexcept;

/// Coroutine frames (defined in simulator.cpp): a DES run starts and ends a frame per task,
/// transfer and op, so freed frames wait on a free list of this thread per size class
/// (⌈bytes / 64⌉, up to 2 KiB; larger ones go to operator new) for the next frame of their
/// class. A frame may be freed on another thread than the one that made it (it joins that
/// thread's list); the lists are freed when their thread ends.
void* allocate_frame(std::size_t bytes);
void free_frame(void* frame, std::size_t bytes) noexcept;

/// State shared by every edx coroutine promise.
struct PromiseBase {
  std::coroutine_handle<> continuation;  ///< awaiting parent, when run as a subroutine
  ProcessRecord* process = nullptr;      ///< the process this coroutine runs in
  std::exception_ptr exception;          ///< escaped exception, rethrown to parent or run()
  bool is_root = false;                  ///< true for a spawned process

  std::suspend_always initial_suspend() noexcept { return {}; }
  void unhandled_exception() noexcept { exception = std::current_exception(); }

  /// The coroutine's frame, from the thread's free lists (allocate_frame).
  static void* operator new(std::size_t bytes) { return allocate_frame(bytes); }
  static void operator delete(void* frame, std::size_t bytes) noexcept { free_frame(frame, bytes); }
};

/// The process a suspending coroutine belongs to (nullptr for foreign coroutine types).
template <class Promise>
ProcessRecord* process_of(std::coroutine_handle<Promise> handle) noexcept {
  if constexpr (std::is_base_of_v<PromiseBase, Promise>) {
    return handle.promise().process;
  } else {
    return nullptr;
  }
}

/// Final suspend: hand control back to the awaiting parent, or retire a spawned process.
struct FinalAwaiter {
  bool await_ready() const noexcept { return false; }
  template <class Promise>
  std::coroutine_handle<> await_suspend(std::coroutine_handle<Promise> handle) const noexcept {
    PromiseBase& promise = handle.promise();
    if (promise.continuation) return promise.continuation;
    if (promise.is_root) finish_process(promise.process, std::move(promise.exception), handle);
    return std::noop_coroutine();
  }
  void await_resume() const noexcept {}
};

template <class T>
class TaskPromise;

}  // namespace detail

/// A lazily started coroutine producing a T (see the top of process.hpp). Move-only; owns its
/// frame until spawned or finished.
template <class T = void>
class [[nodiscard]] Task {
 public:
  using promise_type = detail::TaskPromise<T>;
  using Handle = std::coroutine_handle<promise_type>;

  /// An empty task.
  Task() noexcept = default;
  /// Takes ownership of a coroutine frame (used by the promise).
  explicit Task(Handle handle) noexcept : handle_(handle) {}
  Task(Task&& other) noexcept : handle_(std::exchange(other.handle_, {})) {}
  Task& operator=(Task&& other) noexcept {
    if (this != &other) {
      if (handle_) handle_.destroy();
      handle_ = std::exchange(other.handle_, {});
    }
    return *this;
  }
  Task(const Task&) = delete;
  Task& operator=(const Task&) = delete;
  ~Task() {
    if (handle_) handle_.destroy();
  }

  /// True when the task holds a coroutine.
  bool valid() const noexcept { return static_cast<bool>(handle_); }

  /// Runs the task as a subroutine of the awaiting coroutine; yields its result.
  auto operator co_await() && {
    if (!handle_ || handle_.done()) {
      throw std::logic_error("edx::sim: co_await on an empty or finished Task");
    }
    return Awaiter{handle_};
  }

  /// Gives up ownership of the frame (used by Simulator::spawn).
  Handle release() noexcept { return std::exchange(handle_, {}); }

 private:
  struct Awaiter {
    Handle child;
    bool await_ready() const noexcept { return false; }
    template <class Promise>
    std::coroutine_handle<> await_suspend(std::coroutine_handle<Promise> parent) noexcept {
      child.promise().continuation = parent;
      child.promise().process = detail::process_of(parent);
      return child;
    }
    T await_resume() {
      if (child.promise().exception) std::rethrow_exception(child.promise().exception);
      if constexpr (!std::is_void_v<T>) return std::move(*child.promise().value);
    }
  };

  Handle handle_;
};

/// The coroutine type of a simulated process: `Process worker(Simulator& sim) { ... }`.
using Process = Task<void>;

namespace detail {

template <class T>
class TaskPromise : public PromiseBase {
 public:
  Task<T> get_return_object() noexcept {
    return Task<T>(std::coroutine_handle<TaskPromise>::from_promise(*this));
  }
  FinalAwaiter final_suspend() noexcept { return {}; }
  template <class U>
  void return_value(U&& result) {
    value.emplace(std::forward<U>(result));
  }
  std::optional<T> value;
};

template <>
class TaskPromise<void> : public PromiseBase {
 public:
  Task<void> get_return_object() noexcept {
    return Task<void>(std::coroutine_handle<TaskPromise>::from_promise(*this));
  }
  FinalAwaiter final_suspend() noexcept { return {}; }
  void return_void() noexcept {}
};

}  // namespace detail

/// Awaiter of `co_await handle` / `co_await sim.join(handle)`: resumes once the process ends.
class JoinAwaiter {
 public:
  JoinAwaiter(detail::ProcessRecord* record, std::uint64_t id) noexcept
      : record_(record), id_(id) {}
  bool await_ready() const noexcept { return record_ == nullptr || record_->id != id_; }
  template <class Promise>
  void await_suspend(std::coroutine_handle<Promise> handle) noexcept {
    node_.handle = handle;
    node_.process = detail::process_of(handle);
    record_->joiners.push_back(&node_);
  }
  void await_resume() const noexcept {}

 private:
  detail::ProcessRecord* record_;
  std::uint64_t id_;
  detail::WaiterNode node_;
};

/// A reference to a spawned process, valid for the lifetime of its Simulator. Cheap to copy.
/// `co_await handle` suspends until the process has finished (at once if it already has, or if
/// the handle is empty).
class ProcessHandle {
 public:
  ProcessHandle() noexcept = default;
  ProcessHandle(detail::ProcessRecord* record, std::uint64_t id) noexcept
      : record_(record), id_(id) {}

  /// True once the process has finished (also for an empty handle).
  bool done() const noexcept { return record_ == nullptr || record_->id != id_; }
  /// The spawn number of the process (1 for the first spawned process), 0 for an empty handle.
  std::uint64_t id() const noexcept { return id_; }
  /// Waits for the process to finish.
  JoinAwaiter operator co_await() const noexcept { return JoinAwaiter(record_, id_); }

 private:
  detail::ProcessRecord* record_ = nullptr;
  std::uint64_t id_ = 0;
};

}  // namespace edx::sim
