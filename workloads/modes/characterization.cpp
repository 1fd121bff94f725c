#include "workloads/modes/characterization.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <utility>

#include "workloads/modes/mix_runner.hpp"
#include "workloads/trace/reader.hpp"

namespace edx::modes {

namespace fs = std::filesystem;
using trace::BackendMode;
using Scenario = synthetic::Scenario;

std::vector<CharacterizationCell> characterization_cells() {
  std::vector<CharacterizationCell> cells;
  for (Scenario s : {Scenario::kIndoorUnknown, Scenario::kIndoorKnown, Scenario::kOutdoorUnknown,
                     Scenario::kOutdoorKnown}) {
    cells.push_back({s, BackendMode::Vio});
    cells.push_back({s, BackendMode::Slam});
    if (synthetic::has_map_run(s)) cells.push_back({s, BackendMode::Registration});
  }
  return cells;
}

MixPlan characterization_plan(const CharacterizationCell& cell, int frames,
                              synthetic::Resolution resolution, std::uint64_t seed) {
  const bool outdoor = synthetic::is_outdoor(cell.scenario);
  const std::string world = outdoor ? "street" : "warehouse";
  const std::string scenario(synthetic::to_string(cell.scenario));
  MixPlan plan;
  plan.name = fmt::format("characterization {} {}", scenario, trace::to_string(cell.backend));
  plan.resolution = resolution;
  plan.seed = seed;
  const trace::Scenario unknown =
      outdoor ? trace::Scenario::OutdoorUnknown : trace::Scenario::IndoorUnknown;
  if (synthetic::has_map_run(cell.scenario)) {
    const trace::Scenario known =
        outdoor ? trace::Scenario::OutdoorKnown : trace::Scenario::IndoorKnown;
    plan.segments = {MixSegment{world + " map", unknown, cell.scenario, "map", frames,
                                world + "-known", BackendMode::Slam},
                     MixSegment{world + " loc", known, cell.scenario, "loc", frames,
                                world + "-known", cell.backend}};
  } else {
    plan.segments = {
        MixSegment{world, unknown, cell.scenario, "", frames, world + "-unknown", cell.backend}};
  }
  return plan;
}

void CharacterizationOptions::validate() const {
  if (seeds < 1 || seeds > 100) {
    throw std::invalid_argument(fmt::format("seeds: expected 1 to 100, got {}", seeds));
  }
  if (frames < 8 || frames > 100'000) {
    throw std::invalid_argument(fmt::format("frames: expected 8 to 100000, got {}", frames));
  }
  if (resolution.width < 64 || resolution.height < 48) {
    throw std::invalid_argument(fmt::format("resolution: expected at least 64x48, got {}x{}",
                                            resolution.width, resolution.height));
  }
}

nlohmann::json CharacterizationRun::to_json() const {
  return {{"scenario", std::string(synthetic::to_string(cell.scenario))},
          {"backend", trace::to_string(cell.backend)},
          {"seed", seed},
          {"trace", trace.string()},
          {"first_frame_id", first_frame_id},
          {"frames", frames},
          {"ate_rmse_m", ate_rmse_m ? nlohmann::json(*ate_rmse_m) : nlohmann::json()},
          {"ate_pairs", ate_pairs},
          {"registration_failures", registration_failures}};
}

CharacterizationRun CharacterizationRun::from_json(const nlohmann::json& j) {
  CharacterizationRun r;
  r.cell.scenario = synthetic::parse_scenario(j.at("scenario").get<std::string>());
  r.cell.backend = trace::parse_backend_mode(j.at("backend").get<std::string>());
  r.seed = j.at("seed").get<std::uint64_t>();
  r.trace = j.at("trace").get<std::string>();
  r.first_frame_id = j.at("first_frame_id").get<std::int64_t>();
  r.frames = j.at("frames").get<std::size_t>();
  if (!j.at("ate_rmse_m").is_null()) r.ate_rmse_m = j.at("ate_rmse_m").get<double>();
  r.ate_pairs = j.at("ate_pairs").get<std::size_t>();
  r.registration_failures = j.at("registration_failures").get<std::size_t>();
  return r;
}

namespace {

/// The run's record beside its trace, when both are there (a resumed characterization). Throws
/// std::runtime_error when the trace is of another precision than `precision`.
std::optional<CharacterizationRun> reusable(const fs::path& trace, const fs::path& record,
                                            trace::Precision precision) {
  if (!fs::exists(trace) || !fs::exists(record)) return std::nullopt;
  const trace::Precision traced = trace::trace_precision(trace::TraceReader(trace).meta());
  if (traced != precision) {
    throw std::runtime_error(fmt::format(
        "{}: traced at {}, asked for {} (give another --out, or --force to trace again)",
        trace.string(), trace::to_string(traced), trace::to_string(precision)));
  }
  std::ifstream in(record);
  try {
    return CharacterizationRun::from_json(nlohmann::json::parse(in));
  } catch (const std::exception&) {
    return std::nullopt;  // a record cut short by an interrupted run: run it again
  }
}

}  // namespace

std::vector<CharacterizationRun> run_characterization(const CharacterizationOptions& options,
                                                      const CharacterizationProgress& progress) {
  options.validate();
  fs::create_directories(options.trace_dir);
  std::vector<CharacterizationRun> runs;
  // A known scenario's runs (vio, slam, registration, one after another) share their first
  // segment, SLAM over the mapping run: traced by the first of them that is not reused, replayed
  // by the others (mix_runner.hpp, SegmentCache). One cache per (seed, scenario): the entry goes
  // with the scenario's last run.
  std::shared_ptr<SegmentCache> mapping;
  std::optional<std::pair<std::uint64_t, Scenario>> mapping_of;
  for (int k = 0; k < options.seeds; ++k) {
    const std::uint64_t seed = kCharacterizationFirstSeed + static_cast<std::uint64_t>(k);
    for (const CharacterizationCell& cell : characterization_cells()) {
      if (!options.scenarios.empty() &&
          std::find(options.scenarios.begin(), options.scenarios.end(), cell.scenario) ==
              options.scenarios.end()) {
        continue;
      }
      const std::string name = fmt::format("{}-{}-s{}", synthetic::to_string(cell.scenario),
                                           trace::to_string(cell.backend), seed);
      const fs::path trace = options.trace_dir / (name + ".db");
      const fs::path record = options.trace_dir / (name + ".json");
      if (!options.overwrite) {
        if (std::optional<CharacterizationRun> done = reusable(trace, record, options.precision)) {
          runs.push_back(std::move(*done));
          continue;
        }
      }
      if (mapping_of != std::pair(seed, cell.scenario)) {
        mapping = make_segment_cache();
        mapping_of = std::pair(seed, cell.scenario);
      }
      MixRunOptions mix;
      if (synthetic::has_map_run(cell.scenario)) mix.segment_cache = mapping;
      mix.plan = characterization_plan(cell, options.frames, options.resolution, seed);
      mix.data_dir = options.data_dir;
      mix.out = trace;
      mix.overwrite = true;
      mix.generator_threads = options.generator_threads;
      mix.precision = options.precision;
      const MixRunSummary summary =
          run_mix(mix, [&](std::string_view stage, std::size_t done, std::size_t total) {
            if (progress) progress(name, stage, done, total);
          });
      const SegmentRunSummary& measured = summary.segments.back();
      CharacterizationRun run;
      run.cell = cell;
      run.seed = seed;
      run.trace = trace;
      run.first_frame_id = measured.first_frame_id;
      run.frames = measured.frames;
      const std::string mode = trace::to_string(cell.backend);
      if (const auto it = measured.ate_rmse_m.find(mode); it != measured.ate_rmse_m.end()) {
        run.ate_rmse_m = it->second;
        run.ate_pairs = measured.ate_pairs.at(mode);
      }
      run.registration_failures = measured.registration_failures;
      // The record last, whole or not at all: it marks the run done.
      const fs::path partial = record.string() + ".partial";
      std::ofstream(partial) << run.to_json().dump(2) << "\n";
      fs::rename(partial, record);
      runs.push_back(std::move(run));
    }
  }
  return runs;
}

}  // namespace edx::modes
