// The frontend's task graph on the host's cores (arch/host/frontend_graph.hpp): the stages and
// chains of the traced pipeline's task rows, their times, and the list-scheduled latency by hand.
#include "arch/host/frontend_graph.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

namespace edx::arch {
namespace {

using trace::Image;
using trace::Task;

trace::TaskRecord row(Task task, Image image) {
  trace::TaskRecord r;
  r.task = task;
  r.image = image;
  return r;
}

/// The pipeline's rows in trace order (workloads/frontend/stereo_frontend.cpp).
std::vector<trace::TaskRecord> rows() {
  return {row(Task::FD, Image::Left),  row(Task::IF, Image::Left),  row(Task::FD, Image::Right),
          row(Task::IF, Image::Right), row(Task::DC, Image::Left),  row(Task::LSS, Image::Left),
          row(Task::FC, Image::Left),  row(Task::FC, Image::Right), row(Task::MO, Image::Stereo),
          row(Task::DR, Image::Stereo)};
}

TEST(FrontendGraph, StagesAndChainsFollowThePipeline) {
  const HostFrontendGraph g = frontend_graph(rows());
  const std::size_t rest = HostFrontendGraph::kRest;
  using Stages = std::vector<std::vector<std::vector<std::size_t>>>;
  EXPECT_EQ(g.stages, (Stages{{{4, 5}, {0, 1}, {2, 3}}, {{6}, {7}}, {{8, 9, rest}}}));
}

TEST(FrontendGraph, ChainTimesAndLatencyByHand) {
  // FD L 10, IF L 2, FD R 9, IF R 2, DC 3, LSS 12, FC L 5, FC R 4, MO 1, DR 1; rest 0.5.
  const std::vector<double> ms = {10, 2, 9, 2, 3, 12, 5, 4, 1, 1};
  const auto chains = chain_times(rows(), ms, 0.5);
  EXPECT_EQ(chains, (StageChains{{{15}, {12}, {11}}, {{5}, {4}}, {{2.5}}}));
  EXPECT_DOUBLE_EQ(frontend_latency_ms(chains, 1), 49.5);  // every task and the rest
  // Two cores: stage 1 15 | 12 then 11 -> 23; stage 2 5; stage 3 2.5.
  EXPECT_DOUBLE_EQ(frontend_latency_ms(chains, 2), 23 + 5 + 2.5);
  EXPECT_DOUBLE_EQ(frontend_latency_ms(chains, 4), 15 + 5 + 2.5);
  EXPECT_THROW(frontend_latency_ms(chains, 0), std::invalid_argument);
  EXPECT_THROW(chain_times(rows(), {1, 2}, 0), std::invalid_argument);
}

TEST(FrontendGraph, TheCoprocessorsRowsRunOneAtATime) {
  // The same rows; FD, IF, DC, LSS and DR on the device (its times as given). Stage 1: every
  // chain on the device, 15 + 12 + 11 = 38 ms one after another; stage 2 on the cores, 5 ms on
  // two; stage 3: MO 1 and the rest 0.5 on a core, DR 1 on the device, 2.5 ms.
  const std::vector<double> ms = {10, 2, 9, 2, 3, 12, 5, 4, 1, 1};
  const std::vector<bool> device = {true, true, true, true, true, true, false, false, false, true};
  const StageChains chains = chain_times(rows(), ms, 0.5, device);
  EXPECT_EQ(chains, (StageChains{{{0, 15}, {0, 12}, {0, 11}}, {{5}, {4}}, {{1.5, 1}}}));
  EXPECT_DOUBLE_EQ(frontend_latency_ms(chains, 4), 38 + 5 + 2.5);
  EXPECT_DOUBLE_EQ(frontend_latency_ms(chains, 1), 38 + 9 + 2.5);
  EXPECT_THROW(chain_times(rows(), ms, 0.5, {true}), std::invalid_argument);
}

TEST(FrontendGraph, AnUnknownTaskJoinsTheLastStage) {
  std::vector<trace::TaskRecord> r = {row(Task::FD, Image::Left), row(Task::MO, Image::Stereo)};
  const HostFrontendGraph g = frontend_graph(r);
  EXPECT_EQ(g.stages[2][0].front(), 1u);
  EXPECT_EQ(g.stages[0][1], (std::vector<std::size_t>{0}));
  EXPECT_TRUE(g.stages[0][0].empty());  // no tracking rows: an empty chain of 0 ms
}

}  // namespace
}  // namespace edx::arch
