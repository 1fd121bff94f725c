// A results database of schema version 3 (built from that version's CREATE statements, kept as
// the fixture schema_v3.sql), holding a run and a sweep written then, gets a run from today's
// writer: the file is brought to the current version (offload's spill columns added) and the
// report's reader reads the old rows (the new columns NULL) and the new ones.
#include <SQLiteCpp/SQLiteCpp.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "arch/results/results_db.hpp"
#include "arch/results/schema.hpp"
#include "reports/results_reader.hpp"
#include "tests/support/temp_dir.hpp"

namespace edx::results {
namespace {

std::string fixture_sql() {
  std::ifstream in(std::string(EDX_SOURCE_DIR) + "/tests/arch/results/schema_v3.sql");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// A run of today's writer: one offload row with a spill.
RunRows new_run() {
  RunRows rows;
  const nlohmann::json summary = {{"frames", 1},
                                  {"baseline", nlohmann::json::object()},
                                  {"accelerated", nlohmann::json::object()},
                                  {"comparison", nlohmann::json::object()},
                                  {"resources", nlohmann::json::object()}};
  rows.run = {run_id_of("c2", "t2"),    "c2",   "t2", "new", "t.db", 1, "oracle",
              nlohmann::json::object(), summary};
  rows.frame_rows.push_back({rows.run.run_id, "accelerated", 0, "vio", 1, 2, 3, 1, 1, 0.5});
  rows.offload.push_back({rows.run.run_id, 0, 0, "kalman_gain", 40, 2.0, 1.5, 1.0, 0.25, false,
                          false, true, 0.25, 4096});
  rows.latency.push_back({rows.run.run_id, "accelerated", "all", "e2e", 1, 3, 0, 0, 3, 3, 3, 3});
  return rows;
}

TEST(ResultsUpgrade, AVersion3DatabaseGainsTheNewColumnsAndKeepsItsRows) {
  testing::TempDir dir;
  const std::filesystem::path path = dir.path() / "v3.db";
  {
    SQLite::Database db(path.string(), SQLite::OPEN_READWRITE | SQLite::OPEN_CREATE);
    db.exec(fixture_sql());
    db.exec(
        "INSERT INTO runs VALUES ('c1-t1', 'c1', 't1', 'old', 'o.db', 1, 'regression', '{}', "
        "'{\"frames\": 1, \"baseline\": {}, \"accelerated\": {}, \"comparison\": {}, "
        "\"resources\": {}}');"
        "INSERT INTO frames VALUES ('c1-t1', 'baseline', 0, 'slam', 4, 5, 9, 9, 0, 1.25);"
        "INSERT INTO offload VALUES ('c1-t1', 0, 0, 'projection', 10, 1.0, NULL, 0.5, 0.1, 0, 1, "
        "0);"
        "INSERT INTO sweeps VALUES ('s', 's.yaml', 'b.yaml', 'o.db', 1, "
        "'{\"objectives\": [{\"minimize\": \"e2e_latency_mean\"}]}');"
        "INSERT INTO sweep_points VALUES ('s', 0, 'c1-t1', '{\"backend.gemm_block\": \"2\"}', "
        "'{\"e2e_latency_mean\": 9.0}', 1, 1, '', NULL);");
    EXPECT_EQ(db.execAndGet("PRAGMA user_version").getInt(), 3);
  }
  arch::write_results(path, new_run());
  {
    SQLite::Database db(path.string());
    EXPECT_EQ(db.execAndGet("PRAGMA user_version").getInt(), kSchemaVersion);
    EXPECT_EQ(existing_columns(db, "offload").size(), offload_table().spec.columns.size());
    EXPECT_EQ(db.execAndGet("SELECT COUNT(*) FROM offload WHERE spill_ms IS NULL").getInt(), 1);
  }

  const reports::ResultsData data = reports::read_results(path);
  ASSERT_EQ(data.runs.size(), 2u);
  const reports::RunData& old_run = *data.find("c1-t1");
  EXPECT_EQ(old_run.platform, "old");
  EXPECT_EQ(old_run.summary["frames"], 1);
  ASSERT_EQ(old_run.frame_rows.size(), 1u);
  EXPECT_EQ(old_run.frame_rows[0].energy_j, 1.25);
  ASSERT_EQ(old_run.offload.size(), 1u);
  EXPECT_TRUE(std::isnan(old_run.offload[0].accel_ms));  // NULL: did not fit, then
  EXPECT_TRUE(std::isnan(old_run.offload[0].spill_ms));  // not stored before version 4
  EXPECT_EQ(old_run.offload[0].spill_bytes, 0);
  EXPECT_TRUE(old_run.offload[0].training);

  const reports::RunData& new_one = *data.find(run_id_of("c2", "t2"));
  ASSERT_EQ(new_one.offload.size(), 1u);
  EXPECT_EQ(new_one.offload[0].spill_ms, 0.25);
  EXPECT_EQ(new_one.offload[0].spill_bytes, 4096);
  EXPECT_FALSE(new_one.offload[0].fits_spm);
  ASSERT_EQ(new_one.latency.size(), 1u);
  EXPECT_EQ(new_one.latency[0].mean, 3);

  ASSERT_TRUE(data.has_sweeps);
  ASSERT_EQ(data.sweeps.size(), 1u);
  ASSERT_EQ(data.sweeps[0].points.size(), 1u);
  EXPECT_EQ(data.sweeps[0].points[0].parameters["backend.gemm_block"], "2");
  EXPECT_TRUE(data.sweeps[0].points[0].pareto);
  EXPECT_EQ(data.sweeps[0].objectives.at(0).metric, "e2e_latency_mean");
}

TEST(ResultsUpgrade, ExportedRunRowsImportByColumnName) {
  SQLite::Database db(":memory:", SQLite::OPEN_READWRITE | SQLite::OPEN_CREATE);
  arch::create_results_tables(db);
  const RunRows rows = new_run();
  nlohmann::json exported = arch::export_run_rows(rows);
  // Columns in another order (and one left out) still land in their columns.
  nlohmann::json& offload = exported["tables"]["offload"];
  std::reverse(offload["columns"].begin(), offload["columns"].end());
  std::reverse(offload["rows"][0].begin(), offload["rows"][0].end());
  offload["columns"].erase(0);  // spill_bytes
  offload["rows"][0].erase(0);
  arch::import_run_rows(db, exported);
  EXPECT_EQ(db.execAndGet("SELECT spill_ms FROM offload").getDouble(), 0.25);
  EXPECT_TRUE(db.execAndGet("SELECT spill_bytes FROM offload").isNull());
  EXPECT_EQ(db.execAndGet("SELECT kernel FROM offload").getString(), "kalman_gain");
  EXPECT_EQ(arch::export_run_rows(db, rows.run.run_id)["tables"]["latency"],
            arch::export_run_rows(rows)["tables"]["latency"]);
  exported["tables"]["offload"]["columns"][0] = "nope";
  EXPECT_THROW(arch::import_run_rows(db, exported), std::runtime_error);
  exported["tables"]["nope"] = exported["tables"]["runs"];
  EXPECT_THROW(arch::import_run_rows(db, exported), std::runtime_error);
}

}  // namespace
}  // namespace edx::results
