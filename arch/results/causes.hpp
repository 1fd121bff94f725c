#pragma once
// Critical-path attribution as data (docs/MODEL.md, "Critical-path attribution"): each frame's
// latency in one variant and run split into causes "<resource>.run|wait" that add up to it,
// and their summaries per backend mode and over all frames. The system model fills a
// CauseTable from its DES; `edx explain` and the report rebuild it from the results database
// (table frame_causes) and summarize it here, so both print the same figures. No model code.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "arch/results/schema.hpp"

namespace edx::results {

/// One variant's attribution over one run ("isolated": a frame alone, the paper's latency;
/// "streamed": frames at the sensor rate, queueing included).
struct CauseTable {
  std::vector<std::string> causes;  ///< column names
  struct Frame {
    std::int64_t frame_id = 0;
    std::string mode;  ///< registration | vio | slam | none
    bool dropped = false;
    double latency_ms = 0;  ///< Σ of its row
  };
  std::vector<Frame> frames;
  std::vector<double> ms;  ///< frames × causes, row-major
  double at(std::size_t frame, std::size_t cause) const {
    return ms[frame * causes.size() + cause];
  }
};

/// The resource of a cause: "frontend.FC.run" -> "frontend.FC", "sensor.wait" -> "sensor".
std::string_view cause_resource(std::string_view cause);

struct CauseShare {
  std::string name;    ///< a cause, or a resource
  double mean_ms = 0;  ///< over the summary's processed frames
  double share = 0;    ///< mean_ms / mean latency
};

/// The causes of a set of frames (a mode, or "all").
struct CauseSummary {
  std::string mode;
  std::size_t frames = 0;             ///< processed (not dropped)
  double latency_ms = 0;              ///< mean
  std::vector<CauseShare> causes;     ///< by mean, largest first; causes of mean 0 left out
  std::vector<CauseShare> resources;  ///< run + wait per resource, largest first
  /// The resource holding the largest share of the mean latency ("" without frames).
  std::string bottleneck() const { return resources.empty() ? "" : resources.front().name; }
  nlohmann::json to_json() const;
};

/// Summaries per mode present (sorted by name), then "all".
std::vector<CauseSummary> summarize_causes(const CauseTable& table);

/// {mode: summary.to_json()} of summarize_causes.
nlohmann::json causes_json(const CauseTable& table);

/// The table's rows of frame_causes (its causes of 0 ms left out of each row).
std::vector<FrameCausesRow> frame_causes_rows(const std::string& run_id, const std::string& variant,
                                              const std::string& run, const CauseTable& table);
/// The CauseTable of `variant` and `run` from a run's frame_causes rows, the frames' modes
/// from its frames rows (a frame without one: "none"); causes in the order first seen. Throws
/// std::runtime_error naming the frame when a cause is not a finite number.
CauseTable cause_table_of(const std::vector<FrameCausesRow>& rows,
                          const std::vector<FrameRow>& frames, const std::string& variant,
                          const std::string& run);

}  // namespace edx::results
