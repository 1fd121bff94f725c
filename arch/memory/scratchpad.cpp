#include "arch/memory/scratchpad.hpp"

#include <fmt/format.h>

#include <stdexcept>

namespace edx::arch {

void ScratchpadSpec::validate() const {
  if (word_bits < 1) {
    throw std::runtime_error(fmt::format(
        "scratchpad '{}': word_bits: expected an integer >= 1, got {}", name, word_bits));
  }
  for (std::size_t r = 0; r < regions.size(); ++r) {
    if (regions[r].name.empty()) {
      throw std::runtime_error(
          fmt::format("scratchpad '{}': regions[{}].name: expected a non-empty name", name, r));
    }
    if (regions[r].bytes < 0) {
      throw std::runtime_error(
          fmt::format("scratchpad '{}': region '{}': bytes: expected >= 0, got {}", name,
                      regions[r].name, regions[r].bytes));
    }
  }
}

nlohmann::json ScratchpadSpec::to_json() const {
  nlohmann::json list = nlohmann::json::array();
  for (const ScratchpadRegion& r : regions) list.push_back({{"name", r.name}, {"bytes", r.bytes}});
  return {{"name", name}, {"word_bits", word_bits}, {"regions", list}};
}

nlohmann::json ScratchpadSizing::to_json() const {
  return {{"spec", spec.to_json()},
          {"bytes", bytes},
          {"words", words},
          {"depth_words", depth_words},
          {"structure", structure.to_json()}};
}

ScratchpadSizing size_scratchpad(const ScratchpadSpec& spec) {
  spec.validate();
  ScratchpadSizing s;
  s.spec = spec;
  for (const ScratchpadRegion& r : spec.regions) {
    const std::int64_t words = (8 * r.bytes + spec.word_bits - 1) / spec.word_bits;  // ceil
    s.words.push_back(words);
    s.bytes += r.bytes;
    s.depth_words += words;
  }
  s.structure = MemoryStructure{spec.name, spec.word_bits, s.depth_words, 1};
  return s;
}

}  // namespace edx::arch
