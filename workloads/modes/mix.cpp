#include "workloads/modes/mix.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <map>
#include <optional>
#include <stdexcept>
#include <tuple>
#include <utility>

namespace edx::modes {

int MixPlan::total_frames() const {
  int total = 0;
  for (const MixSegment& s : segments) total += s.frames;
  return total;
}

std::string MixPlan::to_string() const {
  std::string text = fmt::format("mix {} at {}x{}, seed {}: {} frames\n", name, resolution.width,
                                 resolution.height, seed, total_frames());
  for (const MixSegment& s : segments) {
    text += fmt::format("  {:<11} {:>5} frames  {} ({}{})\n", s.name, s.frames,
                        trace::to_string(s.scenario), synthetic::to_string(s.world_scenario),
                        s.run.empty() ? "" : ", " + s.run + " run");
  }
  return text;
}

std::vector<std::string> mix_names() {
  return {"paper", "outdoor", "indoor_unknown", "indoor_known"};
}

MixPlan make_mix(std::string_view name, int frames, synthetic::Resolution resolution,
                 std::uint64_t seed, std::optional<int> map_frames) {
  const std::vector<std::string> names = mix_names();
  if (std::find(names.begin(), names.end(), name) == names.end()) {
    throw std::runtime_error(
        fmt::format("unknown mix '{}' (expected one of: {})", name, fmt::join(names, ", ")));
  }
  if (frames < 8) {
    throw std::runtime_error(
        fmt::format("mix {}: expected at least 8 frames, got {}", name, frames));
  }
  if (map_frames && (*map_frames < 2 || *map_frames > 1'000'000)) {
    throw std::runtime_error(
        fmt::format("mix {}: map frames: expected 2 to 1000000 frames, got {}", name, *map_frames));
  }
  const bool maps = name == "paper" || name == "indoor_known";
  if (map_frames && !maps) {
    throw std::runtime_error(fmt::format("mix {}: has no mapping run to size (map frames)", name));
  }
  MixPlan plan;
  plan.name = std::string(name);
  plan.resolution = resolution;
  plan.seed = seed;
  using synthetic::Scenario;
  const auto outdoor = [](int n) {
    return MixSegment{
        "outdoor",   trace::Scenario::OutdoorUnknown, Scenario::kOutdoorUnknown, "", n, "street",
        std::nullopt};
  };
  // The warehouse's mapping run (SLAM, its map saved) and a later run through it (registration).
  const auto indoor_map = [](int n) {
    return MixSegment{
        "indoor map", trace::Scenario::IndoorUnknown, Scenario::kIndoorKnown, "map", n, "warehouse",
        std::nullopt};
  };
  const auto indoor_loc = [](int n) {
    return MixSegment{
        "indoor loc", trace::Scenario::IndoorKnown, Scenario::kIndoorKnown, "loc", n, "warehouse",
        std::nullopt};
  };
  if (name == "paper") {
    // Sec. VII-A: 50 % outdoor, 25 % indoor without a map, 25 % indoor with a map.
    const int indoor = frames / 4;
    plan.segments = {outdoor(frames - 2 * indoor), indoor_map(map_frames.value_or(indoor)),
                     indoor_loc(indoor)};
  } else if (name == "outdoor") {
    plan.segments = {outdoor(frames)};  // VIO with GPS throughout
  } else if (name == "indoor_unknown") {
    plan.segments = {MixSegment{"indoor", trace::Scenario::IndoorUnknown, Scenario::kIndoorUnknown,
                                "", frames, "warehouse-unknown", std::nullopt}};
  } else {  // indoor_known: half mapping, half localizing in the map
    plan.segments = {indoor_map(map_frames.value_or(frames / 2)), indoor_loc(frames - frames / 2)};
  }
  return plan;
}

namespace {

/// Frames of a world's runs: its single run, or its loc run and (when it differs) its map run.
std::pair<int, std::optional<int>> world_frames(const MixPlan& plan, const MixSegment& segment) {
  int frames = segment.frames;
  std::optional<int> map_frames;
  for (const MixSegment& s : plan.segments) {
    if (s.world != segment.world) continue;
    if (s.run == "loc") frames = s.frames;
  }
  for (const MixSegment& s : plan.segments) {
    if (s.world == segment.world && s.run == "map" && s.frames != frames) map_frames = s.frames;
  }
  return {frames, map_frames};
}

/// One folder per world: every option the mix sets is in its name (a map run of its own length
/// adds -m<frames>).
std::filesystem::path world_dir(const MixPlan& plan, const MixSegment& segment,
                                const std::filesystem::path& dir) {
  const auto [frames, map_frames] = world_frames(plan, segment);
  return dir / fmt::format("{}-{}x{}-f{}{}-s{}", synthetic::to_string(segment.world_scenario),
                           plan.resolution.width, plan.resolution.height, frames,
                           map_frames ? fmt::format("-m{}", *map_frames) : std::string(),
                           plan.seed);
}

}  // namespace

std::filesystem::path segment_mav0(const MixPlan& plan, const MixSegment& segment,
                                   const std::filesystem::path& dir) {
  const std::filesystem::path world = world_dir(plan, segment, dir);
  return segment.run.empty() ? world / "mav0" : world / segment.run / "mav0";
}

void generate_mix_data(const MixPlan& plan, const std::filesystem::path& dir,
                       const synthetic::ProgressFn& progress, int threads) {
  std::map<std::filesystem::path, const MixSegment*> worlds;
  for (const MixSegment& s : plan.segments) worlds.emplace(world_dir(plan, s, dir), &s);
  for (const auto& [path, segment] : worlds) {
    // A finished dataset has its edx_gen.yaml (the generator renames the folder into place
    // last); the folder name holds every option the mix sets.
    if (std::filesystem::exists(path / "edx_gen.yaml")) continue;
    if (std::filesystem::exists(path)) {
      throw std::runtime_error(fmt::format(
          "{}: exists but holds no generated dataset (no edx_gen.yaml); remove it", path.string()));
    }
    synthetic::GenerateOptions options;
    options.scenario = segment->world_scenario;
    std::tie(options.frames, options.map_frames) = world_frames(plan, *segment);
    options.resolution = plan.resolution;
    options.seed = plan.seed;
    options.out = path;
    options.threads = threads;
    synthetic::generate_dataset(options, progress);
  }
}

}  // namespace edx::modes
