#include "arch/host/frontend_graph.hpp"

#include <algorithm>
#include <iterator>
#include <stdexcept>

namespace edx::arch {

namespace {

/// Stage and chain of a task row (the table in the header); the rest: stage 3's chain.
struct Slot {
  std::size_t stage, chain;
};
constexpr std::size_t kChains[] = {3, 2, 1};  // chains per stage
constexpr Slot kRestSlot = {2, 0};

Slot slot_of(const trace::TaskRecord& task) {
  using trace::Task;
  const bool right = task.image == trace::Image::Right;
  switch (task.task) {
    case Task::DC:
    case Task::LSS:
      return {0, 0};
    case Task::FD:
    case Task::IF:
      return {0, right ? 2u : 1u};
    case Task::FC:
      return {1, right ? 1u : 0u};
    default:
      return kRestSlot;
  }
}

}  // namespace

HostFrontendGraph frontend_graph(const std::vector<trace::TaskRecord>& tasks) {
  HostFrontendGraph g;
  for (std::size_t chains : kChains) g.stages.emplace_back(chains);
  for (std::size_t i = 0; i < tasks.size(); ++i) {
    const Slot s = slot_of(tasks[i]);
    g.stages[s.stage][s.chain].push_back(i);
  }
  g.stages[kRestSlot.stage][kRestSlot.chain].push_back(HostFrontendGraph::kRest);
  return g;
}

StageChains chain_times(const std::vector<trace::TaskRecord>& tasks,
                        const std::vector<double>& task_ms, double rest_ms,
                        const std::vector<bool>& on_device) {
  if (task_ms.size() != tasks.size() || (!on_device.empty() && on_device.size() != tasks.size())) {
    throw std::invalid_argument("chain_times: one time (and device flag) per task row expected");
  }
  StageChains out;
  out.reserve(std::size(kChains));
  for (std::size_t chains : kChains) out.emplace_back(chains);
  for (std::size_t i = 0; i < tasks.size(); ++i) {
    const Slot s = slot_of(tasks[i]);
    ChainTime& chain = out[s.stage][s.chain];
    (!on_device.empty() && on_device[i] ? chain.device_ms : chain.host_ms) += task_ms[i];
  }
  out[kRestSlot.stage][kRestSlot.chain].host_ms += rest_ms;
  return out;
}

double frontend_latency_ms(const StageChains& stage_chains, int cores) {
  if (cores < 1) throw std::invalid_argument("frontend_latency_ms: cores must be >= 1");
  double total = 0;
  std::vector<double> free_at;
  std::vector<std::pair<double, std::size_t>> ready;  // (D_i, i) of the chains with host work
  for (const std::vector<ChainTime>& chains : stage_chains) {
    double device_free = 0, makespan = 0;
    ready.clear();
    for (std::size_t i = 0; i < chains.size(); ++i) {
      double at = 0;
      if (chains[i].device_ms > 0) at = device_free += chains[i].device_ms;
      makespan = std::max(makespan, at);
      if (chains[i].host_ms > 0) ready.emplace_back(at, i);
    }
    std::stable_sort(ready.begin(), ready.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    // Each host part on the earliest free core, when it is ready (list scheduling).
    free_at.assign(std::min<std::size_t>(static_cast<std::size_t>(cores), chains.size()), 0.0);
    for (const auto& [at, i] : ready) {
      const auto core = std::min_element(free_at.begin(), free_at.end());
      *core = std::max(*core, at) + chains[i].host_ms;
      makespan = std::max(makespan, *core);
    }
    total += makespan;
  }
  return total;
}

}  // namespace edx::arch
