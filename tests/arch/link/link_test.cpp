// The link kind `dma` through the Link interface: its parameters (presets, the nested `dma:`
// map, errors at their line), the idle-link formula, and its DES model under contention.
#include "arch/link/link.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

namespace edx::arch {
namespace {

using sim::Time;

/// A dma link with `params` (YAML text of its keys) over its defaults.
std::shared_ptr<const Link> dma(const std::string& params = "{}") {
  return make_component<Link>("dma", params, "link");
}

/// The brief's example: 7.9 GB/s, 4 KiB chunks, 1 us setup, 8 outstanding, no latency.
const std::string kExample =
    "{latency_ns: 0, dma: {setup_ns: 1000, chunk_bytes: 4096, max_outstanding: 8}}";

/// The `link:` section of `text` read as a platform reads it.
std::shared_ptr<const Link> parse(const std::string& text, const std::string& where) {
  const YAML::Node root = YAML::Load(text);
  YamlFields fields(root["link"], where, "link");
  return parse_component<Link>(fields, kDefaultLinkKind);
}

std::string error_of(const std::string& text) {
  try {
    parse(text, "car.yaml");
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

/// Runs transfers started at time 0 concurrently; returns each one's completion time.
std::vector<Time> run_concurrent(LinkModel& link, sim::Simulator& sim,
                                 const std::vector<std::pair<std::int64_t, Direction>>& jobs) {
  std::vector<Time> done(jobs.size(), 0);
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    sim.spawn([](LinkModel& l, sim::Simulator& s, std::int64_t bytes, Direction d,
                 Time& out) -> sim::Process {
      co_await l.transfer(bytes, d);
      out = s.now();
    }(link, sim, jobs[i].first, jobs[i].second, done[i]));
  }
  sim.run();
  return done;
}

Time des_time(const Link& link, std::int64_t bytes) {
  sim::Simulator sim;
  const std::unique_ptr<LinkModel> model = link.make_model(sim);
  return run_concurrent(*model, sim, {{bytes, Direction::HostToFpga}})[0];
}

/// The stats a model registered, as JSON.
nlohmann::json stats_of(const LinkModel& model) {
  sim::StatsRegistry stats;
  model.register_stats(stats, "link");
  return stats.to_json()["link"];
}

TEST(DmaLink, DefaultsArePcie3x8AndPresetsCarryThePaperBandwidths) {
  const nlohmann::json pcie = component_json(*dma());
  EXPECT_EQ(pcie["kind"], "dma");
  EXPECT_EQ(pcie["name"], "pcie3_x8");
  EXPECT_DOUBLE_EQ(pcie["bandwidth_gb_per_s"].get<double>(), 7.9);  // paper Sec. VII-A
  EXPECT_EQ(pcie["dma"]["chunk_bytes"], 4096);
  EXPECT_EQ(component_json(*dma("{preset: pcie3_x8}")), pcie);
  EXPECT_TRUE(dma()->full_duplex());

  const nlohmann::json axi = component_json(*dma("{preset: axi4}"));
  EXPECT_EQ(axi["name"], "axi4");
  EXPECT_DOUBLE_EQ(axi["bandwidth_gb_per_s"].get<double>(), 1.2);  // paper Sec. VII-A
  // AXI4 bursts may not cross 4 KB (AMBA AXI4).
  EXPECT_EQ(axi["dma"]["chunk_bytes"], 4096);
  // No preset sets the energy per byte: both keep the default.
  EXPECT_EQ(axi["pj_per_byte"], pcie["pj_per_byte"]);
  EXPECT_EQ(dma("{pj_per_byte: 12.5}")->pj_per_byte(), 12.5);
}

TEST(DmaLink, KeysOverrideThePresetAndTheDmaMapOverridesItsKeys) {
  const std::shared_ptr<const Link> link = parse(
      "link:\n  preset: axi4\n  bandwidth_gb_per_s: 2.4\n  dma:\n    chunk_bytes: 1024\n"
      "    max_outstanding: 4\n",
      "drone.yaml");
  const nlohmann::json j = link->params_json();
  const nlohmann::json axi = dma("{preset: axi4}")->params_json();
  EXPECT_EQ(j["name"], "axi4");
  EXPECT_DOUBLE_EQ(j["bandwidth_gb_per_s"].get<double>(), 2.4);
  EXPECT_EQ(j["latency_ns"], axi["latency_ns"]);
  EXPECT_EQ(j["dma"]["chunk_bytes"], 1024);
  EXPECT_EQ(j["dma"]["max_outstanding"], 4);
  EXPECT_EQ(j["dma"]["setup_ns"], axi["dma"]["setup_ns"]);
  // The same through `kind: dma` and with no section at all (the defaults).
  EXPECT_EQ(parse("link: {kind: dma, preset: axi4}\n", "x.yaml")->params_json(), axi);
  EXPECT_EQ(parse("other: 1\n", "x.yaml")->params_json(), dma()->params_json());
}

TEST(DmaLink, ErrorsNameTheFileLineAndKey) {
  EXPECT_EQ(error_of("link:\n  preset: axi4\n  bandwith_gb_per_s: 2\n"),
            "car.yaml:3: link.bandwith_gb_per_s: unknown key");
  EXPECT_NE(
      error_of("link:\n  dma:\n    chunk_bytes: -5\n").find("car.yaml:3: link.dma.chunk_bytes"),
      std::string::npos);
  EXPECT_EQ(error_of("link:\n  dma:\n    chunk: 5\n"), "car.yaml:3: link.dma.chunk: unknown key");
  EXPECT_NE(error_of("link:\n  preset: usb\n").find("car.yaml:2: link.preset"), std::string::npos);
  EXPECT_NE(error_of("link:\n  dma: 5\n").find("car.yaml:2: link.dma: expected a map"),
            std::string::npos);
  EXPECT_NE(
      error_of("link:\n  bandwidth_gb_per_s: 0\n").find("car.yaml:2: link.bandwidth_gb_per_s"),
      std::string::npos);
  EXPECT_NE(error_of("link:\n  latency_ns: -1\n").find("car.yaml:2: link.latency_ns"),
            std::string::npos);
  EXPECT_NE(error_of("link:\n  dma: {max_outstanding: 0}\n").find("link.dma.max_outstanding"),
            std::string::npos);
  EXPECT_NE(error_of("link:\n  name: ''\n").find("car.yaml:2: link.name"), std::string::npos);
  EXPECT_EQ(error_of("link:\n  kind: usb\n"),
            "car.yaml:2: link.kind: expected one of dma, got 'usb'");
}

TEST(DmaLink, ReferenceListsThePresetTheLinkAndTheDmaKeys) {
  std::vector<std::string> keys;
  for (const ReferenceRow& row : component_reference<Link>("link", kDefaultLinkKind)) {
    keys.push_back(row.key);
  }
  for (const char* key :
       {"link.kind", "link.preset", "link.bandwidth_gb_per_s", "link.pj_per_byte",
        "link.dma.setup_ns", "link.dma.chunk_bytes", "link.dma.max_outstanding"}) {
    EXPECT_NE(std::find(keys.begin(), keys.end(), key), keys.end()) << key;
  }
}

TEST(DmaLinkTiming, WireTimesRoundToPicosecondsOnceATransfer) {
  // No setup, no latency, 8 slots: the wire never idles and T is the transfer's wire time.
  // 4096 B / 7.9e9 B/s = 518481.01 ps; 904 B -> 114430.38 ps.
  const auto wire = dma("{latency_ns: 0, dma: {setup_ns: 0}}");
  EXPECT_EQ(wire->transfer_time(4096), 518481u);
  EXPECT_EQ(wire->transfer_time(904), 114430u);
  // At 1.2 GB/s 9600 B take exactly 8 us, in chunks of 4096 + 4096 + 1408 B: rounding each
  // chunk alone (3413333 + 3413333 + 1173333 ps) would lose a picosecond; the chunks take
  // wire(o + b) - wire(o) and add up to wire(9600).
  const auto axi = dma("{preset: axi4, latency_ns: 0, dma: {setup_ns: 0}}");
  EXPECT_EQ(axi->transfer_time(9600), sim::us(8));
  EXPECT_EQ(axi->transfer_time(1200), sim::us(1));
}

TEST(DmaLinkTiming, WireTimesRoundHalvesAwayFromZeroAsLlroundDoes) {
  // At 16 GB/s a byte takes 62.5 ps: odd counts end on a half picosecond, which rounds up
  // (1 B -> 63 ps, 3 B -> 188 ps), even ones are whole (5000 B -> 312500 ps).
  const auto sixteen = dma("{bandwidth_gb_per_s: 16, latency_ns: 0, dma: {setup_ns: 0}}");
  EXPECT_EQ(sixteen->transfer_time(1), 63u);
  EXPECT_EQ(sixteen->transfer_time(3), 188u);
  EXPECT_EQ(sixteen->transfer_time(5000), 312500u);
  EXPECT_EQ(des_time(*sixteen, 3), 188u);
  // One chunk per transfer: T = wire(B) = llround(B x 1000 / GB/s) for every size and rate.
  for (const double gbps : {7.9, 1.2, 16.0, 3.0, 0.7, 123.456}) {
    const auto link = dma(fmt::format(
        "{{bandwidth_gb_per_s: {}, latency_ns: 0, dma: {{setup_ns: 0, chunk_bytes: 1073741824}}}}",
        gbps));
    for (std::int64_t bytes = 1; bytes < 5000; bytes += 7) {
      const auto expected = static_cast<Time>(std::llround(double(bytes) * 1e3 / gbps));
      ASSERT_EQ(link->transfer_time(bytes), expected) << gbps << " GB/s, " << bytes << " B";
    }
  }
}

TEST(DmaLinkTiming, WireTimeBeyondTheTimeRangeIsAnErrorNamingTheBandwidth) {
  // 1e-7 GB/s = 100 B/s: 1 MB takes 1e4 s = 1e16 ps (representable); 1e12 B take 1e22 ps.
  const auto slow =
      dma("{bandwidth_gb_per_s: 1e-7, latency_ns: 0, dma: {setup_ns: 0, chunk_bytes: 1073741824}}");
  EXPECT_EQ(slow->transfer_time(1'000'000), sim::Time{10'000'000'000'000'000});
  try {
    (void)slow->transfer_time(1'000'000'000'000);
    FAIL() << "expected std::out_of_range";
  } catch (const std::out_of_range& e) {
    EXPECT_NE(std::string(e.what()).find("link.bandwidth_gb_per_s"), std::string::npos) << e.what();
  }
}

TEST(DmaLinkTiming, OneMebibyteAt7p9GBps) {
  // 256 chunks of ~518481 ps behind one 1 us setup: the 8 slots cover setup + one chunk (8 x 518
  // ns > 1518 ns), so the wire never idles: T = 1 us + 2^20 B / 7.9 GB/s = 1 us + 132731139 ps.
  const auto link = dma(kExample);
  const Time expected = sim::us(1) + 132731139;
  EXPECT_EQ(link->transfer_time(1 << 20), expected);
  EXPECT_EQ(des_time(*link, 1 << 20), expected);
  // Against the ideal 1 us + 2^20 B / 7.9 GB/s = 133.731139 us.
  EXPECT_NEAR(sim::to_us(expected), 1.0 + 1048576.0 / 7.9e3, 1e-3);
}

TEST(DmaLinkTiming, SlotLimitedTransfersHandComputed) {
  // Latency 500 ns. One slot: each chunk setup + wire + latency = 1000000 + 518481 + 500000 ps,
  // 4 in a row.
  const auto one = dma("{dma: {setup_ns: 1000, chunk_bytes: 4096, max_outstanding: 1}}");
  EXPECT_EQ(one->transfer_time(4 * 4096), 4u * 2018481u);
  EXPECT_EQ(des_time(*one, 4 * 4096), 4u * 2018481u);
  // Two slots: D0 = 2018481, D1 = 2536962 (wire after chunk 0), chunk 2 starts at D0 and
  // reaches the wire at 3018481, chunk 3 starts at D1 and reaches it at 3536962 = E2;
  // T = 3536962 + 518481 + 500000.
  const auto two = dma("{dma: {setup_ns: 1000, chunk_bytes: 4096, max_outstanding: 2}}");
  EXPECT_EQ(two->transfer_time(4 * 4096), 4555443u);
  EXPECT_EQ(des_time(*two, 4 * 4096), 4555443u);
}

TEST(DmaLinkTiming, PartialLastChunkAndZeroBytes) {
  const auto link = dma("{latency_ns: 0, dma: {setup_ns: 0}}");
  EXPECT_EQ(link->transfer_time(5000), 518481u + 114430u);
  EXPECT_EQ(des_time(*link, 5000), 518481u + 114430u);
  EXPECT_EQ(link->transfer_time(0), 0u);
  EXPECT_EQ(des_time(*link, 0), 0u);
  EXPECT_THROW((void)link->transfer_time(-1), std::runtime_error);
  sim::Simulator sim;
  const std::unique_ptr<LinkModel> model = link->make_model(sim);
  EXPECT_THROW(run_concurrent(*model, sim, {{-1, Direction::HostToFpga}}), std::runtime_error);
}

TEST(DmaLinkTiming, DesMatchesTheFormulaOnAnIdleLink) {
  // PCIe's defaults and kExample: slots never wait (closed form); AXI4 and two slots: they do
  // (the recurrence); four slots: 3 chunks of 518 ns just cover setup + latency (1.5 us).
  for (const std::string& params :
       {std::string("{}"), std::string("{preset: axi4}"), kExample,
        std::string("{dma: {max_outstanding: 2}}"), std::string("{dma: {max_outstanding: 4}}")}) {
    const auto link = dma(params);
    for (const std::int64_t bytes : {1, 100, 4095, 4096, 4097, 65536, 100000, 3 << 20}) {
      EXPECT_EQ(des_time(*link, bytes), link->transfer_time(bytes)) << params << " " << bytes;
    }
  }
}

TEST(DmaLinkContention, TwoConcurrentTransfersTakeTheSumOfTheirWireTimes) {
  sim::Simulator sim;
  const auto link = dma(kExample);
  const std::unique_ptr<LinkModel> model = link->make_model(sim);
  const std::vector<Time> done = run_concurrent(
      *model, sim, {{1 << 20, Direction::HostToFpga}, {1 << 20, Direction::HostToFpga}});
  // 512 chunks share the wire, which never idles after the first setup.
  const Time expected = sim::us(1) + 2 * 132731139;
  EXPECT_EQ(std::max(done[0], done[1]), expected);
  EXPECT_GT(std::min(done[0], done[1]), link->transfer_time(1 << 20));
  const nlohmann::json j = stats_of(*model);
  EXPECT_EQ(j["host_to_fpga"]["bytes"], 2u << 20);
  EXPECT_EQ(j["host_to_fpga"]["transfers"], 2);
  EXPECT_EQ(j["host_to_fpga"]["chunks"], 512);
  EXPECT_EQ(j["fpga_to_host"]["bytes"], 0);
  // Wire busy integral = both transfers' wire times.
  EXPECT_EQ(j["host_to_fpga"]["wire_busy_ps"], 2u * 132731139u);
  EXPECT_EQ(j["fpga_to_host"]["wire_busy_ps"], 0);
  // Busy from the first setup's end to the end: 2 wire times over 1 us + 2 wire times.
  EXPECT_DOUBLE_EQ(model->wire_utilization(Direction::HostToFpga),
                   2.0 * 132731139.0 / static_cast<double>(expected));
}

TEST(DmaLinkContention, FullDuplexDirectionsDoNotContendHalfDuplexDo) {
  {
    sim::Simulator sim;
    const auto link = dma(kExample);
    const std::unique_ptr<LinkModel> model = link->make_model(sim);
    const std::vector<Time> done = run_concurrent(
        *model, sim, {{1 << 20, Direction::HostToFpga}, {1 << 20, Direction::FpgaToHost}});
    EXPECT_EQ(done[0], link->transfer_time(1 << 20));
    EXPECT_EQ(done[1], link->transfer_time(1 << 20));
  }
  {
    sim::Simulator sim;
    const auto half =
        dma("{latency_ns: 0, full_duplex: false, dma: {setup_ns: 1000, chunk_bytes: 4096, "
            "max_outstanding: 8}}");
    EXPECT_FALSE(half->full_duplex());
    const std::unique_ptr<LinkModel> model = half->make_model(sim);
    const std::vector<Time> done = run_concurrent(
        *model, sim, {{1 << 20, Direction::HostToFpga}, {1 << 20, Direction::FpgaToHost}});
    EXPECT_EQ(std::max(done[0], done[1]), sim::us(1) + 2 * 132731139);
    // One wire carries both directions' chunks: one wire_busy_ps for the link.
    const nlohmann::json j = stats_of(*model);
    EXPECT_EQ(j["wire_busy_ps"], 2u * 132731139u);
    EXPECT_DOUBLE_EQ(model->wire_utilization(Direction::HostToFpga),
                     model->wire_utilization(Direction::FpgaToHost));
  }
}

TEST(DmaLinkStats, RegisteredUnderThePrefixAndSpansOnTheTimeline) {
  sim::Simulator sim;
  const auto link = dma(kExample);
  const std::unique_ptr<LinkModel> model = link->make_model(sim);
  sim::Timeline timeline;
  model->set_timeline(timeline, timeline.track("FPGA", "pcie"));
  sim.spawn([](LinkModel& l) -> sim::Process {
    co_await l.transfer(10000, Direction::FpgaToHost, "f3 results");
  }(*model));
  sim.run();
  const nlohmann::json j = stats_of(*model);
  EXPECT_EQ(j["fpga_to_host"]["bytes"], 10000);
  EXPECT_EQ(j["fpga_to_host"]["chunks"], 3);
  EXPECT_EQ(j["fpga_to_host"]["transfers"], 1);
  EXPECT_EQ(j["host_to_fpga"]["transfers"], 0);
  EXPECT_DOUBLE_EQ(j["fpga_to_host"]["latency_us"]["max"].get<double>(),
                   sim::to_us(link->transfer_time(10000)));
  // 10000 B / 7.9 GB/s = 1265822.78 ps.
  EXPECT_EQ(j["fpga_to_host"]["wire_busy_ps"], 1265823);
  EXPECT_NE(timeline.to_json().dump().find("f3 results 10000 B"), std::string::npos);
}

/// The link as processes: a chunk holds one of K slots (a Resource) from its setup until it has
/// arrived and the wire (a Resource of 1) while on it, its wire time round(bytes x 1000 / GB/s)
/// ps over its byte range. The dma kind books the same without processes; this reference
/// checks that the booking is the same schedule under contention.
struct ReferenceLink {
  struct Spec {
    std::string params;  ///< the same link as dma() parameters
    double bandwidth_gb_per_s, latency_ns, setup_ns;
    std::int64_t chunk_bytes;
    int max_outstanding;
    bool full_duplex;
  };
  ReferenceLink(sim::Simulator& s, const Spec& spec)
      : sim(s),
        spec(spec),
        h2c(s, static_cast<std::size_t>(spec.max_outstanding)),
        c2h(s, static_cast<std::size_t>(spec.max_outstanding)),
        own_wire_h2c(s, 1),
        own_wire_c2h(s, 1) {}
  Time wire(std::int64_t bytes) const {
    return static_cast<Time>(std::llround(double(bytes) * 1e3 / spec.bandwidth_gb_per_s));
  }
  sim::Process chunk(sim::Resource& wire_resource, std::int64_t offset, std::int64_t bytes,
                     sim::Lease slot) {
    const Time setup = sim::seconds(spec.setup_ns * 1e-9);
    if (setup > 0) co_await sim.delay(setup);
    {
      sim::Lease w = co_await wire_resource.acquire();
      co_await sim.delay(wire(offset + bytes) - wire(offset));
    }
    const Time latency = sim::seconds(spec.latency_ns * 1e-9);
    if (latency > 0) co_await sim.delay(latency);
    slot.release();
  }
  sim::Task<void> transfer(std::int64_t bytes, Direction d) {
    sim::Resource& slots = d == Direction::HostToFpga || !spec.full_duplex ? h2c : c2h;
    sim::Resource& wire_resource =
        d == Direction::HostToFpga || !spec.full_duplex ? own_wire_h2c : own_wire_c2h;
    std::vector<sim::ProcessHandle> pending;
    for (std::int64_t offset = 0; offset < bytes; offset += spec.chunk_bytes) {
      sim::Lease slot = co_await slots.acquire();
      pending.push_back(sim.spawn(chunk(
          wire_resource, offset, std::min(spec.chunk_bytes, bytes - offset), std::move(slot))));
    }
    for (const sim::ProcessHandle& h : pending) co_await h;
  }
  sim::Simulator& sim;
  Spec spec;
  sim::Resource h2c, c2h, own_wire_h2c, own_wire_c2h;
};

using Jobs = std::vector<std::tuple<std::int64_t, Direction, int>>;

/// Completion times of transfers (bytes, direction, start ns) on `link`.
template <class Model>
std::vector<Time> staggered(sim::Simulator& sim, Model& link, const Jobs& jobs) {
  std::vector<Time> done(jobs.size(), 0);
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    sim.spawn([](Model& l, sim::Simulator& s, std::int64_t bytes, Direction d, int start_ns,
                 Time& out) -> sim::Process {
      co_await s.delay(sim::ns(start_ns));
      co_await l.transfer(bytes, d);
      out = s.now();
    }(link, sim, std::get<0>(jobs[i]), std::get<1>(jobs[i]), std::get<2>(jobs[i]), done[i]));
  }
  sim.run();
  return done;
}

/// `count` transfers drawn by an LCG (Knuth's MMIX constants) from `seed`: sizes below
/// `max_bytes`, a third of them FPGA to host, starts below `max_start`.
Jobs lcg_jobs(std::uint64_t seed, int count, std::uint64_t max_bytes, std::uint64_t max_start) {
  Jobs jobs;
  std::uint64_t x = seed;
  for (int i = 0; i < count; ++i) {
    x = x * 6364136223846793005ull + 1442695040888963407ull;
    const auto bytes = static_cast<std::int64_t>((x >> 33) % max_bytes);
    const Direction d = (x >> 20) % 3 == 0 ? Direction::FpgaToHost : Direction::HostToFpga;
    jobs.emplace_back(bytes, d, static_cast<int>((x >> 40) % max_start));
  }
  return jobs;
}

/// On each link of `specs`, the dma kind's completion times of `jobs` equal those of the
/// one-process-per-chunk reference.
void expect_booked_equals_chunk_processes(const Jobs& jobs,
                                          const std::vector<ReferenceLink::Spec>& specs) {
  for (const ReferenceLink::Spec& spec : specs) {
    sim::Simulator booked_sim;
    const std::unique_ptr<LinkModel> model = dma(spec.params)->make_model(booked_sim);
    const std::vector<Time> booked = staggered(booked_sim, *model, jobs);
    sim::Simulator reference_sim;
    ReferenceLink reference_link(reference_sim, spec);
    const std::vector<Time> reference = staggered(reference_sim, reference_link, jobs);
    for (std::size_t i = 0; i < jobs.size(); ++i) {
      EXPECT_EQ(booked[i], reference[i]) << spec.params << " transfer " << i;
    }
  }
}

/// Links for long transfers: PCIe-like full duplex with 8 and with 2 requests in flight (slots
/// that wait: the chunk loop only), and a slow half-duplex link.
std::vector<ReferenceLink::Spec> long_transfer_links() {
  return {{"{bandwidth_gb_per_s: 7.9, latency_ns: 500, dma: {setup_ns: 1000, max_outstanding: 8}}",
           7.9, 500, 1000, 4096, 8, true},
          {"{bandwidth_gb_per_s: 1.2, latency_ns: 100, full_duplex: false, dma: {setup_ns: 200}}",
           1.2, 100, 200, 4096, 8, false},
          {"{bandwidth_gb_per_s: 7.9, latency_ns: 500, dma: {setup_ns: 1000, max_outstanding: 2}}",
           7.9, 500, 1000, 4096, 2, true}};
}

TEST(DmaLinkContention, BookedScheduleEqualsTheChunkProcessModel) {
  // Transfers of many sizes started at staggered times in both directions contend for slots
  // and wires; the dma kind's booked chunks must finish exactly when chunk processes would.
  expect_booked_equals_chunk_processes(
      lcg_jobs(12345, 40, 70000, 20000),
      {{"{bandwidth_gb_per_s: 7.9, latency_ns: 500, dma: {setup_ns: 1000, max_outstanding: 8}}",
        7.9, 500, 1000, 4096, 8, true},
       {"{bandwidth_gb_per_s: 1.2, latency_ns: 100, dma: {setup_ns: 200, max_outstanding: 8}}", 1.2,
        100, 200, 4096, 8, true},
       {"{bandwidth_gb_per_s: 1.2, latency_ns: 100, full_duplex: false, dma: {setup_ns: 200}}", 1.2,
        100, 200, 4096, 8, false},
       {"{bandwidth_gb_per_s: 7.9, latency_ns: 500, dma: {setup_ns: 1000, max_outstanding: 2}}",
        7.9, 500, 1000, 4096, 2, true}});
}

TEST(DmaLinkContention, LongTransfersBookedInStretchesEqualTheChunkProcessModel) {
  // Transfers of hundreds of chunks (spills), alone on the link for long stretches and
  // overlapping others: the stretches the dma kind books at once (book_steady) must give the
  // same completion times as chunk processes, on links whose slots never wait and on one whose
  // slots do (two outstanding requests: the chunk loop only).
  expect_booked_equals_chunk_processes(lcg_jobs(777, 14, 1500000, 900000), long_transfer_links());
}

TEST(DmaLinkContention, TransfersOnAnIdleLinkBookedWholeEqualTheChunkProcessModel) {
  // Transfers mostly alone on the link (starts spread over 3 ms, up to 600 kB each: 76 us at
  // 7.9 GB/s, 500 us at 1.2 GB/s), which the dma kind books whole when nothing else can happen
  // before their end (book_idle), among others that overlap: the same completion times as
  // chunk processes.
  expect_booked_equals_chunk_processes(lcg_jobs(4242, 30, 600000, 3000000), long_transfer_links());
}

TEST(DmaLinkContention, ShortTransfersOnAnIdleLinkBookedWholeEqualTheChunkProcessModel) {
  // Transfers of fewer chunks than slots (below 40 kB: at most ten 4 KiB chunks, mostly under
  // eight), mostly alone on the link (starts spread over 0.4 ms) and booked whole with their
  // slots replaced at once (book_idle), among others that overlap and reuse those slots: the
  // same completion times as chunk processes.
  expect_booked_equals_chunk_processes(lcg_jobs(31337, 60, 40000, 400000), long_transfer_links());
}

TEST(DmaLinkStats, TransfersBookedWholeCountTheirChunksAndWireTime) {
  // One process, three transfers one after the other on an idle link (each booked whole):
  // 10000 B (3 chunks), 1 MiB (256) and 1 B (1) host to FPGA; the wire carried each for its
  // wire(B): 1265823 + 132731139 + 127 ps (1 B / 7.9 GB/s = 126.58 ps).
  sim::Simulator sim;
  const auto link = dma();
  const std::unique_ptr<LinkModel> model = link->make_model(sim);
  std::vector<Time> took;
  sim.spawn([](LinkModel& l, sim::Simulator& s, std::vector<Time>& out) -> sim::Process {
    for (const std::int64_t bytes : {10000, 1 << 20, 1}) {
      const Time begin = s.now();
      co_await l.transfer(bytes, Direction::HostToFpga);
      out.push_back(s.now() - begin);
    }
  }(*model, sim, took));
  sim.run();
  ASSERT_EQ(took.size(), 3u);
  EXPECT_EQ(took[0], link->transfer_time(10000));
  EXPECT_EQ(took[1], link->transfer_time(1 << 20));
  EXPECT_EQ(took[2], link->transfer_time(1));
  const nlohmann::json j = stats_of(*model);
  EXPECT_EQ(j["host_to_fpga"]["chunks"], 3 + 256 + 1);
  EXPECT_EQ(j["host_to_fpga"]["transfers"], 3);
  EXPECT_EQ(j["host_to_fpga"]["wire_busy_ps"], 1265823 + 132731139 + 127);
}

}  // namespace
}  // namespace edx::arch
