#pragma once
// A bad value in an input file (a platform, a sweep spec, the paper targets, the host cost table,
// a workload's parameters) or in options built in code, as data: the file and line it was
// written on, its dotted key, and what was expected and found. what() is the one line edx
// prints (README: errors name the file, line and key):
//   car.yaml:12: frontend.clock_mhz: expected a number in (0, 1000], got 'fast'
//   car.yaml: frontend.units: expected the 7 tasks' units, got 8        (no line known)
//   vio.max_clones: expected an integer in [3, 200], got '1'           (options built in code)
// Code that knows better where a value came from re-places the error (at()) instead of editing
// its text.
#include <optional>
#include <stdexcept>
#include <string>

namespace edx {

/// Where a value was written: its file ("" unknown), its 1-based line (0 unknown) and, for a
/// value the file does not hold as written, what made it (`via`: "parameters.backend.clock_mhz =
/// 150", a sweep's generated value), printed after the line in parentheses.
struct InputPlace {
  InputPlace() = default;
  InputPlace(std::string file, int line = 0, std::string via = {})
      : file(std::move(file)), line(line), via(std::move(via)) {}

  std::string file;
  int line = 0;
  std::string via;
  bool known() const { return !file.empty(); }
};

class InputError : public std::runtime_error {
 public:
  /// "place: key: message"; an empty key: the file as a whole ("place: message").
  InputError(InputPlace place, std::string key, std::string message);
  /// "key: expected <expected>[, got '<got>']", placed later (at()).
  static InputError expected(std::string key, std::string expected,
                             std::optional<std::string> got = std::nullopt);

  const std::string& file() const { return place_.file; }
  int line() const { return place_.line; }
  const InputPlace& place() const { return place_; }
  const std::string& key() const { return key_; }  ///< dotted: "backend.units.gemm.block"
  /// What is wrong, after "key: ": "expected a number > 0, got '-1'", "unknown key".
  const std::string& message() const { return message_; }
  /// What the key accepts, when that is what the message says ("a number > 0"); else "".
  const std::string& expected() const { return expected_; }
  /// The value found, when the message quotes it.
  const std::optional<std::string>& got() const { return got_; }

  /// The same error at `place`.
  InputError at(InputPlace place) const;
  /// The same error under `key`.
  InputError with_key(std::string key) const;

 private:
  InputError(InputPlace place, std::string key, std::string message, std::string expected,
             std::optional<std::string> got);

  InputPlace place_;
  std::string key_, message_, expected_;
  std::optional<std::string> got_;
};

}  // namespace edx
