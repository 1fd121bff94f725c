#include "arch/host/host_model.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <map>
#include <optional>
#include <stdexcept>

#include "arch/host/host_costs.hpp"

namespace edx::arch {
namespace {

/// S_trace(f) for f = 0 .. frames-1: the median of the kLocalSamples samples nearest frame f's
/// middle (f + 0.5; a sample's position is the number of frames traced before it). Positions
/// ascend, so the nearest k form a window that only slides right as f grows.
std::vector<double> local_speeds(const std::vector<std::int64_t>& positions,
                                 const std::vector<double>& samples_ms) {
  const std::size_t n = positions.size();
  const std::size_t k = std::min(kLocalSamples, n);
  const std::int64_t frames = n ? positions.back() : 0;
  std::vector<double> speed(static_cast<std::size_t>(std::max<std::int64_t>(frames, 0)));
  std::size_t left = 0;  // window [left, left + k)
  for (std::int64_t f = 0; f < frames; ++f) {
    const double middle = static_cast<double>(f) + 0.5;
    // Slide while the sample after the window is nearer than the window's first.
    while (left + k < n && std::abs(static_cast<double>(positions[left + k]) - middle) <
                               std::abs(static_cast<double>(positions[left]) - middle)) {
      ++left;
    }
    speed[static_cast<std::size_t>(f)] = trace::median_of(
        std::vector<double>(samples_ms.begin() + static_cast<std::ptrdiff_t>(left),
                            samples_ms.begin() + static_cast<std::ptrdiff_t>(left + k)));
  }
  return speed;
}

}  // namespace

const char* to_string(HostTimeSource times) {
  return times == HostTimeSource::kModeled ? "modeled" : "measured";
}

HostTimeSource parse_host_times(const std::string& text) {
  if (text == "modeled") return HostTimeSource::kModeled;
  if (text == "measured") return HostTimeSource::kMeasured;
  throw std::invalid_argument("expected modeled or measured, got '" + text + "'");
}

double HostMapping::scale(const Part& part, std::int64_t frame_id) {
  if (part.per_frame.empty()) return part.overall;
  const auto last = static_cast<std::int64_t>(part.per_frame.size()) - 1;
  return part.per_frame[static_cast<std::size_t>(std::clamp<std::int64_t>(frame_id, 0, last))];
}

nlohmann::json HostMapping::to_json() const {
  return {{"frontend_scale", frontend_.overall},
          {"backend_scale", backend_.overall},
          {"frontend_basis", frontend_basis_},
          {"backend_basis", backend_basis_},
          {"per_frame", !frontend_.per_frame.empty()}};
}

HostMapping map_host(const SuiteTimes& host, const trace::TraceMeta& trace_meta,
                     const std::string& trace_name) {
  HostMapping m;
  if (host.identity()) return m;
  const trace::HostSpeed traced = trace::host_speed_of(trace_meta, trace_name);
  if (traced.suite != host.suite) {
    throw std::runtime_error(fmt::format(
        "{}: host speed measured with reference suite v{}, but host '{}' states suite v{} times "
        "(re-trace with the matching edx, or restate the host)",
        trace_name, traced.suite, host.host, host.suite));
  }
  // t_platform(f) = t_trace(f) x S_platform / S_trace(f) (host_model.hpp).
  const auto part = [&](double platform_ms, double overall_ms, const std::vector<double>& samples) {
    HostMapping::Part p;
    p.overall = platform_ms / overall_ms;
    if (!traced.sample_frames.empty()) {
      for (double s : local_speeds(traced.sample_frames, samples)) {
        p.per_frame.push_back(platform_ms / s);
      }
    }
    return p;
  };
  m.frontend_ = part(host.frontend_ms, traced.frontend_ms, traced.frontend_samples_ms);
  m.backend_ = part(host.backend_ms, traced.backend_ms, traced.backend_samples_ms);
  const std::string local = traced.sample_frames.empty()
                                ? ""
                                : fmt::format(", each frame by its {} nearest of {} samples",
                                              std::min(kLocalSamples, traced.sample_frames.size()),
                                              traced.sample_frames.size());
  m.frontend_basis_ = fmt::format("x{:.4g} = {:.4g} ms / {:.4g} ms on the suite v{}{} ({})",
                                  m.frontend_.overall, host.frontend_ms, traced.frontend_ms,
                                  host.suite, local, host.frontend_provenance);
  m.backend_basis_ =
      fmt::format("x{:.4g} = {:.4g} ms / {:.4g} ms on the suite v{}{} ({})", m.backend_.overall,
                  host.backend_ms, traced.backend_ms, host.suite, local, host.backend_provenance);
  return m;
}

nlohmann::json PlatformHostTimes::to_json() const {
  nlohmann::json j = mapping.to_json();
  j["times"] = to_string(source);
  return j;
}

PlatformHostTimes PlatformHostTimes::suite_scaled(const SuiteTimes& host, HostTimeSource source,
                                                  const std::vector<trace::FrameTrace>& frames,
                                                  const trace::TraceMeta& trace_meta,
                                                  const std::string& trace_name,
                                                  const HostCostModel* costs,
                                                  const RowFactor& factor) {
  PlatformHostTimes t;
  const bool modeled = source == HostTimeSource::kModeled && !host.identity();
  t.source = modeled ? HostTimeSource::kModeled : HostTimeSource::kMeasured;
  if (modeled) {
    if (costs == nullptr) costs = &HostCostModel::bundled();
    if (costs->suite != host.suite) {
      throw std::runtime_error(fmt::format(
          "host '{}' states suite v{} times, but the host cost table is for suite v{} (re-fit "
          "it: edx host-costs fit)",
          host.host, host.suite, costs->suite));
    }
    // t = S_platform x sum_j c_j x_j: the factors are the suite times themselves (ms per
    // suite-ms), applied to ns per suite-ms.
    t.mapping.frontend_.overall = host.frontend_ms;
    t.mapping.backend_.overall = host.backend_ms;
    const std::string basis =
        "x{:.5g} ms on the suite v{} over the op-count host model of the trace's work "
        "(configs/host/host_costs.yaml{}) ({})";
    // The bundled table is named by its path; another one (a test's) also by its provenance.
    const std::string table = costs == &HostCostModel::bundled() ? "" : ": " + costs->provenance;
    t.mapping.frontend_basis_ = fmt::format(fmt::runtime(basis), host.frontend_ms, host.suite,
                                            table, host.frontend_provenance);
    t.mapping.backend_basis_ = fmt::format(fmt::runtime(basis), host.backend_ms, host.suite, table,
                                           host.backend_provenance);
  } else {
    t.mapping = map_host(host, trace_meta, trace_name);
  }
  // The factor of a row (1 without one), looked up once per kind: this runs per row per frame.
  std::map<std::pair<CostPart, std::string>, double> factors;
  const auto factor_of = [&](CostPart part, std::string_view kind) {
    if (!factor) return 1.0;
    const auto key = std::make_pair(part, std::string(kind));
    auto it = factors.find(key);
    if (it == factors.end()) it = factors.emplace(key, factor(part, kind)).first;
    return it->second;
  };
  const std::string_view frontend_rest = "frontend_rest";
  std::optional<RowCoster> coster;  // the tasks' and kernels' rows, kinds looked up once
  if (modeled) coster.emplace(*costs);
  for (const trace::FrameTrace& frame : frames) {
    const std::int64_t id = frame.frame.frame_id;
    const double fe = t.mapping.frontend_scale(id) * 1e-6;  // ns -> ms
    const double be = t.mapping.backend_scale(id) * 1e-6;
    std::vector<double> tasks, kernels;
    tasks.reserve(frame.tasks.size());
    kernels.reserve(frame.kernels.size());
    double frontend = 0, backend = 0;  // the parts' times, ms: their rows and rests
    if (modeled) {
      // The row's modeled time; an error names the frame (formatted only then). The sums are
      // in ns per suite-ms, scaled once at the end.
      const auto cost = [&](const WorkRow& row) {
        if (const std::optional<double> t = costs->try_predict(row)) return *t;
        return costs->predict(row, fmt::format("{}: frame {}", trace_name, id));
      };
      double frontend_units = 0, backend_units = 0;
      if (!frame.tasks.empty()) {
        frontend_units =
            cost(frontend_rest_of(frame)) * factor_of(CostPart::kFrontendRest, frontend_rest);
      }
      const double pixels = image_pixels(frame);
      for (const trace::TaskRecord& task : frame.tasks) {
        const std::optional<double> modeled_units = coster->task(task, pixels);
        const double units = (modeled_units ? *modeled_units : cost(work_of(task, pixels))) *
                             factor_of(CostPart::kFrontendTask, trace::to_string(task.task));
        tasks.push_back(units * fe);
        frontend_units += units;
      }
      if (ran_backend(frame)) {
        const WorkRow rest = backend_rest_of(frame);
        backend_units = cost(rest) * factor_of(CostPart::kBackendRest, rest.kind);
      }
      for (const trace::KernelRecord& kernel : frame.kernels) {
        const std::optional<double> kernel_units = coster->kernel(kernel);
        kernels.push_back((kernel_units ? *kernel_units : cost(work_of(kernel))) *
                          factor_of(CostPart::kBackendKernel, kernel.kernel) * be);
        backend_units += kernels.back() / be;
      }
      frontend = frontend_units * fe;
      backend = backend_units * be;
    } else {
      // Measured: the rows' times, and the part's time outside them as its rest.
      const double frontend_total = static_cast<double>(frame.frame.frontend_host_ns) * fe;
      const double backend_total = static_cast<double>(frame.frame.backend_host_ns) * be;
      double task_sum = 0, kernel_sum = 0;
      for (const trace::TaskRecord& task : frame.tasks) {
        const double ms = static_cast<double>(task.host_ns) * fe;
        task_sum += ms;
        tasks.push_back(ms * factor_of(CostPart::kFrontendTask, trace::to_string(task.task)));
        frontend += tasks.back();
      }
      for (const trace::KernelRecord& kernel : frame.kernels) {
        const double ms = static_cast<double>(kernel.host_ns) * be;
        kernel_sum += ms;
        kernels.push_back(ms * factor_of(CostPart::kBackendKernel, kernel.kernel));
        backend += kernels.back();
      }
      if (!factor) {  // the part's measured time as it is
        frontend = frontend_total;
        backend = backend_total;
      } else {
        frontend += std::max(0.0, frontend_total - task_sum) *
                    factor_of(CostPart::kFrontendRest, frontend_rest);
        backend += std::max(0.0, backend_total - kernel_sum) *
                   factor_of(CostPart::kBackendRest, backend_rest_of(frame).kind);
      }
    }
    t.frontend_ms.push_back(frontend);
    t.backend_ms.push_back(backend);
    t.task_ms.push_back(std::move(tasks));
    t.kernel_ms.push_back(std::move(kernels));
  }
  return t;
}

}  // namespace edx::arch
