#include "arch/system/system_des.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <deque>
#include <limits>
#include <memory>
#include <stdexcept>

#include "arch/backend/offload_accelerator.hpp"
#include "arch/link/link.hpp"
#include "common/input_error.hpp"

namespace edx::arch {

std::vector<BackendStep> split_backend(const trace::FrameTrace& frame, double backend_ms,
                                       const std::vector<double>& kernel_host_ms,
                                       const std::vector<bool>& offloaded) {
  const std::size_t n = frame.kernels.size();
  if (kernel_host_ms.size() != n || offloaded.size() != n) {
    throw std::logic_error("split_backend: one host time and one flag per kernel expected");
  }
  double all_kernels = 0, offloaded_ms = 0;
  std::size_t offloads = 0;
  for (std::size_t k = 0; k < n; ++k) {
    all_kernels += kernel_host_ms[k];
    if (offloaded[k]) {
      offloaded_ms += kernel_host_ms[k];
      ++offloads;
    }
  }
  // Gap g holds the host kernels between offload g − 1 and offload g, plus an even share of the
  // host time outside every kernel.
  std::vector<double> gaps(
      offloads + 1, std::max(0.0, backend_ms - all_kernels) / static_cast<double>(offloads + 1));
  for (std::size_t k = 0, gap = 0; k < n; ++k) {
    if (offloaded[k]) {
      ++gap;
    } else {
      gaps[gap] += kernel_host_ms[k];
    }
  }
  double sum = 0;
  for (double g : gaps) sum += g;
  const double host = std::max(0.0, backend_ms - offloaded_ms);
  if (sum > 0 && sum != host) {
    for (double& g : gaps) g *= host / sum;
  }
  std::vector<BackendStep> steps;
  steps.reserve(gaps.size() + offloads);  // at most a gap and an offload each
  for (std::size_t g = 0; g < gaps.size(); ++g) {
    if (gaps[g] > 0) steps.push_back({gaps[g], -1});
    if (g < offloads) steps.push_back({0, static_cast<int>(g)});
  }
  return steps;
}

CauseLayout::CauseLayout(std::vector<std::string> backend_resources)
    : names_(kFixed + 2 * backend_resources.size()) {
  const auto name_pair = [&](std::size_t run, const std::string& resource) {
    names_[run] = resource + ".run";
    names_[run + kWait] = resource + ".wait";
  };
  names_[kSensorWait] = "sensor.wait";
  for (trace::Task task : trace::kTasks) {
    name_pair(frontend(task), std::string("frontend.") + trace::to_string(task));
  }
  for (Direction d : {Direction::HostToFpga, Direction::FpgaToHost}) {
    name_pair(link(d), std::string("link.") + to_string(d));
  }
  name_pair(kHost, "host");
  name_pair(kCoprocessor, "coprocessor");
  name_pair(kSpill, "backend.spill");
  names_[kResultsWait] = "queue.results.wait";
  for (std::size_t i = 0; i < backend_resources.size(); ++i) {
    name_pair(backend(i), "backend." + backend_resources[i]);
  }
}

nlohmann::json SystemRun::to_json() const {
  nlohmann::json use = nlohmann::json::object();
  for (const ResourceUse& r : resources) use[r.name] = {{"busy", r.busy}, {"max", r.max}};
  return {{"run", isolated ? "isolated" : "streamed"},
          {"frames", frames.size()},
          {"dropped", dropped},
          {"makespan_ms", makespan_ms},
          {"fps", fps},
          {"host_busy_ms", host_busy_ms},
          {"resources", use}};
}

namespace {

constexpr std::size_t kEnd = std::numeric_limits<std::size_t>::max();

sim::Time ms_to_time(double ms) { return sim::seconds(ms * 1e-3); }

/// Adds a link transfer of `took` ps to a resource's causes (CauseLayout): run its time on the
/// idle link `idle`, wait the rest.
void split_transfer(sim::Time* row, std::size_t run_cause, sim::Time took, sim::Time idle) {
  const sim::Time run = std::min(took, idle);
  row[run_cause] += run;
  row[run_cause + CauseLayout::kWait] += took - run;
}

/// The predecessors of a frontend task in the graph of frontend_model.hpp (DR after MO; MO after
/// both FC; FC after FD of its image; LSS after DC; DC after IF(L)): at most two, the first
/// `count` of `tasks` (no list allocated: this runs for every task on a frame's critical path).
struct FrontendPredecessors {
  std::array<std::pair<trace::Task, trace::Image>, 2> tasks{};
  std::size_t count = 0;
};
FrontendPredecessors frontend_predecessors(trace::Task task, trace::Image image) {
  using trace::Image;
  using trace::Task;
  switch (task) {
    case Task::DR:
      return {{{{Task::MO, Image::Stereo}}}, 1};
    case Task::MO:
      return {{{{Task::FC, Image::Left}, {Task::FC, Image::Right}}}, 2};
    case Task::FC:
      return {{{{Task::FD, image}}}, 1};
    case Task::LSS:
      return {{{{Task::DC, Image::Left}}}, 1};
    case Task::DC:
      return {{{{Task::IF, Image::Left}}}, 1};
    default:
      return {};
  }
}

/// A frame's frontend critical path (CauseLayout) from `origin` to the last of DR and LSS: from
/// that task back through the predecessor that finished last, each task's run its span, its wait
/// from its ready time (its predecessors done, or `origin`) to its start (its unit busy, its
/// clock edge). Adds up to max(DR end, LSS end) − origin.
void attribute_frontend(const FrontendFrameTiming& t, sim::Time origin, sim::Time* row) {
  const auto span_of = [&](trace::Task task, trace::Image image) -> const TaskSpan& {
    for (const TaskSpan& s : t.tasks) {
      if (s.task == task && s.image == image) return s;
    }
    throw std::logic_error("attribute_frontend: a task row of the graph is missing");
  };
  const TaskSpan& dr = span_of(trace::Task::DR, trace::Image::Stereo);
  const TaskSpan& lss = span_of(trace::Task::LSS, trace::Image::Left);
  const TaskSpan* task = dr.end >= lss.end ? &dr : &lss;
  while (task != nullptr) {
    const std::size_t cause = CauseLayout::frontend(task->task);
    row[cause] += task->end - task->start;
    const TaskSpan* last = nullptr;
    const FrontendPredecessors before = frontend_predecessors(task->task, task->image);
    for (std::size_t i = 0; i < before.count; ++i) {
      const TaskSpan& p = span_of(before.tasks[i].first, before.tasks[i].second);
      if (last == nullptr || p.end > last->end) last = &p;
    }
    row[cause + CauseLayout::kWait] += task->start - (last != nullptr ? last->end : origin);
    task = last;
  }
}

/// One run: the components, the queues and the threads of one variant (see the header).
class SystemSimulation {
 public:
  SystemSimulation(const std::vector<SystemFrameWork>& work, const FrontendConfig& frontend,
                   const OffloadAccelerator& backend, const Link& link, int host_cores,
                   const SystemConfig& system, bool accelerated, bool isolated,
                   const SystemTimelineOptions& timeline)
      : work_(work),
        system_(system),
        accelerated_(accelerated),
        isolated_(isolated),
        contention_(system.contention),
        unbounded_(work.size() + 2),
        link_kind_(&link),
        cores_(sim_, contention_ ? static_cast<std::size_t>(host_cores) : unbounded_, "host.cores"),
        device_(sim_, 1, "coprocessor"),
        admission_(sim_, isolated ? 1 : unbounded_, "admission"),
        arrived_(sim_, "camera"),
        results_(sim_,
                 contention_ ? static_cast<std::size_t>(system.results_queue_depth) : unbounded_,
                 "queue.results"),
        camera_queue_(sim_),
        layout_(accelerated ? backend.resource_names() : std::vector<std::string>{}),
        timeline_(timeline) {
    system.validate();
    // Rows are zeroed as frames are taken (open_row): one row's fill is a few stores, the whole
    // table's at once a large memset per run. Reserved whole, so rows never move.
    cause_ps_.reserve(work.size() * layout_.size());
    if (accelerated_) {
      frontend_.emplace(sim_, frontend);
      link_ = link.make_model(sim_);
      if (contention_) {
        backend_ = backend.instantiate(sim_);
        backend_resources_ = backend.resource_names();
      } else {
        frontend_link_ = link.make_model(sim_);  // transfer 1 alone on its link, as the analytical
      }
    }
    frames_.resize(work.size());
    admissions_.resize(work.size());
    for (std::size_t f = 0; f < work.size(); ++f) frames_[f].frame_id = work[f].frame_id;
    // A timeline writes every frame's spans at the end: each keeps its own record then.
    if (accelerated_ && timeline_.timeline != nullptr) fe_.resize(work.size());
    if (timeline_.timeline != nullptr) set_up_timeline();
  }

