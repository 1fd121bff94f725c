#include "arch/system/system_model.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <unordered_map>

#include "arch/backend/kernel_replay.hpp"
#include "arch/backend/offload_accelerator.hpp"
#include "arch/link/frame_transfers.hpp"
#include "arch/memory/bram.hpp"
#include "common/atomic_file.hpp"
#include "common/parallel.hpp"
#include "sim_core/time.hpp"

namespace edx::arch {
namespace {

/// One run's plans and transfers of the accelerable invocations, made once per kernel shape. A
/// plan (OffloadAccelerator::plan) and a transfer (kernel_transfer) read a kernel's name, sizes
/// (m, n, k), detail and its ops' kinds, sizes, flags and batches, never a host time, so the
/// invocations of one shape share them: a trace repeats shapes (the car mix at 1280x720: 1 109
/// accelerable invocations of 422 shapes; stretched to 2000 frames, 5 545 of the same 422).
class KernelShapeMemo {
 public:
  struct Costs {
    std::shared_ptr<const OffloadPlan> plan;
    KernelTransfer transfer;
    double link_s = 0;   ///< kernel_transfer_time, s
    double spill_s = 0;  ///< spill_seconds
  };

  explicit KernelShapeMemo(const Platform& platform)
      : platform_(platform), planner_(platform.backend->planner()) {}

  /// `kernel`'s costs (it must outlive the memo: it keys them).
  const Costs& costs(const trace::KernelRecord& kernel) {
    if (const auto it = costs_.find(&kernel); it != costs_.end()) return it->second;
    Costs c;
    c.plan = planner_->plan(kernel);
    c.transfer = kernel_transfer(kernel, platform_.transfers, platform_.backend->matrix_format());
    c.link_s = sim::to_seconds(kernel_transfer_time(*platform_.link, c.transfer));
    c.spill_s = spill_seconds(*c.plan, *platform_.link);
    return costs_.emplace(&kernel, std::move(c)).first->second;
  }

 private:
  /// FNV-1a over the shape's fields (a hash only: the map compares whole shapes).
  struct ShapeHash {
    std::size_t operator()(const trace::KernelRecord* k) const {
      std::uint64_t h = 14695981039346656037ull;
      const auto mix = [&h](std::uint64_t v) { h = (h ^ v) * 1099511628211ull; };
      for (unsigned char c : k->kernel) mix(c);
      for (unsigned char c : k->detail_json) mix(c);
      for (std::int64_t v : {k->m, k->n, k->k}) mix(static_cast<std::uint64_t>(v));
      for (const trace::OpRecord& op : k->ops) {
        mix(static_cast<std::uint64_t>(op.op));
        for (std::int64_t v : {op.m, op.n, op.k, op.batch}) mix(static_cast<std::uint64_t>(v));
        mix(op.flags);
      }
      return static_cast<std::size_t>(h);
    }
  };
  struct SameShape {
    bool operator()(const trace::KernelRecord* a, const trace::KernelRecord* b) const {
      const auto same_op = [](const trace::OpRecord& x, const trace::OpRecord& y) {
        return x.op == y.op && x.m == y.m && x.n == y.n && x.k == y.k && x.flags == y.flags &&
               x.batch == y.batch;
      };
      return a->kernel == b->kernel && a->m == b->m && a->n == b->n && a->k == b->k &&
             a->detail_json == b->detail_json &&
             std::equal(a->ops.begin(), a->ops.end(), b->ops.begin(), b->ops.end(), same_op);
    }
  };

