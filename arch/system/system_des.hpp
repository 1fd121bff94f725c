#pragma once
// The whole platform as one discrete-event simulation on sim_core (docs/MODEL.md, "System
// DES"): frames arrive from the cameras, the frontend (the accelerator's task units, or a host
// thread on the CPU baseline) turns them into results that cross the link (transfer 1) into a
// bounded queue, and the backend thread on a host core takes them in order and runs the frame's
// backend: its host work on a core, each offloaded kernel as transfer 2 (operands, host -> FPGA),
// its spill reads when its operands exceed the SPM, the kernel's ops on the backend units, its
// spill writes, transfer 3 (results, FPGA -> host), the thread blocked meanwhile. Everything that
// is shared is a sim::Resource and contends: the frontend units, the frame buffers, each link
// direction's DMA slots and wire (transfer 1 of the next frame against this frame's kernel
// transfers), the backend units, the host cores.
//
//   camera ──► camera queue (queue_depth, drop) ──► frontend ──► link ──► results queue
//      (results_queue_depth, back-pressure: a full queue holds the frontend's frame buffer)
//   ──► backend thread: [host work | transfer 2 → units → transfer 3]* ──► frame done
//
// Two runs per variant:
//   isolated  one frame in the system at a time, back to back: per-frame latency as the paper
//             defines it (frontend + backend of a frame alone), and FPS without FE/BE pipelining
//   streamed  frames at the sensor rate (or back to back): FPS with FE/SM and FE/BE pipelining,
//             latency from arrival including queueing, drops, utilization of every resource
// With `contention: false` every transfer has an idle link to itself, a kernel takes its
// analytical Σ op cycles, the queues are unbounded: the model of docs/MODEL.md "System" (the
// analytical one), which the DES then reproduces (a test).
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "arch/backend/offload_accelerator.hpp"
#include "arch/frontend/frontend_model.hpp"
#include "arch/host/frontend_graph.hpp"
#include "arch/link/link.hpp"
#include "arch/platform/system_config.hpp"
#include "sim_core/engine.hpp"

namespace edx::arch {

/// One offloaded kernel invocation as the DES runs it.
struct OffloadWork {
  const OffloadPlan* plan = nullptr;  ///< its plan on the offload accelerator
  std::int64_t input_bytes = 0;       ///< transfer 2
  std::int64_t output_bytes = 0;      ///< transfer 3
  std::string label;  ///< "f<frame> <kernel>" (names timeline spans; may be empty without one)
  /// Out of core (docs/MODEL.md, "SPM spills"): DRAM bytes its ops read before the units run
  /// and write after them, on the link (the accelerator's path to DRAM); 0 when it fits.
  std::int64_t spill_read_bytes = 0, spill_write_bytes = 0;
};

/// One step of a frame's backend thread: host work, or an offloaded kernel.
struct BackendStep {
  double host_ms = 0;  ///< host work on a core (offload < 0)
  int offload = -1;    ///< index into SystemFrameWork::offloads
};

/// A frame's work, as both variants run it.
struct SystemFrameWork {
  std::int64_t frame_id = 0;
  double frontend_host_ms = 0;  ///< CPU baseline: the frontend thread's work
  /// CPU baseline: the frontend's chains by stage (ms; arch/host/frontend_graph.hpp), each chain
  /// on a core of its own when one is free, its device part on the baseline's coprocessor (one
  /// row at a time); empty: frontend_host_ms on one core.
  StageChains frontend_host_chains;
  double backend_host_ms = 0;              ///< CPU baseline: the backend thread's work on a core
  double backend_device_ms = 0;            ///< CPU baseline: then its work on the coprocessor
  std::vector<BackendStep> backend_steps;  ///< accelerated: host work and offloads in order
  std::vector<OffloadWork> offloads;
  FrontendFrameTiming frontend;  ///< accelerated: prepared task rows and transfer-1 bytes
};

/// Splits a frame's backend into the steps of its thread on the accelerated platform: the
/// offloaded kernels (`offloaded[k]` for accelerable kernel k of the frame, in trace order) at
/// their trace positions, the host work around them. The trace records no time stamps inside the
/// backend, so the host time outside the frame's kernels is spread evenly over the gaps before,
/// between and after them; the host kernels sit in their gaps. The steps' host time adds up to
/// H = max(0, backend_ms − Σ_offloaded host_ms) (scaled to it when the kernels' host times add up
/// to more than the backend's own).
std::vector<BackendStep> split_backend(const trace::FrameTrace& frame, double backend_ms,
                                       const std::vector<double>& kernel_host_ms,
                                       const std::vector<bool>& offloaded);

/// Critical-path attribution (docs/MODEL.md, "Critical-path attribution"): each frame's latency
/// split into causes that add up to it exactly (integer ps). A cause is a resource and a state,
/// "<resource>.run" (the frame's own work held it) or "<resource>.wait" (the frame waited for
/// it). The frame's path is sequential except in the frontend, whose critical path is walked back
/// through its task graph from the last of DR and LSS (the predecessor that finished last, each
/// task's wait from its ready time to its start), and the CPU baseline's frontend chains, of
/// which the last to finish counts. Resources:
///   sensor                    wait: in the camera queue (streamed runs)
///   frontend.<task>           the frontend units (accelerated)
///   link.<direction>          run: the transfer's time on the idle link; wait: the rest
///   host                      the host cores (backend thread, baseline frontend)
///   coprocessor               the CPU baseline's GPU or DSP
///   backend.spill             a kernel's spill traffic on the link (run and wait as a link's)
///   queue.results             wait: the results waited for the backend thread
///   backend.<unit>            the offload accelerator's resources (resource_names())
class CauseLayout {
 public:
  explicit CauseLayout(std::vector<std::string> backend_resources);
  static constexpr std::size_t kSensorWait = 0;
  static std::size_t frontend(trace::Task task) { return 1 + 2 * static_cast<std::size_t>(task); }
  static std::size_t link(Direction d) { return 15 + (d == Direction::HostToFpga ? 0 : 2); }
  static constexpr std::size_t kHost = 19, kCoprocessor = 21, kSpill = 23;
  static constexpr std::size_t kResultsWait = 25;
  /// Causes before the backend units' (a frame's fixed part).
  static constexpr std::size_t kFixed = 26;
  /// The run cause of backend resource i (its wait is the next).
  static std::size_t backend(std::size_t i) { return kFixed + 2 * i; }
  /// A resource's wait cause: run cause + 1.
  static constexpr std::size_t kWait = 1;
  std::size_t size() const { return names_.size(); }
  /// "sensor.wait", "frontend.FD.run", ... (sensor and queue.results have a wait only).
  const std::vector<std::string>& names() const { return names_; }

