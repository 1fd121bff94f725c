#pragma once
// The frontend comparison of the paper's Sec. VII-C for one platform and trace: the CPU
// baseline (trace host times scaled to the target CPU) against the accelerator model, latency
// and its FE/SM/TM breakdown, throughput without and with FE/SM pipelining, unit utilizations.
#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "arch/cost/energy.hpp"
#include "arch/frontend/frontend_model.hpp"
#include "arch/frontend/memory_plan.hpp"
#include "arch/host/frontend_graph.hpp"
#include "arch/platform/platform.hpp"
#include "workloads/trace/records.hpp"

namespace edx::arch {

/// Mean, SD and percentiles of a per-frame figure (ms).
struct Distribution {
  std::size_t count = 0;
  double mean = 0, sd = 0, rsd = 0, p50 = 0, p90 = 0, p99 = 0, max = 0;
  static Distribution of(const std::vector<double>& values);
  nlohmann::json to_json() const;
};

struct FrontendStudy {
  std::string platform;
  std::shared_ptr<const HostProcessor> host;       ///< the CPU baseline's host
  std::shared_ptr<const Coprocessor> coprocessor;  ///< the CPU baseline's, or nullptr
  PlatformHostTimes host_times;  ///< this trace's host times on that host (frontend and backend)
  /// The trace's host times on the accelerated system's host when it is another CPU
  /// (Platform::baseline_host); empty: the same as host_times.
  std::optional<PlatformHostTimes> accelerated_times;
  /// The accelerated system's host times: its backend work and the kernels it keeps.
  const PlatformHostTimes& accelerated_host_times() const {
    return accelerated_times ? *accelerated_times : host_times;
  }
  std::size_t frames = 0;
  int width = 0, height = 0;
  Distribution cpu_ms;    ///< the frontend's host time per frame (host_times.frontend_ms)
  Distribution accel_ms;  ///< accelerator latency, frames one at a time (no FE/SM pipelining)
  Distribution fe_ms, sm_ms, tm_ms;
  double speedup = 0;                                          ///< cpu_ms.mean / accel_ms.mean
  double cpu_fps = 0;                                          ///< 1000 / cpu_ms.mean
  double fps_without_pipelining = 0, fps_with_pipelining = 0;  ///< frames back to back
  std::vector<std::pair<std::string, double>> utilization;     ///< pipelined run
  FrontendMemoryPlan memory;  ///< SBs, FIFOs, SPM for the pipelined run's timing
  // Per frame, in trace order (not in to_json(); the system model reads them):
  std::vector<double> frame_cpu_ms;  ///< CPU baseline frontend latency
  /// CPU baseline: each frame's frontend chains (ms) by stage (arch/host/frontend_graph.hpp),
  /// their coprocessor parts included (its per-frame setup a stage of its own, first).
  std::vector<StageChains> frame_cpu_chains;
  /// CPU baseline: the backend's time on the host (its kernels not on the coprocessor, with ROS
  /// the backend node's messages) and on the coprocessor (its kernels, their launches, the
  /// frame's setup when the frontend did not use it), ms.
  std::vector<double> frame_backend_host_ms, frame_backend_device_ms;
  std::vector<double> frame_accel_ms;             ///< accelerator latency, frames one at a time
  std::vector<double> frame_pipelined_end_ms;     ///< end of each frame, frames back to back with
                                                  ///< FE/SM pipelining (from the first start)
  std::vector<std::int64_t> frame_results_bytes;  ///< transfer (1), FPGA -> host
  /// A frame's accelerated frontend as the system model reads it: its rows for the DES
  /// (prepare_frontend_frame: task cycles, transfer-1 bytes) and its work for the energy model
  /// (frontend_activity, in all and by task). They read only the frame and what
  /// frontend_study_key covers (frontend, transfers, resolution), so the sweep points sharing a
  /// study share them instead of making them again (shared: a copy of the study is cheap).
  struct PreparedFrame {
    FrontendFrameTiming timing;
    cost::FrameActivity activity;
    std::array<cost::FrameActivity, 7> task_activity{};
  };
  /// Per frame, in trace order; null in a study not made by study_frontend (then the system
  /// model makes them itself).
  std::shared_ptr<const std::vector<PreparedFrame>> prepared_frames;
  nlohmann::json to_json() const;
};

/// Host times a caller already has for the same frames and trace meta (a sweep computes its base
/// platform's host's to check the trace before its first point): `host_key` is the host's
/// component_json().dump(), `times` what its host_times(frames, meta, name) returned.
struct KnownHostTimes {
  std::string host_key;
  std::shared_ptr<const PlatformHostTimes> times;
};

struct FrontendStudyOptions {
  /// The pipelined run's Perfetto timeline of frames [first, first + count) (link and transfers
  /// are the platform's).
  FrontendSimOptions timeline;
  /// Host times to use when they are the study host's (its key equal), instead of computing
  /// them again (same values: host_times is a function of the host's parameters, the frames and
  /// the meta).
  const KnownHostTimes* known = nullptr;
  /// Threads for the study's independent parts (the host times and the CPU baseline's chains,
  /// the two frontend runs, the frames' preparation); the result does not depend on it. One
  /// when a timeline is written (a failing part must leave no file behind).
  int threads = 1;
};

/// `trace_meta`: the trace's meta (resolution "WxH", host_speed); a malformed or missing value is
/// an error naming `trace_name` and the key (the first part's error, in the order above).
FrontendStudy study_frontend(const Platform& platform, const std::vector<trace::FrameTrace>& frames,
                             const trace::TraceMeta& trace_meta, const std::string& trace_name,
                             const FrontendStudyOptions& options = {});

std::string format_frontend_study(const FrontendStudy& study);

}  // namespace edx::arch