  const Platform& platform_;
  const std::unique_ptr<OffloadPlanner> planner_;  ///< this run's op memo
  std::unordered_map<const trace::KernelRecord*, Costs, ShapeHash, SameShape> costs_;
};

/// Bounds of up to `parts` runs of consecutive frames with about as many kernel rows each
/// (b[0] = 0, b.back() = frames.size(); one run when `parts` <= 1): the runs a pass over the
/// frames' kernels splits into to go side by side.
std::vector<std::size_t> frame_runs(const std::vector<trace::FrameTrace>& frames, int parts) {
  std::vector<std::size_t> bounds{0};
  std::size_t total = 0;
  for (const trace::FrameTrace& f : frames) total += f.kernels.size();
  const std::size_t n = static_cast<std::size_t>(std::max(1, parts));
  std::size_t seen = 0;
  for (std::size_t f = 0; f < frames.size() && bounds.size() < n; ++f) {
    seen += frames[f].kernels.size();
    // Run i ends at the first frame whose running count reaches i/n of the kernels.
    if (seen * n >= total * bounds.size() && f + 1 < frames.size()) bounds.push_back(f + 1);
  }
  bounds.push_back(frames.size());
  return bounds;
}

/// The study's prepared frames when it has them for these `frames` (FrontendStudy::
/// prepared_frames), else nullptr.
const FrontendStudy::PreparedFrame* prepared_frames(const FrontendStudy& study,
                                                    std::size_t frames) {
  const auto& prepared = study.prepared_frames;
  return prepared != nullptr && prepared->size() == frames ? prepared->data() : nullptr;
}

/// JSON has no infinity: a kernel that cannot be offloaded has no accelerator time (null).
nlohmann::json finite_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nullptr; }

ModeSummary summarize(const std::vector<const FrameResult*>& frames) {
  std::vector<double> fe, be, e2e, energy;
  for (const FrameResult* f : frames) {
    fe.push_back(f->frontend_ms);
    be.push_back(f->backend_ms);
    e2e.push_back(f->e2e_ms);
    energy.push_back(f->energy.total_j);
  }
  ModeSummary s;
  s.frames = frames.size();
  s.frontend_ms = Distribution::of(fe);
  s.backend_ms = Distribution::of(be);
  s.e2e_ms = Distribution::of(e2e);
  s.energy_j = Distribution::of(energy);
  return s;
}

/// Per-mode and "all" summaries, and the two throughputs (see the header). `fe_end_ms`: when
/// each frame's frontend results are in, frames back to back.
void finish_variant(VariantResult& v, const std::vector<double>& fe_end_ms) {
  std::map<std::string, std::vector<const FrameResult*>> by_mode;
  double total_ms = 0;
  // A run of frames of one mode looks its list up once (map references stay valid); "all" is
  // created after the first frame's mode, as a look-up per frame would.
  std::vector<const FrameResult*>* all = nullptr;
  std::vector<const FrameResult*>* mode = nullptr;
  const std::string* mode_name = nullptr;
  for (const FrameResult& f : v.frames) {
    if (mode_name == nullptr || *mode_name != f.mode) {
      mode = &by_mode[f.mode];
      mode_name = &f.mode;
    }
    mode->push_back(&f);
    if (all == nullptr) all = &by_mode["all"];
    all->push_back(&f);
    total_ms += f.e2e_ms;
  }
  for (const auto& [mode, frames] : by_mode) v.modes[mode] = summarize(frames);
  const std::size_t n = v.frames.size();
  v.fps_without_pipelining = total_ms > 0 ? 1e3 * double(n) / total_ms : 0.0;
  if (v.stream) {
    v.fps_with_pipelining = v.stream->fps;
    return;
  }
  double b_end = 0, first_end = 0;
  for (std::size_t f = 0; f < n; ++f) {
    b_end = std::max(fe_end_ms[f], b_end) + v.frames[f].backend_ms;
    if (f == 0) first_end = b_end;
  }
  if (n >= 2 && b_end > first_end) {
    v.fps_with_pipelining = 1e3 * double(n - 1) / (b_end - first_end);
  } else {
    v.fps_with_pipelining = b_end > 0 ? 1e3 * double(n) / b_end : 0.0;
  }
}

/// The per-byte energies of the platform's on-chip memory and link (their kinds').
cost::ByteEnergies byte_energies(const Platform& platform) {
  return {platform.memory->pj_per_byte(), platform.link->pj_per_byte()};
}

/// Energy of a frame from its activity, period and host busy time (docs/MODEL.md, "Energy").
/// `accelerated`: the frame of the accelerated variant (its host's power), else the baseline's.
void set_energy(FrameResult& f, const Platform& platform, bool accelerated) {
  f.activity.frame_s = std::max(1e-3 * f.e2e_ms, 1e-12);
  f.activity.host_busy_s = std::min(1e-3 * f.host_busy_ms, f.activity.frame_s);
  f.energy = cost::frame_energy(f.activity, platform.power, platform.host_of(accelerated).power(),
                                byte_energies(platform));
}

/// The streamed run's summary. Energy (docs/MODEL.md, "Energy per resource"): over the run's
/// span T (makespan), each FPGA unit E = busy·P_active + idle·P_idle with P_active its processed
/// frames' work energy over its busy time and P_idle = fpga_idle_fraction · P_active; each link
/// direction its bytes' energy (idle power 0); the host package
/// s_host·(P_active·min(B, T) + P_idle·(T − min(B, T))), B the cores' busy time (the package
/// draws its active power at most); the device static P_static·T; DRAM its bytes' energy.
/// energy_j = Σ / processed frames.
StreamSummary summarize_stream(const SystemRun& run, const std::vector<FrameResult>& frames,
                               double sensor_fps, const Platform& platform) {
  const cost::PowerConfig& power = platform.power;
  StreamSummary s;
  s.sensor_fps = sensor_fps;
  s.frames = run.frames.size();
  s.dropped = run.dropped;
  s.fps = run.fps;
  s.resources = run.resources;
  std::vector<double> latency;
  EnergyParts parts;
  const std::vector<std::string> backend_resources = platform.backend->resource_names();
  parts.backend.assign(backend_resources.size(), 0.0);
  for (std::size_t f = 0; f < run.frames.size(); ++f) {
    const SystemFrameTiming& t = run.frames[f];
    if (t.dropped) continue;
    latency.push_back(sim::to_ms(t.end - t.arrival));
    parts += frames[f].parts;
  }
  s.latency_ms = Distribution::of(latency);
  if (latency.empty()) return s;
  const double span = std::max(1e-3 * run.makespan_ms, 1e-12);
  const auto busy_s = [&](const std::string& name) {
    for (const ResourceUse& u : run.resources) {
      if (u.name == name) return u.busy * u.max * span;
    }
    return 0.0;  // not tracked (contention off): the unit keeps its work energy
  };
  // A unit's copy-seconds over the run: its copies x the span.
  const auto copies_s = [&](const std::string& name) {
    for (const ResourceUse& u : run.resources) {
      if (u.name == name) return u.max * span;
    }
    return span;
  };
  std::vector<cost::ResourceEnergy>& out = s.energy_by_resource;
  const bool fpga = !frames.empty() && frames.front().activity.fpga_present;
  if (fpga) {
    cost::ResourceEnergy st;
    st.name = "fpga.static";
    st.idle_s = span;
    st.active_w = st.idle_w = power.fpga_static_w;
    st.energy_j = power.fpga_static_w * span;
    out.push_back(st);
    for (trace::Task task : trace::kTasks) {
      const std::string name = std::string("frontend.") + trace::to_string(task);
      out.push_back(cost::unit_energy(name, busy_s(name), copies_s(name),
                                      parts.frontend[static_cast<std::size_t>(task)], power));
    }
    for (std::size_t u = 0; u < backend_resources.size(); ++u) {
      const std::string name = "backend." + backend_resources[u];
      out.push_back(cost::unit_energy(name, busy_s(name), copies_s(name), parts.backend[u], power));
    }
    const auto link = [&](const std::string& name, double j) {
      cost::ResourceEnergy e;
      e.name = name;
      e.busy_s = busy_s(name);
      e.idle_s = std::max(0.0, span - e.busy_s);
      e.active_w = e.busy_s > 0 ? j / e.busy_s : 0.0;
      e.energy_j = j;
      out.push_back(e);
    };
    if (platform.link->full_duplex()) {
      link("link.host_to_fpga", parts.link_to_fpga);
      link("link.fpga_to_host", parts.link_to_host);
    } else {
      link("link.wire", parts.link_to_fpga + parts.link_to_host);
    }
    cost::ResourceEnergy dram;
    dram.name = "dram";
    dram.energy_j = parts.dram;
    out.push_back(dram);
  }
  cost::ResourceEnergy host;
  host.name = "host.cores";
  host.busy_s = std::min(1e-3 * run.host_busy_ms, span);
  host.idle_s = span - host.busy_s;
  const HostPower package = platform.host_of(run.accelerated).power();
  host.active_w = power.host_power_scale * package.active_w;
  host.idle_w = power.host_power_scale * package.idle_w;
  host.energy_j = host.busy_s * host.active_w + host.idle_s * host.idle_w;
  out.push_back(host);
  double total = 0;
  for (const cost::ResourceEnergy& e : out) total += e.energy_j;
  s.energy_j = total / static_cast<double>(latency.size());
  return s;
}

/// A run's attribution (SystemRun::cause_ps) as a CauseTable: the causes that took time in
/// some frame, in ms; the frames' modes from `frames`.
results::CauseTable cause_table(const SystemRun& run, const std::vector<FrameResult>& frames) {
  const std::size_t n = run.causes.size();
  std::vector<std::size_t> kept;
  for (std::size_t c = 0; c < n; ++c) {
    for (std::size_t f = 0; f < run.frames.size(); ++f) {
      if (run.cause_ps[f * n + c] != 0) {
        kept.push_back(c);
        break;
      }
    }
  }
  results::CauseTable t;
  for (std::size_t c : kept) t.causes.push_back(run.causes[c]);
  t.frames.reserve(run.frames.size());
  t.ms.reserve(run.frames.size() * kept.size());
  for (std::size_t f = 0; f < run.frames.size(); ++f) {
    const SystemFrameTiming& timing = run.frames[f];
    sim::Time sum = 0;
    for (std::size_t c : kept) {
      sum += run.cause_ps[f * n + c];
      t.ms.push_back(sim::to_ms(run.cause_ps[f * n + c]));
    }
    t.frames.push_back({timing.frame_id, frames[f].mode, timing.dropped, sim::to_ms(sum)});
  }
  return t;
}

/// The runs of a variant on `platform` (system_des.hpp: run_system).
/// The CPU baseline's work per frame (its frontend study's host times and chains).
std::vector<SystemFrameWork> baseline_frame_work(const std::vector<trace::FrameTrace>& frames,
                                                 const FrontendStudy& study) {
  std::vector<SystemFrameWork> work(frames.size());
  for (std::size_t f = 0; f < frames.size(); ++f) {
    SystemFrameWork& w = work[f];
    w.frame_id = frames[f].frame.frame_id;
    w.frontend_host_ms = study.frame_cpu_ms[f];
    w.frontend_host_chains = study.frame_cpu_chains[f];
    w.backend_host_ms = study.frame_backend_host_ms[f];
    w.backend_device_ms = study.frame_backend_device_ms[f];
  }
  return work;
}

SystemRun run_variant(const std::vector<SystemFrameWork>& work, const Platform& platform,
                      bool accelerated, bool isolated, const SystemTimelineOptions& timeline) {
  return run_system(work, platform.frontend, *platform.backend, *platform.link,
                    platform.host_of(accelerated).cores(), platform.system, accelerated, isolated,
                    timeline);
}

/// Model "des": runs the whole-system DES (system_des.hpp) for both variants, isolated and
/// streamed (the baseline's from `options.baseline` when given), and replaces the analytical
/// latencies of `r`'s frames by the isolated runs'.
/// `accel`, `transfers`: per accelerable invocation, in the order of r.decisions; `study`: the
/// platform's frontend study.
void simulate_platform_des(const Platform& platform, const std::vector<trace::FrameTrace>& frames,
                           const FrontendStudy& study, SystemResult& r,
                           const std::vector<std::shared_ptr<const OffloadPlan>>& accel,
                           const std::vector<KernelTransfer>& transfers,
                           const SystemSimOptions& options) {
  const PlatformHostTimes& host = study.accelerated_host_times();
  const std::int64_t level0 = static_cast<std::int64_t>(study.width) * study.height;
  const FrontendStudy::PreparedFrame* prepared = prepared_frames(study, frames.size());
  // The accelerated variant's work (the baseline's fields are run_baseline_des's).
  std::vector<SystemFrameWork> work(frames.size());
  std::size_t next = 0;  // index into decisions
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const trace::FrameTrace& frame = frames[f];
    SystemFrameWork& w = work[f];
    w.frame_id = frame.frame.frame_id;
    w.frontend = prepared != nullptr
                     ? prepared[f].timing
                     : prepare_frontend_frame(frame, level0, platform.frontend, platform.transfers);
    const std::vector<double>& kernel_ms = host.kernel_ms[f];
    std::vector<bool> offloaded;
    offloaded.reserve(frame.kernels.size());
    for (std::size_t k = 0; k < frame.kernels.size(); ++k) {
      bool off = false;
      // The decisions list the candidates in trace order (frame ids are unique in a trace).
      if (next < r.decisions.size() && r.decisions[next].frame_id == w.frame_id &&
          r.decisions[next].kernel_seq == static_cast<int>(k)) {
        const KernelDecision& d = r.decisions[next];
        off = d.offloaded;
        if (off) {
          // Its label names timeline spans only: made when a timeline is asked for.
          w.offloads.push_back(
              {accel[next].get(), transfers[next].input_bytes, transfers[next].output_bytes,
               options.timeline ? fmt::format("f{} {}", w.frame_id, d.kernel) : std::string(),
               accel[next]->spill.read_bytes, accel[next]->spill.write_bytes});
        }
        ++next;
      }
      offloaded.push_back(off);
    }
    w.backend_steps = split_backend(frame, host.backend_ms[f], kernel_ms, offloaded);
  }
  sim::Timeline timeline;
  SystemTimelineOptions timeline_options;
  if (options.timeline) {
    timeline_options = {&timeline, options.timeline_first, options.timeline_count};
  }
  // Up to four independent runs (common::run_jobs: an error is the first run's in this order,
  // the order they ran in one after another).
  std::shared_ptr<const BaselineRuns> baseline = options.baseline;
  BaselineRuns made, accelerated;
  std::vector<std::function<void()>> des_runs;
  if (!baseline) {
    const std::vector<SystemFrameWork> baseline_work = baseline_frame_work(frames, study);
    des_runs.push_back(
        [&] { made.isolated = run_variant(baseline_work, platform, false, true, {}); });
    des_runs.push_back(
        [&] { made.streamed = run_variant(baseline_work, platform, false, false, {}); });
    des_runs.push_back([&] { accelerated.isolated = run_variant(work, platform, true, true, {}); });
    des_runs.push_back(
        [&] { accelerated.streamed = run_variant(work, platform, true, false, timeline_options); });
    common::run_jobs(des_runs, options.threads);
    baseline = std::make_shared<const BaselineRuns>(std::move(made));
  } else {
    des_runs.push_back([&] { accelerated.isolated = run_variant(work, platform, true, true, {}); });
    des_runs.push_back(
        [&] { accelerated.streamed = run_variant(work, platform, true, false, timeline_options); });
    common::run_jobs(des_runs, options.threads);
  }
  // Each variant's frames and summaries from its runs (the two side by side).
  const auto summarize_variant = [&](VariantResult& v, const BaselineRuns& runs) {
    for (std::size_t f = 0; f < frames.size(); ++f) {
      const SystemFrameTiming& t = runs.isolated.frames[f];
      FrameResult& out = v.frames[f];
      out.frontend_ms = sim::to_ms(t.frontend_end - t.start);
      out.backend_ms = sim::to_ms(t.end - t.backend_start);
      out.e2e_ms = sim::to_ms(t.end - t.start);
      out.host_busy_ms = std::min(t.host_busy_ms, out.e2e_ms);
    }
    v.isolated_causes = cause_table(runs.isolated, v.frames);
    v.stream = summarize_stream(runs.streamed, v.frames, platform.system.sensor_fps, platform);
    v.streamed_causes = cause_table(runs.streamed, v.frames);
  };
  common::run_jobs({[&] { summarize_variant(r.baseline, *baseline); },
                    [&] { summarize_variant(r.accelerated, accelerated); }},
                   options.threads);
  if (options.timeline) {
    r.timeline_json = timeline.to_json().dump();
    r.timeline_first = options.timeline_first;
    r.timeline_frames = std::min(options.timeline_count, frames.size() - options.timeline_first);
    common::write_file_atomically(*options.timeline, r.timeline_json);
  }
}

}  // namespace

