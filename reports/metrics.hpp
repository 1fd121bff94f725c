#pragma once
// Figures of one run that `edx check` compares with the paper and `edx report` tabulates.
//
// The metric tree of a run is a JSON object:
//   system.*   the run's summary (runs.summary_json = `edx simulate --json` "system"), e.g.
//              system.comparison.all.e2e_speedup, system.accelerated.fps_with_pipelining
//   frontend.* the frontend study (`edx simulate --json` "frontend"); only when the run is
//              simulated by `edx check --config --trace` (the results database does not hold it)
//   derived.*  computed here from the frames and offload/schedule tables:
//     derived.kernels.<k>.speedup            Σ host_ms / Σ accel_ms over the invocations of k that
//                                            fit the SPM (the accelerator's speedup of the kernel)
//     derived.kernels.<k>.latency_reduction  1 − Σ accel_ms / Σ host_ms (same invocations)
//     derived.schedule.<k>.r_squared_eval / r_squared_train / gap_to_oracle
//     derived.schedule.<k>.offloaded_fraction  offloaded / invocations (evaluation frames)
//     derived.schedule.<k>.always_vs_policy    always_s / policy_s − 1 (null: never fits)
//     derived.backend.<mode>.<variant>.<part>  mean ms per frame of the backend split into each
//                                              accelerable kernel and "other" (host-only code)
// A metric path is the dotted list of keys from the root, e.g.
// "derived.kernels.projection.speedup".
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "reports/confidence.hpp"
#include "reports/results_reader.hpp"

namespace edx::reports {

/// Backend time of the frames of one mode and variant split into parts (kernels, "other").
struct BackendBreakdown {
  std::string mode, variant;
  std::size_t frames = 0;
  std::vector<std::pair<std::string, double>> parts;  ///< (kernel or "other", mean ms per frame)
};

/// Per mode (registration, vio, slam, none present in the run, then "all") and variant
/// (baseline, accelerated): a kernel costs host_ms on the baseline and, on the accelerated
/// variant, accel_ms when offloaded else host_ms; other = backend_ms(baseline) − Σ host_ms.
std::vector<BackendBreakdown> backend_breakdown(const RunData& run);

/// The metric tree of `run` (see above) without "frontend".
nlohmann::json run_metrics(const RunData& run);

/// Every number of `tree` by dotted path (objects only: arrays are left out), in key order.
std::vector<std::pair<std::string, double>> numeric_figures(const nlohmann::json& tree);

/// Over several runs' metric trees (seeds of one workload): each figure of numeric_figures that
/// every tree holds, with its mean and 95 % Student-t interval (reports/confidence.hpp), in the
/// first tree's order.
std::vector<std::pair<std::string, Interval>> figures_over_runs(
    const std::vector<nlohmann::json>& trees);

/// The headline figures of a run's summary tree ({"system": ...}): per variant and mode the
/// mean e2e latency and energy per frame, the FPS with and without pipelining, the e2e speedup
/// per mode.
bool is_headline_figure(const std::string& path);

/// figures_over_runs as a table (`edx simulate --seeds`): figure, mean, [low, high], n;
/// `headline_only`: is_headline_figure's.
std::string format_figures_over_runs(const std::vector<std::pair<std::string, Interval>>& figures,
                                     bool headline_only);

/// The value at dotted `path` in `tree`, when it is there and a number.
std::optional<double> metric_at(const nlohmann::json& tree, const std::string& path);

/// The backend mode whose frames a metric is computed from, by the tree's keying: the <mode> of
/// system.comparison.<mode>.*, system.<variant>.modes.<mode>.* and derived.backend.<mode>.*, and
/// the mode that runs kernel <k> (arch/kernels: AccelerableKernel::mode) of derived.kernels.<k>.*
/// and derived.schedule.<k>.*. std::nullopt for figures over all frames (<mode> "all"), of no
/// mode (resources, FPS, baselines, frontend) and of a kernel edx does not know.
std::optional<std::string> metric_mode(const std::string& path);

/// The modes the run of a metric tree has frames of: the keys of system.baseline.modes but "all"
/// whose `frames` is not 0. std::nullopt when the tree has no per-mode summary (then no mode can
/// be said to be absent).
std::optional<std::set<std::string>> modes_with_frames(const nlohmann::json& metrics);

/// The modes of a run in display order (registration, vio, slam, none; only those present).
std::vector<std::string> run_modes(const RunData& run);

}  // namespace edx::reports
