// The host processor as a registered component kind (arch/host/host_processor.hpp): today's host,
// `suite_scaled`, read over its defaults in a platform's `host:`, its errors at their file:line
// (the power keys that moved from `power:` among them), its JSON and reference; and a kind of the
// tests' own (fixed_speed_host.cpp, one file and its registration) selected by `host.kind` and
// simulated end to end against hand-computed host times and energy.
#include "arch/host/host_processor.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include "arch/platform/platform.hpp"
#include "arch/system/system_model.hpp"
#include "tests/arch/host/platform_text.hpp"
#include "tests/arch/system/hand_tasks.hpp"

namespace edx::arch {
namespace {

using ::testing::HasSubstr;

TEST(SuiteScaledHost, ReadsItsKeysOverItsDefaults) {
  const Platform p = parse("name: p\nhost:\n  cores: 3\n  active_w: 20\n");
  EXPECT_EQ(p.host->kind(), "suite_scaled");  // kind: optional
  EXPECT_EQ(p.host->cores(), 3);
  EXPECT_EQ(p.host->power().active_w, 20.0);
  EXPECT_EQ(p.host->power().idle_w, 2.0);  // the default
  EXPECT_EQ(p.host->display_name(), "trace host");
  EXPECT_EQ(p.host->params_json()["frontend_suite_ms"], 0.0);
  EXPECT_EQ(p.host->params_json()["times"], "modeled");

  const Platform named = parse("name: p\nhost: {kind: suite_scaled, name: Kaby Lake}\n");
  EXPECT_EQ(named.host->display_name(), "Kaby Lake");
  EXPECT_EQ(named.host->cores(), 2);

  // No `host:`: the default kind with every key at its default.
  const Platform bare = parse("name: p\n");
  EXPECT_EQ(component_json(*bare.host),
            component_json(*ComponentRegistry<HostProcessor>::instance().make("suite_scaled")));
  EXPECT_EQ(component_json(*bare.host), component_json(*Platform{}.host));
}

TEST(SuiteScaledHost, ItsJsonHasItsKindAndEveryParameter) {
  const nlohmann::json host = parse("name: p\nhost: {idle_w: 1.5}\n").to_json()["host"];
  std::set<std::string> keys;
  for (const auto& [key, value] : host.items()) keys.insert(key);
  EXPECT_EQ(keys, (std::set<std::string>{"kind", "name", "suite", "frontend_suite_ms", "provenance",
                                         "backend_suite_ms", "backend_provenance", "times", "cores",
                                         "active_w", "idle_w"}));
  EXPECT_EQ(host["kind"], "suite_scaled");
  EXPECT_EQ(host["idle_w"], 1.5);
}

TEST(SuiteScaledHost, ErrorsNameTheFileLineAndKey) {
  EXPECT_EQ(
      error_of("name: p\nhost:\n  kind: gpu\n"),
      "p.yaml:3: host.kind: expected one of datasheet, fixed_speed or suite_scaled, got 'gpu'");
  EXPECT_EQ(error_of("name: p\nhost:\n  kind: fixed_speed\n  frontend_suite_ms: 1\n"),
            "p.yaml:4: host.frontend_suite_ms: unknown key");
  EXPECT_EQ(error_of("name: p\nhost:\n  active_w: 5\n  idle_w: 6\n"),
            "p.yaml:4: host.idle_w: expected a power in [0, active_w] W");
  EXPECT_EQ(error_of("name: p\nhost:\n  cores: 0\n"),
            "p.yaml:3: host.cores: expected an integer >= 1, got '0'");
  EXPECT_THAT(error_of("name: p\nhost:\n  frontend_suite_ms: 5\n"),
              HasSubstr("host.backend_suite_ms: expected both suite times or neither"));
}

TEST(SuiteScaledHost, ThePowerKeysThatMovedFromPowerSayWhereTheyWent) {
  EXPECT_EQ(error_of("name: p\npower:\n  host_active_w: 20\n"),
            "p.yaml:3: power.host_active_w: moved: now host.active_w (docs/CONFIG.md)");
  EXPECT_EQ(error_of("name: p\npower:\n  fpga_static_w: 1\n  host_idle_w: 1\n"),
            "p.yaml:4: power.host_idle_w: moved: now host.idle_w (docs/CONFIG.md)");
  // The calibration hook stays in power:.
  EXPECT_EQ(parse("name: p\npower: {host_power_scale: 0.5}\n").power.host_power_scale, 0.5);
}

TEST(HostReference, ListsTheKindThenEachKindsKeys) {
  const std::vector<ReferenceRow> rows = Platform::reference();
  const auto row = [&rows](const std::string& key, const std::string& kind) {
    return std::find_if(rows.begin(), rows.end(), [&](const ReferenceRow& r) {
      return r.key == key && r.group.find("of kind `" + kind + "`") != std::string::npos;
    });
  };
  const auto kind = std::find_if(rows.begin(), rows.end(),
                                 [](const ReferenceRow& r) { return r.key == "host.kind"; });
  ASSERT_NE(kind, rows.end());
  EXPECT_EQ(kind->value, "suite_scaled");
  EXPECT_EQ(kind->accepted, "datasheet, fixed_speed or suite_scaled");
  EXPECT_NE(row("host.active_w", "suite_scaled"), rows.end());
  EXPECT_NE(row("host.frontend_suite_ms", "suite_scaled"), rows.end());
  EXPECT_NE(row("host.speed", "fixed_speed"), rows.end());
  EXPECT_EQ(row("host.speed", "suite_scaled"), rows.end());
}

/// One registration frame: frontend 3 ms and backend 10 ms on the tracing machine, 4 ms of it
/// in a kernel that stays on the host.
std::vector<trace::FrameTrace> one_frame() { return {hand_frame("tracking", 4'000'000)}; }

const trace::TraceMeta kMeta = {
    {"resolution", "40x25"}, {"dataset", "hand"}, {"precision", "fp64"}};

TEST(HostKind, AKindOfOneFileIsSelectedByTheHostSectionAndSetsTheHostTimes) {
  const Platform fast =
      parse("name: p\nhost: {kind: fixed_speed, speed: 2, cores: 1, active_w: 20, idle_w: 1}\n");
  EXPECT_EQ(fast.host->kind(), "fixed_speed");
  EXPECT_EQ(fast.host->display_name(), "fixed-speed host");
  EXPECT_EQ(fast.to_json()["host"], (nlohmann::json{{"kind", "fixed_speed"},
                                                    {"speed", 2.0},
                                                    {"cores", 1},
                                                    {"active_w", 20.0},
                                                    {"idle_w", 1.0}}));

  // Twice the tracing machine's speed: every host time halves.
  const std::vector<trace::FrameTrace> frames = one_frame();
  const PlatformHostTimes t = fast.host->host_times(frames, kMeta, "hand.db");
  EXPECT_DOUBLE_EQ(t.frontend_ms[0], 1.5);   // 3 ms / 2
  EXPECT_DOUBLE_EQ(t.backend_ms[0], 5.0);    // 10 ms / 2
  EXPECT_DOUBLE_EQ(t.kernel_ms[0][0], 2.0);  // 4 ms / 2

  // The baseline frame runs on that host: 1.5 ms of frontend, then 5 ms of backend, on its one
  // core; its energy is the host's active power over the frame (no FPGA): 20 W x 6.5 ms.
  const SystemResult r = simulate_system(fast, frames, kMeta, "hand.db");
  const FrameResult& b = r.baseline.frames[0];
  EXPECT_NEAR(b.frontend_ms, 1.5, 1e-9);
  EXPECT_NEAR(b.backend_ms, 5.0, 1e-9);
  EXPECT_NEAR(b.e2e_ms, 6.5, 1e-9);
  EXPECT_NEAR(b.energy.host_j, 20.0 * 6.5e-3, 1e-12);
  EXPECT_NEAR(r.frontend.cpu_ms.mean, 1.5, 1e-12);
  EXPECT_EQ(r.frontend.to_json()["host"]["kind"], "fixed_speed");
  const auto cores =
      std::find_if(r.baseline.stream->resources.begin(), r.baseline.stream->resources.end(),
                   [](const ResourceUse& u) { return u.name == "host.cores"; });
  ASSERT_NE(cores, r.baseline.stream->resources.end());
  EXPECT_EQ(cores->max, 1.0);

  // The same frame on the default host without suite times: the trace's own times.
  const SystemResult same = simulate_system(parse("name: p\n"), frames, kMeta, "hand.db");
  EXPECT_NEAR(same.baseline.frames[0].e2e_ms, 13.0, 1e-9);  // 3 ms + 10 ms
}

}  // namespace
}  // namespace edx::arch