const char* to_string(SystemModelKind kind) {
  return kind == SystemModelKind::kDes ? "des" : "analytical";
}

SystemModelKind parse_system_model(const std::string& text) {
  if (text == "des") return SystemModelKind::kDes;
  if (text == "analytical") return SystemModelKind::kAnalytical;
  throw std::runtime_error(fmt::format("expected des or analytical, got '{}'", text));
}

nlohmann::json StreamSummary::to_json() const {
  nlohmann::json use = nlohmann::json::object();
  for (const ResourceUse& r : resources) use[r.name] = {{"busy", r.busy}, {"max", r.max}};
  nlohmann::json energy = nlohmann::json::object();
  for (const cost::ResourceEnergy& e : energy_by_resource) energy[e.name] = e.to_json();
  return {{"sensor_fps", sensor_fps},
          {"frames", frames},
          {"dropped", dropped},
          {"fps", fps},
          {"latency_ms", latency_ms.to_json()},
          {"energy_j", energy_j},
          {"energy_by_resource", energy},
          {"utilization", use}};
}

std::string fnv1a_hex(const std::string& text) {
  std::uint64_t h = 14695981039346656037ull;  // FNV-1a 64 offset basis
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;  // FNV prime
  }
  return fmt::format("{:016x}", h);
}

