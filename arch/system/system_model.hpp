#pragma once
// The whole-system model of `edx simulate` (paper Sec. VII-C..E; docs/MODEL.md, "System"): per
// frame, the frontend (CPU: its host time on the platform's host, PlatformHostTimes: modeled
// from the trace's work or measured and scaled; accelerated: the frontend accelerator), the
// backend (CPU: its host time likewise; accelerated: the same with every kernel
// the scheduler offloads replaced by its transfers and its ops on the backend units), latency,
// throughput with and without FE/BE pipelining, energy per frame, and the FPGA resources of the
// platform. Two variants of one platform: "baseline" (CPU only: no FPGA, every kernel on the
// host) and "accelerated". Statistics per mode of the trace's frames (registration, vio, slam,
// none) and over all frames.
//
// Model "des" (the default): the whole platform as one discrete-event simulation
// (system_des.hpp): latency and FPS without pipelining from its isolated run (one frame in the
// system at a time), FPS with pipelining, latency with queueing, drops and utilization from its
// streamed run. Model "analytical" (cross-check; what the DES gives with `system.contention:
// false`), with t_host the platform host times (PlatformHostTimes) and O_f the offloaded
// kernels:
//   be_cpu(f) = t_host,backend(f)
//   be_acc(f) = be_cpu(f) − Σ_{k∈O_f} t_host(k) + Σ_{k∈O_f} (t_accel(k) + t_link(k))
// t_accel: the kernel's compute time on the offload accelerator (its plan; the paper's FPGA
// matrix units: Σ op cycles on the backend units / clock, accelerate_kernel);
// t_link: its inputs and results over an idle link (kernel_transfer_time), plus, for a kernel
// whose operands exceed the backend SPM, its spill traffic (kernel_replay.hpp: spill_seconds).
// Throughput (frames back to back): without FE/BE pipelining N / Σ_f e2e(f); with it, the backend
// of frame f starts when its frontend results are in and the backend of f−1 is done:
//   b_start(f) = max(fe_end(f), b_end(f−1)),  b_end(f) = b_start(f) + be(f),
//   FPS = (N − 1) / (b_end(N−1) − b_end(0))
// fe_end: accelerated, the frontend DES run with the platform's FE/SM pipelining, frames back
// to back; CPU, Σ_{g≤f} fe_cpu(g) (one frontend thread, a backend thread beside it).
#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "arch/cost/energy.hpp"
#include "arch/cost/resource_report.hpp"
#include "arch/platform/platform.hpp"
#include "arch/results/causes.hpp"
#include "arch/scheduler/scheduler.hpp"
#include "arch/system/frontend_study.hpp"
#include "arch/system/system_des.hpp"
#include "workloads/trace/records.hpp"

