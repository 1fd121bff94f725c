// The host mapping t_platform = t_trace x S_platform / S_trace (arch/host/host_model.hpp), on
// hand-computed suite times, and its errors.
#include "arch/host/host_model.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace edx::arch {
namespace {

using ::testing::HasSubstr;

trace::TraceMeta meta_with(const std::string& host_speed) { return {{"host_speed", host_speed}}; }

SuiteTimes host(double frontend_ms, double backend_ms) {
  SuiteTimes h;
  h.host = "target";
  h.frontend_ms = frontend_ms;
  h.backend_ms = backend_ms;
  h.frontend_provenance = "measured";
  return h;
}

TEST(HostModel, ScalesAreThePlatformsSuiteTimesOverTheTracersOnes) {
  const trace::TraceMeta meta =
      meta_with(R"({"suite": 1, "frontend_ms": 40.0, "backend_ms": 8.0, "samples": 5})");
  const HostMapping m = map_host(host(100.0, 10.0), meta, "t.db");
  EXPECT_DOUBLE_EQ(m.frontend_scale(0), 2.5);  // 100 / 40
  EXPECT_DOUBLE_EQ(m.backend_scale(7), 1.25);  // 10 / 8
  EXPECT_THAT(m.frontend_basis(), HasSubstr("x2.5 = 100 ms / 40 ms on the suite v1 (measured)"));
}

TEST(HostModel, AMachineTwiceAsFastGivesTheSamePlatformTimes) {
  // The same work traced on a machine twice as fast: host times and suite times both halve.
  const double slow_trace_ms = 30.0, fast_trace_ms = 15.0;
  const HostMapping slow = map_host(
      host(60.0, 6.0),
      meta_with(R"({"suite": 1, "frontend_ms": 20.0, "backend_ms": 4.0, "samples": 3})"), "slow");
  const HostMapping fast = map_host(
      host(60.0, 6.0),
      meta_with(R"({"suite": 1, "frontend_ms": 10.0, "backend_ms": 2.0, "samples": 3})"), "fast");
  EXPECT_DOUBLE_EQ(slow_trace_ms * slow.frontend_scale(0), 90.0);
  EXPECT_DOUBLE_EQ(fast_trace_ms * fast.frontend_scale(0), 90.0);
}

TEST(HostModel, NoSuiteTimesReplaysTheTraceAsItIsAndNeedsNoHostSpeed) {
  const HostMapping m = map_host(SuiteTimes{}, trace::TraceMeta{}, "t.db");
  EXPECT_EQ(m.frontend_scale(3), 1.0);
  EXPECT_EQ(m.backend_scale(3), 1.0);
}

TEST(HostModel, EachFrameIsMappedByTheNineSamplesNearestIt) {
  // 20 frames; samples at positions (frames traced before): 0 0 0, then 2 4 ... 18, 20 20.
  // The machine ran at 10 ms on the suite for the first half and 20 ms for the second.
  std::vector<std::int64_t> positions{0, 0, 0};
  std::vector<double> frontend{10, 10, 10}, backend{1, 1, 1};
  for (std::int64_t p = 2; p <= 18; p += 2) {
    positions.push_back(p);
    frontend.push_back(p <= 10 ? 10.0 : 20.0);
    backend.push_back(p <= 10 ? 1.0 : 2.0);
  }
  for (int i = 0; i < 2; ++i) {
    positions.push_back(20);
    frontend.push_back(20);
    backend.push_back(2);
  }
  trace::HostSpeed speed;
  speed.frontend_ms = 15;
  speed.backend_ms = 1.5;
  speed.samples = static_cast<int>(positions.size());
  speed.sample_frames = positions;
  speed.frontend_samples_ms = frontend;
  speed.backend_samples_ms = backend;
  const HostMapping m = map_host(host(40.0, 4.0), {{"host_speed", to_meta_value(speed)}}, "t");
  // Frame 0 (middle 0.5): nearest nine are positions 0 0 0 2 4 6 8 10 12 -> median 10 ms.
  EXPECT_DOUBLE_EQ(m.frontend_scale(0), 4.0);
  EXPECT_DOUBLE_EQ(m.backend_scale(0), 4.0);
  // Frame 19 (middle 19.5): 20 20 18 16 14 12 10 8 6 -> five of 20 ms, median 20 ms.
  EXPECT_DOUBLE_EQ(m.frontend_scale(19), 2.0);
  EXPECT_DOUBLE_EQ(m.backend_scale(19), 2.0);
  // Frame 9 (middle 9.5): 10 8 12 6 14 4 16 2 18 -> four of 10 ms (2..8, 10), 12..18 of 20:
  // 2 4 6 8 10 at 10 ms, 12 14 16 18 at 20 ms -> median 10 ms.
  EXPECT_DOUBLE_EQ(m.frontend_scale(9), 4.0);
  // Frame 11 (middle 11.5): 12 10 14 8 16 6 18 4 20 -> 10 ms: 10 8 6 4; 20 ms: 12 14 16 18 20.
  EXPECT_DOUBLE_EQ(m.frontend_scale(11), 2.0);
  // The overall factor is the medians'; frames past the last sample take the last window's.
  EXPECT_DOUBLE_EQ(m.mean_frontend_scale(), 40.0 / 15.0);
  EXPECT_DOUBLE_EQ(m.frontend_scale(25), 2.0);
}

TEST(HostModel, ErrorsNameTheTraceAndWhatIsWrong) {
  const auto error_of = [](const trace::TraceMeta& meta, SuiteTimes h) -> std::string {
    try {
      map_host(h, meta, "t.db");
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_THAT(error_of({}, host(1, 1)), HasSubstr("t.db: meta lacks host_speed"));
  EXPECT_THAT(error_of(meta_with("fast"), host(1, 1)),
              HasSubstr("t.db: meta host_speed: expected a JSON object, got 'fast'"));
  EXPECT_THAT(
      error_of(meta_with(R"({"suite": 1, "frontend_ms": 0, "backend_ms": 1, "samples": 1})"),
               host(1, 1)),
      HasSubstr("expected frontend_ms and backend_ms > 0"));
  EXPECT_THAT(error_of(meta_with(R"({"suite": 1, "frontend_ms": 1, "backend_ms": 1, "samples": 2,
                "sample_frames": [5, 3], "frontend_samples_ms": [1, 1],
                "backend_samples_ms": [1, 1]})"),
                       host(1, 1)),
              HasSubstr("expected sample_frames non-negative and non-decreasing"));
  EXPECT_THAT(error_of(meta_with(R"({"suite": 1, "frontend_ms": 1, "backend_ms": 1, "samples": 2,
                "sample_frames": [0, 3], "frontend_samples_ms": [1, 0],
                "backend_samples_ms": [1, 1]})"),
                       host(1, 1)),
              HasSubstr("expected every sample > 0 ms"));
  SuiteTimes v2 = host(1, 1);
  v2.suite = 2;
  EXPECT_THAT(
      error_of(meta_with(R"({"suite": 1, "frontend_ms": 1, "backend_ms": 1, "samples": 1})"), v2),
      HasSubstr("t.db: host speed measured with reference suite v1, but host 'target' states "
                "suite v2"));
}

}  // namespace
}  // namespace edx::arch
