#pragma once
// Sizing of a scratchpad memory (SPM; paper Sec. V-C for arbitrary accesses such as MO, and
// Sec. VI-A: "the SPMs need to accommodate the size of the entire input matrices"): a list of
// named regions in one address space of `word_bits`-wide words. Each region starts on a word
// boundary, so it takes ceil(8 * bytes / word_bits) words; the SPM is one structure of
// word_bits x sum(words) (the platform's memory kind maps it onto blocks).
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "arch/memory/bram.hpp"

namespace edx::arch {

struct ScratchpadRegion {
  std::string name;
  std::int64_t bytes = 0;
};

struct ScratchpadSpec {
  std::string name = "spm";
  int word_bits = 64;  ///< one double per word (assumption; the paper does not give the width)
  std::vector<ScratchpadRegion> regions;
  /// Throws std::runtime_error naming the SPM and the bad field or region.
  void validate() const;
  nlohmann::json to_json() const;
};

struct ScratchpadSizing {
  ScratchpadSpec spec;
  std::int64_t bytes = 0;           ///< sum of region bytes
  std::vector<std::int64_t> words;  ///< per region: ceil(8 * bytes / word_bits)
  std::int64_t depth_words = 0;     ///< sum of words
  MemoryStructure structure;        ///< word_bits x depth_words
  nlohmann::json to_json() const;
};

/// Sizes `spec` (validated first).
ScratchpadSizing size_scratchpad(const ScratchpadSpec& spec);

}  // namespace edx::arch
