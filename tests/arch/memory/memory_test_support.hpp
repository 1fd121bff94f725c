#pragma once
// The memory kind `bram` for tests that map structures without a platform file.
#include <map>
#include <memory>
#include <string>

#include "arch/memory/on_chip_memory.hpp"

namespace edx::arch {

/// The `bram` kind with `params` (YAML text of its keys, e.g. "{allow_bram18: false}") over its
/// defaults; one instance per text, kept for the test binary's life.
inline const OnChipMemory& bram(const std::string& params = "{}") {
  static std::map<std::string, std::shared_ptr<const OnChipMemory>> made;
  std::shared_ptr<const OnChipMemory>& memory = made[params];
  if (!memory) memory = make_component<OnChipMemory>("bram", params, "memory");
  return *memory;
}

}  // namespace edx::arch