  SystemRun run() {
    const bool camera = !isolated_ && system_.sensor_fps > 0;
    if (camera) {
      // The last frame arrives at (F - 1) / fps: inside simulated time (2^64 ps), or the rate
      // is named (its own range allows 18 000 frames at the slowest).
      const double last = work_.empty() ? 0.0 : static_cast<double>(work_.size() - 1);
      const double last_ps = 1e12 * last / system_.sensor_fps;
      if (!(last_ps < 0x1p64)) {
        throw InputError({}, "system.sensor_fps",
                         fmt::format("{:g} frames/s: the trace's {} frames would arrive over "
                                     "{:.3g} s, beyond the 213 days simulated time holds",
                                     system_.sensor_fps, work_.size(), last_ps * 1e-12));
      }
      sim_.spawn(camera_process(), "camera");
    } else {
      for (std::size_t f = 0; f < work_.size(); ++f) camera_queue_items_.push_back(f);
      camera_closed_ = true;
    }
    sim_.spawn(accelerated_ ? accelerator_frontend() : host_frontend(), "frontend");
    sim_.spawn(backend_thread(), "backend thread");
    sim_.run();
    return summarize();
  }

 private:
  // --- Camera and frontend ---

  sim::Process camera_process() {
    const double period_s = 1.0 / system_.sensor_fps;
    for (std::size_t f = 0; f < work_.size(); ++f) {
      co_await sim_.delay_until(sim::seconds(period_s * static_cast<double>(f)));
      frames_[f].arrival = sim_.now();
      const bool full = static_cast<int>(camera_queue_items_.size()) >= system_.queue_depth;
      if (full && contention_ && system_.drop == DropPolicy::kNewest) {
        drop(f);
        continue;
      }
      if (full && contention_ && system_.drop == DropPolicy::kOldest) {
        drop(camera_queue_items_.front());
        camera_queue_items_.pop_front();
      }
      camera_queue_items_.push_back(f);
      camera_queue_.set(static_cast<double>(camera_queue_items_.size()));
      arrived_.notify();
    }
    camera_closed_ = true;
    arrived_.notify();
  }

