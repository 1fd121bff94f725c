#pragma once
// Runs one piece of benchmark work in a forked child process and brings its result back through
// a pipe. Used where a library allows a single run per process (SystemC elaborates and simulates
// once) and to give every measured run a fresh heap. Anything the child prints goes to stderr,
// so the parent's stdout stays machine readable.
#include <cstring>
#include <functional>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace edx::bench {

/// Runs `work` in a child process and returns the bytes it produced. Throws std::runtime_error
/// with the child's message if `work` threw, or if the child crashed or exited abnormally.
std::string run_in_child_process_bytes(const std::string& label,
                                       const std::function<std::string()>& work);

/// Typed wrapper for trivially copyable results.
template <typename Result>
Result run_in_child_process(const std::string& label, const std::function<Result()>& work) {
  static_assert(std::is_trivially_copyable_v<Result>);
  const std::string bytes = run_in_child_process_bytes(label, [&] {
    const Result result = work();
    return std::string(reinterpret_cast<const char*>(&result), sizeof(Result));
  });
  if (bytes.size() != sizeof(Result)) {
    throw std::runtime_error(label + ": child process sent a truncated result");
  }
  Result result;
  std::memcpy(&result, bytes.data(), sizeof(Result));
  return result;
}

}  // namespace edx::bench
