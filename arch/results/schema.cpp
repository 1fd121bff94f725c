// The results tables, each declared once (schema.hpp; docs/RESULTS.md is generated from here).
// Table and column names, column order and primary keys are those of the databases already
// written: a column is only ever added at the end of its table, with the version that added it.
#include "arch/results/schema.hpp"

#include <fmt/format.h>

#include <span>
#include <stdexcept>
#include <type_traits>

namespace edx::results {
namespace {

constexpr TableGroup kRun = TableGroup::kRun;
constexpr TableGroup kSweep = TableGroup::kSweep;

template <class Row>
Column<Row> run_id_column(std::string Row::*member) {
  return column("run_id", member, "", "the run: `<config_hash>-<trace_hash>`").not_null();
}

template <class Row>
Column<Row> variant_column(std::string Row::*member) {
  return column("variant", member, "", "baseline (CPU only) or accelerated").not_null();
}

template <class Row>
Column<Row> sweep_id_column(std::string Row::*member) {
  return column("sweep_id", member, "", "the sweep: its spec's name").not_null();
}

/// A table's spec before its columns (Table adds them).
TableSpec spec(std::string name, TableGroup group, std::string doc,
               std::vector<std::string> primary_key, int since = 0) {
  TableSpec t;
  t.name = std::move(name);
  t.group = group;
  t.doc = std::move(doc);
  t.primary_key = std::move(primary_key);
  t.since = since;
  return t;
}

}  // namespace

void check_schema_version(int version, const std::string& path) {
  if (version > kSchemaVersion) {
    throw std::runtime_error(fmt::format(
        "{}: results schema version {} is newer than this edx reads ({}); use a newer edx", path,
        version, kSchemaVersion));
  }
  if (version < 0) {
    throw std::runtime_error(
        fmt::format("{}: results schema version {} (user_version) is not one edx writes (0 to {})",
                    path, version, kSchemaVersion));
  }
}

std::string run_id_of(const std::string& config_hash, const std::string& trace_hash) {
  return config_hash + "-" + trace_hash;
}

const Table<RunRow>& runs_table() {
  using R = RunRow;
  static const Table<R> table(
      spec("runs", kRun, "One row per simulated run (platform x trace).", {"run_id"}),
      {run_id_column(&R::run_id),
       column("config_hash", &R::config_hash, "",
              "FNV-1a 64 of the platform's full JSON (every key, defaults included), hex")
           .not_null(),
       column("trace_hash", &R::trace_hash, "",
              "FNV-1a 64 of the trace's meta table and frame count, hex")
           .not_null(),
       column("platform", &R::platform, "", "the platform's name").not_null(),
       column("trace", &R::trace, "", "the trace file as given").not_null(),
       column("frames", &R::frames, "", "frames simulated").not_null(),
       column("policy", &R::policy, "", "the offload scheduler's policy").not_null(),
       column("config_json", &R::config, "", "the platform as JSON, every key resolved")
           .not_null()
           .json_object({}),
       column("summary_json", &R::summary, "",
              "the run's summary: what `edx simulate --json` prints under `system`")
           .not_null()
           .json_object({"baseline", "accelerated", "comparison", "resources"})});
  return table;
}

const Table<FrameRow>& frames_table() {
  using R = FrameRow;
  static const Table<R> table(
      spec("frames", kRun,
           "Per variant and frame (runs written with per-frame rows: `edx simulate`, sweeps with "
           "`--per-frame`).",
           {"run_id", "variant", "frame_id"}),
      {run_id_column(&R::run_id), variant_column(&R::variant),
       column("frame_id", &R::frame_id, "", "the trace's frame id").not_null(),
       column("mode", &R::mode, "", "the frame's backend: registration, vio, slam or none")
           .not_null(),
       column("frontend_ms", &R::frontend_ms, "ms", "frontend latency"),
       column("backend_ms", &R::backend_ms, "ms", "backend latency"),
       column("e2e_ms", &R::e2e_ms, "ms", "end-to-end latency"),
       column("host_busy_ms", &R::host_busy_ms, "ms", "host computing within the frame"),
       column("offloaded", &R::offloaded, "", "backend kernels offloaded"),
       column("energy_j", &R::energy_j, "J", "energy of the frame")});
  return table;
}

const Table<LatencyRow>& latency_table() {
  using R = LatencyRow;
  const auto ms = [](const char* name, double R::*member, const char* label, const char* doc) {
    return column(name, member, "ms", doc).label(label);
  };
  static const Table<R> table(
      spec("latency", kRun, "Latency statistics per variant, mode (and `all`) and stage.",
           {"run_id", "variant", "mode", "stage"}),
      {run_id_column(&R::run_id), variant_column(&R::variant),
       column("mode", &R::mode, "", "registration, vio, slam, none, or all frames (all)")
           .not_null(),
       column("stage", &R::stage, "", "frontend, backend or e2e").not_null(),
       column("count", &R::count, "", "frames").label("frames"),
       ms("mean", &R::mean, "mean", "mean"), ms("sd", &R::sd, "SD", "standard deviation"),
       column("rsd", &R::rsd, "", "relative standard deviation: sd / mean").label("RSD"),
       ms("p50", &R::p50, "p50", "median"), ms("p90", &R::p90, "p90", "90th percentile"),
       ms("p99", &R::p99, "p99", "99th percentile"), ms("max", &R::max, "max", "maximum")});
  return table;
}

const Table<ThroughputRow>& throughput_table() {
  using R = ThroughputRow;
  static const Table<R> table(
      spec("throughput", kRun, "Frame rate per variant.", {"run_id", "variant"}),
      {run_id_column(&R::run_id), variant_column(&R::variant),
       column("fps_without_pipelining", &R::fps_without_pipelining, "FPS",
              "frames per second, a frame's backend after its frontend")
           .label("without FE/BE pipelining"),
       column("fps_with_pipelining", &R::fps_with_pipelining, "FPS",
              "frames per second, frontend and backend of successive frames overlapped")
           .label("with FE/BE pipelining")});
  return table;
}

const Table<EnergyRow>& energy_table() {
  using R = EnergyRow;
  static const Table<R> table(
      spec("energy", kRun, "Energy per frame per variant and mode.", {"run_id", "variant", "mode"}),
      {run_id_column(&R::run_id), variant_column(&R::variant),
       column("mode", &R::mode, "", "registration, vio, slam, none, or all frames (all)")
           .not_null(),
       column("mean_j", &R::mean_j, "J", "mean").label("mean"),
       column("sd_j", &R::sd_j, "J", "standard deviation").label("SD"),
       column("p99_j", &R::p99_j, "J", "99th percentile").label("p99"),
       column("max_j", &R::max_j, "J", "maximum").label("max")});
  return table;
}

const Table<OffloadRow>& offload_table() {
  using R = OffloadRow;
  static const Table<R> table(
      spec("offload", kRun,
           "Per accelerable kernel invocation, the offload scheduler's inputs and decision (runs "
           "written with per-frame rows).",
           {"run_id", "frame_id", "kernel_seq"}),
      {run_id_column(&R::run_id),
       column("frame_id", &R::frame_id, "", "the trace's frame id").not_null(),
       column("kernel_seq", &R::kernel_seq, "", "position among the frame's kernels").not_null(),
       column("kernel", &R::kernel, "", "projection, kalman_gain or marginalization").not_null(),
       column("size", &R::size, "", "the kernel's m (the scheduler's feature)"),
       column("host_ms", &R::host_ms, "ms", "on the target CPU"),
       column("accel_ms", &R::accel_ms, "ms",
              "on the accelerator: units + transfers + spill traffic (NULL in databases written "
              "before spills were modelled, 2026-11-26, when it did not fit the SPM)"),
       column("compute_ms", &R::compute_ms, "ms", "the backend units only"),
       column("transfer_ms", &R::transfer_ms, "ms", "inputs and results on an idle link"),
       column("fits_spm", &R::fits_spm, "", "1: its operands fit the scratchpad; 0: it spills"),
       column("training", &R::training, "", "1: profiled on the host to fit the models"),
       column("offloaded", &R::offloaded, "", "1: run on the accelerator"),
       column("spill_ms", &R::spill_ms, "ms",
              "spill traffic on an idle link (0 when it fits the SPM)")
           .since(4),
       column("spill_bytes", &R::spill_bytes, "bytes", "DRAM bytes read and written out of core")
           .since(4)});
  return table;
}

const Table<ScheduleRow>& schedule_table() {
  using R = ScheduleRow;
  static const Table<R> table(
      spec("schedule", kRun,
           "Per accelerable kernel, the offload scheduler over the evaluation frames (those after "
           "training).",
           {"run_id", "kernel"}),
      {run_id_column(&R::run_id), column("kernel", &R::kernel, "", "the kernel").not_null(),
       column("invocations", &R::invocations, "", "invocations"),
       column("offloaded", &R::offloaded, "", "invocations offloaded by the policy"),
       column("host_only_s", &R::host_only_s, "s", "every invocation on the host")
           .label("host only"),
       column("always_s", &R::always_s, "s",
              "every invocation offloaded (NULL: the kernel never fits the SPM)")
           .label("always offload"),
       column("policy_s", &R::policy_s, "s", "as the policy decided").label("policy"),
       column("oracle_s", &R::oracle_s, "s", "as the oracle decides").label("oracle"),
       column("r_squared_train", &R::r_squared_train, "",
              "R² of the regression model on its training samples")
           .label("R² train"),
       column("r_squared_eval", &R::r_squared_eval, "", "R² on the evaluation samples")
           .label("R² eval"),
       column("gap_to_oracle", &R::gap_to_oracle, "", "policy_s / oracle_s - 1")
           .label("gap to oracle")});
  return table;
}

const Table<ResourceRow>& resources_table() {
  using R = ResourceRow;
  const auto count = [](const char* name, double R::*member, const char* label, const char* unit,
                        const char* doc) { return column(name, member, unit, doc).label(label); };
  static const Table<R> table(
      spec("resources", kRun,
           "FPGA resources per unit, memory and control entry, then `total` (group `all`).", {}),
      {run_id_column(&R::run_id),
       column("entry", &R::entry, "", "FD, gemm, fe.L0.line_fifo, control, ... or total")
           .not_null(),
       column("grp", &R::group, "", "frontend, backend or all").not_null().label("group"),
       column("kind", &R::kind, "", "unit, memory, control or total").not_null(),
       count("lut", &R::lut, "LUT", "", "LUTs as built (shared across modes and kernels)"),
       count("ff", &R::ff, "FF", "", "flip-flops as built"),
       count("dsp", &R::dsp, "DSP", "", "DSP slices as built"),
       count("bram", &R::bram, "BRAM", "36 Kb blocks", "block RAM as built"),
       count("ns_lut", &R::ns_lut, "N.S. LUT", "", "LUTs without sharing (the paper's N.S.)"),
       count("ns_ff", &R::ns_ff, "N.S. FF", "", "flip-flops without sharing"),
       count("ns_dsp", &R::ns_dsp, "N.S. DSP", "", "DSP slices without sharing"),
       count("ns_bram", &R::ns_bram, "N.S. BRAM", "36 Kb blocks", "block RAM without sharing")});
  return table;
}

const Table<TimelineRow>& timelines_table() {
  using R = TimelineRow;
  static const Table<R> table(
      spec("timelines", kRun,
           "The whole-system Perfetto timeline of a run simulated with `--timeline` and `--out` "
           "(model des); `edx report` writes it beside the report and links it.",
           {"run_id"}, 1),
      {run_id_column(&R::run_id),
       column("first_frame", &R::first_frame, "", "the first frame it shows").not_null(),
       column("frames", &R::frames, "", "frames it shows").not_null(),
       column("json", &R::json, "", "Chrome trace-event JSON (opens in Perfetto)").not_null()});
  return table;
}

const Table<FrameCausesRow>& frame_causes_table() {
  using R = FrameCausesRow;
  static const Table<R> table(
      spec("frame_causes", kRun,
           "Per variant, run and frame, the critical-path attribution of its latency (model des; "
           "runs written with per-frame rows). docs/MODEL.md \"Critical-path attribution\".",
           {"run_id", "variant", "run", "frame_id"}, 5),
      {run_id_column(&R::run_id), variant_column(&R::variant),
       column("run", &R::run, "",
              "isolated (a frame alone: the latency of table frames) or streamed (frames at the "
              "sensor rate, queueing included)")
           .not_null(),
       column("frame_id", &R::frame_id, "", "the trace's frame id").not_null(),
       column("dropped", &R::dropped, "", "1: the camera queue dropped it (no causes)").not_null(),
       column("latency_ms", &R::latency_ms, "ms", "its latency in that run"),
       column("causes_json", &R::causes, "",
              "{cause: ms}: `<resource>.run` or `.wait`, those that took time; they add up to "
              "latency_ms")
           .not_null()});
  return table;
}

const Table<SeedRunRow>& seed_runs_table() {
  using R = SeedRunRow;
  static const Table<R> table(
      spec("seed_runs", kRun,
           "A run of one seed of a workload simulated over seeds (`edx simulate --workload W "
           "--seeds S --out`): the runs of one platform and workload are one figure's samples "
           "(the report's intervals).",
           {"run_id"}, 5),
      {run_id_column(&R::run_id),
       column("workload", &R::workload, "",
              "FNV-1a 64 of the resolved workload without its seed and the tracing code's version "
              "(the group of seeds)")
           .not_null(),
       column("workload_json", &R::workload_json, "", "the workload's parameters, without the seed")
           .not_null(),
       column("seed", &R::seed, "", "the seed of its worlds").not_null()});
  return table;
}

const Table<SweepRow>& sweeps_table() {
  using R = SweepRow;
  static const Table<R> table(
      spec("sweeps", kSweep, "One row per sweep (`edx sweep`).", {"sweep_id"}),
      {sweep_id_column(&R::sweep_id),
       column("spec", &R::spec, "", "the spec file as given").not_null(),
       column("base", &R::base, "", "the base platform file").not_null(),
       column("trace", &R::trace, "", "the trace, or a workload sweep's trace store").not_null(),
       column("points", &R::points, "", "design points of the spec (grid size or samples)")
           .not_null(),
       column("spec_json", &R::spec_json, "",
              "the spec as run; objectives: [{\"minimize\"|\"maximize\": metric}, ...]")
           .not_null()});
  return table;
}

const Table<SweepPointRow>& sweep_points_table() {
  using R = SweepPointRow;
  static const Table<R> table(
      spec("sweep_points", kSweep, "One row per evaluated design point.", {"sweep_id", "point"}),
      {sweep_id_column(&R::sweep_id),
       column("point", &R::point, "",
              "its index in the spec's points (grid: last parameter "
              "fastest)")
           .not_null(),
       column("run_id", &R::run_id, "", "its run (joins runs and the run tables); '' when none")
           .not_null()
           .label("run"),
       column("parameters_json", &R::parameters, "", "{dotted platform key: value}").not_null(),
       column("metrics_json", &R::metrics, "", "{objective or constraint metric: value}")
           .not_null(),
       column("feasible", &R::feasible, "", "1: every constraint holds").not_null(),
       column("pareto", &R::pareto, "", "1: on the Pareto front of the feasible points")
           .not_null_default("0")
           .label("Pareto"),
       column("workload", &R::workload, "",
              "hash of its workload point ('' when the sweep names a trace)")
           .not_null_default("''")
           .since(3),
       column("error", &R::error, "", "why it has no run (its workload failed), else NULL")
           .since(3),
       column("bottleneck", &R::bottleneck, "",
              "the resource holding the largest share of its accelerated variant's mean latency "
              "(isolated run; frame_causes), NULL when not modelled")
           .since(5)});
  return table;
}

const Table<SweepLockRow>& sweep_locks_table() {
  using R = SweepLockRow;
  static const Table<R> table(
      spec("sweep_locks", kSweep,
           "The process running a sweep (one at a time per database); removed when it ends.",
           {"sweep_id"}),
      {sweep_id_column(&R::sweep_id), column("pid", &R::pid, "", "its process id").not_null(),
       column("host", &R::host, "", "its host name").not_null(),
       column("started", &R::started, "UTC", "when it took the lock (YYYY-MM-DD HH:MM:SS)")
           .not_null()});
  return table;
}

const Table<RunClaimRow>& run_claims_table() {
  using R = RunClaimRow;
  static const Table<R> table(
      spec("run_claims", kSweep,
           "A run being simulated by a sweep: a sweep that needs the same run (another spec over "
           "the same design and trace) waits for it instead of simulating it twice; removed when "
           "the run is stored or its sweep ends.",
           {"run_id"}, 6),
      {sweep_id_column(&R::sweep_id),
       column("run_id", &R::run_id, "", "the run being simulated").not_null(),
       column("pid", &R::pid, "", "its process id").not_null(),
       column("host", &R::host, "", "its host name").not_null(),
       column("since", &R::since, "UTC", "when it claimed the run (YYYY-MM-DD HH:MM:SS)")
           .not_null()});
  return table;
}

const Table<SweepGenerationRow>& sweep_generations_table() {
  using R = SweepGenerationRow;
  static const Table<R> table(
      spec("sweep_generations", kSweep, "A search's convergence (nsga2 only), per generation.",
           {"sweep_id", "generation"}, 2),
      {sweep_id_column(&R::sweep_id),
       column("generation", &R::generation, "", "0: the initial population").not_null(),
       column("evaluations", &R::evaluations, "", "distinct designs evaluated so far")
           .not_null()
           .label("designs simulated"),
       column("front_size", &R::front_size, "", "designs on the feasible front")
           .not_null()
           .label("front"),
       column("hypervolume", &R::hypervolume, "",
              "hypervolume of the feasible front (objectives normalized)")
           .not_null()});
  return table;
}

const Table<SweepWorkloadRow>& sweep_workloads_table() {
  using R = SweepWorkloadRow;
  static const Table<R> table(
      spec("sweep_workloads", kSweep,
           "A workload sweep's traces: per workload point, its trace in the trace store or the "
           "error that stopped it.",
           {"sweep_id", "workload"}, 3),
      {sweep_id_column(&R::sweep_id),
       column("workload", &R::workload, "", "content hash of the workload point").not_null(),
       column("workload_json", &R::workload_json, "", "its resolved parameters").not_null(),
       column("trace", &R::trace, "", "its trace file in the trace store").not_null(),
       column("trace_hash", &R::trace_hash, "", "the trace's trace_hash (its runs' trace_hash)")
           .not_null(),
       column("error", &R::error, "", "why it could not be traced, else NULL"),
       column("seconds", &R::seconds, "s", "tracing time (NULL: found in the store)"),
       column("host", &R::host, "", "host that traced it (NULL: found in the store)")});
  return table;
}

const std::vector<const TableSpec*>& all_tables() {
  static const std::vector<const TableSpec*> tables{
      &runs_table().spec,           &frames_table().spec,
      &latency_table().spec,        &throughput_table().spec,
      &energy_table().spec,         &offload_table().spec,
      &schedule_table().spec,       &resources_table().spec,
      &timelines_table().spec,      &frame_causes_table().spec,
      &seed_runs_table().spec,      &sweeps_table().spec,
      &sweep_points_table().spec,   &sweep_locks_table().spec,
      &run_claims_table().spec,     &sweep_generations_table().spec,
      &sweep_workloads_table().spec};
  return tables;
}

std::vector<const TableSpec*> tables_of(TableGroup group) {
  std::vector<const TableSpec*> out;
  for (const TableSpec* t : all_tables()) {
    if (t->group == group) out.push_back(t);
  }
  return out;
}

const TableSpec* find_table(std::string_view name) {
  for (const TableSpec* t : all_tables()) {
    if (t->name == name) return t;
  }
  return nullptr;
}

namespace {

/// `rows` by view: the run's one row is read in place, not copied into a vector (its summary
/// and config JSON are large).
template <class Row>
TableValues values_of(const Table<Row>& table, std::type_identity_t<std::span<const Row>> rows) {
  TableValues out{&table.spec, {}};
  for (const Row& r : rows) out.rows.push_back(table.values(r));
  return out;
}

}  // namespace

std::vector<TableValues> run_values(const RunRows& rows) {
  return {values_of(runs_table(), {&rows.run, 1}),
          values_of(frames_table(), rows.frame_rows),
          values_of(latency_table(), rows.latency),
          values_of(throughput_table(), rows.throughput),
          values_of(energy_table(), rows.energy),
          values_of(offload_table(), rows.offload),
          values_of(schedule_table(), rows.schedule),
          values_of(resources_table(), rows.resources),
          values_of(timelines_table(), rows.timelines),
          values_of(frame_causes_table(), rows.frame_causes),
          values_of(seed_runs_table(), rows.seed_runs)};
}

std::string results_reference_markdown() {
  std::string md = fmt::format(
      "# Results database reference\n\n"
      "Every table and column of a results database (`edx simulate --out`, `edx sweep --db`), "
      "schema version {}. Generated by `edx export --reference` from the declaration of each "
      "table (`arch/results/schema.cpp`, with `arch/results/table.hpp`); a test fails when this "
      "file is not its current output. How runs are keyed and replaced: "
      "[MODEL.md](MODEL.md) \"Results database\"; sweeps: [SWEEPS.md](SWEEPS.md).\n\n"
      "The schema version is SQLite's `user_version`. A writer brings an older database to the "
      "current version (missing tables created, missing columns added, NULL in the rows already "
      "there); readers read every older version (a missing column reads as NULL) and refuse a "
      "newer one. A REAL that is not finite is stored as NULL; in a nullable TEXT column, an "
      "empty text is NULL. `edx export DB --table T` writes a table as CSV with these columns as "
      "its header.\n",
      kSchemaVersion);
  md += "\n## Run tables\n\nEvery row carries its run's `run_id`.\n";
  for (const TableSpec* t : tables_of(kRun)) md += fmt::format("\n{}", table_reference(*t));
  md += "\n## Sweep tables\n\nWritten by `edx sweep`; every row carries its sweep's `sweep_id`.\n";
  for (const TableSpec* t : tables_of(kSweep)) md += fmt::format("\n{}", table_reference(*t));
  return md;
}

}  // namespace edx::results