  void drop(std::size_t f) {
    frames_[f].dropped = true;
    ++dropped_;
  }

  /// The next frame for the frontend, kEnd when the camera is done and the queue empty.
  sim::Task<std::size_t> next_frame() {
    while (camera_queue_items_.empty() && !camera_closed_) co_await arrived_;
    if (camera_queue_items_.empty()) co_return kEnd;
    const std::size_t f = camera_queue_items_.front();
    camera_queue_items_.pop_front();
    camera_queue_.set(static_cast<double>(camera_queue_items_.size()));
    if (!(!isolated_ && system_.sensor_fps > 0)) frames_[f].arrival = sim_.now();
    open_row(f);
    co_return f;
  }

  /// The accelerator: takes a frame buffer, then the next frame, and runs it (frames overlap
  /// as far as the buffers allow: FE/SM pipelining).
  sim::Process accelerator_frontend() {
    std::vector<sim::ProcessHandle> running;
    for (;;) {
      sim::Lease admit = co_await admission_.acquire();
      sim::Lease buffer = co_await frontend_->frame_buffers().acquire();
      const std::size_t f = co_await next_frame();
      if (f == kEnd) break;
      admissions_[f] = std::move(admit);
      running.push_back(sim_.spawn(accelerator_frame(f, std::move(buffer)), "frame"));
    }
    for (const sim::ProcessHandle& h : running) co_await h;
    co_await results_.put(kEnd);
  }

