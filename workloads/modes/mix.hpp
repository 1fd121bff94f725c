#pragma once
// Mixed sequences (`edx trace --mix paper`): the paper's evaluation mix of operating scenarios
// (Sec. VII-A: 50 % outdoor frames, 25 % indoor without a map, 25 % indoor with a map) built from
// synthetic worlds, one segment after another in one trace.
//
// The paper mix, for N frames:
//   1. outdoor      N/2 frames of an outdoor street run (GPS)    -> the switch picks VIO
//   2. indoor map   N/4 frames of a warehouse mapping run        -> no GPS, no map: SLAM, whose
//                                                                   map is saved for later
//   3. indoor loc   N/4 frames of a later run through the same   -> no GPS, the saved map
//                   warehouse (the generator's known scenario)      registers: registration
// The mode of each frame is not scripted: the mode switch (mode_switch.hpp) decides it from the
// GPS stream and from whether a map of the current world registers.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "workloads/datasets/synthetic/generator.hpp"
#include "workloads/trace/records.hpp"

namespace edx::modes {

/// One segment of a mix: a run of a synthetic world.
struct MixSegment {
  std::string name;                    ///< "outdoor", "indoor map", "indoor loc"
  trace::Scenario scenario;            ///< recorded on the segment's frames
  synthetic::Scenario world_scenario;  ///< what the generator renders
  std::string run;                     ///< "" (single-run scenario), "map" or "loc"
  int frames = 0;
  std::string world;  ///< segments with the same world share a map
  /// The backend every frame of the segment runs instead of the mode switch's choice (the
  /// characterization's fixed-algorithm runs, characterization.hpp); unset: the switch decides.
  std::optional<trace::BackendMode> mode;
};

struct MixPlan {
  std::string name;  ///< "paper"
  synthetic::Resolution resolution;
  std::uint64_t seed = 1;
  std::vector<MixSegment> segments;

  int total_frames() const;
  std::string to_string() const;
};

/// Names accepted by make_mix: "paper" (above), and one scenario each: "outdoor" (the street
/// run alone: VIO with GPS), "indoor_unknown" (a warehouse without a map: SLAM),
/// "indoor_known" (half mapping the warehouse with SLAM, half registering in its map).
std::vector<std::string> mix_names();

/// The named mix with `frames` frames (>= 8) at `resolution`. `map_frames` sets the length of
/// the mapping run of the mixes that have one ("paper": default frames/4, the mix then has
/// frames - frames/4 + map_frames frames; "indoor_known": default frames/2): the size of the
/// map later frames register in. Throws std::runtime_error for an unknown name, too few frames
/// or a map_frames the mix cannot take.
MixPlan make_mix(std::string_view name, int frames, synthetic::Resolution resolution,
                 std::uint64_t seed, std::optional<int> map_frames = std::nullopt);

/// Where a segment's data lives once generated: `dir/<scenario>-<W>x<H>-f<frames>-s<seed>`, then
/// mav0 or <run>/mav0.
std::filesystem::path segment_mav0(const MixPlan& plan, const MixSegment& segment,
                                   const std::filesystem::path& dir);

/// Generates the datasets of the plan under `dir` (one per world), reusing those already there
/// (same options give the same bytes, docs/DATASETS.md). Progress: segment name, done, total.
/// `threads`: render threads of the generator.
void generate_mix_data(const MixPlan& plan, const std::filesystem::path& dir,
                       const synthetic::ProgressFn& progress = {}, int threads = 2);

}  // namespace edx::modes