EnergyParts& EnergyParts::operator+=(const EnergyParts& other) {
  for (std::size_t t = 0; t < frontend.size(); ++t) frontend[t] += other.frontend[t];
  if (backend.size() < other.backend.size()) backend.resize(other.backend.size(), 0.0);
  for (std::size_t u = 0; u < other.backend.size(); ++u) backend[u] += other.backend[u];
  link_to_fpga += other.link_to_fpga;
  link_to_host += other.link_to_host;
  dram += other.dram;
  return *this;
}

double EnergyParts::total() const {
  double sum = 0;
  for (double j : frontend) sum += j;
  for (double j : backend) sum += j;
  return sum + link_to_fpga + link_to_host + dram;
}

nlohmann::json KernelDecision::to_json() const {
  return {{"frame_id", frame_id},     {"kernel_seq", kernel_seq},
          {"kernel", kernel},         {"size", size},
          {"host_ms", host_ms},       {"accel_ms", finite_or_null(accel_ms)},
          {"compute_ms", compute_ms}, {"transfer_ms", transfer_ms},
          {"spill_ms", spill_ms},     {"spill_bytes", spill_bytes},
          {"fits_spm", fits_spm},     {"training", training},
          {"offloaded", offloaded}};
}

nlohmann::json ModeSummary::to_json() const {
  return {{"frames", frames},
          {"frontend_ms", frontend_ms.to_json()},
          {"backend_ms", backend_ms.to_json()},
          {"e2e_ms", e2e_ms.to_json()},
          {"energy_j", energy_j.to_json()}};
}

nlohmann::json VariantResult::to_json() const {
  nlohmann::json m = nlohmann::json::object();
  for (const auto& [mode, s] : modes) m[mode] = s.to_json();
  nlohmann::json j = {{"variant", variant},
                      {"modes", m},
                      {"fps_without_pipelining", fps_without_pipelining},
                      {"fps_with_pipelining", fps_with_pipelining}};
  if (stream) j["stream"] = stream->to_json();
  if (isolated_causes && streamed_causes) {
    j["attribution"] = {{"isolated", results::causes_json(*isolated_causes)},
                        {"streamed", results::causes_json(*streamed_causes)}};
  }
  return j;
}

nlohmann::json SystemResult::comparison() const {
  const auto ratio = [](double a, double b) { return b > 0 ? a / b : 0.0; };
  const auto reduction = [](double base, double acc) { return base > 0 ? 1.0 - acc / base : 0.0; };
  nlohmann::json out = nlohmann::json::object();
  for (const auto& [mode, base] : baseline.modes) {
    const ModeSummary& acc = accelerated.modes.at(mode);
    out[mode] = {
        {"e2e_speedup", ratio(base.e2e_ms.mean, acc.e2e_ms.mean)},
        {"frontend_speedup", ratio(base.frontend_ms.mean, acc.frontend_ms.mean)},
        {"backend_speedup", ratio(base.backend_ms.mean, acc.backend_ms.mean)},
        {"backend_latency_reduction", reduction(base.backend_ms.mean, acc.backend_ms.mean)},
        {"e2e_sd_reduction", reduction(base.e2e_ms.sd, acc.e2e_ms.sd)},
        {"backend_sd_reduction", reduction(base.backend_ms.sd, acc.backend_ms.sd)},
        {"energy_reduction", reduction(base.energy_j.mean, acc.energy_j.mean)}};
  }
  return out;
}