  /// A frame on the frontend accelerator: a copy of its prepared record (the run fills its
  /// spans), kept per frame with a timeline, else a spare record (as many as frames in flight:
  /// copying into one reuses its rows' storage, no allocation a frame).
  sim::Process accelerator_frame(std::size_t f, sim::Lease buffer) {
    std::unique_ptr<FrontendFrameTiming> spare;
    if (fe_.empty()) {
      if (spare_fe_.empty()) {
        spare = std::make_unique<FrontendFrameTiming>();
      } else {
        spare = std::move(spare_fe_.back());
        spare_fe_.pop_back();
      }
    }
    FrontendFrameTiming& fe = spare ? *spare : fe_[f];
    fe = work_[f].frontend;
    co_await frontend_->run_frame(fe, contention_ ? link_.get() : frontend_link_.get());
    finish_frontend_frame(fe);
    frames_[f].start = fe.start;
    frames_[f].frontend_end = sim_.now();
    sim::Time* causes = row(f);
    attribute_frontend(fe, fe.start, causes);
    const std::int64_t bytes = fe.transfer_bytes;
    split_transfer(causes, CauseLayout::link(Direction::FpgaToHost), fe.end - fe.transfer_start,
                   bytes > 0 ? link_kind_->transfer_time(bytes) : 0);
    if (spare) spare_fe_.push_back(std::move(spare));
    co_await results_.put(f);  // waits while the results queue is full, holding the buffer
    buffer.release();
  }

  /// The CPU baseline's frontend thread: one frame at a time on a core.
  sim::Process host_frontend() {
    for (;;) {
      sim::Lease admit = co_await admission_.acquire();
      const std::size_t f = co_await next_frame();
      if (f == kEnd) break;
      admissions_[f] = std::move(admit);
      frames_[f].start = sim_.now();
      if (work_[f].frontend_host_chains.empty()) {
        co_await host_work(f, work_[f].frontend_host_ms, frontend_thread_track_, row(f));
      } else {
        // Each stage's chains side by side on the cores (their device parts first, on the
        // coprocessor in chain order), the stages one after the other; the critical path goes
        // through the chain that finished last.
        for (const std::vector<ChainTime>& stage : work_[f].frontend_host_chains) {
          std::vector<sim::ProcessHandle> chains;
          std::vector<ChainCauses> causes(stage.size());
          chains.reserve(stage.size());
          for (std::size_t c = 0; c < stage.size(); ++c) {
            chains.push_back(sim_.spawn(host_chain(f, stage[c], causes[c]), "frontend chain"));
          }
          for (const sim::ProcessHandle& h : chains) co_await h;
          const ChainCauses* last = nullptr;
          for (const ChainCauses& c : causes) {
            if (last == nullptr || c.end > last->end) last = &c;
          }
          if (last != nullptr) {
            for (std::size_t k = 0; k < CauseLayout::kFixed; ++k) row(f)[k] += last->ps[k];
          }
        }
      }
      frames_[f].frontend_end = sim_.now();
      co_await results_.put(f);
    }
    co_await results_.put(kEnd);
  }

  // --- Backend ---

  sim::Process backend_thread() {
    for (;;) {
      const std::size_t f = co_await results_.get();
      if (f == kEnd) break;
      frames_[f].backend_start = sim_.now();
      sim::Time* causes = row(f);
      // The camera queue (the isolated run's latency starts with the frontend) and the results
      // queue.
      if (!isolated_) causes[CauseLayout::kSensorWait] += frames_[f].start - frames_[f].arrival;
      causes[CauseLayout::kResultsWait] += frames_[f].backend_start - frames_[f].frontend_end;
      const SystemFrameWork& w = work_[f];
      if (!accelerated_) {
        co_await host_work(f, w.backend_host_ms, backend_thread_track_, causes);
        co_await device_work(w.backend_device_ms, causes);
      } else {
        for (const BackendStep& step : w.backend_steps) {
          if (step.offload < 0) {
            co_await host_work(f, step.host_ms, backend_thread_track_, causes);
          } else {
            co_await offload(w.offloads[static_cast<std::size_t>(step.offload)], causes);
          }
        }
      }
      frames_[f].end = sim_.now();
      admissions_[f].release();
    }
  }

