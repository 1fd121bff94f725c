#include "bench/des/models.hpp"

#include <time.h>

#include <algorithm>
#include <chrono>
#include <vector>

namespace edx::bench::des {
namespace {

double process_cpu_seconds() {
  timespec now{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

}  // namespace

void time_run_phase(RunResult& result, const std::function<void()>& run) {
  const double cpu_start = process_cpu_seconds();
  const auto start = std::chrono::steady_clock::now();
  run();
  const auto stop = std::chrono::steady_clock::now();
  result.cpu_seconds = process_cpu_seconds() - cpu_start;
  result.seconds = std::chrono::duration<double>(stop - start).count();
}

std::uint64_t pipeline_end_time_ps(const PipelineSpec& spec) {
  constexpr std::size_t kStages = PipelineSpec::kStages;
  const std::size_t capacity = spec.fifo_capacity;
  // get_history[i][j % C] = g_i(j) for the last C tokens of node i (1..S stages, S+1 sink).
  std::vector<std::vector<std::uint64_t>> get_history(kStages + 2,
                                                      std::vector<std::uint64_t>(capacity, 0));
  std::vector<std::uint64_t> last_put(kStages + 1, 0);  // p_i(j-1), i = 0..S
  std::uint64_t sink_get = 0;
  for (std::uint64_t token = 0; token < spec.tokens; ++token) {
    const std::size_t slot = token % capacity;
    const bool fifo_may_be_full = token >= capacity;
    // Source: p_0(j) = g_1(j-C) (read before node 1 overwrites the slot with g_1(j)).
    std::uint64_t put_upstream = fifo_may_be_full ? get_history[1][slot] : 0;
    for (std::size_t stage = 1; stage <= kStages; ++stage) {
      const std::uint64_t get = std::max(put_upstream, last_put[stage]);
      const std::uint64_t room = fifo_may_be_full ? get_history[stage + 1][slot] : 0;
      const std::uint64_t put = std::max(get + spec.stage_delay_ps[stage - 1], room);
      get_history[stage][slot] = get;
      last_put[stage] = put;
      put_upstream = put;
    }
    sink_get = std::max(put_upstream, sink_get);
    get_history[kStages + 1][slot] = sink_get;
  }
  return sink_get;
}

std::uint64_t timed_end_time_ps(const TimedSpec& spec) {
  std::uint64_t end = 0;
  for (std::size_t process = 0; process < spec.processes; ++process) {
    DelayStream delays(process);
    std::uint64_t finish = 0;
    for (std::uint64_t wait = 0; wait < spec.waits_per_process; ++wait) {
      finish += delays.next_delay_ps();
    }
    end = std::max(end, finish);
  }
  return end;
}

}  // namespace edx::bench::des
