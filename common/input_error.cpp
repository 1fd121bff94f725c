#include "common/input_error.hpp"

#include <fmt/format.h>

namespace edx {
namespace {

/// "file:line (via): key: message", each part left out when unknown.
std::string one_line(const InputPlace& place, const std::string& key, const std::string& message) {
  std::string text;
  if (place.known()) {
    text = place.file;
    if (place.line > 0) text += fmt::format(":{}", place.line);
    if (!place.via.empty()) text += fmt::format(" ({})", place.via);
    text += ": ";
  }
  if (!key.empty()) text += key + ": ";
  return text + message;
}

}  // namespace

InputError::InputError(InputPlace place, std::string key, std::string message)
    : InputError(std::move(place), std::move(key), std::move(message), {}, std::nullopt) {}

InputError::InputError(InputPlace place, std::string key, std::string message, std::string expected,
                       std::optional<std::string> got)
    : std::runtime_error(one_line(place, key, message)),
      place_(std::move(place)),
      key_(std::move(key)),
      message_(std::move(message)),
      expected_(std::move(expected)),
      got_(std::move(got)) {}

InputError InputError::expected(std::string key, std::string expected,
                                std::optional<std::string> got) {
  std::string message = "expected " + expected;
  if (got) message += fmt::format(", got '{}'", *got);
  return {{}, std::move(key), std::move(message), std::move(expected), std::move(got)};
}

InputError InputError::at(InputPlace place) const {
  return {std::move(place), key_, message_, expected_, got_};
}

InputError InputError::with_key(std::string key) const {
  return {place_, std::move(key), message_, expected_, got_};
}

}  // namespace edx
