// Timeline: Chrome trace-event JSON that parses back with the expected spans.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include "sim_core/engine.hpp"

namespace edx::sim {
namespace {

std::filesystem::path temp_path(const std::string& name) {
  return std::filesystem::temp_directory_path() /
         (name + "." + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "." +
          std::to_string(reinterpret_cast<std::uintptr_t>(&name)));
}

TEST(Timeline, WritesChromeTraceEventsThatParseBack) {
  Simulator sim;
  Timeline timeline;
  const Timeline::TrackId fd = timeline.track("FPGA", "FD");
  const Timeline::TrackId lss = timeline.track("FPGA", "LSS");
  const Timeline::TrackId host = timeline.track("Host", "backend");
  EXPECT_EQ(timeline.track("FPGA", "FD"), fd);  // same names, same track
  auto worker = [&]() -> Process {
    const Time begin = sim.now();
    co_await sim.delay(ns(1500));
    timeline.span(fd, "FD frame 0", begin, sim.now(), {{"pixels", 307200}});
    co_await sim.delay(ps(2500));
    timeline.span(lss, "LSS", ns(1500), sim.now());
  };
  sim.spawn(worker());
  sim.run();
  timeline.span(host, "projection", us(1), us(3));

  const std::filesystem::path path = temp_path("edx_timeline_test.json");
  timeline.write(path);
  std::ifstream in(path);
  ASSERT_TRUE(in.good());
  const nlohmann::json trace = nlohmann::json::parse(in);
  std::filesystem::remove(path);

  ASSERT_TRUE(trace.contains("traceEvents"));
  std::map<int, std::string> process_names;
  std::map<std::pair<int, int>, std::string> thread_names;
  std::vector<nlohmann::json> spans;
  for (const nlohmann::json& event : trace["traceEvents"]) {
    if (event["ph"] == "M" && event["name"] == "process_name") {
      process_names[event["pid"]] = event["args"]["name"];
    } else if (event["ph"] == "M" && event["name"] == "thread_name") {
      thread_names[{event["pid"], event["tid"]}] = event["args"]["name"];
    } else if (event["ph"] == "X") {
      spans.push_back(event);
    }
  }
  EXPECT_EQ(process_names.size(), 2u);
  EXPECT_EQ(thread_names.size(), 3u);
  ASSERT_EQ(spans.size(), 3u);

  const auto track_of = [&](const nlohmann::json& span) {
    const int pid = span["pid"];
    const int tid = span["tid"];
    return process_names.at(pid) + "/" + thread_names.at({pid, tid});
  };
  EXPECT_EQ(spans[0]["name"], "FD frame 0");
  EXPECT_EQ(track_of(spans[0]), "FPGA/FD");
  EXPECT_DOUBLE_EQ(spans[0]["ts"].get<double>(), 0.0);
  EXPECT_DOUBLE_EQ(spans[0]["dur"].get<double>(), 1.5);  // microseconds
  EXPECT_EQ(spans[0]["args"]["pixels"], 307200);

  EXPECT_EQ(spans[1]["name"], "LSS");
  EXPECT_EQ(track_of(spans[1]), "FPGA/LSS");
  EXPECT_DOUBLE_EQ(spans[1]["ts"].get<double>(), 1.5);
  EXPECT_DOUBLE_EQ(spans[1]["dur"].get<double>(), 0.0025);
  EXPECT_FALSE(spans[1].contains("args"));

  EXPECT_EQ(track_of(spans[2]), "Host/backend");
  EXPECT_DOUBLE_EQ(spans[2]["ts"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(spans[2]["dur"].get<double>(), 2.0);
  EXPECT_EQ(timeline.span_count(), 3u);
}

TEST(Timeline, RetainKeepsTheSpansOverlappingAWindow) {
  Timeline t;
  const Timeline::TrackId a = t.track("g", "a");
  t.span(a, "before", ns(0), ns(10));     // ends before the window
  t.span(a, "touching", ns(10), ns(20));  // ends at its start: overlaps
  t.span(a, "inside", ns(30), ns(40));
  t.span(a, "across", ns(45), ns(80));  // starts inside
  t.span(a, "after", ns(51), ns(60));   // starts after its end
  t.retain(ns(20), ns(50));
  EXPECT_EQ(t.span_count(), 3u);
  EXPECT_EQ(t.track_count(), 1u);
  std::vector<std::string> names;
  const nlohmann::json doc = t.to_json();
  for (const auto& e : doc["traceEvents"]) {
    if (e["ph"] == "X") names.push_back(e["name"].get<std::string>());
  }
  EXPECT_EQ(names, (std::vector<std::string>{"touching", "inside", "across"}));
}

TEST(Timeline, DisabledTimelineRecordsNothingAndBadSpansThrow) {
  Timeline off(false);
  const Timeline::TrackId track = off.track("t");
  off.span(track, "ignored", 0, 10);
  EXPECT_EQ(off.span_count(), 0u);

  Timeline on;
  const Timeline::TrackId t = on.track("t");
  EXPECT_THROW(on.span(t, "backwards", 10, 5), std::invalid_argument);
  EXPECT_THROW(on.span(t + 1, "unknown track", 0, 5), std::invalid_argument);
  EXPECT_THROW(on.span(t, "bad args", 0, 5, nlohmann::json::array({1, 2})), std::invalid_argument);
}

TEST(Timeline, WriteFailureNamesTheFileAndLeavesNothing) {
  Timeline timeline;
  timeline.span(timeline.track("t"), "s", 0, 1);
  const std::filesystem::path missing_dir = temp_path("edx_no_such_dir") / "trace.json";
  try {
    timeline.write(missing_dir);
    FAIL() << "write into a missing directory succeeded";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find(missing_dir.string()), std::string::npos);
  }
  EXPECT_FALSE(std::filesystem::exists(missing_dir));
}

}  // namespace
}  // namespace edx::sim
