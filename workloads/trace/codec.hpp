#pragma once
// Text encodings of the composite columns, shared by writer and reader.
#include <string>
#include <vector>

#include "workloads/trace/records.hpp"

namespace edx::trace {

/// per_level column: a JSON array of {"level","width","height","pixels","points","iterations"}.
std::string encode_per_level(const std::vector<LevelWork>& levels);
/// Inverse of encode_per_level; throws std::invalid_argument on malformed text.
std::vector<LevelWork> decode_per_level(const std::string& text);

}  // namespace edx::trace