namespace edx::arch {

/// One invocation of an accelerable kernel and what the scheduler did with it.
struct KernelDecision {
  std::int64_t frame_id = 0;
  int kernel_seq = 0;  ///< position among the frame's kernels
  std::string kernel;
  double size = 0;               ///< the kernel's m (the scheduler's feature)
  double host_ms = 0;            ///< on the target CPU
  double accel_ms = 0;           ///< units + transfers + spill traffic
  double compute_ms = 0;         ///< units only
  double transfer_ms = 0;        ///< inputs + results on an idle link
  double spill_ms = 0;           ///< spill traffic on an idle link (0 when it fits the SPM)
  std::int64_t spill_bytes = 0;  ///< DRAM bytes read and written out of core
  bool fits_spm = true;          ///< false: its operands exceed the SPM and it spills
  bool training = false;         ///< profiled on the host to fit the models
  bool offloaded = false;
  nlohmann::json to_json() const;
};

/// Where an accelerated frame's work-proportional energy (compute + memory + link) goes, by
/// resource (docs/MODEL.md, "Energy per resource"), J.
struct EnergyParts {
  std::array<double, trace::kTasks.size()> frontend{};  ///< its task units, trace::Task order
  std::vector<double> backend;  ///< its matrix units, BackendConfig::units order
  double link_to_fpga = 0, link_to_host = 0, dram = 0;
  EnergyParts& operator+=(const EnergyParts& other);
  double total() const;
};

/// One frame of one variant.
struct FrameResult {
  std::int64_t frame_id = 0;
  std::string mode;  ///< the trace's backend_mode
  double frontend_ms = 0, backend_ms = 0, e2e_ms = 0;
  double host_busy_ms = 0;  ///< host computing within the frame
  int offloaded = 0;        ///< kernels offloaded
  cost::FrameActivity activity;
  cost::FrameEnergy energy;
  /// activity's dynamic energy split by resource (accelerated only).
  EnergyParts parts;
};

/// Which model computes latency and throughput.
enum class SystemModelKind { kDes, kAnalytical };
const char* to_string(SystemModelKind kind);
/// "des" | "analytical"; throws std::runtime_error otherwise.
SystemModelKind parse_system_model(const std::string& text);

/// Options of simulate_system beyond the platform.
/// The CPU baseline's two whole-system DES runs (model "des"), isolated and streamed. They read
/// the frontend study (the baseline's frontend chains, backend host and coprocessor times), the
/// frames' ids, the baseline host's cores and `system:` only: platforms with equal
/// baseline_des_key on one trace have equal runs (sweeps share them).
struct BaselineRuns {
  SystemRun isolated, streamed;
};

struct SystemSimOptions {
  SystemModelKind model = SystemModelKind::kDes;
  /// Model "des": the baseline's runs when already made (run_baseline_des on this platform's
  /// baseline_des_key, frames and frontend study); null: made here.
  std::shared_ptr<const BaselineRuns> baseline;
  /// The whole-system timeline of the accelerated streamed run (frames [first, first + count)),
  /// written as Perfetto JSON; empty: none.
  std::optional<std::filesystem::path> timeline;
  std::size_t timeline_first = 0, timeline_count = 10;
  /// Threads for a run's independent parts: the frontend study's (FrontendStudyOptions) and
  /// the DES's four runs (baseline and accelerated, isolated and streamed). The results do not
  /// depend on it; a sweep, whose points run side by side already, keeps 1.
  int threads = 1;
};

/// The streamed run of a variant (model "des"): frames at the sensor rate or back to back.
struct StreamSummary {
  double sensor_fps = 0;  ///< 0: back to back
  std::size_t frames = 0, dropped = 0;
  double fps = 0;
  Distribution latency_ms;  ///< arrival to backend end, queueing included (processed frames)
  double energy_j = 0;      ///< per processed frame: Σ energy_by_resource / processed frames
  std::vector<ResourceUse> resources;
  /// Every resource's busy/idle energy over the run (docs/MODEL.md, "Energy per resource"),
  /// plus "fpga.static" (device static power over the run) and "dram" (bytes x energy).
  std::vector<cost::ResourceEnergy> energy_by_resource;
  nlohmann::json to_json() const;
};

/// Statistics of a set of frames of one variant.
struct ModeSummary {
  std::size_t frames = 0;
  Distribution frontend_ms, backend_ms, e2e_ms, energy_j;
  nlohmann::json to_json() const;
};

struct VariantResult {
  std::string variant;  ///< "baseline" or "accelerated"
  std::vector<FrameResult> frames;
  std::map<std::string, ModeSummary> modes;  ///< per mode and "all"
  double fps_without_pipelining = 0, fps_with_pipelining = 0;
  std::optional<StreamSummary> stream;  ///< model "des"
  /// Critical-path attribution of each frame (model "des"; docs/MODEL.md "Critical-path
  /// attribution"): in the isolated run (adding up to frames' e2e_ms) and the streamed run.
  std::optional<results::CauseTable> isolated_causes, streamed_causes;
  nlohmann::json to_json() const;  ///< summaries only (frames go to the results database)
};

struct SystemResult {
  std::string platform;
  SystemModelKind model = SystemModelKind::kDes;
  std::string config_hash;  ///< hex FNV-1a 64 of the platform's JSON
  std::string trace_hash;   ///< hex FNV-1a 64 of the trace's meta and frame count
  std::string trace_path;
  Platform config;
  /// The frontend study (its `platform` this one's); empty when the run was given a shared
  /// study (simulate_system with a shared_ptr: a sweep's points).
  FrontendStudy frontend;
  VariantResult baseline, accelerated;
  std::vector<KernelDecision> decisions;
  std::vector<KernelScheduleSummary> schedule;  ///< per kernel, over the evaluation frames
  cost::ResourceReport resources;
  /// The whole-system timeline (Perfetto JSON) of the accelerated streamed run when one was asked
  /// for with model "des"; empty otherwise. write_results keeps it beside the run.
  std::string timeline_json;
  std::size_t timeline_first = 0, timeline_frames = 0;  ///< the frames it shows
  /// baseline / accelerated mean per mode ("all" included): e2e, backend, frontend speedups, SD
  /// and energy reductions.
  nlohmann::json comparison() const;
  nlohmann::json to_json() const;  ///< the summary `edx simulate --json` prints
};

/// FNV-1a 64-bit hash of `text`, as 16 hex digits.
std::string fnv1a_hex(const std::string& text);

/// The frontend's work of one frame as the energy model counts it (docs/MODEL.md, "Energy"):
/// each task row's on its unit (FrontendUnit::activity: pixel operations, MACs, on-chip bytes).
/// `per_task` (optional): the same split by task unit, in trace::Task order (their sum is the
/// result).
cost::FrameActivity frontend_activity(const trace::FrameTrace& frame, const FrontendConfig& fe,
                                      std::array<cost::FrameActivity, 7>* per_task = nullptr);

/// The trace's key in results: FNV-1a of its frame count and meta table (SystemResult::trace_hash).
std::string trace_hash(std::size_t frames, const trace::TraceMeta& trace_meta);

/// The parts of a platform the frontend study reads (host, baseline host, coprocessor, frontend,
/// link, memory, transfers, device, ros) as text: platforms with equal keys have equal frontend
/// studies (sweeps reuse one).
std::string frontend_study_key(const Platform& platform);

/// frontend_study_key and `system:`: platforms with equal keys have equal BaselineRuns on a
/// trace.
std::string baseline_des_key(const Platform& platform);

/// The CPU baseline's DES runs of `platform` on `frames`, `study` being its frontend study; the
/// isolated and the streamed run on up to `threads` threads (same runs whatever the number).
BaselineRuns run_baseline_des(const Platform& platform,
                              const std::vector<trace::FrameTrace>& frames,
                              const FrontendStudy& study, int threads = 1);

/// Throws std::runtime_error, one line naming both, when the trace's precision (meta precision)
/// is not the platform's (backend.precision): a trace is simulated only at its own arithmetic;
/// and, at fp32, when the platform offloads a kernel the backends compute in fp64 only
/// (trace::kKernelsAtTracePrecision).
void check_precision(const Platform& platform, const trace::TraceMeta& trace_meta,
                     const std::string& trace_path);

/// Runs the whole system (check_precision first). `trace_meta` (resolution, host_speed) keys the
/// run.
SystemResult simulate_system(const Platform& platform, const std::vector<trace::FrameTrace>& frames,
                             const trace::TraceMeta& trace_meta, const std::string& trace_path,
                             const SystemSimOptions& options = {});

/// The same with the frontend study already made (study_frontend on this platform's
/// frontend_study_key and these frames; its `platform` name is replaced by this one's).
SystemResult simulate_system(const Platform& platform, const std::vector<trace::FrameTrace>& frames,
                             const trace::TraceMeta& trace_meta, const std::string& trace_path,
                             FrontendStudy frontend, const SystemSimOptions& options = {});

/// The same on a study shared with other runs (a sweep's points with equal frontend_study_key):
/// only read, never copied; the result's `frontend` is left empty (its rows and summary do not
/// hold the study).
SystemResult simulate_system(const Platform& platform, const std::vector<trace::FrameTrace>& frames,
                             const trace::TraceMeta& trace_meta, const std::string& trace_path,
                             const std::shared_ptr<const FrontendStudy>& frontend,
                             const SystemSimOptions& options = {});

std::string format_system_result(const SystemResult& result);

}  // namespace edx::arch