  /// A baseline frontend chain's causes (the fixed part of CauseLayout) and its end.
  struct ChainCauses {
    std::array<sim::Time, CauseLayout::kFixed> ps{};
    sim::Time end = 0;
  };

  /// A frontend chain of the CPU baseline: its rows on the coprocessor, then its host work on a
  /// core (arch/host/frontend_graph.hpp).
  sim::Process host_chain(std::size_t f, ChainTime chain, ChainCauses& causes) {
    co_await device_work(chain.device_ms, causes.ps.data());
    co_await host_work(f, chain.host_ms, frontend_thread_track_, causes.ps.data());
    causes.end = sim_.now();
  }

  /// Work of `ms` on the CPU baseline's coprocessor (waits while it runs another's); its wait
  /// and run added to `causes`.
  sim::Task<void> device_work(double ms, sim::Time* causes) {
    if (!(ms > 0)) co_return;
    const sim::Time asked = sim_.now();
    sim::Lease device = co_await device_.acquire();
    const sim::Time begin = sim_.now();
    co_await sim_.advance(ms_to_time(ms));
    causes[CauseLayout::kCoprocessor + CauseLayout::kWait] += begin - asked;
    causes[CauseLayout::kCoprocessor] += sim_.now() - begin;
  }

  /// Host work of `ms` on a core (waits for one when all are busy); its wait and run added to
  /// `causes`.
  sim::Task<void> host_work(std::size_t f, double ms, sim::Timeline::TrackId track,
                            sim::Time* causes) {
    if (!(ms > 0)) co_return;
    const sim::Time asked = sim_.now();
    sim::Lease core = co_await cores_.acquire();
    const sim::Time begin = sim_.now();
    co_await sim_.advance(ms_to_time(ms));
    causes[CauseLayout::kHost + CauseLayout::kWait] += begin - asked;
    causes[CauseLayout::kHost] += sim_.now() - begin;
    frames_[f].host_busy_ms += ms;
    if (timeline_.timeline != nullptr) {
      timeline_.timeline->span(track, fmt::format("f{}", work_[f].frame_id), begin, sim_.now());
    }
  }

  /// Transfer 2, the spill reads, the kernel on the units, the spill writes, transfer 3 (spill
  /// traffic serialized with the units: the conservative reading, docs/MODEL.md "SPM spills").
  /// Its causes go to `causes`: each transfer's to its link direction (the spill's to
  /// backend.spill), the units' run and wait to their resources. The four transfers are legs of
  /// one loop in this coroutine (a coroutine per transfer would only add a frame each).
  sim::Task<void> offload(const OffloadWork& o, sim::Time* causes) {
    constexpr Direction kIn = Direction::HostToFpga, kOut = Direction::FpgaToHost;
    /// One transfer: its bytes and direction, the cause its time goes to (a link's run cause,
    /// or backend.spill's), its timeline label's suffix, and whether it is made at all (a spill
    /// only when there is one, or with contention off: then its idle time, 0 for 0 bytes).
    struct Leg {
      std::int64_t bytes;
      Direction direction;
      std::size_t cause;
      const char* suffix;
      bool made;
    };
    const std::array<Leg, 4> legs = {{
        {o.input_bytes, kIn, CauseLayout::link(kIn), " in", true},
        {o.spill_read_bytes, kIn, CauseLayout::kSpill, " spill in",
         o.spill_read_bytes > 0 || !contention_},
        {o.spill_write_bytes, kOut, CauseLayout::kSpill, " spill out",
         o.spill_write_bytes > 0 || !contention_},
        {o.output_bytes, kOut, CauseLayout::link(kOut), " out", true},
    }};
    for (std::size_t i = 0; i < legs.size(); ++i) {
      if (i == 2) {  // the kernel, between the reads and the writes
        if (contention_) {
          co_await backend_->run(*o.plan, label(o, ""),
                                 OffloadTimes{causes + CauseLayout::backend(0)});
        } else {
          // On an idle accelerator: its plan's compute time, split by resource.
          const sim::Time compute = sim::seconds(o.plan->compute_s);
          co_await sim_.advance(compute);
          attribute_compute(*o.plan, compute, causes);
        }
      }
      const Leg& leg = legs[i];
      if (!leg.made) continue;
      // On the link (contention off: its idle time); the time it took split into run (its
      // time on the idle link) and wait.
      const sim::Time asked = sim_.now();
      const sim::Time idle = link_kind_->transfer_time(leg.bytes);
      if (contention_) {
        co_await link_->transfer(leg.bytes, leg.direction, label(o, leg.suffix));
      } else {
        co_await sim_.advance(idle);
      }
      split_transfer(causes, leg.cause, sim_.now() - asked, idle);
    }
  }

