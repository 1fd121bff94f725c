// `edx eval` end to end: the built binary on the peer's KITTI files (JSON figures), the text table,
// and the exit codes of a bad command line (2) and of a bad file (1, "file:line:" message).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/support/run_command.hpp"
#include "tests/workloads/eval/eval_test_support.hpp"

namespace {

using edx::testing::built_binary;
using edx::testing::run_command;
using ::testing::HasSubstr;

const std::string kPeerDir =
    std::string(EDX_SHARED_DATA_DIR) + "/trajectory_eval/kitti_odom_eval_09";

std::string peer_command(const std::string& extra) {
  return built_binary("edx") + " eval --gt " + kPeerDir + "/gt_09.txt --est " + kPeerDir +
         "/est_09.txt --format kitti --align sim3 --kitti-odom-eval " + extra;
}

void expect_relative(const nlohmann::json& json, const char* key, double expected) {
  ASSERT_TRUE(json.contains(key)) << key;
  const double actual = json.at(key).get<double>();
  EXPECT_LE(std::abs(actual - expected), 1e-6 * std::abs(expected))
      << key << ": " << actual << " vs " << expected;
}

TEST(EdxEvalCommand, JsonReproducesThePeerFigures) {
  const auto result = run_command(peer_command("--json"));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const nlohmann::json json = nlohmann::json::parse(result.out);
  EXPECT_EQ(json.at("pairs").get<int>(), 1589);
  EXPECT_EQ(json.at("conventions").get<std::string>(), "kitti-odom-eval");
  expect_relative(json, "kitti_t_err_pct", 2.884112511407129);
  expect_relative(json, "kitti_r_err_deg_per_100m", 0.24905618674615418);
  expect_relative(json, "ate_rmse_m", 8.38661922878607);
  expect_relative(json, "rpe_trans_m", 0.34341307706920193);
  expect_relative(json, "rpe_rot_deg", 0.0633886066529585);
  EXPECT_TRUE(result.err.empty()) << result.err;
}

TEST(EdxEvalCommand, TextOutputIsATable) {
  const auto result = run_command(peer_command(""));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_THAT(result.out, HasSubstr("ATE RMSE"));
  EXPECT_THAT(result.out, HasSubstr("8.38662 m"));
  EXPECT_THAT(result.out, HasSubstr("KITTI translational error"));
  EXPECT_THAT(result.out, HasSubstr("2.88411 %"));
}

TEST(EdxEvalCommand, BadArgumentExitsTwo) {
  const auto bad_align = run_command(peer_command("--align 7dof"));
  EXPECT_EQ(bad_align.exit_code, 2);
  EXPECT_THAT(bad_align.err, HasSubstr("--align"));
  const auto missing = run_command(built_binary("edx") + " eval --gt a.txt --format kitti");
  EXPECT_EQ(missing.exit_code, 2);
  const auto wrong_format =
      run_command(built_binary("edx") + " eval --gt " + kPeerDir + "/gt_09.txt --est " + kPeerDir +
                  "/est_09.txt --format tum --align sim3 --kitti-odom-eval");
  EXPECT_EQ(wrong_format.exit_code, 2);
  EXPECT_THAT(wrong_format.err, HasSubstr("--kitti-odom-eval"));
}

TEST(EdxEvalCommand, BadFileExitsOneNamingFileAndLine) {
  edx::eval::testing::ScratchDir dir("cli");
  const std::string est = dir.write("est.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1\n");
  const auto result = run_command(built_binary("edx") + " eval --gt " + kPeerDir +
                                  "/gt_09.txt --est " + est + " --format kitti --align se3");
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_EQ(result.err, "edx: error: " + est + ":2: expected 12 or 13 numbers, got 11\n");
  EXPECT_TRUE(result.out.empty());
}

}  // namespace
