// DMA link model: configuration, the idle-link formula, and the DES under contention.
#include "arch/link/link.hpp"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

namespace edx::arch {
namespace {

using sim::Time;

/// The brief's example: 7.9 GB/s, 4 KiB chunks, 1 us setup, 8 outstanding, no latency.
LinkSpec example_spec() {
  LinkSpec s = LinkSpec::pcie3_x8();
  s.link.latency_ns = 0;
  s.dma = {1000.0, 4096, 8};
  return s;
}

/// Runs transfers started at time 0 concurrently; returns each one's completion time.
std::vector<Time> run_concurrent(DmaLink& link, sim::Simulator& sim,
                                 const std::vector<std::pair<std::int64_t, Direction>>& jobs) {
  std::vector<Time> done(jobs.size(), 0);
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    sim.spawn([](DmaLink& l, sim::Simulator& s, std::int64_t bytes, Direction d,
                 Time& out) -> sim::Process {
      co_await l.transfer(bytes, d);
      out = s.now();
    }(link, sim, jobs[i].first, jobs[i].second, done[i]));
  }
  sim.run();
  return done;
}

Time des_time(const LinkSpec& spec, std::int64_t bytes) {
  sim::Simulator sim;
  DmaLink link(sim, spec);
  return run_concurrent(link, sim, {{bytes, Direction::HostToFpga}})[0];
}

TEST(LinkConfig, ValidateNamesTheBadField) {
  LinkSpec s = LinkSpec::pcie3_x8();
  s.link.bandwidth_gb_per_s = 0;
  try {
    s.validate();
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("link.bandwidth_gb_per_s"), std::string::npos);
  }
  s = LinkSpec::axi4();
  s.dma.chunk_bytes = 0;
  try {
    s.validate();
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("dma.chunk_bytes"), std::string::npos);
  }
  s = LinkSpec::axi4();
  s.dma.max_outstanding = 0;
  EXPECT_THROW(s.validate(), std::runtime_error);
  s = LinkSpec::axi4();
  s.link.latency_ns = -1;
  EXPECT_THROW(s.validate(), std::runtime_error);
}

TEST(LinkConfig, PresetsCarryThePaperBandwidths) {
  EXPECT_DOUBLE_EQ(LinkSpec::pcie3_x8().link.bandwidth_gb_per_s, 7.9);
  EXPECT_DOUBLE_EQ(LinkSpec::axi4().link.bandwidth_gb_per_s, 1.2);
  EXPECT_EQ(LinkSpec::preset("axi4").link.name, "axi4");
  EXPECT_THROW(LinkSpec::preset("usb"), std::runtime_error);
  const nlohmann::json j = LinkSpec::pcie3_x8().to_json();
  EXPECT_EQ(j["dma"]["chunk_bytes"], 4096);
  EXPECT_EQ(j["link"]["name"], "pcie3_x8");
}