  /// `compute` ps of a plan on an idle accelerator, split over its resources in proportion to
  /// their compute_s_by_resource.
  void attribute_compute(const OffloadPlan& plan, sim::Time compute, sim::Time* causes) const {
    const std::vector<double>& by = plan.compute_s_by_resource;
    double total = 0;
    std::size_t last = by.size();
    for (std::size_t i = 0; i < by.size(); ++i) {
      total += by[i];
      if (by[i] > 0) last = i;
    }
    if (last == by.size()) {  // no split known: the first resource
      if (layout_.size() > CauseLayout::kFixed) causes[CauseLayout::backend(0)] += compute;
      return;
    }
    sim::Time given = 0;
    for (std::size_t i = 0; i < last; ++i) {
      const auto share = static_cast<sim::Time>(static_cast<double>(compute) * by[i] / total);
      causes[CauseLayout::backend(i)] += share;
      given += share;
    }
    causes[CauseLayout::backend(last)] += compute - given;
  }

  // --- Timeline and results ---

  /// A timeline label, built only when a timeline is recorded.
  std::string label(const OffloadWork& o, const char* suffix) const {
    return timeline_.timeline != nullptr ? o.label + suffix : std::string();
  }

  void set_up_timeline() {
    sim::Timeline& t = *timeline_.timeline;
    frames_lanes_ = Lanes{"system", "frames", {}};
    if (accelerated_) {
      for (trace::Task task : trace::kTasks) {
        frontend_tracks_[task] = t.track("frontend", trace::to_string(task));
      }
      link_->set_timeline(t, t.track("link", "host_to_fpga"), t.track("link", "fpga_to_host"));
      if (backend_) backend_->set_timeline(t, "backend");
    } else {
      frontend_thread_track_ = t.track("host", "frontend thread");
    }
    backend_thread_track_ = t.track("host", "backend thread");
    camera_lanes_ = Lanes{"queues", "camera queue", {}};
    results_lanes_ = Lanes{"queues", "results queue", {}};
    // The first lane of each exists even when nothing waits.
    t.track("system", "frames");
    t.track("queues", "camera queue");
    t.track("queues", "results queue");
  }