 private:
  std::vector<std::string> names_;
};

/// One frame of a run (ps from the run's start).
struct SystemFrameTiming {
  std::int64_t frame_id = 0;
  bool dropped = false;
  sim::Time arrival = 0;        ///< the camera delivered it (back to back: when taken)
  sim::Time start = 0;          ///< the frontend started it
  sim::Time frontend_end = 0;   ///< its results are at the host
  sim::Time backend_start = 0;  ///< the backend thread took it
  sim::Time end = 0;            ///< the backend finished it
  double host_busy_ms = 0;      ///< host core time of its backend (and baseline frontend)
};

/// A resource's use over a run.
struct ResourceUse {
  std::string name;  ///< e.g. "frontend.DR", "link.fpga_to_host", "host.cores", "queue.camera"
  double busy = 0;   ///< mean busy fraction of its capacity; queues: mean occupancy (frames)
  double max = 0;    ///< queues: largest occupancy; resources: capacity
};

struct SystemRun {
  bool accelerated = false, isolated = false;
  std::vector<SystemFrameTiming> frames;  ///< in trace order (dropped ones flagged)
  std::size_t dropped = 0;
  double makespan_ms = 0;   ///< first start to last end
  double fps = 0;           ///< (n − 1) / (last end − first end) over processed frames
  double host_busy_ms = 0;  ///< Σ core busy time
  std::vector<ResourceUse> resources;
  /// Critical-path attribution (CauseLayout): frames × causes, row-major, ps; a frame's row adds
  /// up to its latency (isolated: end − start; streamed: end − arrival); 0 for a dropped frame.
  std::vector<std::string> causes;
  std::vector<sim::Time> cause_ps;
  nlohmann::json to_json() const;  ///< summary (no frames)
};

/// Optional whole-system timeline of a run: frames [first, first + count) and everything that
/// ran while they were in the system, one Perfetto track per unit, link direction, host thread
/// and queue.
struct SystemTimelineOptions {
  sim::Timeline* timeline = nullptr;
  std::size_t first = 0, count = 10;
};

/// Runs `work` on `platform` (validated). `accelerated`: the FPGA variant, else the CPU
/// baseline. `isolated`: one frame at a time, back to back; else streamed (platform.system).
/// `frontend`, `backend`, `link`, `host_cores` come from the platform (see system_model).
SystemRun run_system(const std::vector<SystemFrameWork>& work, const FrontendConfig& frontend,
                     const OffloadAccelerator& backend, const Link& link, int host_cores,
                     const SystemConfig& system, bool accelerated, bool isolated,
                     const SystemTimelineOptions& timeline = {});

}  // namespace edx::arch