nlohmann::json SystemResult::to_json() const {
  nlohmann::json sched = nlohmann::json::array();
  for (const KernelScheduleSummary& s : schedule) {
    nlohmann::json j = s.to_json();
    j["always_s"] = finite_or_null(s.always_s);
    sched.push_back(j);
  }
  std::size_t offloaded = 0, accelerable = 0, spilling = 0, spilled = 0;
  std::int64_t spilled_bytes = 0;
  for (const KernelDecision& d : decisions) {
    ++accelerable;
    if (d.offloaded) ++offloaded;
    if (!d.fits_spm) ++spilling;
    if (!d.fits_spm && d.offloaded) {
      ++spilled;
      spilled_bytes += d.spill_bytes;
    }
  }
  nlohmann::json table3 = nlohmann::json::array();
  for (const cost::PaperComparison& c : cost::compare_to_table_iii(resources)) {
    table3.push_back(c.to_json());
  }
  return {{"platform", platform},
          {"model", to_string(model)},
          {"config_hash", config_hash},
          {"trace_hash", trace_hash},
          {"trace", trace_path},
          {"frames", baseline.frames.size()},
          {"policy", to_string(config.scheduler.policy)},
          {"baseline", baseline.to_json()},
          {"accelerated", accelerated.to_json()},
          {"comparison", comparison()},
          {"offload",
           {{"accelerable_invocations", accelerable},
            {"offloaded", offloaded},
            // SPM spills (docs/MODEL.md): invocations whose operands exceed backend.spm_bytes,
            // those of them offloaded (run out of core), and the DRAM bytes those moved.
            {"exceeding_spm", spilling},
            {"spilled_offloaded", spilled},
            {"spilled_bytes", spilled_bytes},
            {"kernels", sched}}},
          {"resources",
           {{"device", resources.device.name},
            {"total", resources.total.shared.to_json()},
            {"ns_total", resources.total.ns.to_json()},
            {"utilization", resources.utilization.to_json()},
            {"bram_mib", resources.bram_mib},
            {"ns_bram_mib", resources.ns_bram_mib},
            {"frontend_share", resources.frontend_share.to_json()},
            {"fits", resources.fits},
            {"edx_car_table_iii", table3}}}};
}

cost::FrameActivity frontend_activity(const trace::FrameTrace& frame, const FrontendConfig& fe,
                                      std::array<cost::FrameActivity, 7>* per_task) {
  std::array<cost::FrameActivity, 7> tasks{};
  for (const trace::TaskRecord& t : frame.tasks) {
    const cost::FrameActivity row = fe.unit(t.task).unit->activity(t, fe);
    cost::FrameActivity& a = tasks[static_cast<std::size_t>(t.task)];
    a.int8_ops += row.int8_ops;
    a.fixed_macs += row.fixed_macs;
    a.single_macs += row.single_macs;
    a.bram_bytes += row.bram_bytes;
  }
  cost::FrameActivity a;
  for (const cost::FrameActivity& t : tasks) {
    a.int8_ops += t.int8_ops;
    a.fixed_macs += t.fixed_macs;
    a.single_macs += t.single_macs;
    a.bram_bytes += t.bram_bytes;
  }
  if (per_task != nullptr) *per_task = tasks;
  return a;
}

std::string trace_hash(std::size_t frames, const trace::TraceMeta& trace_meta) {
  std::string fingerprint = fmt::format("frames={}\n", frames);
  for (const auto& [key, value] : trace_meta) fingerprint += key + "=" + value + "\n";
  return fnv1a_hex(fingerprint);
}

std::string frontend_study_key(const Platform& platform) {
  nlohmann::json key = {
      {"host", component_json(*platform.host)},    {"frontend", platform.frontend.to_json()},
      {"link", component_json(*platform.link)},    {"memory", component_json(*platform.memory)},
      {"transfers", platform.transfers.to_json()}, {"device", platform.device}};
  if (platform.baseline_host) key["baseline_host"] = component_json(*platform.baseline_host);
  if (platform.coprocessor) key["coprocessor"] = component_json(*platform.coprocessor);
  if (platform.ros.enabled) key["ros"] = platform.ros.to_json();
  return key.dump();
}

std::string baseline_des_key(const Platform& platform) {
  return frontend_study_key(platform) + "\nsystem=" + platform.system.to_json().dump();
}

BaselineRuns run_baseline_des(const Platform& platform,
                              const std::vector<trace::FrameTrace>& frames,
                              const FrontendStudy& study, int threads) {
  const std::vector<SystemFrameWork> work = baseline_frame_work(frames, study);
  BaselineRuns runs;
  common::run_jobs({[&] { runs.isolated = run_variant(work, platform, false, true, {}); },
                    [&] { runs.streamed = run_variant(work, platform, false, false, {}); }},
                   threads);
  return runs;
}

void check_precision(const Platform& platform, const trace::TraceMeta& trace_meta,
                     const std::string& trace_path) {
  trace::Precision traced;
  try {
    traced = trace::trace_precision(trace_meta);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(fmt::format("{}: meta precision: {}", trace_path, e.what()));
  }
  if (traced != platform.backend->precision()) {
    throw std::runtime_error(fmt::format(
        "{}: the trace computed its backend kernels in {} (meta precision), but platform {} "
        "computes in {} (backend.precision); trace with --precision {} or set "
        "backend.precision: {}",
        trace_path, trace::to_string(traced), platform.name,
        trace::to_string(platform.backend->precision()),
        trace::to_string(platform.backend->precision()), trace::to_string(traced)));
  }
  if (traced == trace::Precision::kFp64) return;
  for (const std::string& kernel : platform.scheduler.offload) {
    if (!trace::computed_at_trace_precision(kernel)) {
      throw std::runtime_error(fmt::format(
          "{}: platform {} offloads {} (scheduler.offload), which the backends compute in fp64 "
          "only; at fp32 the units may run {}",
          trace_path, platform.name, kernel, fmt::join(trace::kKernelsAtTracePrecision, ", ")));
    }
  }
}