TEST(LinkConfig, FromYaml) {
  const YAML::Node node = YAML::Load(
      "preset: axi4\nbandwidth_gb_per_s: 2.4\ndma:\n  chunk_bytes: 1024\n  max_outstanding: 4\n");
  const LinkSpec s = LinkSpec::from_yaml(node, "drone.yaml");
  EXPECT_EQ(s.link.name, "axi4");
  EXPECT_DOUBLE_EQ(s.link.bandwidth_gb_per_s, 2.4);
  EXPECT_DOUBLE_EQ(s.link.latency_ns, LinkSpec::axi4().link.latency_ns);
  EXPECT_EQ(s.dma.chunk_bytes, 1024);
  EXPECT_EQ(s.dma.max_outstanding, 4);
  EXPECT_DOUBLE_EQ(s.dma.setup_ns, LinkSpec::axi4().dma.setup_ns);

  try {
    LinkSpec::from_yaml(YAML::Load("preset: axi4\nbandwith_gb_per_s: 2\n"), "drone.yaml");
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("drone.yaml:2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("bandwith_gb_per_s"), std::string::npos) << e.what();
  }
  try {
    LinkSpec::from_yaml(YAML::Load("dma:\n  chunk_bytes: -5\n"), "car.yaml");
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("car.yaml:2: link.dma.chunk_bytes"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(LinkSpec::from_yaml(YAML::Load("preset: usb\n"), "x.yaml"), std::runtime_error);
}

TEST(LinkTiming, WireTimeRoundsToPicoseconds) {
  // 4096 B / 7.9e9 B/s = 518481.01 ps; 904 B -> 114430.38 ps.
  EXPECT_EQ(wire_time(LinkSpec::pcie3_x8().link, 4096), 518481u);
  EXPECT_EQ(wire_time(LinkSpec::pcie3_x8().link, 904), 114430u);
  // Chunks of a transfer add up to its whole wire time: at 1.2 GB/s 4096 B take 3413333.3 ps;
  // the chunks at offsets 0, 4096, 8192 of 9600 B take 3413333, 3413334 and 1173333 ps = 8 us.
  const LinkConfig axi = LinkSpec::axi4().link;
  EXPECT_EQ(chunk_wire_time(axi, 0, 4096), 3413333u);
  EXPECT_EQ(chunk_wire_time(axi, 4096, 4096), 3413334u);
  EXPECT_EQ(chunk_wire_time(axi, 8192, 1408), 1173333u);
  // 1.2 GB/s: 1200 B take exactly 1 us.
  EXPECT_EQ(wire_time(LinkSpec::axi4().link, 1200), sim::us(1));
}

TEST(LinkTiming, WireTimeBeyondTheTimeRangeIsAnErrorNamingTheBandwidth) {
  // 1e-7 GB/s = 100 B/s: 1 MB takes 1e4 s = 1e16 ps (representable); 1e12 B take 1e22 ps.
  LinkConfig slow = LinkSpec::pcie3_x8().link;
  slow.bandwidth_gb_per_s = 1e-7;
  EXPECT_EQ(wire_time(slow, 1'000'000), sim::Time{10'000'000'000'000'000});
  try {
    wire_time(slow, 1'000'000'000'000);
    FAIL() << "expected std::out_of_range";
  } catch (const std::out_of_range& e) {
    EXPECT_NE(std::string(e.what()).find("link.bandwidth_gb_per_s"), std::string::npos) << e.what();
  }
}

TEST(LinkTiming, OneMebibyteAt7p9GBps) {
  // 256 chunks of ~518481 ps behind one 1 us setup: the 8 slots cover setup + one chunk (8 x 518
  // ns > 1518 ns), so the wire never idles: T = 1 us + 2^20 B / 7.9 GB/s = 1 us + 132731139 ps.
  const Time expected = sim::us(1) + 132731139;
  EXPECT_EQ(wire_time(example_spec().link, 1 << 20), 132731139u);
  EXPECT_EQ(transfer_time(example_spec(), 1 << 20), expected);
  EXPECT_EQ(des_time(example_spec(), 1 << 20), expected);
  // Against the ideal 1 us + 2^20 B / 7.9 GB/s = 133.731139 us.
  EXPECT_NEAR(sim::to_us(expected), 1.0 + 1048576.0 / 7.9e3, 1e-3);
}

TEST(LinkTiming, SlotLimitedTransfersHandComputed) {
  LinkSpec s = LinkSpec::pcie3_x8();  // latency 500 ns
  s.dma = {1000.0, 4096, 1};
  // One slot: each chunk setup + wire + latency = 1000000 + 518481 + 500000 ps, 4 in a row.
  EXPECT_EQ(transfer_time(s, 4 * 4096), 4u * 2018481u);
  EXPECT_EQ(des_time(s, 4 * 4096), 4u * 2018481u);
  // Two slots: D0 = 2018481, D1 = 2536962 (wire after chunk 0), chunk 2 starts at D0 and
  // reaches the wire at 3018481, chunk 3 starts at D1 and reaches it at 3536962 = E2;
  // T = 3536962 + 518481 + 500000.
  s.dma.max_outstanding = 2;
  EXPECT_EQ(transfer_time(s, 4 * 4096), 4555443u);
  EXPECT_EQ(des_time(s, 4 * 4096), 4555443u);
}

TEST(LinkTiming, PartialLastChunkAndZeroBytes) {
  LinkSpec s = LinkSpec::pcie3_x8();
  s.link.latency_ns = 0;
  s.dma = {0.0, 4096, 8};
  EXPECT_EQ(transfer_time(s, 5000), 518481u + 114430u);
  EXPECT_EQ(des_time(s, 5000), 518481u + 114430u);
  EXPECT_EQ(transfer_time(s, 0), 0u);
  EXPECT_EQ(des_time(s, 0), 0u);
  EXPECT_THROW(transfer_time(s, -1), std::runtime_error);
}

TEST(LinkTiming, DesMatchesTheFormulaOnAnIdleLink) {
  for (const LinkSpec& spec : {LinkSpec::pcie3_x8(), LinkSpec::axi4(), example_spec()}) {
    for (const std::int64_t bytes : {1, 100, 4095, 4096, 4097, 65536, 100000, 3 << 20}) {
      EXPECT_EQ(des_time(spec, bytes), transfer_time(spec, bytes))
          << spec.link.name << " " << bytes << " B";
    }
  }
}

TEST(LinkContention, TwoConcurrentTransfersTakeTheSumOfTheirWireTimes) {
  sim::Simulator sim;
  DmaLink link(sim, example_spec());
  const std::vector<Time> done = run_concurrent(
      link, sim, {{1 << 20, Direction::HostToFpga}, {1 << 20, Direction::HostToFpga}});
  // 512 chunks share the wire, which never idles after the first setup.
  const Time expected = sim::us(1) + 2 * 132731139;
  EXPECT_EQ(std::max(done[0], done[1]), expected);
  EXPECT_GT(std::min(done[0], done[1]), link.transfer_time(1 << 20));
  EXPECT_EQ(link.bytes(Direction::HostToFpga), 2u << 20);
  EXPECT_EQ(link.transfers(Direction::HostToFpga), 2u);
  EXPECT_EQ(link.chunks(Direction::HostToFpga), 512u);
  EXPECT_EQ(link.bytes(Direction::FpgaToHost), 0u);
  // Wire busy integral = both transfers' wire times.
  EXPECT_EQ(link.wire_busy_time(Direction::HostToFpga), 2u * 132731139u);
  EXPECT_EQ(link.wire_busy_time(Direction::FpgaToHost), 0u);
  // Busy from the first setup's end to the end: 2 wire times over 1 us + 2 wire times.
  EXPECT_DOUBLE_EQ(link.wire_utilization(Direction::HostToFpga),
                   2.0 * 132731139.0 / static_cast<double>(expected));
}

TEST(LinkContention, FullDuplexDirectionsDoNotContendHalfDuplexDo) {
  {
    sim::Simulator sim;
    DmaLink link(sim, example_spec());
    const std::vector<Time> done = run_concurrent(
        link, sim, {{1 << 20, Direction::HostToFpga}, {1 << 20, Direction::FpgaToHost}});
    EXPECT_EQ(done[0], link.transfer_time(1 << 20));
    EXPECT_EQ(done[1], link.transfer_time(1 << 20));
  }
  {
    LinkSpec half = example_spec();
    half.link.full_duplex = false;
    sim::Simulator sim;
    DmaLink link(sim, half);
    const std::vector<Time> done = run_concurrent(
        link, sim, {{1 << 20, Direction::HostToFpga}, {1 << 20, Direction::FpgaToHost}});
    EXPECT_EQ(std::max(done[0], done[1]), sim::us(1) + 2 * 132731139);
    // One wire carries both directions' chunks.
    EXPECT_EQ(link.wire_busy_time(Direction::HostToFpga), 2u * 132731139u);
    EXPECT_EQ(link.wire_busy_time(Direction::FpgaToHost), 2u * 132731139u);
  }
}

TEST(LinkStats, RegisteredUnderThePrefix) {
  sim::Simulator sim;
  DmaLink link(sim, example_spec());
  sim::Timeline timeline;
  link.set_timeline(timeline, timeline.track("FPGA", "pcie"));
  run_concurrent(link, sim, {{10000, Direction::FpgaToHost}});
  sim::StatsRegistry stats;
  link.register_stats(stats, "link");
  const nlohmann::json j = stats.to_json();
  EXPECT_EQ(j["link"]["fpga_to_host"]["bytes"], 10000);
  EXPECT_EQ(j["link"]["fpga_to_host"]["chunks"], 3);
  EXPECT_EQ(j["link"]["fpga_to_host"]["transfers"], 1);
  EXPECT_EQ(j["link"]["host_to_fpga"]["transfers"], 0);
  EXPECT_DOUBLE_EQ(j["link"]["fpga_to_host"]["latency_us"]["max"].get<double>(),
                   sim::to_us(link.transfer_time(10000)));
  EXPECT_EQ(j["link"]["fpga_to_host"]["wire_busy_ps"], wire_time(example_spec().link, 10000));
}

/// The link as processes: a chunk holds one of K slots (a Resource) from its setup until it has
/// arrived and the wire (a Resource of 1) while on it. DmaLink books the same without processes;
/// this reference checks that the booking is the same schedule under contention.
struct ReferenceLink {
  ReferenceLink(sim::Simulator& s, const LinkSpec& spec)
      : sim(s),
        spec(spec),
        h2c(s, static_cast<std::size_t>(spec.dma.max_outstanding)),
        c2h(s, static_cast<std::size_t>(spec.dma.max_outstanding)),
        own_wire_h2c(s, 1),
        own_wire_c2h(s, 1) {}
  sim::Process chunk(sim::Resource& wire, std::int64_t offset, std::int64_t bytes,
                     sim::Lease slot) {
    const Time setup = sim::seconds(spec.dma.setup_ns * 1e-9);
    if (setup > 0) co_await sim.delay(setup);
    {
      sim::Lease w = co_await wire.acquire();
      co_await sim.delay(chunk_wire_time(spec.link, offset, bytes));
    }
    const Time latency = sim::seconds(spec.link.latency_ns * 1e-9);
    if (latency > 0) co_await sim.delay(latency);
    slot.release();
  }
  sim::Task<void> transfer(std::int64_t bytes, Direction d) {
    sim::Resource& slots = d == Direction::HostToFpga || !spec.link.full_duplex ? h2c : c2h;
    sim::Resource& wire =
        d == Direction::HostToFpga || !spec.link.full_duplex ? own_wire_h2c : own_wire_c2h;
    std::vector<sim::ProcessHandle> pending;
    for (std::int64_t offset = 0; offset < bytes; offset += spec.dma.chunk_bytes) {
      sim::Lease slot = co_await slots.acquire();
      pending.push_back(sim.spawn(
          chunk(wire, offset, std::min(spec.dma.chunk_bytes, bytes - offset), std::move(slot))));
    }
    for (const sim::ProcessHandle& h : pending) co_await h;
  }
  sim::Simulator& sim;
  LinkSpec spec;
  sim::Resource h2c, c2h, own_wire_h2c, own_wire_c2h;
};

/// Completion times of transfers (bytes, direction, start ns) on `Link` (DmaLink or reference).
template <class Link>
std::vector<Time> staggered(const LinkSpec& spec,
                            const std::vector<std::tuple<std::int64_t, Direction, int>>& jobs) {
  sim::Simulator sim;
  Link link(sim, spec);
  std::vector<Time> done(jobs.size(), 0);
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    sim.spawn([](Link& l, sim::Simulator& s, std::int64_t bytes, Direction d, int start_ns,
                 Time& out) -> sim::Process {
      co_await s.delay(sim::ns(start_ns));
      co_await l.transfer(bytes, d);
      out = s.now();
    }(link, sim, std::get<0>(jobs[i]), std::get<1>(jobs[i]), std::get<2>(jobs[i]), done[i]));
  }
  sim.run();
  return done;
}

TEST(LinkContention, BookedScheduleEqualsTheChunkProcessModel) {
  // Transfers of many sizes started at staggered times in both directions contend for slots
  // and wires; DmaLink's booked chunks must finish exactly when chunk processes would.
  std::vector<std::tuple<std::int64_t, Direction, int>> jobs;
  std::uint64_t x = 12345;
  for (int i = 0; i < 40; ++i) {
    x = x * 6364136223846793005ull + 1442695040888963407ull;  // LCG (Knuth MMIX)
    const std::int64_t bytes = static_cast<std::int64_t>((x >> 33) % 70000);
    const Direction d = (x >> 20) % 3 == 0 ? Direction::FpgaToHost : Direction::HostToFpga;
    jobs.emplace_back(bytes, d, static_cast<int>((x >> 40) % 20000));
  }
  LinkSpec half = LinkSpec::axi4();
  half.link.full_duplex = false;
  LinkSpec few_slots = LinkSpec::pcie3_x8();
  few_slots.dma.max_outstanding = 2;
  for (const LinkSpec& spec : {LinkSpec::pcie3_x8(), LinkSpec::axi4(), half, few_slots}) {
    const std::vector<Time> booked = staggered<DmaLink>(spec, jobs);
    const std::vector<Time> reference = staggered<ReferenceLink>(spec, jobs);
    for (std::size_t i = 0; i < jobs.size(); ++i) {
      EXPECT_EQ(booked[i], reference[i]) << spec.link.name << " transfer " << i;
    }
  }
}

}  // namespace
}  // namespace edx::arch
