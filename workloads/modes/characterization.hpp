#pragma once
// The paper's algorithm characterization (Sec. III, "Accuracy Characterizations"; issue 42): each
// of the three backends on each of the four operating scenarios of the synthetic world, several
// seeds, its accuracy against the ground truth and the trace an architect simulates for its frame
// rate. Every applicable backend runs every frame of the measured run (a fixed-algorithm mix
// segment, mix.hpp), the mode switch out of the loop:
//
//   scenario          measured run            backends
//   indoor_unknown    a warehouse, no map     vio (no GPS indoors), slam
//   indoor_known      a later warehouse run   vio, slam, registration (in the map SLAM built on
//                                             the world's mapping run, a segment of its own
//                                             before it)
//   outdoor_unknown   a street run, GPS       vio (with GPS), slam
//   outdoor_known     a later street run      vio (with GPS), slam, registration (as indoors)
//
// Each run is one trace (its mapping segment first when it has one); its accuracy is the ATE
// RMSE of the measured segment alone (position + yaw alignment, the IMU's gravity).
#include <cstdint>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "workloads/datasets/synthetic/generator.hpp"
#include "workloads/modes/mix.hpp"
#include "workloads/trace/records.hpp"

namespace edx::modes {

/// The first seed of the characterization's worlds: seeds no test, tuning or study of edx has
/// used (docs/ record seeds 1..45).
inline constexpr std::uint64_t kCharacterizationFirstSeed = 1001;

/// One (scenario, backend) of the characterization.
struct CharacterizationCell {
  synthetic::Scenario scenario;
  trace::BackendMode backend;
};

/// Every applicable (scenario, backend), scenarios in the paper's order (indoor without and with
/// a map, outdoor without and with), backends vio, slam, registration.
std::vector<CharacterizationCell> characterization_cells();

/// The mix of one run: the scenario's mapping run (SLAM, its map kept) when it has one, then its
/// measured run with `backend` on every frame; `frames` frames each.
MixPlan characterization_plan(const CharacterizationCell& cell, int frames,
                              synthetic::Resolution resolution, std::uint64_t seed);

struct CharacterizationOptions {
  int seeds = 3;                                ///< kCharacterizationFirstSeed and the next ones
  int frames = 400;                             ///< of the measured (and the mapping) run
  synthetic::Resolution resolution{1280, 720};  ///< Edx-Car's cameras
  std::filesystem::path data_dir;               ///< generated worlds, vocabulary
  std::filesystem::path trace_dir;              ///< one trace per run
  int generator_threads = 2;
  /// Runs traced at once: each (seed, scenario)'s runs on one thread, in order (they share the
  /// mapping segment), groups on `threads` threads; the worlds are made first, one after another.
  /// The runs, their traces' rows and their figures do not depend on it (host times aside).
  int threads = 1;
  bool overwrite = false;  ///< replace traces already there (else they are reused)
  /// The backends' offloadable kernels' arithmetic (meta precision). A trace already there of
  /// another precision is an error, not reused.
  trace::Precision precision = trace::Precision::kFp64;
  /// The scenarios to run (empty: all four): a study of some of them, e.g. longer indoor runs.
  std::vector<synthetic::Scenario> scenarios;
  /// Throws std::invalid_argument naming the option (seeds, frames, resolution, threads).
  void validate() const;
};

/// One run: a (scenario, backend, seed) and what it measured.
struct CharacterizationRun {
  CharacterizationCell cell;
  std::uint64_t seed = 0;
  std::filesystem::path trace;       ///< its trace
  std::int64_t first_frame_id = 0;   ///< the measured segment's first frame in the trace
  std::size_t frames = 0;            ///< the measured segment's frames
  std::optional<double> ate_rmse_m;  ///< on the measured segment (none: too few estimates)
  std::size_t ate_pairs = 0;
  std::size_t registration_failures = 0;
  nlohmann::json to_json() const;
  static CharacterizationRun from_json(const nlohmann::json& j);
};

/// Progress: the run ("indoor_known-vio-s1001"), its stage, done, total; one call at a time
/// (runs traced at once take turns).
using CharacterizationProgress = std::function<void(std::string_view run, std::string_view stage,
                                                    std::size_t done, std::size_t total)>;

/// Runs every cell on every seed (characterization_cells × seeds), in that order. A run whose
/// trace exists and whose record (<trace>.json) is beside it is reused unless `overwrite`. On a
/// failure every group still runs to its end (or its first failing run), then the first failure
/// in run order is thrown.
std::vector<CharacterizationRun> run_characterization(
    const CharacterizationOptions& options, const CharacterizationProgress& progress = {});

}  // namespace edx::modes
