#pragma once
// The two models of `edx-bench des`, described once and run unchanged by both engines (edx's
// sim_core and SystemC), plus the figures both runs must reproduce exactly.
//
// What one "event" is: one completed timed wait of a model process, i.e. one resumption of a
// process after `co_await sim.delay(d)` (edx), `wait(d)` (SC_THREAD) or `next_trigger(d)`
// (SC_METHOD). Each model process counts its own completed waits, so the count is the same by
// construction on both sides and is checked against the model's exact figure. Work that is not a
// timed wait (FIFO hand-overs, process start, delta cycles) is done by both engines alike but not
// counted.
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>

namespace edx::bench::des {

/// Model (a): source -> FIFO -> stage 1 -> FIFO -> ... -> stage 8 -> FIFO -> sink. The source
/// puts `tokens` tokens as fast as the first FIFO accepts them; each stage repeatedly gets a
/// token, waits its fixed delay and puts the token on; the sink takes tokens as they come.
/// Events: stages x tokens (one delay per token per stage).
struct PipelineSpec {
  static constexpr std::size_t kStages = 8;
  std::uint64_t tokens = 10'000'000;
  std::size_t fifo_capacity = 4;
  /// Per-stage delay in picoseconds (2..5 ns; stage 3 and 7 are the 5 ns bottleneck).
  std::array<std::uint64_t, kStages> stage_delay_ps = {2000, 3000, 5000, 3000,
                                                       4000, 2000, 5000, 3000};

  std::uint64_t expected_events() const { return tokens * kStages; }
};

/// Model (b): `processes` independent processes, process k waiting `waits_per_process` delays
/// drawn from DelayStream(k). Events: processes x waits_per_process.
struct TimedSpec {
  std::size_t processes = 1000;
  std::uint64_t waits_per_process = 20'000;

  std::uint64_t expected_events() const { return processes * waits_per_process; }
};

/// Deterministic per-process delays of 1..1000 ns (whole ns, in ps) from SplitMix64
/// (Steele, Lea, Flood 2014): x += 0x9E3779B97F4A7C15; z = x;
/// z = (z ^ z>>30) * 0xBF58476D1CE4E5B9; z = (z ^ z>>27) * 0x94D049BB133111EB; z ^= z>>31;
/// delay = (1 + z mod 1000) ns.
class DelayStream {
 public:
  explicit DelayStream(std::uint64_t seed) : state_(seed) {}

  std::uint64_t next_delay_ps() {
    state_ += 0x9E3779B97F4A7C15ULL;
    std::uint64_t z = state_;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    z ^= z >> 31;
    return (1 + z % 1000) * 1000;
  }

 private:
  std::uint64_t state_;
};

/// What one engine run reports. Trivially copyable: it crosses a pipe from a child process.
struct RunResult {
  std::uint64_t events = 0;         ///< completed timed waits counted by the model processes
  std::uint64_t end_time_ps = 0;    ///< simulated time when the run ran out of events
  std::uint64_t tokens_out = 0;     ///< pipeline only: tokens the sink received
  std::uint64_t engine_events = 0;  ///< the engine's own event count (edx only; 0 for SystemC)
  double seconds = 0.0;             ///< wall time of the run phase (steady_clock)
  double cpu_seconds = 0.0;         ///< CPU time of the run phase (shows a busy machine)
};

/// Runs `run` (the run phase of a model, after elaboration) and stores its wall time
/// (std::chrono::steady_clock) and the process's CPU time in `result`.
void time_run_phase(RunResult& result, const std::function<void()>& run);

/// Exact simulated end time of the pipeline: the sink's last get, from the max-plus recurrence
/// of blocking FIFOs with capacity C (g = get time, p = put time, d = stage delay, node 0 is the
/// source, nodes 1..S the stages, node S+1 the sink):
///   g_i(j) = max(p_{i-1}(j), p_i(j-1))                   (token j arrives, node i is free)
///   p_i(j) = max(g_i(j) + d_i, g_{i+1}(j-C))             (delay done, room in the next FIFO)
/// with p_0(j) = g_1(j-C) for the source, and terms with negative token index equal to 0.
std::uint64_t pipeline_end_time_ps(const PipelineSpec& spec);

/// Exact simulated end time of the timed model: max over k of the sum of DelayStream(k) draws.
std::uint64_t timed_end_time_ps(const TimedSpec& spec);

/// Model runs on each engine. The SystemC ones may run only once per process (SystemC can
/// elaborate and simulate a single time), so callers run each in its own child process.
RunResult run_edx_pipeline(const PipelineSpec& spec);
RunResult run_edx_timed(const TimedSpec& spec);

enum class SystemCStyle { kThread, kMethod };
RunResult run_systemc_pipeline(const PipelineSpec& spec, SystemCStyle style);
RunResult run_systemc_timed(const TimedSpec& spec, SystemCStyle style);

}  // namespace edx::bench::des
