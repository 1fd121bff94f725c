// Trace metadata about host and build, and the sample statistics of summaries.
#include "workloads/frontend/trace_meta.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>

#include "tests/support/temp_dir.hpp"
#include "workloads/frontend/sample_stats.hpp"

namespace edx::frontend {
namespace {

using ::testing::HasSubstr;

TEST(TraceMeta, CpuModelFromCpuinfo) {
  const testing::TempDir dir;
  const auto file = dir.path() / "cpuinfo";
  {
    std::ofstream out(file);
    out << "processor\t: 0\nvendor_id\t: GenuineIntel\nmodel name\t: Intel(R) Xeon(R) CPU @ "
           "2.20GHz  \n"
           "processor\t: 1\nmodel name\t: Intel(R) Xeon(R) CPU @ 2.20GHz\n";
  }
  EXPECT_EQ(cpu_model(file), "Intel(R) Xeon(R) CPU @ 2.20GHz");
  {
    std::ofstream out(file);
    out << "processor\t: 0\nBogoMIPS\t: 50.00\nHardware\t: BCM2835\n";
  }
  EXPECT_EQ(cpu_model(file), "BCM2835");
  EXPECT_EQ(cpu_model(dir.path() / "missing"), "unknown");
  EXPECT_FALSE(cpu_model().empty());
}

TEST(TraceMeta, Iso8601Utc) {
  // 1 600 000 000 s after the epoch is 2020-09-13 12:26:40 UTC.
  const auto t = std::chrono::system_clock::time_point(std::chrono::seconds(1'600'000'000));
  EXPECT_EQ(iso8601_utc(t), "2020-09-13T12:26:40Z");
}

TEST(TraceMeta, HostAndBuild) {
  const trace::TraceMeta meta = host_and_build_meta();
  for (const char* key :
       {"host_cpu", "host_cores", "compiler_flags", "source_revision", "created_utc"}) {
    ASSERT_TRUE(meta.contains(key)) << key;
    EXPECT_FALSE(meta.at(key).empty()) << key;
  }
  EXPECT_THAT(meta.at("compiler_flags"), HasSubstr("-std=c++20"));
  EXPECT_THAT(meta.at("created_utc"), ::testing::MatchesRegex("20[0-9-]+T[0-9:]+Z"));
}

TEST(SampleStats, KnownValues) {
  // 1..100: mean 50.5, sample SD sqrt(100 * 101 / 12), p99 at rank 98.01 -> 99.01.
  std::vector<double> values;
  for (int i = 100; i >= 1; --i) values.push_back(i);
  const SampleStats s = summarize(values);
  EXPECT_EQ(s.count, 100u);
  EXPECT_DOUBLE_EQ(s.mean, 50.5);
  EXPECT_NEAR(s.sd, std::sqrt(100.0 * 101.0 / 12), 1e-12);
  EXPECT_DOUBLE_EQ(s.min, 1);
  EXPECT_DOUBLE_EQ(s.max, 100);
  EXPECT_NEAR(s.p50, 50.5, 1e-12);
  EXPECT_NEAR(s.p99, 99.01, 1e-12);
  EXPECT_EQ(summarize({}).count, 0u);
  EXPECT_DOUBLE_EQ(summarize({7}).p99, 7);
  EXPECT_DOUBLE_EQ(summarize({7}).sd, 0);
}

}  // namespace
}  // namespace edx::frontend
