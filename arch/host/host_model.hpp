#pragma once
// A trace's host times on a host processor (DESIGN.md, "Host CPU"; docs/MODEL.md, "Host CPU"):
// the host time of every frontend task and backend kernel on a CPU given by its times on the
// reference suite (SuiteTimes; the `suite_scaled` host kind, host_processor.hpp), from one of two
// sources (`host.times`):
//
//   modeled (the default):  t(row) = S_platform x sum_j c_j x_j(row)      (host_costs.hpp)
//   measured:               t_platform(f) = t_trace(f) x S_platform / S_trace(f)
//
// Modeled times cost the work the trace records (x) by the bundled table (c), so the same work
// gives the same times whatever machine traced it. Measured times map the trace's CPU times from
// the machine that traced them through the two machines' speeds on the same reference suite
// (trace/host_speed.hpp). S is the suite's frontend part for frontend work and the backend part
// for the backend (each kernel and the backend's whole time of a frame). S_platform is declared
// in the config with its provenance (measured on that CPU with `edx host-speed`, derived from a
// datasheet ratio, or calibrated against a paper figure: then say so). S_trace(f) is measured
// while tracing (meta host_speed): the median of the kLocalSamples samples taken nearest frame f,
// so that a tracing machine whose speed drifts during the trace (another tenant, a frequency
// change) is measured beside the frames it slowed; a trace without per-sample data uses its
// overall medians. A host that declares no suite times replays the trace's host times as they
// are.
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "workloads/trace/host_speed.hpp"

namespace edx::arch {

/// Samples of the tracing machine's speed a frame is mapped by (the nearest ones).
inline constexpr std::size_t kLocalSamples = 9;

/// Where a platform's host times come from (docs/MODEL.md, "Host CPU").
enum class HostTimeSource {
  /// The op-count model (host_costs.hpp): each row's work × the bundled costs × the suite time.
  kModeled,
  /// The trace's measured CPU times × the suite-time ratio (this host over the tracing one).
  kMeasured,
};
const char* to_string(HostTimeSource times);
/// Throws std::invalid_argument on anything but "modeled" or "measured".
HostTimeSource parse_host_times(const std::string& text);

/// A host's times on the reference suite (docs/TRACE.md "Host speed"): S_platform, the factor
/// of its modeled times and the map of measured ones. Both parts 0: the trace host is the target.
struct SuiteTimes {
  std::string host;  ///< the host's name (errors, bases)
  /// Reference-suite version the times are for (a trace's and the cost table's must match).
  int suite = trace::kHostSpeedSuite;
  double frontend_ms = 0;  ///< the suite's frontend part on this host, CPU ms
  double backend_ms = 0;   ///< its backend part
  std::string frontend_provenance, backend_provenance;  ///< where each comes from
  bool identity() const { return frontend_ms == 0 && backend_ms == 0; }
};

/// The factors a trace's host times are multiplied by on a platform, per frame.
class HostMapping {
 public:
  HostMapping() = default;
  /// S_platform over the trace's speed around `frame_id` (0-based, the trace's frame order).
  double frontend_scale(std::int64_t frame_id) const { return scale(frontend_, frame_id); }
  double backend_scale(std::int64_t frame_id) const { return scale(backend_, frame_id); }
  /// The factors at the trace's overall medians (what the summary prints).
  double mean_frontend_scale() const { return frontend_.overall; }
  /// e.g. "x1.86 = 172.1 ms / 92.6 ms on the suite v1 (calibrated: ...)".
  const std::string& frontend_basis() const { return frontend_basis_; }
  const std::string& backend_basis() const { return backend_basis_; }
  /// Adds `text` to both parts' basis (a processor that scales the rows further says how).
  void append_basis(const std::string& text) {
    frontend_basis_ += text;
    backend_basis_ += text;
  }
  nlohmann::json to_json() const;

 private:
  friend HostMapping map_host(const SuiteTimes&, const trace::TraceMeta&, const std::string&);
  friend struct PlatformHostTimes;
  /// One part's factors: at the overall median, and per frame id (empty: the overall one).
  struct Part {
    double overall = 1.0;
    std::vector<double> per_frame;
  };
  static double scale(const Part& part, std::int64_t frame_id);
  Part frontend_, backend_;
  std::string frontend_basis_ = "x1: the trace host is the target";
  std::string backend_basis_ = "x1: the trace host is the target";
};

/// The mapping of a trace (its meta) onto `host`. Throws std::runtime_error naming `trace_name`
/// when the platform states suite times and the trace has no usable host_speed, or the two
/// suite versions differ.
HostMapping map_host(const SuiteTimes& host, const trace::TraceMeta& trace_meta,
                     const std::string& trace_name);

struct HostCostModel;
enum class CostPart;

/// A factor on each row's host time by the row's part and kind (a datasheet processor's ratio
/// to its reference, arch/host/throughput.hpp); nullptr: 1 for every row.
using RowFactor = std::function<double(CostPart part, std::string_view kind)>;

/// A trace's host times on a platform's host (ms): what HostProcessor::host_times answers.
struct PlatformHostTimes {
  std::vector<double> frontend_ms;             ///< per frame, the whole frontend
  std::vector<std::vector<double>> task_ms;    ///< per frame, per task row (trace order)
  std::vector<double> backend_ms;              ///< per frame, kernels and the rest
  std::vector<std::vector<double>> kernel_ms;  ///< per frame, per kernel row
  HostMapping mapping;                         ///< the factors and their basis
  HostTimeSource source = HostTimeSource::kMeasured;
  nlohmann::json to_json() const;

  /// The times on a host of suite times `host`, from `source`:
  ///   modeled: t = S_platform × Σ_j c_j x_j(row) (host_costs.hpp), a frame's frontend the sum
  ///     over its tasks plus the frontend rest, its backend the sum over its kernels plus its
  ///     mode's backend rest;
  ///   measured: t = t_trace × S_platform / S_trace(f) (map_host);
  ///   a host without suite times (either source): the trace's times as they are.
  /// Each row (a task, a kernel, a part's rest: a frame's measured time outside its rows) then
  /// times `factor(part, kind)` when given.
  /// `costs`: the cost table of modeled times (nullptr: the bundled one). Throws
  /// std::runtime_error naming `trace_name` (map_host's errors; a row the cost table has no
  /// costs for; a cost table of another suite version than the host's).
  static PlatformHostTimes suite_scaled(const SuiteTimes& host, HostTimeSource source,
                                        const std::vector<trace::FrameTrace>& frames,
                                        const trace::TraceMeta& trace_meta,
                                        const std::string& trace_name,
                                        const HostCostModel* costs = nullptr,
                                        const RowFactor& factor = nullptr);
};

}  // namespace edx::arch
