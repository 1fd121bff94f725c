// The two benchmark models on edx's own engine: each process is a C++20 coroutine that awaits
// `sim.delay(d)` and bounded `Fifo` put/get.
#include <fmt/core.h>

#include <memory>
#include <string>
#include <vector>

#include "bench/des/models.hpp"
#include "sim_core/fifo.hpp"
#include "sim_core/simulator.hpp"

namespace edx::bench::des {
namespace {

using Token = std::uint64_t;

/// Tallies shared by the processes of one run.
struct Tally {
  std::uint64_t events = 0;
  std::uint64_t tokens_out = 0;
};

sim::Process source(sim::Fifo<Token>& out, std::uint64_t tokens) {
  for (Token token = 0; token < tokens; ++token) co_await out.put(token);
}

sim::Process stage(sim::Simulator& sim, sim::Fifo<Token>& in, sim::Fifo<Token>& out,
                   sim::Time delay, Tally& tally) {
  for (;;) {
    const Token token = co_await in.get();
    co_await sim.delay(delay);
    ++tally.events;
    co_await out.put(token);
  }
}

sim::Process sink(sim::Fifo<Token>& in, std::uint64_t tokens, Tally& tally) {
  while (tally.tokens_out < tokens) {
    co_await in.get();
    ++tally.tokens_out;
  }
}

sim::Process timed(sim::Simulator& sim, std::uint64_t seed, std::uint64_t waits, Tally& tally) {
  DelayStream delays(seed);
  for (std::uint64_t done = 0; done < waits; ++done) {
    co_await sim.delay(sim::Time{delays.next_delay_ps()});
    ++tally.events;
  }
}

/// Runs the spawned processes to the end of events and fills in the timing and tallies.
RunResult simulate(sim::Simulator& sim, const Tally& tally) {
  RunResult result;
  time_run_phase(result, [&] { sim.run(); });
  result.events = tally.events;
  result.tokens_out = tally.tokens_out;
  result.end_time_ps = sim.now();
  result.engine_events = sim.events_processed();
  return result;
}

}  // namespace

RunResult run_edx_pipeline(const PipelineSpec& spec) {
  sim::Simulator sim;
  Tally tally;
  std::vector<std::unique_ptr<sim::Fifo<Token>>> fifos;
  for (std::size_t i = 0; i <= PipelineSpec::kStages; ++i) {
    fifos.push_back(std::make_unique<sim::Fifo<Token>>(sim, spec.fifo_capacity));
  }
  sim.spawn(source(*fifos.front(), spec.tokens), "source");
  for (std::size_t i = 0; i < PipelineSpec::kStages; ++i) {
    sim.spawn(stage(sim, *fifos[i], *fifos[i + 1], sim::Time{spec.stage_delay_ps[i]}, tally),
              fmt::format("stage{}", i));
  }
  sim.spawn(sink(*fifos.back(), spec.tokens, tally), "sink");
  return simulate(sim, tally);
}

RunResult run_edx_timed(const TimedSpec& spec) {
  sim::Simulator sim;
  Tally tally;
  for (std::size_t k = 0; k < spec.processes; ++k) {
    sim.spawn(timed(sim, k, spec.waits_per_process, tally), fmt::format("p{}", k));
  }
  return simulate(sim, tally);
}

}  // namespace edx::bench::des