SystemResult simulate_system(const Platform& platform, const std::vector<trace::FrameTrace>& frames,
                             const trace::TraceMeta& trace_meta, const std::string& trace_path,
                             const SystemSimOptions& options) {
  check_precision(platform, trace_meta, trace_path);
  // The analytical model's timeline is the frontend's pipelined run (the frontend study's).
  FrontendStudyOptions study_options;
  if (options.model == SystemModelKind::kAnalytical && options.timeline) {
    study_options.timeline.timeline = options.timeline;
    study_options.timeline.timeline_first = options.timeline_first;
    study_options.timeline.timeline_count = options.timeline_count;
  }
  study_options.threads = options.threads;
  try {
    return simulate_system(platform, frames, trace_meta, trace_path,
                           study_frontend(platform, frames, trace_meta, trace_path, study_options),
                           options);
  } catch (const InputError& e) {
    throw platform.locate(e);  // a key's value the trace takes past what the model holds
  } catch (const sim::TimeRangeError&) {
    // Simulated time (2^64 ps) or a cycle count ran out: the trace's work on this platform is
    // more than the model holds, said in the words of the inputs rather than of sim_core.
    throw std::runtime_error(fmt::format(
        "{}: simulating its {} frames on {} passes the 213 days simulated time holds (2^64 ps): "
        "a trace count or platform value beyond what the model takes (docs/RELIABILITY.md, "
        "\"Input limits\")",
        trace_path, frames.size(), platform.file.empty() ? platform.name : platform.file));
  } catch (const sim::EventCountError&) {
    throw std::runtime_error(fmt::format(
        "{}: simulating its {} frames on {} schedules more than the 2^48 events one simulation "
        "holds: a trace too long for one run",
        trace_path, frames.size(), platform.file.empty() ? platform.name : platform.file));
  }
}

