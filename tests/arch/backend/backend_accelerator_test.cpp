// The backend accelerator as a DES component (arch/backend/backend_accelerator.hpp).
#include "arch/backend/backend_accelerator.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "tests/arch/backend/backend_test_support.hpp"

namespace edx::arch {
namespace {

namespace flags = trace::op_flags;
using testing::kalman_gain;
using testing::kernel_of;
using testing::small_config;
using trace::Op;
using trace::OpRecord;

TEST(BackendAccelerator, IdleRunEqualsTheAnalyticalSum) {
  const BackendConfig c = small_config();
  sim::Simulator sim;
  BackendAccelerator accel(sim, c);
  const trace::KernelRecord k = kalman_gain(10, 8);
  sim::Time end = 0;
  auto process = [&]() -> sim::Process {
    co_await accel.run(k);
    end = sim.now();
  };
  sim.spawn(process(), "kalman");
  sim.run();
  const std::int64_t cycles = accelerate_kernel(k, c).cycles;
  EXPECT_EQ(cycles, 933);  // kernel_replay_test: 96 + 96 + 203 + 249 + 249 + 40
  EXPECT_EQ(end, accel.clock(0).time_of_cycles(static_cast<std::uint64_t>(cycles)));
  EXPECT_EQ(end, sim::ps(6220000));  // 933 cycles at 150 MHz = 6.22 µs exactly
  EXPECT_EQ(accel.kernels(), 1u);
  EXPECT_EQ(accel.ops(), 6u);
  EXPECT_DOUBLE_EQ(accel.kernel_latency_us().mean(), 6.22);
}

TEST(BackendAccelerator, ConcurrentKernelsSerializeOnASharedUnit) {
  const BackendConfig c = small_config();
  sim::Simulator sim;
  BackendAccelerator accel(sim, c);
  // Two projections (gemm only) issued at the same instant: 25 tiles x 12 = 300 cycles each.
  const trace::KernelRecord a = kernel_of("projection", {OpRecord{Op::Gemm, 3, 100, 4, 0, 0}});
  const trace::KernelRecord b = a;
  // A transpose-only kernel uses another unit: it overlaps the gemms (⌈35/2⌉ = 18 cycles).
  const trace::KernelRecord t = kernel_of("other", {OpRecord{Op::Transpose, 7, 5, 0, 0, 0}});
  sim::Time end_a = 0, end_b = 0, end_t = 0;
  auto run = [&](const trace::KernelRecord& k, sim::Time& end) -> sim::Process {
    co_await accel.run(k);
    end = sim.now();
  };
  sim.spawn(run(a, end_a), "a");
  sim.spawn(run(b, end_b), "b");
  sim.spawn(run(t, end_t), "t");
  sim.run();
  EXPECT_EQ(end_a, accel.clock(0).time_of_cycles(300));
  EXPECT_EQ(end_b, accel.clock(0).time_of_cycles(600));  // waited for a's gemm
  EXPECT_EQ(end_t, accel.clock(0).time_of_cycles(18));
  // The multiplication unit was busy the whole run; the transpose unit 18 of 600 cycles.
  EXPECT_NEAR(accel.unit(testing::unit_index(c, "gemm"))->busy().mean(), 1.0, 1e-12);
  EXPECT_NEAR(accel.unit(testing::unit_index(c, "transpose"))->busy().mean(),
              sim::to_seconds(accel.clock(0).time_of_cycles(18)) /
                  sim::to_seconds(accel.clock(0).time_of_cycles(600)),
              1e-12);

  sim::StatsRegistry stats;
  accel.register_stats(stats, "backend");
  const nlohmann::json json = stats.to_json();
  EXPECT_EQ(json["backend"]["kernels"], 3);
  EXPECT_EQ(json["backend"]["ops"], 3);
  EXPECT_NEAR(json["backend"]["gemm"]["busy"]["mean"].get<double>(), 1.0, 1e-12);
  EXPECT_EQ(json["backend"]["kernel_latency_us"]["count"], 3);
}

TEST(BackendAccelerator, OpsOfOneKernelWaitForEachOther) {
  const BackendConfig c = small_config();
  sim::Simulator sim;
  BackendAccelerator accel(sim, c);
  // gemm (300 cycles) then transpose (18): the transpose starts after the gemm even though its
  // unit is free.
  const trace::KernelRecord k = kernel_of(
      "chain", {OpRecord{Op::Gemm, 3, 100, 4, 0, 0}, OpRecord{Op::Transpose, 7, 5, 0, 0, 0}});
  sim::Timeline timeline;
  accel.set_timeline(timeline, "backend");
  auto process = [&]() -> sim::Process { co_await accel.run(k); };
  sim.spawn(process(), "chain");
  sim.run();
  EXPECT_EQ(sim.now(), accel.clock(0).time_of_cycles(318));
  EXPECT_EQ(timeline.span_count(), 3u);  // two ops and the kernel
  const nlohmann::json doc = timeline.to_json();
  bool found = false;
  for (const nlohmann::json& e : doc["traceEvents"]) {
    if (e.value("ph", "") == "X" && e.value("name", "") == "chain transpose 7x5x0") {
      found = true;
      EXPECT_NEAR(e["ts"].get<double>(), sim::to_us(accel.clock(0).time_of_cycles(300)), 1e-9);
    }
  }
  EXPECT_TRUE(found) << doc.dump();
}

TEST(BackendAccelerator, AttributesAKernelsTimeToRunAndWaitPerUnit) {
  // Two projections issued at once on two gemm copies (CopiesOfAUnitShareAnOpOrServeTwoKernels):
  // the first runs its planned 156 cycles; the second waits 156 cycles for the copies, then
  // runs its 156. Run and wait add up to each kernel's time.
  BackendConfig c = small_config();
  const std::size_t gemm = testing::unit_index(c, "gemm");
  c.units[gemm].count = 2;
  std::size_t resource = 0;  // gemm's index among the units of count > 0
  for (std::size_t u = 0; u < gemm; ++u) resource += c.units[u].count > 0 ? 1 : 0;
  const KernelAccelResult plan =
      accelerate_kernel(kernel_of("projection", {OpRecord{Op::Gemm, 3, 100, 4, 0, 0}}), c);
  sim::Simulator sim;
  BackendAccelerator accel(sim, c);
  const std::size_t resources = 2 * c.units.size();
  std::vector<sim::Time> times_a(resources, 0), times_b(resources, 0);
  auto run = [&](std::vector<sim::Time>& times) -> sim::Process {
    co_await accel.run(plan, "", OffloadTimes{times.data()});
  };
  sim.spawn(run(times_a), "a");
  sim.spawn(run(times_b), "b");
  sim.run();
  const sim::Time cycles156 = accel.clock(gemm).time_of_cycles(156);
  EXPECT_EQ(times_a[2 * resource], cycles156);
  EXPECT_EQ(times_a[2 * resource + 1], 0);
  EXPECT_EQ(times_b[2 * resource + 1], cycles156);
  EXPECT_EQ(times_b[2 * resource], accel.clock(gemm).time_of_cycles(312) - cycles156);
  sim::Time sum_b = 0;
  for (sim::Time t : times_b) sum_b += t;
  EXPECT_EQ(sum_b, accel.clock(gemm).time_of_cycles(312));
}

TEST(BackendAccelerator, CopiesOfAUnitShareAnOpOrServeTwoKernels) {
  BackendConfig c = small_config();
  c.units[testing::unit_index(c, "gemm")].count = 2;
  // One projection alone (3x100x4, 25 tiles of 12): both arrays, 13 tiles each = 156 cycles.
  const trace::KernelRecord a = kernel_of("projection", {OpRecord{Op::Gemm, 3, 100, 4, 0, 0}});
  {
    sim::Simulator sim;
    BackendAccelerator accel(sim, c);
    auto process = [&]() -> sim::Process { co_await accel.run(a); };
    sim.spawn(process(), "a");
    sim.run();
    EXPECT_EQ(sim.now(), accel.clock(0).time_of_cycles(156));
    EXPECT_EQ(accelerate_kernel(a, c).cycles, 156);  // the analytical figure: all copies
  }
  // Two issued at once: the first takes both arrays (every copy free when it starts), the
  // second waits for them: 156 and 312, where one array alone ends them at 300 and 600.
  sim::Simulator sim;
  BackendAccelerator accel(sim, c);
  sim::Time end_a = 0, end_b = 0;
  auto run = [&](sim::Time& end) -> sim::Process {
    co_await accel.run(a);
    end = sim.now();
  };
  sim.spawn(run(end_a), "a");
  sim.spawn(run(end_b), "b");
  sim.run();
  EXPECT_EQ(end_a, accel.clock(0).time_of_cycles(156));
  EXPECT_EQ(end_b, accel.clock(0).time_of_cycles(312));
  EXPECT_NEAR(accel.unit(testing::unit_index(c, "gemm"))->busy().mean(), 2.0, 1e-12);
  // An op that arrives while another kernel holds every copy waits for them (FIFO), then takes
  // every copy free: a transpose-then-gemm kernel issued beside a projection.
  sim::Simulator sim2;
  BackendAccelerator accel2(sim2, c);
  const trace::KernelRecord chain = kernel_of(
      "chain", {OpRecord{Op::Transpose, 2, 1, 0, 0, 0}, OpRecord{Op::Gemm, 3, 100, 4, 0, 0}});
  sim::Time end_chain = 0, end_a2 = 0;
  auto run2 = [&](const trace::KernelRecord& k, sim::Time& end) -> sim::Process {
    co_await accel2.run(k);
    end = sim2.now();
  };
  sim2.spawn(run2(a, end_a2), "a");
  sim2.spawn(run2(chain, end_chain), "chain");
  sim2.run();
  EXPECT_EQ(end_a2, accel2.clock(0).time_of_cycles(156));  // both arrays: nothing else asked
  // The transpose (1 cycle) ends while a holds both arrays: the gemm waits for them (156),
  // then takes both: 156 + 156.
  EXPECT_EQ(end_chain, accel2.clock(0).time_of_cycles(312));
}

TEST(BackendAccelerator, KernelThatSpillsRunsItsOpsOnTheUnits) {
  // Out of core the units take the same cycles; the spill traffic is the caller's (the system
  // DES puts it on the link), so the kernel alone takes its Σ op cycles.
  BackendConfig c = small_config();
  c.spm_bytes = 1000;
  sim::Simulator sim;
  BackendAccelerator accel(sim, c);
  const trace::KernelRecord k = kalman_gain(10, 8);
  const KernelAccelResult plan = accelerate_kernel(k, c);
  ASSERT_FALSE(plan.fits_local_memory);
  auto process = [&]() -> sim::Process { co_await accel.run(k); };
  sim.spawn(process(), "kalman");
  sim.run();
  EXPECT_EQ(accel.kernels(), 1u);
  EXPECT_EQ(sim.now(), accel.clock(0).time_of_cycles(static_cast<std::uint64_t>(plan.cycles)));
}

}  // namespace
}  // namespace edx::arch
