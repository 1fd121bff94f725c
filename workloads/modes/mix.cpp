#include "workloads/modes/mix.hpp"

#include <fmt/format.h>

#include <map>
#include <stdexcept>

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

std::vector<std::string> mix_names() { return {"paper"}; }

MixPlan make_mix(std::string_view name, int frames, synthetic::Resolution resolution,
                 std::uint64_t seed) {
  if (name != "paper") {
    throw std::runtime_error(fmt::format("unknown mix '{}' (expected: paper)", name));
  }
  if (frames < 8) {
    throw std::runtime_error(fmt::format("mix paper: expected at least 8 frames, got {}", frames));
  }
  MixPlan plan;
  plan.name = "paper";
  plan.resolution = resolution;
  plan.seed = seed;
  // Sec. VII-A: 50 % outdoor, 25 % indoor without a map, 25 % indoor with a map.
  const int indoor = frames / 4;
  const int outdoor = frames - 2 * indoor;
  using synthetic::Scenario;
  plan.segments = {
      {"outdoor", trace::Scenario::OutdoorUnknown, Scenario::kOutdoorUnknown, "", outdoor,
       "street"},
      {"indoor map", trace::Scenario::IndoorUnknown, Scenario::kIndoorKnown, "map", indoor,
       "warehouse"},
      {"indoor loc", trace::Scenario::IndoorKnown, Scenario::kIndoorKnown, "loc", indoor,
       "warehouse"},
  };
  return plan;
}

namespace {

std::filesystem::path world_dir(const MixPlan& plan, const MixSegment& segment,
                                const std::filesystem::path& dir) {
  return dir / fmt::format("{}-{}x{}-f{}-s{}", synthetic::to_string(segment.world_scenario),
                           plan.resolution.width, plan.resolution.height, segment.frames,
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
    options.frames = segment->frames;
    options.resolution = plan.resolution;
    options.seed = plan.seed;
    options.out = path;
    options.threads = threads;
    synthetic::generate_dataset(options, progress);
  }
}

}  // namespace edx::modes
