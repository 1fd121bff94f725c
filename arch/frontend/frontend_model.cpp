#include "arch/frontend/frontend_model.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <map>
#include <stdexcept>

#include "arch/frontend/task_timing.hpp"
#include "sim_core/engine.hpp"

namespace edx::arch {
namespace {

using sim::Lease;
using sim::Process;
using sim::ProcessHandle;
using sim::Resource;
using sim::Simulator;
using trace::Image;
using trace::Task;

/// The seven task units; the feature-extraction engine (FD, IF, FC) serves both images.
struct Units {
  explicit Units(Simulator& sim)
      : fd(sim, 1, "FD"),
        if_(sim, 1, "IF"),
        fc(sim, 1, "FC"),
        mo(sim, 1, "MO"),
        dr(sim, 1, "DR"),
        dc(sim, 1, "DC"),
        lss(sim, 1, "LSS") {}
  Resource& of(Task task) {
    switch (task) {
      case Task::FD:
        return fd;
      case Task::IF:
        return if_;
      case Task::FC:
        return fc;
      case Task::MO:
        return mo;
      case Task::DR:
        return dr;
      case Task::DC:
        return dc;
      case Task::LSS:
        return lss;
    }
    return fd;
  }
  Resource fd, if_, fc, mo, dr, dc, lss;
};

constexpr std::array<Task, 7> kTasks = {Task::FD, Task::IF, Task::FC, Task::MO,
                                        Task::DR, Task::DC, Task::LSS};

/// One task: waits for its predecessors, then holds its unit for its cycles.
Process run_task(Simulator& sim, const sim::ClockDomain& clock, Resource& unit,
                 std::vector<ProcessHandle> after, TaskSpan& span) {
  for (ProcessHandle& handle : after) co_await handle;
  Lease lease = co_await unit.acquire();
  span.start = sim.now();
  if (span.cycles > 0) co_await sim.cycles(clock, static_cast<std::uint64_t>(span.cycles));
  span.end = sim.now();
}

/// Index of the (task, image) row in a frame's spans.
std::size_t find_span(const std::vector<TaskSpan>& spans, Task task, Image image,
                      std::int64_t frame_id) {
  for (std::size_t i = 0; i < spans.size(); ++i) {
    if (spans[i].task == task && spans[i].image == image) return i;
  }
  throw std::runtime_error(
      fmt::format("frame {}: no {} {} task row (a frontend trace has ten per "
                  "frame, docs/TRACE.md)",
                  frame_id, trace::to_string(task), trace::to_string(image)));
}

/// One frame: arrives, takes a frame buffer, runs the task graph, frees the buffer.
Process run_frame(Simulator& sim, const sim::ClockDomain& clock, Units& units, Resource& buffers,
                  DmaLink* link, FrontendFrameTiming& timing) {
  co_await sim.delay_until(timing.arrival);
  Lease buffer = co_await buffers.acquire();
  std::vector<TaskSpan>& s = timing.tasks;
  const auto at = [&](Task task, Image image) -> TaskSpan& {
    return s[find_span(s, task, image, timing.frame_id)];
  };
  const auto spawn = [&](Task task, Image image, std::vector<ProcessHandle> after) {
    return sim.spawn(
        run_task(sim, clock, units.of(task), std::move(after), at(task, image)),
        fmt::format("{} {} f{}", trace::to_string(task), trace::to_string(image), timing.frame_id));
  };
  // Spawn order is the queue order on each unit: the left image before the right one.
  const ProcessHandle fd_l = spawn(Task::FD, Image::Left, {});
  const ProcessHandle if_l = spawn(Task::IF, Image::Left, {});
  const ProcessHandle fd_r = spawn(Task::FD, Image::Right, {});
  spawn(Task::IF, Image::Right, {});
  const ProcessHandle dc = spawn(Task::DC, Image::Left, {if_l});
  const ProcessHandle lss = spawn(Task::LSS, Image::Left, {dc});
  const ProcessHandle fc_l = spawn(Task::FC, Image::Left, {fd_l});
  const ProcessHandle fc_r = spawn(Task::FC, Image::Right, {fd_r});
  const ProcessHandle mo = spawn(Task::MO, Image::Stereo, {fc_l, fc_r});
  ProcessHandle dr = spawn(Task::DR, Image::Stereo, {mo});
  ProcessHandle lss_done = lss;
  co_await dr;
  co_await lss_done;
  timing.transfer_start = sim.now();
  if (link != nullptr && timing.transfer_bytes > 0) {
    co_await link->transfer(timing.transfer_bytes, Direction::FpgaToHost);
  }
  timing.end = sim.now();
}

double span_ms(sim::Time begin, sim::Time end) { return sim::to_ms(end - begin); }

}  // namespace

FrontendSimResult simulate_frontend(const std::vector<trace::FrameTrace>& frames,
                                    std::int64_t level0_pixels, const FrontendConfig& config,
                                    const FrontendSimOptions& options) {
  config.validate();
  Simulator sim;
  const sim::ClockDomain clock("frontend", config.clock_mhz);
  Units units(sim);
  Resource buffers(sim, config.pipeline_fe_sm ? 2 : 1, "frame buffers");
  std::optional<DmaLink> link;
  if (options.link) link.emplace(sim, *options.link);

  FrontendSimResult result;
  result.frames.resize(frames.size());
  const sim::Time period = sim::seconds(config.frame_interval_ms * 1e-3);
  for (std::size_t f = 0; f < frames.size(); ++f) {
    FrontendFrameTiming& timing = result.frames[f];
    timing.frame_id = frames[f].frame.frame_id;
    timing.arrival = period * f;
    timing.transfer_bytes = frame_transfers(frames[f], options.transfers).frontend_to_host();
    for (const trace::TaskRecord& task : frames[f].tasks) {
      timing.tasks.push_back(
          {task.task, task.image, task_cycles(task, level0_pixels, config), 0, 0});
    }
    if (timing.tasks.empty()) {
      throw std::runtime_error(
          fmt::format("frame {}: no frontend task rows (the frontend model needs a frontend trace)",
                      timing.frame_id));
    }
    // Check the graph's rows exist before simulating (errors name the frame).
    for (const auto& [task, image] :
         std::vector<std::pair<Task, Image>>{{Task::FD, Image::Left},
                                             {Task::IF, Image::Left},
                                             {Task::FD, Image::Right},
                                             {Task::IF, Image::Right},
                                             {Task::DC, Image::Left},
                                             {Task::LSS, Image::Left},
                                             {Task::FC, Image::Left},
                                             {Task::FC, Image::Right},
                                             {Task::MO, Image::Stereo},
                                             {Task::DR, Image::Stereo}}) {
      find_span(timing.tasks, task, image, timing.frame_id);
    }
  }
  for (FrontendFrameTiming& timing : result.frames) {
    sim.spawn(run_frame(sim, clock, units, buffers, link ? &*link : nullptr, timing),
              fmt::format("frame {}", timing.frame_id));
  }
  sim.run();

  std::map<Task, sim::Time> busy;
  sim::Time first_start = sim::kTimeMax, last_end = 0;
  for (FrontendFrameTiming& t : result.frames) {
    const auto span_of = [&](Task task, Image image) -> const TaskSpan& {
      return t.tasks[find_span(t.tasks, task, image, t.frame_id)];
    };
    const TaskSpan& fd_l = span_of(Task::FD, Image::Left);
    const TaskSpan& fc_l = span_of(Task::FC, Image::Left);
    const TaskSpan& fc_r = span_of(Task::FC, Image::Right);
    const TaskSpan& mo = span_of(Task::MO, Image::Stereo);
    const TaskSpan& dr = span_of(Task::DR, Image::Stereo);
    const TaskSpan& dc = span_of(Task::DC, Image::Left);
    const TaskSpan& lss = span_of(Task::LSS, Image::Left);
    t.start = fd_l.start;
    for (const TaskSpan& s : t.tasks) t.start = std::min(t.start, s.start);
    t.latency_ms = span_ms(t.start, t.end);
    t.response_ms = span_ms(t.arrival, t.end);
    t.fe_ms = span_ms(fd_l.start, std::max(fc_l.end, fc_r.end));
    t.sm_ms = span_ms(mo.start, dr.end);
    t.tm_ms = span_ms(dc.start, lss.end);
    for (const TaskSpan& s : t.tasks) busy[s.task] += s.end - s.start;
    first_start = std::min(first_start, t.start);
    last_end = std::max(last_end, t.end);
  }
  result.makespan_ms = frames.empty() ? 0.0 : span_ms(first_start, last_end);
  if (result.frames.size() >= 2) {
    result.throughput_fps = static_cast<double>(result.frames.size() - 1) /
                            sim::to_seconds(result.frames.back().end - result.frames.front().end);
  } else if (result.makespan_ms > 0) {
    result.throughput_fps = 1e3 / result.makespan_ms;
  }
  for (Task task : kTasks) {
    result.utilization.emplace_back(
        trace::to_string(task),
        result.makespan_ms > 0 ? sim::to_ms(busy[task]) / result.makespan_ms : 0.0);
  }

  if (options.timeline) {
    sim::Timeline timeline;
    std::map<Task, sim::Timeline::TrackId> tracks;
    for (Task task : kTasks) tracks[task] = timeline.track("frontend", trace::to_string(task));
    const sim::Timeline::TrackId frame_track = timeline.track("frontend", "frames");
    const std::size_t last =
        std::min(result.frames.size(), options.timeline_first + options.timeline_count);
    for (std::size_t f = options.timeline_first; f < last; ++f) {
      const FrontendFrameTiming& t = result.frames[f];
      timeline.span(frame_track, fmt::format("frame {}", t.frame_id), t.start, t.end,
                    {{"latency_ms", t.latency_ms},
                     {"fe_ms", t.fe_ms},
                     {"sm_ms", t.sm_ms},
                     {"tm_ms", t.tm_ms}});
      for (const TaskSpan& s : t.tasks) {
        timeline.span(tracks[s.task],
                      fmt::format("{} {} f{}", trace::to_string(s.task), trace::to_string(s.image),
                                  t.frame_id),
                      s.start, s.end, {{"cycles", s.cycles}});
      }
    }
    timeline.write(*options.timeline);
  }
  return result;
}

}  // namespace edx::arch
