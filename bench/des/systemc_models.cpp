// The two benchmark models written the way SystemC users write them: SC_THREAD processes with
// wait(delay) and blocking sc_fifo read/write, or SC_METHOD processes with next_trigger(delay)
// and non-blocking sc_fifo access woken by the FIFO events.
#include <fmt/core.h>

#include <cstdlib>
#include <exception>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <systemc>
#include <vector>

#include "bench/des/models.hpp"

namespace {

/// The model run by the next sc_main call (SystemC's entry point is a free function).
std::function<void()> g_sc_main_job;

}  // namespace

/// SystemC's entry point, reached through sc_core::sc_elab_and_sim in run_with_systemc below.
int sc_main(int /*argc*/, char* /*argv*/[]) {
  g_sc_main_job();
  return 0;
}

namespace edx::bench::des {
namespace {

using sc_core::sc_fifo;
using sc_core::sc_fifo_in;
using sc_core::sc_fifo_out;
using sc_core::sc_module;
using sc_core::sc_module_name;
using sc_core::sc_time;
using Token = std::uint64_t;

/// Delays go in as raw time values: SystemC's default resolution is 1 ps (checked before the run),
/// so this avoids the floating-point sc_time(double, unit) constructor on the hot path.
sc_time picoseconds(std::uint64_t ps) { return sc_time::from_value(ps); }

/// Tallies shared by the processes of one run.
struct Tally {
  std::uint64_t events = 0;
  std::uint64_t tokens_out = 0;
};

// ---- Model (a), SC_THREAD style ------------------------------------------------------------

class ThreadSource : public sc_module {
 public:
  sc_fifo_out<Token> out;
  SC_HAS_PROCESS(ThreadSource);
  ThreadSource(sc_module_name name, std::uint64_t tokens) : sc_module(name), tokens_(tokens) {
    SC_THREAD(run);
  }

 private:
  void run() {
    for (Token token = 0; token < tokens_; ++token) out.write(token);
  }
  std::uint64_t tokens_;
};

class ThreadStage : public sc_module {
 public:
  sc_fifo_in<Token> in;
  sc_fifo_out<Token> out;
  SC_HAS_PROCESS(ThreadStage);
  ThreadStage(sc_module_name name, std::uint64_t delay_ps, Tally& tally)
      : sc_module(name), delay_(picoseconds(delay_ps)), tally_(tally) {
    SC_THREAD(run);
  }

 private:
  void run() {
    for (;;) {
      const Token token = in.read();
      wait(delay_);
      ++tally_.events;
      out.write(token);
    }
  }
  sc_time delay_;
  Tally& tally_;
};

class ThreadSink : public sc_module {
 public:
  sc_fifo_in<Token> in;
  SC_HAS_PROCESS(ThreadSink);
  ThreadSink(sc_module_name name, std::uint64_t tokens, Tally& tally)
      : sc_module(name), tokens_(tokens), tally_(tally) {
    SC_THREAD(run);
  }

 private:
  void run() {
    while (tally_.tokens_out < tokens_) {
      in.read();
      ++tally_.tokens_out;
    }
  }
  std::uint64_t tokens_;
  Tally& tally_;
};

// ---- Model (a), SC_METHOD style ------------------------------------------------------------

class MethodSource : public sc_module {
 public:
  sc_fifo_out<Token> out;
  SC_HAS_PROCESS(MethodSource);
  MethodSource(sc_module_name name, std::uint64_t tokens) : sc_module(name), tokens_(tokens) {
    SC_METHOD(step);
  }

 private:
  void step() {
    while (next_ < tokens_ && out.nb_write(next_)) ++next_;
    if (next_ < tokens_) next_trigger(out.data_read_event());
  }
  std::uint64_t tokens_;
  Token next_ = 0;
};

/// A stage as a state machine: take a token, time out after the delay, put it on, repeat.
class MethodStage : public sc_module {
 public:
  sc_fifo_in<Token> in;
  sc_fifo_out<Token> out;
  SC_HAS_PROCESS(MethodStage);
  MethodStage(sc_module_name name, std::uint64_t delay_ps, Tally& tally)
      : sc_module(name), delay_(picoseconds(delay_ps)), tally_(tally) {
    SC_METHOD(step);
  }

 private:
  enum class State { kWaitingForToken, kDelaying, kWaitingForRoom };

  void step() {
    if (state_ == State::kDelaying) {
      ++tally_.events;
      state_ = State::kWaitingForRoom;
    }
    if (state_ == State::kWaitingForRoom) {
      if (!out.nb_write(token_)) {
        next_trigger(out.data_read_event());
        return;
      }
      state_ = State::kWaitingForToken;
    }
    if (!in.nb_read(token_)) {
      next_trigger(in.data_written_event());
      return;
    }
    state_ = State::kDelaying;
    next_trigger(delay_);
  }

  sc_time delay_;
  Tally& tally_;
  State state_ = State::kWaitingForToken;
  Token token_ = 0;
};

class MethodSink : public sc_module {
 public:
  sc_fifo_in<Token> in;
  SC_HAS_PROCESS(MethodSink);
  MethodSink(sc_module_name name, std::uint64_t tokens, Tally& tally)
      : sc_module(name), tokens_(tokens), tally_(tally) {
    SC_METHOD(step);
  }

