#pragma once
// Sizing of a FIFO (paper Sec. V-C: "many stencil operations read from a list sequentially, for
// which a FIFO is suitable", e.g. FC reading the points FD detected): N entries of E bytes, one
// memory structure of 8*E bits x N words (the platform's memory kind maps it onto blocks).
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "arch/memory/bram.hpp"

namespace edx::arch {

struct FifoSpec {
  std::string name = "fifo";
  std::int64_t entries = 1;      ///< N
  std::int64_t entry_bytes = 1;  ///< E
  /// Throws std::runtime_error naming the FIFO and the bad field.
  void validate() const;
  nlohmann::json to_json() const;
};

struct FifoSizing {
  FifoSpec spec;
  std::int64_t bytes = 0;     ///< N * E
  MemoryStructure structure;  ///< 8*E bits x N words
  nlohmann::json to_json() const;
};

/// Sizes `spec` (validated first): bytes = N * E; structure 8*E bits x N words.
FifoSizing size_fifo(const FifoSpec& spec);

}  // namespace edx::arch
