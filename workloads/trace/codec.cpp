#include "workloads/trace/codec.hpp"

#include <cstdint>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string_view>

namespace edx::trace {
namespace {

/// encode_per_level's own text read without a JSON parser: `[]` or `[{...},...]`, each object
/// its six keys in the order nlohmann's dump writes them (sorted), no spaces, every value an
/// integer without leading zeros that fits its field. nullopt for any other text (then the JSON
/// parser reads it): what this accepts is JSON that the parser reads to the same values (a
/// value out of its field's range, "-0", whitespace, another key order all go to the parser).
std::optional<std::vector<LevelWork>> decode_canonical_per_level(std::string_view text) {
  std::size_t at = 0;
  const auto literal = [&](std::string_view expected) {
    if (text.substr(at, expected.size()) != expected) return false;
    at += expected.size();
    return true;
  };
  // An integer in [lo, hi]: an optional '-', then "0" or a nonzero digit and at most 17 more
  // (|value| < 10^18: no overflow).
  const auto integer = [&](std::int64_t lo, std::int64_t hi, std::int64_t& out) {
    const bool negative = at < text.size() && text[at] == '-';
    if (negative) ++at;
    const std::size_t first = at;
    std::int64_t value = 0;
    while (at < text.size() && text[at] >= '0' && text[at] <= '9' && at - first < 18) {
      value = value * 10 + (text[at++] - '0');
    }
    const std::size_t digits = at - first;
    if (digits == 0 || (digits > 1 && text[first] == '0') || (negative && value == 0)) return false;
    if (at < text.size() && text[at] >= '0' && text[at] <= '9') return false;  // 19+ digits
    out = negative ? -value : value;
    return out >= lo && out <= hi;
  };
  constexpr std::int64_t kIntMin = std::numeric_limits<int>::min();
  constexpr std::int64_t kIntMax = std::numeric_limits<int>::max();
  constexpr std::int64_t kMin = std::numeric_limits<std::int64_t>::min();
  constexpr std::int64_t kMax = std::numeric_limits<std::int64_t>::max();
  std::vector<LevelWork> levels;
  if (text == "[]") return levels;
  if (!literal("[")) return std::nullopt;
  for (;;) {
    std::int64_t height = 0, level = 0, width = 0;
    LevelWork w;
    if (!(literal("{\"height\":") && integer(kIntMin, kIntMax, height) &&
          literal(",\"iterations\":") && integer(kMin, kMax, w.iterations) &&
          literal(",\"level\":") && integer(kIntMin, kIntMax, level) && literal(",\"pixels\":") &&
          integer(kMin, kMax, w.pixels) && literal(",\"points\":") &&
          integer(kMin, kMax, w.points) && literal(",\"width\":") &&
          integer(kIntMin, kIntMax, width) && literal("}"))) {
      return std::nullopt;
    }
    w.level = static_cast<int>(level);
    w.width = static_cast<int>(width);
    w.height = static_cast<int>(height);
    levels.push_back(w);
    if (literal("]")) return at == text.size() ? std::optional(std::move(levels)) : std::nullopt;
    if (!literal(",")) return std::nullopt;
  }
}

}  // namespace

std::string encode_per_level(const std::vector<LevelWork>& levels) {
  nlohmann::json array = nlohmann::json::array();
  for (const LevelWork& level : levels) {
    array.push_back({{"level", level.level},
                     {"width", level.width},
                     {"height", level.height},
                     {"pixels", level.pixels},
                     {"points", level.points},
                     {"iterations", level.iterations}});
  }
  return array.dump();
}

std::vector<LevelWork> decode_per_level(const std::string& text) {
  // The writer's text (every trace edx writes) without building a JSON document; the rest
  // through the parser.
  if (auto levels = decode_canonical_per_level(text)) return std::move(*levels);
  const auto array = nlohmann::json::parse(text, nullptr, false);
  if (array.is_discarded() || !array.is_array()) {
    throw std::invalid_argument("per_level is not a JSON array");
  }
  std::vector<LevelWork> levels;
  try {
    for (const auto& entry : array) {
      LevelWork level;
      level.level = entry.at("level").get<int>();
      level.width = entry.at("width").get<int>();
      level.height = entry.at("height").get<int>();
      level.pixels = entry.at("pixels").get<std::int64_t>();
      level.points = entry.at("points").get<std::int64_t>();
      level.iterations = entry.at("iterations").get<std::int64_t>();
      levels.push_back(level);
    }
  } catch (const nlohmann::json::exception& e) {
    throw std::invalid_argument(std::string("per_level entry malformed: ") + e.what());
  }
  return levels;
}

}  // namespace edx::trace
