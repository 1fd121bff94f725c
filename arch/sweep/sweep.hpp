#pragma once
// Design-space sweeps (`edx sweep`, docs/SWEEPS.md): a YAML spec names a base platform, a trace
// (or a workload to trace, workload.hpp), parameters (dotted platform keys, and workload.* keys,
// with their values), a sampling, objectives and constraints. Every design point is the base
// platform with one value per parameter; points run in parallel (threads, or MPI ranks:
// distributed.hpp) through the whole-system model (simulate_system), each stored in the results
// database as it finishes (one transaction per point, WAL), keyed by its run id (config hash +
// trace hash), so a killed sweep resumes where it stopped. The Pareto front of the objectives over
// the points that meet the constraints is printed and stored.
//
//   name: gemm_block                        # default: the spec's file stem
//   base: ../configs/edx_car.yaml           # relative to the spec
//   trace: ../build/sweep_vio.db            # relative to the spec; `--trace` overrides
//   workload: {mix: paper, frames: 400, resolution: 1280x720}   # instead of trace: the sweep
//                                           # traces each workload point (docs/SWEEPS.md)
//   parameters:
//     workload.features: {values: [500, 1000]}                    # a workload parameter
//     backend.units.gemm.block: {values: [1, 2, 4, 8]}
//     backend.clock_mhz: {range: {from: 100, to: 250, step: 50}}      # from, from+step, ... <= to
//     link.bandwidth_gb_per_s: {log_range: {from: 1.2, to: 7.9, points: 5}}  # geometric
//   sampling: grid                          # or {random: {samples: 20, seed: 1}}
//                                           # or {nsga2: {generations: 20, population: 24, seed:
//                                           1}}
//   objectives: [{minimize: e2e_latency_mean}, {minimize: dsp}, {maximize: fps}]
//   constraints: [{metric: resources, max: 1.0}]    # max and/or min
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "arch/platform/platform.hpp"
#include "arch/sweep/index_permutation.hpp"
#include "arch/sweep/workload.hpp"
#include "common/input_error.hpp"
#include "workloads/trace/records.hpp"

namespace edx::arch {

/// One swept key and its values: listed in the spec (`values: [...]`, each node keeps its line),
/// or generated on demand from a range, so that a range of 10^5 values costs no more memory or
/// time to read than one of two (issue 45):
///   range:     v_i = from + i·step,                    i = 0 .. count−1
///   log_range: v_i = from · (to/from)^(i/(count−1)),   v_{count−1} = to exactly
struct SweepParameter {
  enum class Form { kListed, kLinear, kLog };
  std::string key;  ///< dotted platform key, e.g. "backend.units.gemm.block"
  int line = 0;     ///< of the key in the spec
  Form form = Form::kListed;
  std::vector<YAML::Node> listed;     ///< kListed: the spec's value nodes
  double from = 0, to = 0, step = 0;  ///< a range's (step: kLinear only)
  std::size_t count = 0;              ///< a range's number of values

  std::size_t size() const { return form == Form::kListed ? listed.size() : count; }
  /// Value i as text (tables, CSV, the platform): a listed value as written; a generated one
  /// as an integer without a decimal point, or to 4 significant digits.
  std::string text(std::size_t i) const;
  /// As the spec wrote it: the listed texts, or {"range": {from, to, step}} /
  /// {"log_range": {from, to, points}}.
  nlohmann::json to_json() const;
};

struct SweepObjective {
  std::string metric;
  bool maximize = false;
  int line = 0;  ///< of the metric in the spec
};

/// A bound on a metric: absolute (min and/or max), or relative to a reference workload point:
///   metric(point) <= (1 + max_relative) * metric(reference of point)
/// where the reference of a point is its workload with the `reference` values instead (the same
/// features and windows at fp64, say); only for accuracy metrics, which depend on the workload
/// alone (docs/SWEEPS.md "Accuracy").
struct SweepConstraint {
  std::string metric;
  double min = -1e300, max = 1e300;
  std::optional<double> max_relative;
  nlohmann::json reference;  ///< {"features": "1000", ...}: workload keys (no "workload.")
  std::map<std::string, int> reference_lines;  ///< the spec's line of each reference value
  int line = 0;
  bool relative() const { return max_relative.has_value(); }
  /// The bound on the value the search constrains (the metric, or a relative one's ratio).
  double upper() const { return relative() ? 1 + *max_relative : max; }
  double lower() const { return relative() ? -1e300 : min; }
};

struct SweepSpec {
  std::string file;  ///< the spec file ("" when parsed from text)
  std::string name;
  std::filesystem::path base, trace;
  /// The `workload:` section (parameter name -> value text), null when the spec names a trace:
  /// the sweep then traces every workload point itself (WorkloadTracer, workload.hpp).
  nlohmann::json workload;
  std::map<std::string, int> workload_lines;  ///< the line of each key of `workload:`
  /// Platform parameters and `workload.*` parameters, the workload ones first (so the grid's
  /// points of one workload point are consecutive).
  std::vector<SweepParameter> parameters;
  std::size_t workload_parameters = 0;  ///< how many of `parameters` are workload.* (the first)
  bool traces_workload() const { return !workload.is_null(); }
  bool random = false;
  std::size_t samples = 0;
  std::uint64_t seed = 1;
  /// Multi-objective search (pagmo2's NSGA-II, search.hpp) over the grid's points instead of
  /// evaluating them all: `population` designs evolved for `generations` generations.
  bool nsga2 = false;
  std::size_t generations = 0, population = 0;
  std::vector<SweepObjective> objectives;
  std::vector<SweepConstraint> constraints;
  /// Whether an objective or constraint is an accuracy metric (the sweep then computes each
  /// trace's accuracy, trace_accuracy.hpp).
  bool needs_accuracy() const;
  nlohmann::json to_json() const;