namespace {

/// simulate_system on the platform's frontend study `study` (its `platform` name may be another
/// platform's: the study reads only what frontend_study_key covers); study is the caller's.
SystemResult simulate_on_study(const Platform& platform,
                               const std::vector<trace::FrameTrace>& frames,
                               const trace::TraceMeta& trace_meta, const std::string& trace_path,
                               const FrontendStudy& study, const SystemSimOptions& options) {
  if (options.timeline && options.timeline_first >= frames.size()) {
    throw std::runtime_error(
        fmt::format("{}: the timeline's first frame {} is past the trace's last ({} frames)",
                    trace_path, options.timeline_first, frames.size()));
  }
  platform.validate();  // once per run; the per-kernel and per-transfer functions do not
  check_precision(platform, trace_meta, trace_path);
  SystemResult r;
  r.model = options.model;
  r.platform = platform.name;
  r.config = platform;
  r.trace_path = trace_path;
  r.config_hash = fnv1a_hex(platform.to_json().dump());
  r.trace_hash = trace_hash(frames.size(), trace_meta);

  // Every accelerable kernel: host time, accelerator time (units + link), SPM check.
  // The study's mapping: frontend_study_key includes the host, so it is this platform's. The
  // kernels' host times and the accelerated backend's are the accelerated system's host's.
  const PlatformHostTimes& host = study.accelerated_host_times();
  // The accelerable kernels in trace order, costed in up to `options.threads` runs of frames
  // side by side (frame_runs), each with its own shape memo, then joined in order: a shape's
  // costs are a function of the shape and the platform, so which run costs it changes nothing,
  // and an error is the first run's, as one pass over the frames would meet it.
  struct Candidates {
    std::vector<KernelDecision> decisions;
    std::vector<KernelInvocation> invocations;
    std::vector<std::shared_ptr<const OffloadPlan>> accel;
    std::vector<KernelTransfer> transfers;
  };
  const auto collect = [&](std::size_t first, std::size_t last, Candidates& out) {
    KernelShapeMemo memo(platform);
    for (std::size_t f = first; f < last; ++f) {
      const trace::FrameTrace& frame = frames[f];
      for (std::size_t k = 0; k < frame.kernels.size(); ++k) {
        const trace::KernelRecord& kernel = frame.kernels[k];
        if (!platform.scheduler.offloads(kernel.kernel) || !has_ops(kernel)) continue;
        const KernelShapeMemo::Costs& costs = memo.costs(kernel);
        const OffloadPlan* a = costs.plan.get();
        KernelDecision d;
        d.frame_id = frame.frame.frame_id;
        d.kernel_seq = static_cast<int>(k);
        d.kernel = kernel.kernel;
        d.size = double(kernel.m);
        d.host_ms = host.kernel_ms[f][k];
        d.compute_ms = 1e3 * a->compute_s;
        d.transfer_ms = 1e3 * costs.link_s;
        d.fits_spm = a->fits_local_memory;
        d.spill_ms = 1e3 * costs.spill_s;
        d.spill_bytes = a->spill.bytes();
        d.accel_ms = d.compute_ms + d.transfer_ms + d.spill_ms;
        KernelInvocation inv;
        inv.frame_index = f;
        inv.kernel = kernel.kernel;
        inv.size = d.size;
        inv.host_s = 1e-3 * d.host_ms;
        // The scheduler's estimate is the same analytical profile + idle-link time (spills
        // included: a kernel whose spill costs more than the host saves stays there).
        inv.accel_s = inv.accel_estimate_s = 1e-3 * d.accel_ms;
        out.invocations.push_back(inv);
        out.decisions.push_back(std::move(d));
        out.accel.push_back(costs.plan);
        out.transfers.push_back(costs.transfer);
      }
    }
  };
  const std::vector<std::size_t> bounds = frame_runs(frames, options.threads);
  std::vector<Candidates> runs(bounds.size() - 1);
  std::vector<std::function<void()>> costing;
  for (std::size_t i = 0; i + 1 < bounds.size(); ++i) {
    costing.push_back([&, i] { collect(bounds[i], bounds[i + 1], runs[i]); });
  }
  common::run_jobs(costing, options.threads);
  std::vector<KernelInvocation> invocations;
  std::vector<std::shared_ptr<const OffloadPlan>> accel;
  std::vector<KernelTransfer> transfers;
  for (Candidates& c : runs) {
    const auto append = [](auto& to, auto& from) {
      to.insert(to.end(), std::make_move_iterator(from.begin()),
                std::make_move_iterator(from.end()));
    };
    append(r.decisions, c.decisions);
    append(invocations, c.invocations);
    append(accel, c.accel);
    append(transfers, c.transfers);
  }
  OffloadScheduler scheduler(platform.scheduler.policy, platform.scheduler.training_fraction);
  std::vector<ScheduleDecision> decided;
  r.schedule = evaluate_schedule(scheduler, invocations, &decided);  // trains the models
  for (std::size_t i = 0; i < invocations.size(); ++i) {
    r.decisions[i].training = decided[i].training;
    r.decisions[i].offloaded = decided[i].offloaded;
  }

  // Per frame, both variants.
  r.baseline.variant = "baseline";
  r.accelerated.variant = "accelerated";
  const std::int64_t extra_dram = study.memory.extra_dram_bytes_per_frame;
  std::size_t next = 0;  // index into decisions (frame order)
  const std::size_t backend_resources = platform.backend->resource_names().size();
  const FrontendStudy::PreparedFrame* prepared = prepared_frames(study, frames.size());
  std::vector<double> cpu_fe_end;
  cpu_fe_end.reserve(frames.size());
  r.baseline.frames.reserve(frames.size());
  r.accelerated.frames.reserve(frames.size());
  double cpu_fe_clock = 0;
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const trace::FrameTrace& frame = frames[f];
    FrameResult base;
    base.frame_id = frame.frame.frame_id;
    base.mode = trace::to_string(frame.frame.mode);
    base.frontend_ms = study.frame_cpu_ms[f];
    base.backend_ms = study.frame_backend_host_ms[f] + study.frame_backend_device_ms[f];
    base.e2e_ms = base.frontend_ms + base.backend_ms;
    // The host's work (its cores' busy time, as the DES counts it): the chains' host parts and
    // the backend's; it waits while the coprocessor computes. At most the frame.
    double host_work = study.frame_backend_host_ms[f];
    for (const std::vector<ChainTime>& stage : study.frame_cpu_chains[f]) {
      for (const ChainTime& chain : stage) host_work += chain.host_ms;
    }
    base.host_busy_ms = std::min(host_work, base.e2e_ms);
    base.activity.fpga_present = false;
    cpu_fe_clock += base.frontend_ms;
    cpu_fe_end.push_back(cpu_fe_clock);

    FrameResult acc = base;
    acc.frontend_ms = study.frame_accel_ms[f];
    std::array<cost::FrameActivity, 7> task_activity;
    if (prepared != nullptr) {
      acc.activity = prepared[f].activity;
      task_activity = prepared[f].task_activity;
    } else {
      acc.activity = frontend_activity(frame, platform.frontend, &task_activity);
    }
    acc.activity.fpga_present = true;
    acc.activity.dram_bytes = double(extra_dram);
    acc.activity.link_bytes = double(study.frame_results_bytes[f]);
    // The same work by resource (docs/MODEL.md, "Energy per resource").
    for (std::size_t t = 0; t < task_activity.size(); ++t) {
      acc.parts.frontend[t] =
          cost::dynamic_energy_j(task_activity[t], platform.power, byte_energies(platform));
    }
    std::vector<cost::FrameActivity> resource_activity(backend_resources);
    double to_fpga_bytes = 0, to_host_bytes = acc.activity.link_bytes;
    double backend_ms = host.backend_ms[f], host_ms = host.backend_ms[f];
    for (; next < r.decisions.size() && r.decisions[next].frame_id == frame.frame.frame_id;
         ++next) {
      const KernelDecision& d = r.decisions[next];
      if (!d.offloaded) continue;
      ++acc.offloaded;
      backend_ms += d.accel_ms - d.host_ms;
      host_ms -= d.host_ms;
      // Its work on the accelerator's resources (MACs, local-memory bytes), frame and resource.
      const std::vector<cost::FrameActivity>& work = accel[next]->activity;
      for (std::size_t u = 0; u < work.size(); ++u) {
        acc.activity.single_macs += work[u].single_macs;
        acc.activity.double_macs += work[u].double_macs;
        resource_activity[u].single_macs += work[u].single_macs;
        resource_activity[u].double_macs += work[u].double_macs;
      }
      for (std::size_t u = 0; u < work.size(); ++u) {
        acc.activity.bram_bytes += work[u].bram_bytes;
        resource_activity[u].bram_bytes += work[u].bram_bytes;
      }
      acc.activity.link_bytes += double(transfers[next].input_bytes + transfers[next].output_bytes);
      // Spill traffic: DRAM bytes carried by the link (kernel_replay.hpp: spill_seconds).
      acc.activity.dram_bytes += double(d.spill_bytes);
      acc.activity.link_bytes += double(d.spill_bytes);
      to_fpga_bytes += double(transfers[next].input_bytes + accel[next]->spill.read_bytes);
      to_host_bytes += double(transfers[next].output_bytes + accel[next]->spill.write_bytes);
    }
    acc.parts.backend.resize(resource_activity.size());
    for (std::size_t u = 0; u < resource_activity.size(); ++u) {
      acc.parts.backend[u] =
          cost::dynamic_energy_j(resource_activity[u], platform.power, byte_energies(platform));
    }
    const auto bytes_j = [&](double bytes, double pj) { return 1e-12 * bytes * pj; };
    acc.parts.link_to_fpga = bytes_j(to_fpga_bytes, platform.link->pj_per_byte());
    acc.parts.link_to_host = bytes_j(to_host_bytes, platform.link->pj_per_byte());
    acc.parts.dram = bytes_j(acc.activity.dram_bytes, platform.power.dram_pj_per_byte);
    acc.backend_ms = std::max(0.0, backend_ms);
    acc.e2e_ms = acc.frontend_ms + acc.backend_ms;
    acc.host_busy_ms = std::clamp(host_ms, 0.0, acc.e2e_ms);
    r.baseline.frames.push_back(std::move(base));
    r.accelerated.frames.push_back(std::move(acc));
  }
  if (options.model == SystemModelKind::kDes) {
    simulate_platform_des(platform, frames, study, r, accel, transfers, options);
  }
  // Each variant's energy and summaries (the two side by side).
  common::run_jobs({[&] {
                      for (FrameResult& f : r.baseline.frames) set_energy(f, platform, false);
                      finish_variant(r.baseline, cpu_fe_end);
                    },
                    [&] {
                      for (FrameResult& f : r.accelerated.frames) set_energy(f, platform, true);
                      finish_variant(r.accelerated, study.frame_pipelined_end_ms);
                    }},
                   options.threads);

  std::vector<MemoryStructure> memories;
  for (const StructureUsage& s : study.memory.bram.structures) memories.push_back(s.structure);
  r.resources = cost::build_resource_report(
      platform.frontend, *platform.backend, platform.cost, *platform.memory, memories,
      Device::by_name(platform.device), platform.scheduler.offload);
  return r;
}

}  // namespace

