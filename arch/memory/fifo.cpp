#include "arch/memory/fifo.hpp"

#include <fmt/format.h>

#include <stdexcept>

namespace edx::arch {

void FifoSpec::validate() const {
  if (entries < 1) {
    throw std::runtime_error(
        fmt::format("fifo '{}': entries: expected an integer >= 1, got {}", name, entries));
  }
  if (entry_bytes < 1) {
    throw std::runtime_error(
        fmt::format("fifo '{}': entry_bytes: expected an integer >= 1, got {}", name, entry_bytes));
  }
}

nlohmann::json FifoSpec::to_json() const {
  return {{"name", name}, {"entries", entries}, {"entry_bytes", entry_bytes}};
}

nlohmann::json FifoSizing::to_json() const {
  return {{"spec", spec.to_json()}, {"bytes", bytes}, {"structure", structure.to_json()}};
}

FifoSizing size_fifo(const FifoSpec& spec) {
  spec.validate();
  FifoSizing s;
  s.spec = spec;
  s.bytes = spec.entries * spec.entry_bytes;                                        // N * E
  s.structure = MemoryStructure{spec.name, 8 * spec.entry_bytes, spec.entries, 1};  // 8E x N
  return s;
}

}  // namespace edx::arch
