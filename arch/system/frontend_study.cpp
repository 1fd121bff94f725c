#include "arch/system/frontend_study.hpp"

#include <fmt/format.h>

#include <exception>
#include <functional>
#include <stdexcept>
#include <tuple>

#include "arch/system/system_model.hpp"
#include "common/parallel.hpp"
#include "sim_core/stats.hpp"
#include "workloads/trace/validate.hpp"

namespace edx::arch {
namespace {

/// meta.resolution as (W, H), by the trace reader's own parse (trace::parse_image_size).
std::pair<int, int> parse_wxh(const std::string& text, const std::string& trace_name) {
  const std::optional<trace::ImageSize> size = trace::parse_image_size(text);
  if (!size) {
    throw std::runtime_error(fmt::format(
        "{}: meta.resolution: expected WxH (e.g. 1280x720), got '{}'", trace_name, text));
  }
  return {static_cast<int>(size->width), static_cast<int>(size->height)};
}

}  // namespace

Distribution Distribution::of(const std::vector<double>& values) {
  sim::SampleSet set;
  for (double v : values) set.add(v);
  Distribution d;
  d.count = set.count();
  if (d.count == 0) return d;
  d.mean = set.mean();
  d.sd = d.count >= 2 ? set.sd() : 0.0;  // one sample: no spread
  d.rsd = d.mean > 0 ? d.sd / d.mean : 0.0;
  d.p50 = set.percentile(50);
  d.p90 = set.percentile(90);
  d.p99 = set.percentile(99);
  d.max = set.max();
  return d;
}

nlohmann::json Distribution::to_json() const {
  return {{"count", count}, {"mean", mean}, {"sd", sd},   {"rsd", rsd},
          {"p50", p50},     {"p90", p90},   {"p99", p99}, {"max", max}};
}

nlohmann::json FrontendStudy::to_json() const {
  nlohmann::json util = nlohmann::json::object();
  for (const auto& [unit, u] : utilization) util[unit] = u;
  nlohmann::json j = {{"platform", platform},
                      {"host", component_json(*host)},
                      {"host_mapping", host_times.to_json()},
                      {"frames", frames},
                      {"resolution", fmt::format("{}x{}", width, height)},
                      {"cpu_ms", cpu_ms.to_json()},
                      {"accel_ms", accel_ms.to_json()},
                      {"fe_ms", fe_ms.to_json()},
                      {"sm_ms", sm_ms.to_json()},
                      {"tm_ms", tm_ms.to_json()},
                      {"speedup", speedup},
                      {"cpu_fps", cpu_fps},
                      {"fps_without_pipelining", fps_without_pipelining},
                      {"fps_with_pipelining", fps_with_pipelining},
                      {"utilization", util},
                      {"memory", memory.to_json()}};
  if (coprocessor) j["coprocessor"] = component_json(*coprocessor);  // absent without one
  return j;
}

namespace {

/// The CPU baseline's frontend latency per frame, with the study's chains and backend times
/// (study.host_times, width and height set).
std::vector<double> cpu_baseline_ms(const Platform& platform,
                                    const std::vector<trace::FrameTrace>& frames,
                                    const trace::TraceMeta& trace_meta,
                                    const std::string& trace_name, FrontendStudy& study) {
  // The CPU baseline's frontend latency: the traced task graph on the host's cores (its chains
  // side by side, arch/host/frontend_graph.hpp), the rows its coprocessor states on that device
  // (arch/host/coprocessor.hpp).
  const int cores = study.host->cores();
  const Coprocessor* device = study.coprocessor.get();
  std::optional<PlatformHostTimes> device_times;
  if (device != nullptr) device_times = device->device_times(frames, trace_meta, trace_name);
  std::vector<double> cpu;
  cpu.reserve(frames.size());
  study.frame_cpu_chains.reserve(frames.size());
  for (std::size_t f = 0; f < frames.size(); ++f) {
    std::vector<double> tasks = study.host_times.task_ms[f];
    double task_sum = 0;
    for (double ms : tasks) task_sum += ms;
    const double rest = std::max(0.0, study.host_times.frontend_ms[f] - task_sum);
    std::vector<bool> on_device(tasks.size(), false);
    double backend_host = study.host_times.backend_ms[f], backend_device = 0;
    bool frontend_uses_device = false, backend_uses_device = false;
    if (device != nullptr) {
      for (std::size_t i = 0; i < tasks.size(); ++i) {
        if (!device->runs(CostPart::kFrontendTask, trace::to_string(frames[f].tasks[i].task))) {
          continue;
        }
        tasks[i] = device_times->task_ms[f][i] + device->launch_ms();
        on_device[i] = frontend_uses_device = true;
      }
      for (std::size_t k = 0; k < frames[f].kernels.size(); ++k) {
        if (!device->runs(CostPart::kBackendKernel, frames[f].kernels[k].kernel)) continue;
        backend_host -= study.host_times.kernel_ms[f][k];
        backend_device += device_times->kernel_ms[f][k] + device->launch_ms();
        backend_uses_device = true;
      }
    }
    StageChains chains = chain_times(frames[f].tasks, tasks, rest, on_device);
    // The device's setup, once per frame before its first row (no batching across frames).
    if (frontend_uses_device) {
      chains.insert(chains.begin(), {ChainTime{0.0, device->frame_setup_ms()}});
    } else if (backend_uses_device) {
      backend_device += device->frame_setup_ms();
    }
    // With ROS, the frontend node first receives the two images (ros_transport.hpp).
    const RosTransport::FrameCost ros =
        platform.ros.frame_cost(frames[f], platform.transfers, study.width, study.height);
    if (ros.frontend_ms > 0) chains.insert(chains.begin(), {ChainTime{ros.frontend_ms, 0.0}});
    cpu.push_back(frontend_latency_ms(chains, cores));
    study.frame_cpu_chains.push_back(std::move(chains));
    study.frame_backend_host_ms.push_back(std::max(0.0, backend_host) + ros.backend_ms);
    study.frame_backend_device_ms.push_back(backend_device);
  }
  return cpu;
}

}  // namespace

FrontendStudy study_frontend(const Platform& platform, const std::vector<trace::FrameTrace>& frames,
                             const trace::TraceMeta& trace_meta, const std::string& trace_name,
                             const FrontendStudyOptions& options) {
  const FrontendSimOptions& timeline = options.timeline;
  if (frames.empty())
    throw std::runtime_error(fmt::format("{}: the trace has no frames", trace_name));
  const auto resolution = trace_meta.find("resolution");
  if (resolution == trace_meta.end()) {
    throw std::runtime_error(fmt::format("{}: trace meta has no resolution", trace_name));
  }
  if (timeline.timeline && timeline.timeline_first >= frames.size()) {
    throw std::runtime_error(
        fmt::format("{}: the timeline's first frame {} is past the trace's last ({} frames)",
                    trace_name, timeline.timeline_first, frames.size()));
  }
  for (const trace::FrameTrace& f : frames) {
    if (f.tasks.empty()) {
      throw std::runtime_error(fmt::format(
          "{}: frame {}: no frontend task rows (the frontend model needs a frontend trace)",
          trace_name, f.frame.frame_id));
    }
  }
  FrontendStudy study;
  study.platform = platform.name;
  study.host = platform.baseline_host ? platform.baseline_host : platform.host;
  study.coprocessor = platform.coprocessor;
  study.frames = frames.size();
  // Four independent parts (common::run_jobs: an error is the first part's, in this order, as
  // when they ran one after another): (a) the host times and the CPU baseline's latency, (b) the
  // accelerator's frontend one frame at a time, (c) pipelined and the memory plan its buffers
  // need, (d) the frames' preparation for the system model. Each part reads the resolution
  // itself: (a) first, as it always did.
  const auto level0_pixels = [&] {
    const auto [width, height] = parse_wxh(resolution->second, trace_name);
    return static_cast<std::int64_t>(width) * height;
  };
  std::vector<double> cpu;
  FrontendConfig sequential = platform.frontend;
  sequential.pipeline_fe_sm = false;
  sequential.frame_interval_ms = 0;
  FrontendConfig pipelined = sequential;
  pipelined.pipeline_fe_sm = true;
  FrontendSimResult one_at_a_time, overlapped;
  FrontendMemoryPlan memory;
  std::exception_ptr memory_error;
  auto prepared = std::make_shared<std::vector<FrontendStudy::PreparedFrame>>(frames.size());
  const std::vector<std::function<void()>> parts = {
      [&] {
        const KnownHostTimes* known = options.known;
        if (known != nullptr && known->times &&
            known->host_key == component_json(*study.host).dump()) {
          study.host_times = *known->times;
        } else {
          study.host_times = study.host->host_times(frames, trace_meta, trace_name);
        }
        if (platform.baseline_host) {
          study.accelerated_times = platform.host->host_times(frames, trace_meta, trace_name);
        }
        std::tie(study.width, study.height) = parse_wxh(resolution->second, trace_name);
        cpu = cpu_baseline_ms(platform, frames, trace_meta, trace_name, study);
      },
      [&] {
        FrontendSimOptions sim_options;
        sim_options.link = platform.link;
        sim_options.transfers = platform.transfers;
        one_at_a_time = simulate_frontend(frames, level0_pixels(), sequential, sim_options);
      },
      [&] {
        FrontendSimOptions with_timeline = timeline;
        with_timeline.link = platform.link;
        with_timeline.transfers = platform.transfers;
        overlapped = simulate_frontend(frames, level0_pixels(), pipelined, with_timeline);
        // The memory plan sizes the pipelined run's buffers: made here, beside the other parts,
        // its error kept to be raised after theirs (it came after all four of them).
        try {
          const auto [width, height] = parse_wxh(resolution->second, trace_name);
          memory = plan_frontend_memory(frames, overlapped, width, height, pipelined,
                                        Device::by_name(platform.device), *platform.memory);
        } catch (...) {
          memory_error = std::current_exception();
        }
      },
      [&] {
        const std::int64_t level0 = level0_pixels();
        for (std::size_t f = 0; f < frames.size(); ++f) {
          FrontendStudy::PreparedFrame& p = (*prepared)[f];
          p.timing =
              prepare_frontend_frame(frames[f], level0, platform.frontend, platform.transfers);
          p.activity = frontend_activity(frames[f], platform.frontend, &p.task_activity);
        }
      }};
  common::run_jobs(parts, timeline.timeline ? 1 : options.threads);
  if (memory_error) std::rethrow_exception(memory_error);
  study.prepared_frames = std::move(prepared);

  std::vector<double> accel, fe, sm, tm;
  for (const FrontendFrameTiming& t : one_at_a_time.frames) {
    accel.push_back(t.latency_ms);
    study.frame_results_bytes.push_back(t.transfer_bytes);
    fe.push_back(t.fe_ms);
    sm.push_back(t.sm_ms);
    tm.push_back(t.tm_ms);
  }
  const sim::Time first_start = overlapped.frames.empty() ? 0 : overlapped.frames.front().start;
  for (const FrontendFrameTiming& t : overlapped.frames) {
    study.frame_pipelined_end_ms.push_back(sim::to_seconds(t.end - first_start) * 1e3);
  }
  study.frame_cpu_ms = cpu;
  study.frame_accel_ms = accel;
  study.cpu_ms = Distribution::of(cpu);
  study.accel_ms = Distribution::of(accel);
  study.fe_ms = Distribution::of(fe);
  study.sm_ms = Distribution::of(sm);
  study.tm_ms = Distribution::of(tm);
  study.speedup = study.accel_ms.mean > 0 ? study.cpu_ms.mean / study.accel_ms.mean : 0.0;
  study.cpu_fps = study.cpu_ms.mean > 0 ? 1e3 / study.cpu_ms.mean : 0.0;
  study.fps_without_pipelining = one_at_a_time.throughput_fps;
  study.fps_with_pipelining = overlapped.throughput_fps;
  study.utilization = overlapped.utilization;
  study.memory = std::move(memory);
  return study;
}

std::string format_frontend_study(const FrontendStudy& s) {
  std::string text =
      fmt::format("frontend   {} on {} frames at {}x{}\n", s.platform, s.frames, s.width, s.height);
  text +=
      fmt::format("{:<22} {:>9} {:>9} {:>9} {:>9}\n", "latency (ms)", "mean", "sd", "p99", "max");
  const auto row = [&](const char* name, const Distribution& d) {
    text += fmt::format("{:<22} {:>9.2f} {:>9.2f} {:>9.2f} {:>9.2f}\n", name, d.mean, d.sd, d.p99,
                        d.max);
  };
  row("CPU baseline", s.cpu_ms);
  row("accelerator", s.accel_ms);
  row("  FE (FD..FC, L+R)", s.fe_ms);
  row("  SM (MO..DR)", s.sm_ms);
  row("  TM (DC..LSS)", s.tm_ms);
  text += fmt::format("speedup    {:.2f}x\n", s.speedup);
  text += fmt::format("CPU        {}: {} host time {}\n", s.host->display_name(),
                      to_string(s.host_times.source), s.host_times.mapping.frontend_basis());
  if (s.coprocessor) {
    text += fmt::format(
        "coprocessor {} beside the CPU baseline: {} ms setup a frame, {} ms a call (docs/MODEL.md, "
        "GPU and DSP baselines)\n",
        s.coprocessor->display_name(), s.coprocessor->frame_setup_ms(), s.coprocessor->launch_ms());
  }
  text += fmt::format(
      "throughput CPU {:.1f} FPS; accelerator {:.1f} FPS without FE/SM pipelining, "
      "{:.1f} FPS with it\n",
      s.cpu_fps, s.fps_without_pipelining, s.fps_with_pipelining);
  text += "utilization";
  for (const auto& [unit, u] : s.utilization) text += fmt::format(" {} {:.0f}%", unit, 100 * u);
  text += "\n";
  const FrontendMemoryPlan& m = s.memory;
  text += fmt::format(
      "memory     SB {:.3f} MiB ({} buffers), FIFO {:.3f} MiB, SPM {:.3f} MiB; BRAM {:.0f} of {} "
      "blocks ({:.1f}%){}\n",
      to_mib(static_cast<double>(m.sb_bytes)), m.stencil_buffers.size(),
      to_mib(static_cast<double>(m.fifo_bytes)), to_mib(static_cast<double>(m.spm_bytes)),
      m.bram.total_blocks, m.bram.device_blocks, 100 * m.bram.utilization,
      m.bram.fits ? "" : " DOES NOT FIT");
  const bool on_chip_input = m.input_buffer_bytes > 0;
  text += fmt::format("input      {} ({:.2f} MB on chip); DRAM reads {:.2f} MiB a frame\n",
                      on_chip_input ? "left and right images of two frames double-buffered on chip"
                                    : "images read from DRAM by each stream",
                      1e-6 * static_cast<double>(m.input_buffer_bytes),
                      to_mib(static_cast<double>(m.dram_bytes_per_frame)));
  text += fmt::format(
      "SB opt.    DR has its own SBs and re-reads its pixels: {} ({:.2f} MiB more DRAM reads a "
      "frame); without the optimization the SB grows by {:.2f} MB (paper's rule, lifetime x "
      "rate) or {:.2f} MB (FIFO occupancy bound)\n",
      m.dr_left.replicate && m.dr_right.replicate && m.sb_optimization ? "yes" : "no",
      to_mib(static_cast<double>(m.extra_dram_bytes_per_frame)),
      1e-6 * static_cast<double>(m.sb_bytes_without_optimization - m.sb_bytes),
      1e-6 * static_cast<double>(m.sb_bytes_without_optimization_bound - m.sb_bytes));
  return text;
}

}  // namespace edx::arch
