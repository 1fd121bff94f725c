#pragma once
// Sweeps over workload parameters (docs/SWEEPS.md "Workload parameters"): a spec with a
// `workload:` section traces each distinct workload point once into a trace store beside the
// results database, content-addressed: the file is <store>/<hash>.db with hash = FNV-1a of the
// resolved workload (every parameter, defaults filled in) and the tracing code's version, so the
// same workload and code reuse the trace. Tracing is the pipeline's job (workloads/modes), which
// arch does not link (DESIGN.md: data flows one way): the caller hands run_sweep a tracer.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace edx::arch {

struct WorkloadTracer {
  /// The workload's full parameters (defaults filled in, typed): what the hash covers. Throws
  /// InputError (key: the workload's, "features") on an unknown key or a malformed value, which
  /// the sweep places at the spec's line of that value.
  std::function<nlohmann::json(const nlohmann::json& workload)> resolve;
  /// Traces a resolved workload into `out` (all or nothing), generating data under `data_dir`
  /// (shared by the workloads of a store; the tracer serializes its own use of it).
  std::function<void(const nlohmann::json& resolved, const std::filesystem::path& out,
                     const std::filesystem::path& data_dir)>
      trace;
  /// The tracing code's version (the source revision): part of the hash.
  std::string version;
  explicit operator bool() const { return resolve && trace; }
};

/// FNV-1a 64 of the resolved workload's JSON and the version, as 16 hex digits.
std::string workload_hash(const nlohmann::json& resolved, const std::string& version);

/// The trace of `workload` (its parameters; the tracer resolves them) in `store`:
/// <store>/<workload_hash>.db, traced there first when it is missing (`edx simulate --seeds`,
/// `edx check --seeds`: each seed a workload point traced once). Throws InputError for a bad
/// workload (from the tracer's resolve), std::runtime_error naming the workload when tracing
/// fails.
std::filesystem::path traced_workload(const WorkloadTracer& tracer, const nlohmann::json& workload,
                                      const std::filesystem::path& store);

/// One seed's trace of a workload (trace_seeds).
struct SeedTrace {
  std::uint64_t seed = 0;
  std::filesystem::path trace;
};

/// traced_workload of `workload` with each of `seeds` (its `seed` parameter), in seed order;
/// `tracing` (optional) is told of each seed about to be traced (not found in the store), in
/// seed order, before any tracing starts. The missing seeds are traced on up to `threads`
/// threads at once (as a sweep's workers trace: the tracer serializes its data folder's use per
/// seed), every one to its end; then the error of the first failing seed in order is thrown.
/// The traces do not depend on `threads`.
std::vector<SeedTrace> trace_seeds(const WorkloadTracer& tracer, const nlohmann::json& workload,
                                   const std::vector<std::uint64_t>& seeds,
                                   const std::filesystem::path& store,
                                   const std::function<void(std::uint64_t seed)>& tracing = {},
                                   int threads = 1);

/// The group of a workload's seeds: workload_hash of its resolved parameters without `seed`.
std::string seed_group(const WorkloadTracer& tracer, const nlohmann::json& workload);

/// A workload file (`--workload FILE`): a YAML map of workload parameters to scalars, as a
/// sweep spec's `workload:` section (docs/SWEEPS.md "Workload parameters"), without `seed` (the
/// seeds are given apart). The values as text (the tracer's resolve types them). Errors:
/// InputError "file:line: key: what was expected".
nlohmann::json load_workload_file(const std::filesystem::path& path);

/// The seeds of `--seeds`: "1-5", "1,3,7" or both ("1-3,7"), at most 1000, distinct, in the
/// order given. Throws InputError naming --seeds and what was expected.
std::vector<std::uint64_t> parse_seed_list(const std::string& text);

/// The default trace store of a results database: results.db -> results.traces (a folder beside
/// it); traces are <store>/<hash>.db, generated worlds under <store>/data.
std::filesystem::path default_trace_store(const std::filesystem::path& db);

}  // namespace edx::arch