 private:
  void step() {
    Token token;
    while (tally_.tokens_out < tokens_ && in.nb_read(token)) ++tally_.tokens_out;
    if (tally_.tokens_out < tokens_) next_trigger(in.data_written_event());
  }
  std::uint64_t tokens_;
  Tally& tally_;
};

// ---- Model (b) ---------------------------------------------------------------------------

class TimedThread : public sc_module {
 public:
  SC_HAS_PROCESS(TimedThread);
  TimedThread(sc_module_name name, std::uint64_t seed, std::uint64_t waits, Tally& tally)
      : sc_module(name), delays_(seed), waits_(waits), tally_(tally) {
    SC_THREAD(run);
  }

 private:
  void run() {
    for (std::uint64_t done = 0; done < waits_; ++done) {
      wait(picoseconds(delays_.next_delay_ps()));
      ++tally_.events;
    }
  }
  DelayStream delays_;
  std::uint64_t waits_;
  Tally& tally_;
};

class TimedMethod : public sc_module {
 public:
  SC_HAS_PROCESS(TimedMethod);
  TimedMethod(sc_module_name name, std::uint64_t seed, std::uint64_t waits, Tally& tally)
      : sc_module(name), delays_(seed), waits_(waits), tally_(tally) {
    SC_METHOD(step);
  }

 private:
  /// The first call (initialization) only starts the first wait; every later call is one
  /// completed wait.
  void step() {
    if (issued_ > 0) ++tally_.events;
    if (issued_ < waits_) {
      ++issued_;
      next_trigger(picoseconds(delays_.next_delay_ps()));
    }
  }
  DelayStream delays_;
  std::uint64_t waits_;
  std::uint64_t issued_ = 0;
  Tally& tally_;
};

// ---- Running ------------------------------------------------------------------------------

/// Runs sc_start() to the end of events and fills in the timing and tallies.
RunResult simulate(const Tally& tally) {
  if (sc_core::sc_get_time_resolution() != sc_time(1, sc_core::SC_PS)) {
    throw std::runtime_error("SystemC time resolution is not 1 ps");
  }
  RunResult result;
  time_run_phase(result, [] { sc_core::sc_start(); });
  result.events = tally.events;
  result.tokens_out = tally.tokens_out;
  result.end_time_ps = sc_core::sc_time_stamp().value();
  return result;
}

template <typename Source, typename Stage, typename Sink>
RunResult simulate_pipeline(const PipelineSpec& spec) {
  Tally tally;
  std::vector<std::unique_ptr<sc_fifo<Token>>> fifos;
  for (std::size_t i = 0; i <= PipelineSpec::kStages; ++i) {
    const std::string name = fmt::format("fifo{}", i);
    fifos.push_back(
        std::make_unique<sc_fifo<Token>>(name.c_str(), static_cast<int>(spec.fifo_capacity)));
  }
  Source source("source", spec.tokens);
  source.out(*fifos.front());
  std::vector<std::unique_ptr<Stage>> stages;
  for (std::size_t i = 0; i < PipelineSpec::kStages; ++i) {
    const std::string name = fmt::format("stage{}", i);
    stages.push_back(std::make_unique<Stage>(name.c_str(), spec.stage_delay_ps[i], tally));
    stages.back()->in(*fifos[i]);
    stages.back()->out(*fifos[i + 1]);
  }
  Sink sink("sink", spec.tokens, tally);
  sink.in(*fifos.back());
  return simulate(tally);
}

template <typename Process>
RunResult simulate_timed(const TimedSpec& spec) {
  Tally tally;
  std::vector<std::unique_ptr<Process>> processes;
  processes.reserve(spec.processes);
  for (std::size_t k = 0; k < spec.processes; ++k) {
    const std::string name = fmt::format("p{}", k);
    processes.push_back(std::make_unique<Process>(name.c_str(), k, spec.waits_per_process, tally));
  }
  return simulate(tally);
}

/// Elaborates and simulates `model` through SystemC's own entry sequence (sc_elab_and_sim calls
/// sc_main). Possible once per process.
RunResult run_with_systemc(const std::function<RunResult()>& model) {
  ::setenv("SYSTEMC_DISABLE_COPYRIGHT_MESSAGE", "1", 1);
  RunResult result;
  std::string failure;
  g_sc_main_job = [&] {
    try {
      result = model();
    } catch (const std::exception& e) {
      failure = e.what();
    }
  };
  char program_name[] = "edx-bench";
  char* argv[] = {program_name, nullptr};
  const int status = sc_core::sc_elab_and_sim(1, argv);
  g_sc_main_job = nullptr;
  if (!failure.empty()) throw std::runtime_error("SystemC model: " + failure);
  if (status != 0) {
    throw std::runtime_error(
        fmt::format("SystemC simulation failed (sc_elab_and_sim returned {})", status));
  }
  return result;
}

}  // namespace

RunResult run_systemc_pipeline(const PipelineSpec& spec, SystemCStyle style) {
  return run_with_systemc([&] {
    return style == SystemCStyle::kThread
               ? simulate_pipeline<ThreadSource, ThreadStage, ThreadSink>(spec)
               : simulate_pipeline<MethodSource, MethodStage, MethodSink>(spec);
  });
}

RunResult run_systemc_timed(const TimedSpec& spec, SystemCStyle style) {
  return run_with_systemc([&] {
    return style == SystemCStyle::kThread ? simulate_timed<TimedThread>(spec)
                                          : simulate_timed<TimedMethod>(spec);
  });
}

}  // namespace edx::bench::des