  /// Keeps the spans of the window's frames and of everything that ran meanwhile.
  void write_timeline_window() {
    sim::Timeline& t = *timeline_.timeline;
    const std::size_t last = std::min(frames_.size(), timeline_.first + timeline_.count);
    // The window: from the first of its frames' arrival to the last one's end.
    sim::Time begin = sim::kTimeMax, end = 0;
    for (std::size_t f = timeline_.first; f < last; ++f) {
      begin = std::min(begin, frames_[f].arrival);
      end = std::max(end, frames_[f].dropped ? frames_[f].arrival : frames_[f].end);
    }
    for (std::size_t f = timeline_.first; f < last; ++f) {
      const SystemFrameTiming& s = frames_[f];
      if (s.dropped) {
        frames_lanes_.span(t, fmt::format("frame {} dropped", s.frame_id), s.arrival, s.arrival);
        continue;
      }
      frames_lanes_.span(t, fmt::format("frame {}", s.frame_id), s.arrival, s.end,
                         {{"latency_ms", sim::to_ms(s.end - s.arrival)}});
      if (!isolated_ && system_.sensor_fps > 0 && s.start > s.arrival) {
        camera_lanes_.span(t, fmt::format("f{} waits", s.frame_id), s.arrival, s.start);
      }
      if (s.backend_start > s.frontend_end) {
        results_lanes_.span(t, fmt::format("f{} waits", s.frame_id), s.frontend_end,
                            s.backend_start);
      }
    }
    // Every frame's tasks; the window below keeps those that ran while its frames did.
    if (accelerated_) {
      for (std::size_t f = 0; f < frames_.size(); ++f) {
        if (frames_[f].dropped) continue;
        for (const TaskSpan& span : fe_[f].tasks) {
          t.span(frontend_tracks_.at(span.task),
                 fmt::format("{} {} f{}", trace::to_string(span.task), trace::to_string(span.image),
                             frames_[f].frame_id),
                 span.start, span.end, {{"cycles", span.cycles}});
        }
      }
    }
    if (begin <= end) t.retain(begin, end);
  }

  SystemRun summarize() {
    SystemRun r;
    r.accelerated = accelerated_;
    r.isolated = isolated_;
    r.dropped = dropped_;
    sim::Time first_start = sim::kTimeMax, last_end = 0;
    std::vector<sim::Time> ends;
    for (const SystemFrameTiming& s : frames_) {
      if (s.dropped) continue;
      first_start = std::min(first_start, s.arrival);
      last_end = std::max(last_end, s.end);
      ends.push_back(s.end);
      r.host_busy_ms += s.host_busy_ms;
    }
    std::sort(ends.begin(), ends.end());
    r.makespan_ms = ends.empty() ? 0.0 : sim::to_ms(last_end - first_start);
    if (ends.size() >= 2 && ends.back() > ends.front()) {
      r.fps = static_cast<double>(ends.size() - 1) / sim::to_seconds(ends.back() - ends.front());
    } else if (r.makespan_ms > 0) {
      r.fps = 1e3 * static_cast<double>(ends.size()) / r.makespan_ms;
    }
    const auto use = [&](const std::string& name, const sim::Resource& res) {
      r.resources.push_back({name, res.busy().elapsed() > 0 ? res.utilization() : 0.0,
                             static_cast<double>(res.capacity())});
    };
    const auto occupancy = [&](const std::string& name, const sim::TimeWeighted& w) {
      r.resources.push_back({name, w.elapsed() > 0 ? w.mean() : 0.0, w.max()});
    };
    if (accelerated_) {
      for (trace::Task task : trace::kTasks) {
        use(std::string("frontend.") + trace::to_string(task), frontend_->unit(task));
      }
      use("frontend.frame_buffers", frontend_->frame_buffers());
      if (contention_) {
        if (link_kind_->full_duplex()) {
          r.resources.push_back(
              {"link.host_to_fpga", link_->wire_utilization(Direction::HostToFpga), 1.0});
          r.resources.push_back(
              {"link.fpga_to_host", link_->wire_utilization(Direction::FpgaToHost), 1.0});
        } else {
          r.resources.push_back({"link.wire", link_->wire_utilization(Direction::HostToFpga), 1.0});
        }
        for (std::size_t i = 0; i < backend_resources_.size(); ++i) {
          if (const sim::Resource* resource = backend_->resource(i)) {
            use("backend." + backend_resources_[i], *resource);
          }
        }
      }
    }
    use("host.cores", cores_);
    // Back to back, frames do not wait for a camera: its queue is not a resource then.
    if (!isolated_ && system_.sensor_fps > 0) occupancy("queue.camera", camera_queue_);
    occupancy("queue.results", results_.occupancy());
    if (timeline_.timeline != nullptr) write_timeline_window();
    r.frames = std::move(frames_);
    r.causes = layout_.names();
    cause_ps_.resize(work_.size() * layout_.size());  // the rows of frames never taken: 0
    r.cause_ps = std::move(cause_ps_);
    return r;
  }

