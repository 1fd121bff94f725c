// `edx sweep` and `edx export` end to end: a sweep stopped by --limit and resumed, its JSON and
// CSV, and bad input as one line with exit code 1 (2 for a bad command line).
#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/arch/sweep/sweep_fixture.hpp"
#include "tests/support/run_command.hpp"
#include "tests/support/temp_dir.hpp"

namespace edx::arch {
namespace {

using ::testing::HasSubstr;
using ::testing::StartsWith;

const std::string kEdx = edx::testing::built_binary("edx");

/// In `dir`: the fixture's trace t.db, a platform base.yaml and a spec s.yaml over three GEMM
/// blocks minimizing `objectives` (YAML list items).
void write_block_sweep(const std::filesystem::path& dir, const std::string& objectives) {
  write_sweep_trace(dir / "t.db");
  std::ofstream(dir / "base.yaml")
      << "name: cmd\nbackend: {clock_mhz: 100, spm_bytes: 67108864, units: {gemm: {block: 2}}}\n"
         "scheduler: {policy: always, training_fraction: 0}\n";
  std::ofstream(dir / "s.yaml")
      << "base: base.yaml\ntrace: t.db\nparameters:\n  backend.units.gemm.block: {values: [1, 2, "
         "4]}\nobjectives: ["
      << objectives << "]\n";
}

TEST(SweepCommand, LimitResumeJsonAndCsv) {
  edx::testing::TempDir dir;
  write_block_sweep(dir.path(), "{minimize: e2e_latency_mean}, {minimize: dsp}");
  const std::string db = (dir.path() / "r.db").string();
  const std::string spec = (dir.path() / "s.yaml").string();
  auto r =
      edx::testing::run_command(fmt::format("{} sweep {} --db {} -j 2 --limit 1", kEdx, spec, db));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("3 points (1 simulated, 0 from the database)"));
  EXPECT_THAT(r.out, HasSubstr("stopped by the limit, 2 left"));
  r = edx::testing::run_command(fmt::format("{} sweep {} --db {} --json", kEdx, spec, db));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["computed"], 2);
  EXPECT_EQ(j["skipped"], 1);
  EXPECT_EQ(j["points"].size(), 3u);
  EXPECT_FALSE(j["pareto_front"].empty());
  r = edx::testing::run_command(
      fmt::format("{} export {} --sweep s --out {}/p.csv", kEdx, db, dir.path().string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(
      edx::testing::read_file(dir.path() / "p.csv"),
      StartsWith("point,run_id,backend.units.gemm.block,dsp,e2e_latency_mean,feasible,pareto\n"));
}

TEST(SweepCommand, ConcurrentStartsOnANewDatabaseLoseNothing) {
  // Two sweeps of one spec started at once on a database that does not exist yet, ten times:
  // the database is created once, complete (create_results_database), the process refused by
  // the other's lock never removes it, and every point is stored; no temporary file remains.
  // Two simulate --out of different platforms at once both keep their run.
  edx::testing::TempDir dir;
  write_block_sweep(dir.path(), "{minimize: e2e_latency_mean}");
  std::ofstream(dir.path() / "other.yaml") << "extends: base.yaml\nname: other\n";
  const std::string d = dir.path().string();
  for (int attempt = 0; attempt < 10; ++attempt) {
    const std::string db = fmt::format("{}/r{}.db", d, attempt);
    const std::string one = fmt::format("{} sweep {}/s.yaml --db {} -j 1", kEdx, d, db);
    const auto r = edx::testing::run_command(fmt::format(
        "sh -c '({0} >/dev/null 2>&1; echo $? >{1}/a.rc) & ({0} >/dev/null 2>&1; echo $? "
        ">{1}/b.rc) & wait'",
        one, d));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string a = edx::testing::read_file(dir.path() / "a.rc");
    const std::string b = edx::testing::read_file(dir.path() / "b.rc");
    EXPECT_TRUE(a == "0\n" || b == "0\n") << attempt << ": " << a << b;
    ASSERT_TRUE(std::filesystem::exists(db)) << attempt;
    // The winner (or both, one after the other) stored every point.
    const auto count = edx::testing::run_command(
        fmt::format("{} export {} --sweep s --out {}/p{}.csv", kEdx, db, d, attempt));
    ASSERT_EQ(count.exit_code, 0) << count.err;
    EXPECT_THAT(count.out, HasSubstr("exported   3 rows")) << attempt;

    const std::string runs = fmt::format("{}/s{}.db", d, attempt);
    const std::string simulate = "{} simulate --config {}/{}.yaml --trace {}/t.db --out {}";
    const auto s2 = edx::testing::run_command(
        fmt::format("sh -c '({} >/dev/null 2>&1) & ({} >/dev/null 2>&1) & wait'",
                    fmt::format(fmt::runtime(simulate), kEdx, d, "base", d, runs),
                    fmt::format(fmt::runtime(simulate), kEdx, d, "other", d, runs)));
    ASSERT_EQ(s2.exit_code, 0);
    const auto exported = edx::testing::run_command(
        fmt::format("{} export {} --table runs --out {}/runs{}.csv", kEdx, runs, d, attempt));
    ASSERT_EQ(exported.exit_code, 0) << exported.err;
    EXPECT_THAT(exported.out, HasSubstr("exported   2 rows")) << attempt;
  }
  for (const auto& entry : std::filesystem::directory_iterator(dir.path())) {
    EXPECT_EQ(entry.path().string().find(".tmp-"), std::string::npos) << entry.path();
  }
}

TEST(SweepCommand, BadInputIsOneLine) {
  edx::testing::TempDir dir;
  std::ofstream(dir.path() / "base.yaml") << "name: cmd\n";
  std::ofstream(dir.path() / "s.yaml")
      << "base: base.yaml\nparameters:\n  backend.units.gemm.block: {values: [0]}\n"
         "objectives: [{minimize: dsp}]\n";
  auto r = edx::testing::run_command(fmt::format("{} sweep {}/s.yaml --db {}/r.db", kEdx,
                                                 dir.path().string(), dir.path().string()));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.err,
            fmt::format("edx: error: {}/s.yaml:3: backend.units.gemm.block: expected an integer "
                        "in [1, 256], got '0'\n",
                        dir.path().string()));
  r = edx::testing::run_command(fmt::format("{} export {}/none.db --table runs --out {}/x.csv",
                                            kEdx, dir.path().string(), dir.path().string()));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_THAT(r.err, HasSubstr("no such results database"));
  r = edx::testing::run_command(fmt::format("{} export x.db --out y.csv", kEdx));
  EXPECT_EQ(r.exit_code, 2);
}

}  // namespace
}  // namespace edx::arch
