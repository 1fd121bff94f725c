#pragma once
// `edx explain`: why a run's frames took what they took (docs/MODEL.md, "Critical-path
// attribution"; docs/REPORTS.md, "Explain"): per variant (baseline, accelerated) and run
// (isolated: a frame alone; streamed: at the sensor rate, queueing included) the mean of each
// cause per mode and over all frames, the bottleneck resource, and one frame's causes.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "reports/results_reader.hpp"

namespace edx::reports {

struct ExplainRequest {
  std::string run_id;                 ///< "" : the database's only run
  std::optional<std::int64_t> frame;  ///< also this frame's causes (needs per-frame rows)
};

/// {run_id, platform, trace, attribution: {variant: {run: {mode: summary}}}, frame?: {frame_id,
/// mode, variants: {variant: {run: {latency_ms, dropped, causes: {cause: ms}}}}}}. Throws
/// std::runtime_error (one line naming the database) when the run has no attribution (model
/// analytical, or written before schema version 5), or the frame has no rows.
nlohmann::json explain_run(const ResultsData& data, const ExplainRequest& request);

/// explain_run's JSON as text: per variant and run a table of causes by mode (mean ms and
/// share), the bottleneck of each mode; then the frame's causes.
std::string format_explain(const nlohmann::json& explained);

}  // namespace edx::reports