  sim::Simulator sim_;  // first: everything below is bound to it
  const std::vector<SystemFrameWork>& work_;
  SystemConfig system_;
  bool accelerated_, isolated_, contention_;
  std::size_t unbounded_;
  const Link* link_kind_;  ///< the platform's link kind (outlives the run)
  std::optional<FrontendAccelerator> frontend_;
  std::unique_ptr<OffloadModel> backend_;       ///< the offload accelerator's DES model
  std::vector<std::string> backend_resources_;  ///< its resource_names()
  std::unique_ptr<LinkModel> link_;             ///< the platform's link (every transfer)
  std::unique_ptr<LinkModel> frontend_link_;    ///< contention off: transfer 1 on a link of its own
  sim::Resource cores_;
  sim::Resource device_;     ///< the CPU baseline's coprocessor (one row at a time)
  sim::Resource admission_;  ///< isolated: one frame in the system
  sim::Event arrived_;
  sim::Fifo<std::size_t> results_;
  std::deque<std::size_t> camera_queue_items_;
  sim::TimeWeighted camera_queue_;
  bool camera_closed_ = false;
  std::size_t dropped_ = 0;
  std::vector<SystemFrameTiming> frames_;
  std::vector<FrontendFrameTiming> fe_;  ///< with a timeline: each frame's (else empty)
  std::vector<std::unique_ptr<FrontendFrameTiming>> spare_fe_;  ///< records of frames done
  std::vector<sim::Lease> admissions_;
  CauseLayout layout_;
  std::vector<sim::Time> cause_ps_;  ///< frames × layout_.size() (SystemRun::cause_ps)
  /// Frame f's row of cause_ps_ (opened: open_row).
  sim::Time* row(std::size_t f) { return cause_ps_.data() + f * layout_.size(); }
  /// Zeroes the rows up to frame f's when it is taken (frames are taken in order; reserved, so
  /// no row moves). Every row() of a frame comes after its next_frame().
  void open_row(std::size_t f) {
    const std::size_t end = (f + 1) * layout_.size();
    if (cause_ps_.size() < end) cause_ps_.resize(end);
  }
  SystemTimelineOptions timeline_;
  /// Spans that may overlap (frames in flight, frames waiting in a queue) on as many tracks as
  /// they need: each goes to the first track free at its start ("frames", "frames 2", ...), so
  /// no track holds two overlapping spans.
  struct Lanes {
    std::string group, name;
    std::vector<sim::Time> free_at;  ///< per track, when its last span ends
    void span(sim::Timeline& t, std::string label, sim::Time begin, sim::Time end,
              nlohmann::json args = nullptr) {
      std::size_t lane = 0;
      while (lane < free_at.size() && free_at[lane] > begin) ++lane;
      if (lane == free_at.size()) free_at.push_back(0);
      free_at[lane] = end;
      const std::string track = lane == 0 ? name : fmt::format("{} {}", name, lane + 1);
      t.span(t.track(group, track), std::move(label), begin, end, std::move(args));
    }
  };
  Lanes frames_lanes_, camera_lanes_, results_lanes_;
  sim::Timeline::TrackId frontend_thread_track_{}, backend_thread_track_{};
  std::map<trace::Task, sim::Timeline::TrackId> frontend_tracks_;
};

}  // namespace

SystemRun run_system(const std::vector<SystemFrameWork>& work, const FrontendConfig& frontend,
                     const OffloadAccelerator& backend, const Link& link, int host_cores,
                     const SystemConfig& system, bool accelerated, bool isolated,
                     const SystemTimelineOptions& timeline) {
  if (host_cores < 1) {
    throw std::runtime_error(
        fmt::format("host.cores: expected an integer >= 1, got {}", host_cores));
  }
  SystemSimulation simulation(work, frontend, backend, link, host_cores, system, accelerated,
                              isolated, timeline);
  return simulation.run();
}

}  // namespace edx::arch
