#include "workloads/modes/characterization.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <utility>

#include "common/parallel.hpp"
#include "workloads/frontend/task_timer.hpp"
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
  if (threads < 1 || threads > 256) {
    throw std::invalid_argument(fmt::format("threads: expected 1 to 256, got {}", threads));
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

/// The run's measured segment's figures, its record written beside its trace (whole or not at
/// all: it marks the run done).
CharacterizationRun record_run(const CharacterizationCell& cell, std::uint64_t seed,
                               const fs::path& trace, const MixRunSummary& summary,
                               const fs::path& record) {
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
  const fs::path partial = record.string() + ".partial";
  std::ofstream(partial) << run.to_json().dump(2) << "\n";
  fs::rename(partial, record);
  return run;
}

}  // namespace

std::vector<CharacterizationRun> run_characterization(const CharacterizationOptions& options,
                                                      const CharacterizationProgress& progress) {
  options.validate();
  fs::create_directories(options.trace_dir);
  // Every run in order (seeds, then cells); a run whose trace and record are there is reused
  // (checked first: a trace of the other precision is refused before any work).
  struct Pending {
    std::size_t index;  ///< its place in the runs
    CharacterizationCell cell;
    std::uint64_t seed;
    std::string name;
    MixRunOptions mix;
    fs::path record;
  };
  std::vector<std::optional<CharacterizationRun>> runs;
  std::vector<Pending> pending;
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
      runs.emplace_back();
      if (!options.overwrite) {
        runs.back() = reusable(trace, record, options.precision);
        if (runs.back()) continue;
      }
      MixRunOptions mix;
      mix.plan = characterization_plan(cell, options.frames, options.resolution, seed);
      mix.data_dir = options.data_dir;
      mix.out = trace;
      mix.overwrite = true;
      mix.generator_threads = options.generator_threads;
      mix.precision = options.precision;
      // The maps stay in memory (registration's mapping segment hands its map over within the
      // run); saved, a seed's scenarios without and with a map, which share their world, would
      // write one <world>-map.json together from two threads.
      mix.save_maps = false;
      pending.push_back({runs.size() - 1, cell, seed, name, std::move(mix), record});
    }
  }
  // The progress of runs traced at once, one call at a time.
  std::mutex progress_mutex;
  const auto progress_of = [&](const std::string& name) -> MixProgress {
    return [&progress, &progress_mutex, name](std::string_view stage, std::size_t done,
                                              std::size_t total) {
      if (!progress) return;
      const std::lock_guard lock(progress_mutex);
      progress(name, stage, done, total);
    };
  };
  // The worlds, maps' worlds and vocabularies first, one run after another (no two threads make
  // the same files; a no-op for what is there), OpenCV single-threaded as when run_mix made
  // them. A data folder this made goes again when that fails (run_mix's rule).
  const bool data_dir_is_new = !fs::exists(options.data_dir);
  try {
    const frontend::TracingThreads single_threaded(false);
    for (const Pending& p : pending) prepare_mix_data(p.mix, progress_of(p.name));
  } catch (...) {
    std::error_code ignored;
    if (data_dir_is_new) fs::remove_all(options.data_dir, ignored);
    throw;
  }
  // Then the tracing, one job per (seed, scenario): a known scenario's runs (vio, slam,
  // registration, in this order) share their first segment, SLAM over the mapping run, traced by
  // the first of them and replayed by the others (mix_runner.hpp, SegmentCache, one per group,
  // not thread-safe: the group's runs stay on one thread, in order). Groups run on
  // options.threads threads; each run writes its own trace, record and slot of `runs`.
  std::vector<std::function<void()>> jobs;
  for (std::size_t first = 0; first < pending.size();) {
    std::size_t last = first + 1;
    const auto group_of = [](const Pending& p) { return std::pair(p.seed, p.cell.scenario); };
    while (last < pending.size() && group_of(pending[last]) == group_of(pending[first])) ++last;
    jobs.emplace_back([&, first, last] {
      const std::shared_ptr<SegmentCache> mapping = make_segment_cache();
      for (std::size_t i = first; i < last; ++i) {
        Pending& p = pending[i];
        if (synthetic::has_map_run(p.cell.scenario)) p.mix.segment_cache = mapping;
        const MixRunSummary summary = run_mix(p.mix, progress_of(p.name));
        runs[p.index] = record_run(p.cell, p.seed, p.mix.out, summary, p.record);
      }
    });
    first = last;
  }
  common::run_jobs(jobs, options.threads);
  std::vector<CharacterizationRun> out;
  out.reserve(runs.size());
  for (std::optional<CharacterizationRun>& r : runs) out.push_back(std::move(*r));
  return out;
}

}  // namespace edx::modes