SystemResult simulate_system(const Platform& platform, const std::vector<trace::FrameTrace>& frames,
                             const trace::TraceMeta& trace_meta, const std::string& trace_path,
                             FrontendStudy frontend, const SystemSimOptions& options) {
  frontend.platform = platform.name;
  SystemResult r = simulate_on_study(platform, frames, trace_meta, trace_path, frontend, options);
  r.frontend = std::move(frontend);
  return r;
}

SystemResult simulate_system(const Platform& platform, const std::vector<trace::FrameTrace>& frames,
                             const trace::TraceMeta& trace_meta, const std::string& trace_path,
                             const std::shared_ptr<const FrontendStudy>& frontend,
                             const SystemSimOptions& options) {
  if (!frontend) throw std::logic_error("simulate_system: no frontend study");
  return simulate_on_study(platform, frames, trace_meta, trace_path, *frontend, options);
}

std::string format_system_result(const SystemResult& r) {
  std::string text = fmt::format(
      "system     {} on {} frames, offload policy {}, model {}{}\n", r.platform,
      r.baseline.frames.size(), to_string(r.config.scheduler.policy), to_string(r.model),
      r.model == SystemModelKind::kDes && !r.config.system.contention ? " without contention" : "");
  text += fmt::format("{:<12} {:<6} {:>7} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9}\n", "variant", "mode",
                      "frames", "FE ms", "BE ms", "e2e ms", "e2e sd", "e2e p99", "energy J");
  for (const VariantResult* v : {&r.baseline, &r.accelerated}) {
    for (const auto& [mode, s] : v->modes) {
      text +=
          fmt::format("{:<12} {:<6} {:>7} {:>9.2f} {:>9.2f} {:>9.2f} {:>9.2f} {:>9.2f} {:>9.3f}\n",
                      v->variant, mode, s.frames, s.frontend_ms.mean, s.backend_ms.mean,
                      s.e2e_ms.mean, s.e2e_ms.sd, s.e2e_ms.p99, s.energy_j.mean);
    }
    text += fmt::format("{:<12} FPS {:.1f} without FE/BE pipelining, {:.1f} with it\n", v->variant,
                        v->fps_without_pipelining, v->fps_with_pipelining);
    if (v->stream) {
      const StreamSummary& st = *v->stream;
      text += fmt::format(
          "{:<12} streamed {}: latency with queueing mean {:.2f} ms, p99 {:.2f} ms; {} of {} "
          "frames dropped; {:.3f} J a frame\n",
          v->variant,
          st.sensor_fps > 0 ? fmt::format("at {:g} FPS", st.sensor_fps)
                            : std::string("back to back"),
          st.latency_ms.mean, st.latency_ms.p99, st.dropped, st.frames, st.energy_j);
      std::string busy;
      for (const ResourceUse& u : st.resources) {
        if (u.name.rfind("queue.", 0) == 0) {
          busy += fmt::format(" {} {:.2f} (max {:.0f})", u.name, u.busy, u.max);
        } else {
          busy += fmt::format(" {} {:.0f}%", u.name, 100 * u.busy);
        }
      }
      text += fmt::format("{:<12} busy{}\n", v->variant, busy);
      // Energy a processed frame by resource group (docs/MODEL.md, "Energy per resource").
      std::map<std::string, double> groups;
      for (const cost::ResourceEnergy& e : st.energy_by_resource) {
        groups[e.name.substr(0, e.name.find('.'))] += e.energy_j;
      }
      std::string energy;
      const double n = static_cast<double>(st.frames - st.dropped);
      for (const auto& [group, j] : groups) energy += fmt::format(" {} {:.4f}", group, j / n);
      if (n > 0) text += fmt::format("{:<12} J a frame by resource:{}\n", v->variant, energy);
    }
  }
  const nlohmann::json cmp = r.comparison();
  for (const auto& [mode, c] : cmp.items()) {
    text += fmt::format(
        "speedup    {:<6} e2e {:.2f}x, backend {:.2f}x, e2e SD {:+.1f}%, energy {:+.1f}%\n", mode,
        c["e2e_speedup"].get<double>(), c["backend_speedup"].get<double>(),
        -100 * c["e2e_sd_reduction"].get<double>(), -100 * c["energy_reduction"].get<double>());
  }
  std::size_t exceeding = 0, spilled = 0;
  std::int64_t spilled_bytes = 0;
  for (const KernelDecision& d : r.decisions) {
    if (d.fits_spm) continue;
    ++exceeding;
    if (d.offloaded) {
      ++spilled;
      spilled_bytes += d.spill_bytes;
    }
  }
  if (exceeding > 0) {
    text += fmt::format(
        "spills     {} of {} accelerable invocations exceed the accelerator's {} B local memory; "
        "{} offloaded out of core, {:.2f} MiB of DRAM traffic\n",
        exceeding, r.decisions.size(), r.config.backend->local_memory_bytes(), spilled,
        static_cast<double>(spilled_bytes) / (1024.0 * 1024.0));
  }
  for (const KernelScheduleSummary& s : r.schedule) {
    const std::string model =
        r.config.scheduler.policy != OffloadPolicy::kRegression ? std::string("no model (policy)")
        : s.has_model
            ? fmt::format("R² train {:.3f} eval {:.3f}", s.r_squared_train, s.r_squared_eval)
            : fmt::format("no model: {} training samples (kept on the host)", s.training_samples);
    text += fmt::format(
        "offload    {:<16} {} of {} evaluated invocations offloaded; {}; gap to oracle {:+.2f}%\n",
        s.kernel, s.offloaded, s.invocations, model, 100 * s.gap_to_oracle);
  }
  const cost::Resources& t = r.resources.total.shared;
  text += fmt::format(
      "resources  {}: LUT {:.0f} ({:.1f}%), FF {:.0f} ({:.1f}%), DSP {:.0f} ({:.1f}%), BRAM "
      "{:.2f} MiB ({:.1f}%){}\n",
      r.resources.device.name, t.lut, 100 * r.resources.utilization.lut, t.ff,
      100 * r.resources.utilization.ff, t.dsp, 100 * r.resources.utilization.dsp,
      r.resources.bram_mib, 100 * r.resources.utilization.bram,
      r.resources.fits ? "" : " DOES NOT FIT");
  return text;
}

}  // namespace edx::arch
