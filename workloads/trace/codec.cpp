#include "workloads/trace/codec.hpp"

#include <nlohmann/json.hpp>
#include <stdexcept>

namespace edx::trace {

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