  /// Reads a spec (sweep_spec.cpp); errors are InputErrors, one line "file:line: key: message".
  static SweepSpec load(const std::filesystem::path& path);
  /// Parses spec text; `where` names it in errors, relative paths resolve against `dir`.
  static SweepSpec parse(const std::string& text, const std::string& where,
                         const std::filesystem::path& dir);
};

/// One design point: the index of each parameter's value.
struct SweepPoint {
  std::size_t index = 0;  ///< position in the expansion
  std::vector<std::size_t> choice;
  /// {"backend.units.gemm.block": "4", ...}
  nlohmann::json parameters(const SweepSpec& spec) const;
  /// The spec's workload with this point's workload.* values (null when the spec has none).
  nlohmann::json workload(const SweepSpec& spec) const;
  /// Which workload point this is: the index of its workload.* values in their own grid.
  std::size_t workload_index(const SweepSpec& spec) const;
};

/// The keys of a spec's maps (sweep_spec.cpp's field lists), for the reference
/// (docs/CONFIG.md, "Other input files").
std::vector<ReferenceRow> sweep_spec_reference();

/// Most design points a sweep may have (grid size, or random samples, or search evaluations).
inline constexpr double kMaxSweepPoints = 1e6;
/// Most workload points (traces) a sweep may have.
inline constexpr double kMaxWorkloadPoints = 1e4;
/// Largest grid a search may index: 2^53, every index exact as a double (pagmo's genes).
inline constexpr double kMaxSearchGrid = 9007199254740992.0;
/// Largest grid random sampling may index: 2^126 (IndexPermutation's domain).
inline constexpr double kMaxRandomGrid = 8.507059173023462e37;

/// Points of the full grid (the product of the parameters' value counts), as a double.
double grid_size(const SweepSpec& spec);

/// The design points, enumerated lazily: the full grid (index -> values, last parameter
/// fastest), or `samples` distinct grid points drawn with the spec's seed (point i is grid point
/// perm(i) of a seeded permutation, IndexPermutation: the same seed gives the same points on any
/// machine, and nothing is stored). A search (nsga2) indexes the full grid and visits the points
/// it chooses. Memory does not grow with the grid or the samples. Throws when a grid sweep has
/// more than 10^6 points.
class SweepPoints {
 public:
  explicit SweepPoints(const SweepSpec& spec);  ///< `spec` must outlive this
  std::size_t size() const { return size_; }
  SweepPoint at(std::size_t index) const;
  /// The grid index of a choice of value indices (the inverse of `at` on the full grid).
  std::size_t grid_index(const std::vector<std::size_t>& choice) const;

