#pragma once
// A platform from YAML text named "p.yaml", and the one-line error it gives: the host kind tests'
// shared helpers.
#include <stdexcept>
#include <string>

#include "arch/platform/platform.hpp"

namespace edx::arch {

inline Platform parse(const std::string& yaml) { return Platform::parse(yaml, "p.yaml"); }

/// The error of parsing `yaml`, "no error" when it parses.
inline std::string error_of(const std::string& yaml) {
  try {
    parse(yaml);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace edx::arch
