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

/// A task's predecessors: at most two (MO's), the rest empty handles (awaiting one is a no-op);
/// in the coroutine's frame, so a task allocates no list.
using Predecessors = std::array<ProcessHandle, 2>;

/// One task: waits for its predecessors, then holds a copy of its unit for its cycles (on the
/// unit's clock: a task that can start between its edges starts on the next one).
Process run_task(Simulator& sim, const sim::ClockDomain& clock, Resource& unit, Predecessors after,
                 TaskSpan& span) {
  for (const ProcessHandle& handle : after) co_await handle;
  Lease lease = co_await unit.acquire();
  if (clock.next_edge(sim.now()) != sim.now()) co_await sim.advance_cycles(clock, 0);
  span.start = sim.now();
  if (span.cycles > 0) co_await sim.advance_cycles(clock, static_cast<std::uint64_t>(span.cycles));
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

/// A frame's rows by (task, image), found in one pass (the first of each, as find_span does)
/// instead of a search per look-up: the DES looks up ten rows a frame, its summary seven.
class SpanIndex {
 public:
  explicit SpanIndex(const std::vector<TaskSpan>& spans) : spans_(spans) {
    index_.fill(kNone);
    for (std::size_t i = 0; i < spans.size(); ++i) {
      const std::size_t k = key(spans[i].task, spans[i].image);
      if (k < index_.size() && index_[k] == kNone) index_[k] = i;
    }
  }
  /// find_span(spans, task, image, frame_id): its index, or its error.
  std::size_t at(Task task, Image image, std::int64_t frame_id) const {
    const std::size_t k = key(task, image);
    return k < index_.size() && index_[k] != kNone ? index_[k]
                                                   : find_span(spans_, task, image, frame_id);
  }

 private:
  static constexpr std::size_t kImages = 3;  // Left, Right, Stereo
  static constexpr std::size_t kNone = static_cast<std::size_t>(-1);
  static std::size_t key(Task task, Image image) {
    return static_cast<std::size_t>(task) * kImages + static_cast<std::size_t>(image);
  }
  const std::vector<TaskSpan>& spans_;
  std::array<std::size_t, trace::kTasks.size() * kImages> index_{};
};

/// A frame's task graph, one row per (task, image), in run_frame's spawn order.
constexpr std::array<std::pair<Task, Image>, 10> kFrameGraph = {{{Task::FD, Image::Left},
                                                                 {Task::IF, Image::Left},
                                                                 {Task::FD, Image::Right},
                                                                 {Task::IF, Image::Right},
                                                                 {Task::DC, Image::Left},
                                                                 {Task::LSS, Image::Left},
                                                                 {Task::FC, Image::Left},
                                                                 {Task::FC, Image::Right},
                                                                 {Task::MO, Image::Stereo},
                                                                 {Task::DR, Image::Stereo}}};

/// A frame's task graph in closed form, when it can run alone: every unit of one copy and idle,
/// every task of at least one cycle, and nothing else due before DR and LSS have finished (then
/// no other process runs until the frame goes on, Simulator::try_advance_in_place, so the DES's
/// spans are these). Each task asks for its unit when its predecessors are done (the roots at
/// `now`), gets it at max(ask, the end of the unit's previous task of the frame: left before
/// right), starts on the unit clock's next edge and ends `cycles` edges later:
///   start = next_edge(max(ask, free)),  end = time_of_cycles(cycles_in(start) + cycles).
/// On success the clock is at max(DR end, LSS end), the spans are filled and the units carry the
/// uses (Resource::book_idle) and statistics that the task processes would have left; false (and
/// nothing changed) when the frame cannot run alone.
bool run_alone(Simulator& sim, const std::vector<std::unique_ptr<sim::ClockDomain>>& clocks,
               const std::vector<std::unique_ptr<Resource>>& units, std::vector<TaskSpan>& spans,
               const SpanIndex& index, std::int64_t frame_id) {
  for (const std::unique_ptr<Resource>& unit : units) {
    if (unit->capacity() != 1 || unit->in_use() != 0 || unit->queue_length() != 0) return false;
  }
  // The graph's rows (kFrameGraph: run_frame's spawn order), their uses and spans.
  enum Row : std::size_t { kFdL, kIfL, kFdR, kIfR, kDc, kLss, kFcL, kFcR, kMo, kDr, kRows };
  static_assert(kRows == kFrameGraph.size());
  std::array<TaskSpan*, kRows> row{};
  for (std::size_t r = 0; r < kRows; ++r) {
    row[r] = &spans[index.at(kFrameGraph[r].first, kFrameGraph[r].second, frame_id)];
    if (row[r]->cycles <= 0) return false;
  }
  std::array<Resource::Use, kRows> use{};
  std::array<sim::Time, kRows> start{};
  const auto run = [&](Row r, sim::Time ask, sim::Time free) {
    const sim::ClockDomain& clock = *clocks[static_cast<std::size_t>(kFrameGraph[r].first)];
    start[r] = clock.next_edge(std::max(ask, free));
    use[r] = {ask, clock.time_of_cycles(clock.cycles_in(start[r]) +
                                        static_cast<std::uint64_t>(row[r]->cycles))};
  };
  const sim::Time now = sim.now();
  try {
    run(kFdL, now, 0);
    run(kIfL, now, 0);
    run(kFdR, now, use[kFdL].release);
    run(kIfR, now, use[kIfL].release);
    run(kDc, use[kIfL].release, 0);
    run(kLss, use[kDc].release, 0);
    run(kFcL, use[kFdL].release, 0);
    run(kFcR, use[kFdR].release, use[kFcL].release);
    run(kMo, std::max(use[kFcL].release, use[kFcR].release), 0);
    run(kDr, use[kMo].release, 0);
  } catch (const sim::TimeRangeError&) {
    return false;  // the DES path raises it where the task does
  }
  const sim::Time end = std::max(use[kDr].release, use[kLss].release);
  for (const Resource::Use& u : use) {
    if (u.release > end) return false;  // a task outlives the frame (IF of the right image)
  }
  if (end == sim::kTimeMax || !sim.try_advance_in_place(end)) return false;
  for (std::size_t r = 0; r < kRows; ++r) {
    row[r]->start = start[r];
    row[r]->end = use[r].release;
  }
  // Each unit's uses in its queue order.
  const auto book = [&](Row first, Row second) {
    Resource& unit = *units[static_cast<std::size_t>(kFrameGraph[first].first)];
    if (first == second) {
      unit.book_idle(&use[first], 1);
    } else {
      const std::array<Resource::Use, 2> both = {use[first], use[second]};
      unit.book_idle(both.data(), both.size());
    }
  };
  book(kFdL, kFdR);
  book(kIfL, kIfR);
  book(kFcL, kFcR);
  book(kMo, kMo);
  book(kDr, kDr);
  book(kDc, kDc);
  book(kLss, kLss);
  return true;
}

/// One frame of simulate_frontend, holding its frame buffer.
Process run_frame(FrontendAccelerator& accelerator, LinkModel* link, FrontendFrameTiming& timing,
                  Lease buffer) {
  co_await accelerator.run_frame(timing, link);
  buffer.release();
}

/// Hands frames to the accelerator in order: a frame buffer, then the frame once it has arrived
/// (the whole-system DES dispatches the same way, so both order their events alike).
Process dispatch_frames(Simulator& sim, FrontendAccelerator& accelerator, LinkModel* link,
                        std::vector<FrontendFrameTiming>& frames) {
  std::vector<ProcessHandle> running;
  for (FrontendFrameTiming& timing : frames) {
    Lease buffer = co_await accelerator.frame_buffers().acquire();
    if (timing.arrival > sim.now()) co_await sim.delay_until(timing.arrival);
    running.push_back(sim.spawn(run_frame(accelerator, link, timing, std::move(buffer)), "frame"));
  }
  for (const ProcessHandle& h : running) co_await h;
}

double span_ms(sim::Time begin, sim::Time end) { return sim::to_ms(end - begin); }

}  // namespace

