#pragma once
// The one-line error of a bad input: the message of the std::runtime_error an action throws.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace edx::testing {

/// The message of the std::runtime_error `action` throws ("" and a test failure when none),
/// checked to be one line (docs/RELIABILITY.md: bad input gets a one-line error).
template <typename Action>
std::string error_of(Action action) {
  try {
    action();
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << "not one line: " << message;
    return message;
  }
  ADD_FAILURE() << "no std::runtime_error thrown";
  return "";
}

}  // namespace edx::testing
