#pragma once
// The progress bar of long subcommands, on stderr so that stdout stays machine-readable:
// a bar redrawn in place on a terminal, otherwise one line per quarter of the work.
#include <fmt/core.h>
#include <unistd.h>

#include <cstdio>
#include <string>
#include <string_view>

namespace edx::cli {

class ProgressBar {
 public:
  /// `command` names the subcommand in the line, e.g. "trace".
  explicit ProgressBar(std::string command)
      : command_(std::move(command)), tty_(::isatty(STDERR_FILENO) == 1) {}

  /// Reports `done` of `total` `unit` (e.g. "frames"), with an optional label such as a run name.
  void update(std::size_t done, std::size_t total, std::string_view unit,
              std::string_view label = {}) {
    if (total == 0) return;
    constexpr std::size_t kWidth = 30;
    const std::string prefix = label.empty() ? std::string() : std::string(label) + " ";
    if (tty_) {
      const std::size_t filled = kWidth * done / total;
      fmt::print(stderr, "\redx {}: {}[{}{}] {}/{} {}", command_, prefix, std::string(filled, '#'),
                 std::string(kWidth - filled, ' '), done, total, unit);
      if (done == total) fmt::print(stderr, "\n");
    } else if (done == total || (4 * done) / total != (4 * (done - 1)) / total) {
      fmt::print(stderr, "edx {}: {}{}/{} {}\n", command_, prefix, done, total, unit);
    }
    std::fflush(stderr);
  }

  /// A line of its own (e.g. an event between updates), on a terminal below the bar.
  void note(std::string_view text) {
    fmt::print(stderr, "{}edx {}: {}\n", tty_ ? "\r\033[K" : "", command_, text);
    std::fflush(stderr);
  }

 private:
  std::string command_;
  bool tty_;
};

}  // namespace edx::cli
