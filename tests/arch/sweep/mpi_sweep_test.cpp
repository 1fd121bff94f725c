// `edx sweep` over workload points with the real pipeline, end to end: 2 workload points (the
// paper mix, 16 frames at 320x240, two feature budgets) x 3 platform points under
// `mpirun -np 2`, then the same spec in one process on the same trace store giving identical
// rows; and a job whose rank is SIGKILLed, restarted, ending with every point once.
#include <SQLiteCpp/SQLiteCpp.h>
#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/support/run_command.hpp"
#include "tests/support/temp_dir.hpp"

namespace edx::arch {
namespace {

const std::string kEdx = edx::testing::built_binary("edx");

/// mpirun as the tests run it: as root in CI containers, two ranks even on one core.
std::string mpirun(int ranks) {
  return fmt::format(
      "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 {} -np {} --oversubscribe",
      EDX_MPIEXEC, ranks);
}

/// Every row of a table, ordered, as text (runs' trace column names the store, which is shared).
std::string rows(const std::filesystem::path& db, const std::string& query) {
  SQLite::Database d(db.string());
  SQLite::Statement q(d, query);
  std::string text;
  while (q.executeStep()) {
    for (int c = 0; c < q.getColumnCount(); ++c) text += q.getColumn(c).getString() + "|";
    text += "\n";
  }
  return text;
}

struct MpiSweep : ::testing::Test {
  edx::testing::TempDir dir;
  void SetUp() override {
    if (!EDX_HAVE_MPI) GTEST_SKIP() << "edx was built without MPI";
  }
  std::filesystem::path spec(const std::string& name, const std::string& workload_values,
                             const std::string& platform_values) {
    const std::filesystem::path path = dir.path() / (name + ".yaml");
    std::ofstream(path) << fmt::format(
        "base: {}/configs/edx_car.yaml\n"
        "workload: {{mix: paper, frames: 16, resolution: 320x240, features: 150}}\n"
        "parameters:\n  {}\n  {}\n"
        "objectives: [{{minimize: e2e_latency_mean}}, {{maximize: fps}}]\n",
        EDX_SOURCE_DIR, workload_values, platform_values);
    return path;
  }
};

TEST_F(MpiSweep, TwoRanksGiveTheRowsOfOneProcess) {
  const std::filesystem::path s = spec("wl", "workload.features: {values: [100, 200]}",
                                       "backend.units.gemm.block: {values: [1, 2, 4]}");
  const std::filesystem::path store = dir.path() / "store";
  auto r = edx::testing::run_command(fmt::format("{} {} sweep {} --db {} --trace-store {} --json",
                                                 mpirun(2), kEdx, s.string(),
                                                 (dir.path() / "mpi.db").string(), store.string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);  // rank 0 alone prints
  EXPECT_EQ(j["traced"], 2);
  EXPECT_EQ(j["computed"], 6);
  EXPECT_EQ(j["failed"], 0);
  EXPECT_EQ(j["points"].size(), 6u);
  // The same spec in one process, on the traces of the MPI run: nothing traced, same rows.
  r = edx::testing::run_command(fmt::format("{} sweep {} --db {} --trace-store {} --json -j 2",
                                            kEdx, s.string(), (dir.path() / "one.db").string(),
                                            store.string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["traced"], 0);
  for (const std::string query :
       {"SELECT point, run_id, workload, metrics_json, feasible, pareto, error FROM sweep_points "
        "ORDER BY point",
        "SELECT run_id, trace_hash, config_json, summary_json FROM runs ORDER BY run_id",
        "SELECT * FROM latency ORDER BY run_id, variant, mode, stage",
        "SELECT * FROM resources ORDER BY run_id, entry",
        "SELECT workload, workload_json, trace_hash FROM sweep_workloads ORDER BY workload"}) {
    const std::string mpi_rows = rows(dir.path() / "mpi.db", query);
    EXPECT_FALSE(mpi_rows.empty()) << query;
    EXPECT_EQ(mpi_rows, rows(dir.path() / "one.db", query)) << query;
  }
  // Which rank traced what is on record (both ran here: one host).
  EXPECT_EQ(rows(dir.path() / "mpi.db", "SELECT COUNT(*) FROM sweep_workloads WHERE host != ''"),
            "2|\n");
}

TEST_F(MpiSweep, AKilledRankLosesAndDuplicatesNothing) {
  // The larger workload point traces for longer: the worker is killed while it does.
  const std::filesystem::path s = spec("kill", "workload.resolution: {values: [320x240, 640x480]}",
                                       "backend.clock_mhz: {values: [100, 150, 200, 250]}");
  const std::string db = (dir.path() / "k.db").string();
  const std::string sweep = fmt::format("{} {} sweep {} --db {}", mpirun(2), kEdx, s.string(), db);
  // Start the job, wait for the first workload's trace, SIGKILL the last rank (the newest child
  // of mpirun, found in /proc: no procps needed).
  const auto r = edx::testing::run_command(fmt::format(
      "{} & job=$!; for i in $(seq 1 1200); do n=$(sqlite3 {} 'SELECT COUNT(*) FROM "
      "sweep_workloads' 2>/dev/null || echo 0); [ \"${{n:-0}}\" -ge 1 ] && break; sleep 0.05; "
      "done; for s in /proc/[0-9]*/stat; do set -- $(cat $s 2>/dev/null); [ \"$4\" = $job ] && "
      "echo $1; done | sort -n | tail -1 | xargs kill -9; wait $job; echo \"exit $?\"",
      sweep, db));
  EXPECT_THAT(r.out, ::testing::Not(::testing::HasSubstr("exit 0"))) << r.err;
  const int before = std::stoi(rows(db, "SELECT COUNT(*) FROM sweep_points"));
  EXPECT_LT(before, 8);
  // Restarted: every point once, none failed, and the store holds complete traces only.
  const auto again = edx::testing::run_command(sweep + " --json");
  ASSERT_EQ(again.exit_code, 0) << again.err;
  const nlohmann::json j = nlohmann::json::parse(again.out);
  EXPECT_EQ(j["points"].size(), 8u);
  EXPECT_EQ(j["skipped"].get<int>() + j["computed"].get<int>(), 8);
  EXPECT_EQ(j["skipped"], before);
  EXPECT_EQ(rows(db, "SELECT COUNT(*), COUNT(DISTINCT point), COUNT(error) FROM sweep_points"),
            "8|8|0|\n");
  EXPECT_EQ(rows(db, "SELECT COUNT(*) FROM runs"), "8|\n");
  for (const auto& entry : std::filesystem::directory_iterator(dir.path() / "k.traces")) {
    if (entry.path().extension() == ".db") {
      EXPECT_EQ(rows(entry.path(), "SELECT COUNT(*) > 0 FROM frames"), "1|\n") << entry.path();
    }
  }
}

}  // namespace
}  // namespace edx::arch
