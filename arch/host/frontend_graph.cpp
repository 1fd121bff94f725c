#include "arch/host/frontend_graph.hpp"

#include <algorithm>
#include <stdexcept>

namespace edx::arch {

HostFrontendGraph frontend_graph(const std::vector<trace::TaskRecord>& tasks) {
  using trace::Image;
  using trace::Task;
  HostFrontendGraph g;
  // stage 1: tracking, left detection, right detection; stage 2: the descriptions; stage 3.
  g.stages = {{{}, {}, {}}, {{}, {}}, {{}}};
  for (std::size_t i = 0; i < tasks.size(); ++i) {
    const Task t = tasks[i].task;
    const bool right = tasks[i].image == Image::Right;
    if (t == Task::DC || t == Task::LSS) {
      g.stages[0][0].push_back(i);
    } else if (t == Task::FD || t == Task::IF) {
      g.stages[0][right ? 2 : 1].push_back(i);
    } else if (t == Task::FC) {
      g.stages[1][right ? 1 : 0].push_back(i);
    } else {
      g.stages[2][0].push_back(i);
    }
  }
  g.stages[2][0].push_back(HostFrontendGraph::kRest);
  return g;
}

std::vector<std::vector<double>> chain_times(const HostFrontendGraph& graph,
                                             const std::vector<double>& task_ms, double rest_ms) {
  std::vector<std::vector<double>> out;
  out.reserve(graph.stages.size());
  for (const auto& stage : graph.stages) {
    std::vector<double> chains;
    chains.reserve(stage.size());
    for (const auto& chain : stage) {
      double ms = 0;
      for (std::size_t i : chain) ms += i == HostFrontendGraph::kRest ? rest_ms : task_ms.at(i);
      chains.push_back(ms);
    }
    out.push_back(std::move(chains));
  }
  return out;
}

double frontend_latency_ms(const std::vector<std::vector<double>>& stage_chains, int cores) {
  if (cores < 1) throw std::invalid_argument("frontend_latency_ms: cores must be >= 1");
  double total = 0;
  std::vector<double> free_at;
  for (const std::vector<double>& chains : stage_chains) {
    // Each chain in order on the earliest free core (list scheduling).
    free_at.assign(std::min<std::size_t>(static_cast<std::size_t>(cores), chains.size()), 0.0);
    double makespan = 0;
    for (double ms : chains) {
      const auto core = std::min_element(free_at.begin(), free_at.end());
      *core += ms;
      makespan = std::max(makespan, *core);
    }
    total += makespan;
  }
  return total;
}

}  // namespace edx::arch
