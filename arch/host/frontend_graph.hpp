#pragma once
// The frontend's work on the host's cores as the traced pipeline runs it (docs/MODEL.md, "Host
// CPU: the frontend on the cores"; issue 41): stages one after the other, each stage's chains
// side by side, a chain's tasks one after another (workloads/frontend/stereo_frontend.cpp):
//
//   stage 1  [DC, LSS]  [FD L, IF L]  [FD R, IF R]    temporal matching beside both detections
//   stage 2  [FC L]  [FC R]                           the two descriptions
//   stage 3  [MO, DR, the frame's rest]               matching, refinement, bookkeeping
//
// The graph is the pipeline's dependency structure, whatever the tracing machine did with it: a
// trace made with `frontend.parallel_images: false` ran the chains one after the other on the
// tracing machine, but its task rows are the same work (their CPU times, or the op-count model
// of their work). The latency on c cores list-schedules each stage's chains in the order above (the
// pipeline starts the longest chain first) onto the earliest free of min(c, chains) cores:
//
//   t_fe = Σ_stages makespan(stage, c)        (c = 1: the sum of every task and the rest)
//
// The whole-system DES runs the same chains on the host's cores, where the backend thread
// competes for them when frames stream.
#include <cstddef>
#include <vector>

#include "workloads/trace/records.hpp"

namespace edx::arch {

/// Task indices (into a frame's task rows) by stage and chain; kRest stands for the frame's
/// time outside its tasks.
struct HostFrontendGraph {
  static constexpr std::size_t kRest = static_cast<std::size_t>(-1);
  std::vector<std::vector<std::vector<std::size_t>>> stages;
};

/// The graph of a frame's task rows; a task the pipeline does not know joins the last stage.
HostFrontendGraph frontend_graph(const std::vector<trace::TaskRecord>& tasks);

/// A chain's time, ms: on the baseline's offload coprocessor (arch/host/coprocessor.hpp), then on
/// a host core. The chain's device rows run first (the coprocessors' image tasks lead their
/// chains: FD before IF, DC before LSS; stage 3's one chain is the same latency in any order),
/// the thread waiting for them without a core.
struct ChainTime {
  double host_ms = 0;
  double device_ms = 0;
  bool operator==(const ChainTime&) const = default;
};
/// A frame's chains by stage.
using StageChains = std::vector<std::vector<ChainTime>>;

/// Each stage's chains' times of a frame: the sums of its tasks' `task_ms` (one per row of
/// `tasks`) by frontend_graph's stages and chains, the rest `rest_ms` in the last stage's chain.
/// A task with `on_device[i]` (empty: none) counts as the chain's device time.
StageChains chain_times(const std::vector<trace::TaskRecord>& tasks,
                        const std::vector<double>& task_ms, double rest_ms,
                        const std::vector<bool>& on_device = {});

/// Σ over stages of the stage's latency on `cores` cores (>= 1) and one coprocessor. In a stage
/// the device runs the chains' device parts back to back in chain order, chain i's ending at
/// D_i = Σ_{j <= i} device_ms_j (0 for a chain without one); the host parts then take the
/// earliest free of min(cores, chains) cores in the order they become ready (D_i, then chain
/// order), each starting at max(D_i, the core's free time); the stage ends when the last part
/// does. Without device parts: the chains list-scheduled in order (c = 1: their sum).
double frontend_latency_ms(const StageChains& stage_chains, int cores);

}  // namespace edx::arch
