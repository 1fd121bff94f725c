// The characterization's runs traced at once (workloads/modes/characterization.hpp,
// CharacterizationOptions::threads): two (seed, scenario) groups on two threads give exactly the
// runs of one thread, in the same order, with the same rows of work in their traces.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <bit>
#include <mutex>
#include <set>
#include <string>
#include <thread>

#include "tests/support/temp_dir.hpp"
#include "tests/support/trace_rows.hpp"
#include "workloads/modes/characterization.hpp"
#include "workloads/trace/reader.hpp"

namespace edx::modes {
namespace {

using edx::testing::without_host_meta;
using edx::testing::without_host_times;

TEST(CharacterizationThreads, TwoThreadsGiveTheRunsOfOne) {
  const edx::testing::TempDir dir;
  CharacterizationOptions options;
  options.seeds = 2;
  options.frames = 12;
  options.resolution = {376, 240};
  // A known scenario (three runs sharing their mapping segment) on two seeds: two groups.
  options.scenarios = {synthetic::Scenario::kIndoorKnown};
  options.data_dir = dir.path() / "data";
  options.trace_dir = dir.path() / "one";
  options.threads = 1;
  const std::vector<CharacterizationRun> one = run_characterization(options);

  options.trace_dir = dir.path() / "two";
  options.threads = 2;
  // The progress is one call at a time and names its run; both groups report.
  std::mutex inside;
  std::set<std::string> named;
  const std::vector<CharacterizationRun> two = run_characterization(
      options, [&](std::string_view run, std::string_view, std::size_t, std::size_t) {
        ASSERT_TRUE(inside.try_lock()) << "two progress calls at once";
        named.emplace(run);
        std::this_thread::yield();
        inside.unlock();
      });
  EXPECT_EQ(named,
            (std::set<std::string>{"indoor_known-vio-s1001", "indoor_known-slam-s1001",
                                   "indoor_known-registration-s1001", "indoor_known-vio-s1002",
                                   "indoor_known-slam-s1002", "indoor_known-registration-s1002"}));

  ASSERT_EQ(one.size(), 6u);
  ASSERT_EQ(two.size(), one.size());
  std::size_t with_ate = 0;
  for (std::size_t i = 0; i < one.size(); ++i) {
    const CharacterizationRun& a = one[i];
    const CharacterizationRun& b = two[i];
    const std::string name = fmt::format("{}-{}-s{}", synthetic::to_string(a.cell.scenario),
                                         trace::to_string(a.cell.backend), a.seed);
    EXPECT_EQ(a.seed, i < 3 ? 1001u : 1002u) << name;  // seeds, then cells: the order of one
    EXPECT_EQ(b.cell.scenario, a.cell.scenario) << name;
    EXPECT_EQ(b.cell.backend, a.cell.backend) << name;
    EXPECT_EQ(b.seed, a.seed) << name;
    EXPECT_EQ(b.first_frame_id, 12) << name;  // after the mapping segment
    EXPECT_EQ(b.frames, a.frames) << name;
    EXPECT_EQ(b.ate_pairs, a.ate_pairs) << name;
    EXPECT_EQ(b.registration_failures, a.registration_failures) << name;
    ASSERT_EQ(b.ate_rmse_m.has_value(), a.ate_rmse_m.has_value()) << name;
    if (a.ate_rmse_m) {
      ++with_ate;
      // To the bit: the same arithmetic on the same data, whichever thread ran it.
      EXPECT_EQ(std::bit_cast<std::uint64_t>(*b.ate_rmse_m),
                std::bit_cast<std::uint64_t>(*a.ate_rmse_m))
          << name;
    }
    EXPECT_EQ(a.trace, dir.path() / "one" / (name + ".db"));
    EXPECT_EQ(b.trace, dir.path() / "two" / (name + ".db"));
    const trace::TraceReader ra(a.trace);
    const trace::TraceReader rb(b.trace);
    EXPECT_EQ(ra.frame_count(), 24u) << name;
    EXPECT_EQ(without_host_times(rb.read_all()), without_host_times(ra.read_all())) << name;
    EXPECT_EQ(without_host_meta(rb.meta()), without_host_meta(ra.meta())) << name;
  }
  EXPECT_GE(with_ate, 4u);  // slam and registration estimate within 12 frames

  // A bad thread count is refused, naming the option.
  options.threads = 0;
  EXPECT_THROW(
      {
        try {
          options.validate();
        } catch (const std::invalid_argument& e) {
          EXPECT_STREQ(e.what(), "threads: expected 1 to 256, got 0");
          throw;
        }
      },
      std::invalid_argument);
}

}  // namespace
}  // namespace edx::modes