FrontendAccelerator::FrontendAccelerator(sim::Simulator& sim, const FrontendConfig& config)
    : sim_(&sim),
      clock_("frontend", (config.validate(), config.clock_mhz)),
      buffers_(sim, config.pipeline_fe_sm ? 2 : 1, "frame buffers") {
  for (const FrontendUnitInstance& u : config.units) {
    clocks_.push_back(std::make_unique<sim::ClockDomain>(u.name, config.clock_of(u)));
    units_.push_back(
        std::make_unique<Resource>(sim, static_cast<std::size_t>(u.count), std::string(u.name)));
  }
}

sim::Task<void> FrontendAccelerator::run_frame(FrontendFrameTiming& timing, LinkModel* link) {
  Simulator& sim = *sim_;
  // A frame starts on a clock edge: its latency does not depend on when the previous one ended.
  if (clock_.next_edge(sim.now()) != sim.now()) co_await sim.advance_cycles(clock_, 0);
  std::vector<TaskSpan>& s = timing.tasks;
  const SpanIndex index(s);
  if (!run_alone(sim, clocks_, units_, s, index, timing.frame_id)) {
    // The DES: a process per task.
    const auto at = [&](Task task, Image image) -> TaskSpan& {
      return s[index.at(task, image, timing.frame_id)];
    };
    const auto spawn = [&](Task task, Image image, const Predecessors& after) {
      // The unit's name (short: no allocation a task) names the process in the event log.
      return sim.spawn(run_task(sim, *clocks_[static_cast<std::size_t>(task)], unit(task), after,
                                at(task, image)),
                       trace::to_string(task));
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
  }
  timing.transfer_start = sim.now();
  if (link != nullptr && timing.transfer_bytes > 0) {
    co_await link->transfer(timing.transfer_bytes, Direction::FpgaToHost);
  }
  timing.end = sim.now();
}

FrontendFrameTiming prepare_frontend_frame(const trace::FrameTrace& frame,
                                           std::int64_t level0_pixels, const FrontendConfig& config,
                                           const FrameTransferConfig& transfers) {
  FrontendFrameTiming timing;
  timing.frame_id = frame.frame.frame_id;
  timing.transfer_bytes = frontend_transfer(frame, transfers).frontend_to_host();
  timing.tasks.reserve(frame.tasks.size());
  for (const trace::TaskRecord& task : frame.tasks) {
    timing.tasks.push_back({task.task, task.image, task_cycles(task, level0_pixels, config), 0, 0});
  }
  if (timing.tasks.empty()) {
    throw std::runtime_error(
        fmt::format("frame {}: no frontend task rows (the frontend model needs a frontend trace)",
                    timing.frame_id));
  }
  // Check the graph's rows exist before simulating (errors name the frame).
  for (const auto& [task, image] : kFrameGraph) {
    find_span(timing.tasks, task, image, timing.frame_id);
  }
  return timing;
}

void finish_frontend_frame(FrontendFrameTiming& t) {
  const SpanIndex index(t.tasks);
  const auto span_of = [&](Task task, Image image) -> const TaskSpan& {
    return t.tasks[index.at(task, image, t.frame_id)];
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
}

FrontendSimResult simulate_frontend(const std::vector<trace::FrameTrace>& frames,
                                    std::int64_t level0_pixels, const FrontendConfig& config,
                                    const FrontendSimOptions& options) {
  config.validate();
  Simulator sim;
  FrontendAccelerator accelerator(sim, config);
  const std::unique_ptr<LinkModel> link = options.link ? options.link->make_model(sim) : nullptr;

  FrontendSimResult result;
  result.frames.reserve(frames.size());
  const sim::Time period = sim::seconds(config.frame_interval_ms * 1e-3);
  for (std::size_t f = 0; f < frames.size(); ++f) {
    result.frames.push_back(
        prepare_frontend_frame(frames[f], level0_pixels, config, options.transfers));
    result.frames.back().arrival = period * f;
  }
  sim.spawn(dispatch_frames(sim, accelerator, link.get(), result.frames), "frames");
  sim.run();

  std::map<Task, sim::Time> busy;
  sim::Time first_start = sim::kTimeMax, last_end = 0;
  for (FrontendFrameTiming& t : result.frames) {
    finish_frontend_frame(t);
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
  for (Task task : trace::kTasks) {
    result.utilization.emplace_back(
        trace::to_string(task),
        result.makespan_ms > 0 ? sim::to_ms(busy[task]) / result.makespan_ms : 0.0);
  }

  if (options.timeline) {
    sim::Timeline timeline;
    std::map<Task, sim::Timeline::TrackId> tracks;
    for (Task task : trace::kTasks)
      tracks[task] = timeline.track("frontend", trace::to_string(task));
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
