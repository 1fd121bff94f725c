#pragma once
// The frontend accelerator as a discrete-event model on sim_core (paper Sec. V-B), replaying the
// frontend tasks of a trace: their work counts, not their host times.
//
// Units: FD, IF, FC (the feature-extraction engine, time-shared between the left and right
// images: one copy of each), MO, DR (stereo matching), DC, LSS (temporal matching), each a
// sim::Resource of its instance's copies (frontend.units.<task>.count, 1 in the paper's design)
// on its clock. Per frame, the task graph:
//   FD(L) ∥ IF(L); FC(L) after FD(L); FD(R) ∥ IF(R) queue behind the left image on their units;
//   FC(R) after FD(R); MO after FC(L) and FC(R); DR after MO; DC after IF(L); LSS after DC.
// A frame enters the accelerator when it has arrived (camera period, or back to back) and a
// frame buffer is free: one buffer without FE/SM pipelining (frame t+1 starts when frame t has
// finished), two with it (FE of frame t+1 overlaps SM of frame t). A frame has finished when DR
// and LSS have and, when a link is configured, its results (transfer 1 of Sec. VII-A: features
// and the frame's IMU/GPS samples, arch/link/frame_transfers.hpp) have reached the host.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "arch/frontend/frontend_config.hpp"
#include "arch/link/frame_transfers.hpp"
#include "arch/link/link.hpp"
#include "sim_core/engine.hpp"
#include "workloads/trace/records.hpp"

namespace edx::arch {

/// When each task of one frame ran on the accelerator (ps from the start of the simulation).
struct TaskSpan {
  trace::Task task = trace::Task::FD;
  trace::Image image = trace::Image::Left;
  std::int64_t cycles = 0;
  sim::Time start = 0, end = 0;
};

struct FrontendFrameTiming {
  std::int64_t frame_id = 0;
  sim::Time arrival = 0;            ///< the frame is available (camera) or, back to back, 0
  sim::Time start = 0;              ///< its first task started (it held a frame buffer)
  sim::Time end = 0;                ///< DR and LSS finished and the results reached the host
  sim::Time transfer_start = 0;     ///< results transfer to the host (== end without a link)
  std::int64_t transfer_bytes = 0;  ///< FrameTransfers::frontend_to_host()
  std::vector<TaskSpan> tasks;
  /// Latency figures in ms: end - start (the accelerator's own), FE (first FD to the last FC),
  /// SM (MO start to DR end), TM (DC start to LSS end).
  double latency_ms = 0, fe_ms = 0, sm_ms = 0, tm_ms = 0;
  /// end - arrival: includes waiting for a frame buffer (camera rate faster than the frontend).
  double response_ms = 0;
};

struct FrontendSimResult {
  std::vector<FrontendFrameTiming> frames;
  double makespan_ms = 0;     ///< first start to last end
  double throughput_fps = 0;  ///< (frames - 1) / (last end - first end); frames / makespan if 1
  /// Busy fraction of each unit over the makespan, by unit name (FD, IF, FC, MO, DR, DC, LSS).
  std::vector<std::pair<std::string, double>> utilization;
};

struct FrontendSimOptions {
  /// The host link the results cross; none: the frame ends when DR and LSS do.
  std::shared_ptr<const Link> link;
  FrameTransferConfig transfers;
  /// Frames [first, last) of the timeline written; empty: no timeline.
  std::optional<std::filesystem::path> timeline;
  std::size_t timeline_first = 0, timeline_count = 10;
};

/// A frame's timing record before simulation: its task rows with their cycles
/// (task_timing.hpp) and its transfer-1 bytes. Throws std::runtime_error naming the frame when a
/// task row of the graph is missing.
FrontendFrameTiming prepare_frontend_frame(const trace::FrameTrace& frame,
                                           std::int64_t level0_pixels, const FrontendConfig& config,
                                           const FrameTransferConfig& transfers);

/// The frontend accelerator as a component of a simulation (the whole-system DES reuses it):
/// its seven task units on the frontend clock and its frame buffers (one, or two with FE/SM
/// pipelining). Must be destroyed before its Simulator.
class FrontendAccelerator {
 public:
  FrontendAccelerator(sim::Simulator& sim, const FrontendConfig& config);
  FrontendAccelerator(const FrontendAccelerator&) = delete;
  FrontendAccelerator& operator=(const FrontendAccelerator&) = delete;

  /// The frame buffers; a frame holds one while it runs (the caller acquires and releases it).
  sim::Resource& frame_buffers() noexcept { return buffers_; }
  /// The unit of a task (its copies).
  sim::Resource& unit(trace::Task task) noexcept { return *units_[static_cast<std::size_t>(task)]; }
  /// Runs a prepared frame's task graph, then its results (transfer 1) over `link` (nullptr:
  /// the frame ends when DR and LSS do). The graph runs as a process per task, or in closed form
  /// when the frame can run alone (its units of one copy and idle, nothing else due before it
  /// ends: the same spans, unit statistics and order of everything else, without the events). Fills
  /// the spans, transfer_start and end of `timing`, which must outlive the task.
  sim::Task<void> run_frame(FrontendFrameTiming& timing, LinkModel* link);

 private:
  sim::Simulator* sim_;
  sim::ClockDomain clock_;                                 ///< frames start on its edges
  std::vector<std::unique_ptr<sim::ClockDomain>> clocks_;  ///< each unit's, trace::Task order
  std::vector<std::unique_ptr<sim::Resource>> units_;      ///< trace::Task order
  sim::Resource buffers_;
};

/// Latency figures of a simulated frame (start, latency_ms, response_ms, fe/sm/tm_ms) from its
/// spans, arrival and end.
void finish_frontend_frame(FrontendFrameTiming& timing);

/// Runs the frames of a trace through the model. Frames without task rows are an error
/// (std::runtime_error naming the frame): a frontend model needs the frontend's work.
/// `level0_pixels`: the image size W*H (from the trace's resolution).
FrontendSimResult simulate_frontend(const std::vector<trace::FrameTrace>& frames,
                                    std::int64_t level0_pixels, const FrontendConfig& config,
                                    const FrontendSimOptions& options = {});

}  // namespace edx::arch