 private:
  const SweepSpec* spec_;
  std::size_t size_ = 0;
  std::optional<IndexPermutation> draws_;  ///< random sampling: grid index of point i
};

/// Where the spec wrote value `v` of parameter `p`: its line, or for a generated value (a range's)
/// the parameter's line and "parameters.<key> = <value>".
InputPlace parameter_value_place(const SweepSpec& spec, std::size_t p, std::size_t v);

/// The base platform with the point's values; errors name the spec (for a swept key) or the
/// platform file that wrote the offending key. The second form starts from a loaded base.
Platform sweep_platform(const SweepSpec& spec, const SweepPoint& point);
Platform sweep_platform(const SweepSpec& spec, const SweepPoint& point, const PlatformSource& base);

/// Named metrics of a run's summary (SystemResult::to_json()), or a JSON pointer
/// ("/accelerated/modes/all/e2e_ms/p99"). Names: e2e_latency_mean, e2e_latency_p99,
/// frontend_latency_mean, backend_latency_mean, fps, fps_without_pipelining, energy_mean,
/// e2e_speedup, lut, ff, dsp, bram (shared totals), lut_util, ff_util, dsp_util, bram_util,
/// resources (the largest utilization, 1 = the whole device).
double sweep_metric(const nlohmann::json& summary, const std::string& metric);
/// Whether `metric` names a metric: a name, or a well-formed JSON pointer (RFC 6901; whether the
/// summary has a number there is known when it is evaluated).
bool is_sweep_metric(const std::string& metric);

/// Accuracy metrics: ATE RMSE (m) of the point's trace, over all its estimates (`ate_rmse`) or
/// those of one backend mode (`ate_rmse_vio`, `ate_rmse_slam`, `ate_rmse_registration`), each
/// (segment, mode) aligned on its own and pooled (workloads/eval/trace_accuracy.hpp).
bool is_accuracy_metric(const std::string& metric);
/// An accuracy metric of a trace's accuracy (eval::TraceAccuracy::to_json()); NaN when the trace
/// has too few estimates of that mode (the point is then infeasible where the metric is used).
double accuracy_metric(const nlohmann::json& accuracy, const std::string& metric);
/// The metric of a point: an accuracy metric of its trace's accuracy, any other of its run summary.
double point_metric(const nlohmann::json& summary, const nlohmann::json& accuracy,
                    const std::string& metric);

/// Indices of the non-dominated rows of `values` (each row: one value per objective; a row
/// dominates another when it is no worse in every objective and better in one; `maximize[i]`
/// flips objective i). Equal rows are all kept. Result in increasing index order.
std::vector<std::size_t> pareto_front(const std::vector<std::vector<double>>& values,
                                      const std::vector<bool>& maximize);

/// One finished point of a sweep.
struct SweepPointResult {
  std::size_t index = 0;
  std::string run_id;    ///< "" when the point failed (error)
  std::string workload;  ///< hash of its workload point ("" when the spec names a trace)
  std::string error;     ///< why the point has no run (its workload could not be traced)
  nlohmann::json parameters;
  std::vector<double> objectives;
  /// Per constraint, the value bounded (the metric; a relative constraint's ratio to the
  /// reference's), as the search constrains it; NaN when undefined.
  std::vector<double> constraints;
  nlohmann::json metrics;  ///< objectives and constraint metrics by name (null: undefined)
  std::string bottleneck;  ///< its accelerated variant's bottleneck resource ("" unmodelled)
  bool feasible = true;
  bool computed = false;  ///< simulated in this run (false: found in the database)
  bool pareto = false;
};

struct SweepOptions {
  std::filesystem::path db;
  std::filesystem::path trace;  ///< overrides the spec's trace when not empty
  int jobs = 1;
  std::size_t limit = 0;   ///< stop after this many simulated points (0: no limit)
  bool per_frame = false;  ///< also store frames and offload rows of every point
  /// Called after each point (done, total, that point), from one thread at a time.
  std::function<void(std::size_t, std::size_t, const SweepPointResult&)> progress;
  /// Traces workload points (specs with a workload: section; required for them).
  WorkloadTracer tracer;
  /// Where workload traces go (default: default_trace_store(db)).
  std::filesystem::path trace_store;
  /// Called when a workload point starts and ends tracing (its index, parameters, error or "").
  std::function<void(std::size_t, const nlohmann::json&, const std::string*)> trace_progress;
  /// Run as rank 0 of an MPI job (distributed.hpp): this process owns the database and hands
  /// points to the other ranks (which run serve_sweep) and to one worker thread of its own.
  bool distributed = false;
};

/// One generation of a search: the designs evaluated so far (distinct) and the hypervolume of
/// the feasible front among them, against the reference point of the whole search.
struct SearchGeneration {
  std::size_t generation = 0;   ///< 0: the initial population
  std::size_t evaluations = 0;  ///< distinct designs evaluated up to this generation
  std::size_t front_size = 0;
  double hypervolume = 0;
};

struct SweepOutcome {
  std::string sweep_id;
  std::size_t total = 0, computed = 0, skipped = 0;
  bool complete = true;                       ///< false: stopped by the limit
  std::vector<SweepPointResult> points;       ///< finished points, by index
  std::vector<std::size_t> front;             ///< indices into points (complete sweeps only)
  std::vector<SearchGeneration> generations;  ///< a search's convergence table
  std::size_t traced = 0;                     ///< workload points traced in this run
  std::size_t failed = 0;                     ///< points with an error (workload not traced)
  double seconds = 0;                         ///< wall time
  nlohmann::json to_json(const SweepSpec& spec) const;
};

/// Runs (or resumes) a sweep on the trace of the spec or the options. Tables: docs/SWEEPS.md.
SweepOutcome run_sweep(const SweepSpec& spec, const SweepOptions& options);
/// The same on frames in memory (benchmarks stretch a trace); `trace_name` is stored with runs.
SweepOutcome run_sweep(const SweepSpec& spec, const SweepOptions& options,
                       const std::vector<trace::FrameTrace>& frames,
                       const trace::TraceMeta& trace_meta, const std::string& trace_name);

std::string format_sweep(const SweepSpec& spec, const SweepOutcome& outcome);

/// Writes a table of a results database to CSV (header row, RFC 4180 quoting), or with
/// `sweep` not empty that sweep's points: point, run_id, a column per parameter and metric,
/// feasible, pareto. Returns the rows written.
std::size_t export_csv(const std::filesystem::path& db, const std::string& table,
                       const std::string& sweep, const std::filesystem::path& out);

}  // namespace edx::arch
