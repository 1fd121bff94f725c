// The machinery of a declared results table (arch/results/table.hpp) on a small table of its
// own: the SQL it generates, a row written and read back (NULLs, JSON, a column an older table
// lacks), CSV and the reference.
#include <SQLiteCpp/SQLiteCpp.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>

#include "arch/results/schema.hpp"
#include "arch/results/table.hpp"

namespace edx::results {
namespace {

using ::testing::HasSubstr;

struct Sample {
  std::string id;
  std::int64_t count = 0;
  double ms = 0;
  bool ok = false;
  std::string note;
  nlohmann::json extra;
};

const Table<Sample>& sample_table() {
  TableSpec spec;
  spec.name = "samples";
  spec.doc = "Samples.";
  spec.primary_key = {"id"};
  static const Table<Sample> table(
      spec, {column("id", &Sample::id, "", "its name").not_null(),
             column("count", &Sample::count, "", "how many").not_null_default("0"),
             column("ms", &Sample::ms, "ms", "a time").label("time"),
             column("ok", &Sample::ok, "", "a flag"), column("note", &Sample::note, "", "a note"),
             column("extra", &Sample::extra, "", "some JSON").since(2)});
  return table;
}

SQLite::Database memory() {
  return SQLite::Database(":memory:", SQLite::OPEN_READWRITE | SQLite::OPEN_CREATE);
}

TEST(ResultsTable, GeneratesItsSql) {
  const TableSpec& t = sample_table().spec;
  EXPECT_EQ(t.create_sql(),
            "CREATE TABLE IF NOT EXISTS samples (id TEXT NOT NULL, count INTEGER NOT NULL DEFAULT "
            "0, ms REAL, ok INTEGER, note TEXT, extra TEXT, PRIMARY KEY (id))");
  EXPECT_EQ(t.insert_sql(false),
            "INSERT INTO samples (id, count, ms, ok, note, extra) VALUES (?, ?, ?, ?, ?, ?)");
  EXPECT_EQ(t.insert_sql(true).substr(0, 30), "INSERT OR REPLACE INTO samples");
  EXPECT_EQ(t.columns[t.index_of("ms")].heading(), "time (ms)");
  EXPECT_EQ(t.columns[t.index_of("count")].heading(), "count");
  EXPECT_THROW(t.index_of("nope"), std::logic_error);
}

TEST(ResultsTable, ARowRoundTripsWithNullsAndJson) {
  SQLite::Database db = memory();
  create_or_upgrade(db, sample_table().spec);
  Sample full{"a", 3, 1.5, true, "x, \"y\"", {{"k", 1}}};
  Sample empty{"b", 0, std::numeric_limits<double>::infinity(), false, "", nullptr};
  insert_rows(db, sample_table(), {full, empty});
  // Not finite is NULL, "" in a nullable text column is NULL.
  EXPECT_EQ(
      db.execAndGet("SELECT COUNT(*) FROM samples WHERE ms IS NULL AND note IS NULL").getInt(), 1);
  const std::vector<Sample> back = select_rows(db, sample_table(), {"", {}, "id"});
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[0].id, "a");
  EXPECT_EQ(back[0].count, 3);
  EXPECT_EQ(back[0].ms, 1.5);
  EXPECT_TRUE(back[0].ok);
  EXPECT_EQ(back[0].note, "x, \"y\"");
  EXPECT_EQ(back[0].extra, (nlohmann::json{{"k", 1}}));
  EXPECT_TRUE(std::isnan(back[1].ms));
  EXPECT_EQ(back[1].note, "");
  const auto b = select_rows(db, sample_table(), {"id = ?1", {std::string("b")}, ""});
  ASSERT_EQ(b.size(), 1u);
  EXPECT_FALSE(b[0].ok);
  // Replacing by primary key.
  full.count = 4;
  insert_rows(db, sample_table(), {full}, true);
  EXPECT_EQ(db.execAndGet("SELECT count FROM samples WHERE id = 'a'").getInt(), 4);
  EXPECT_THROW(insert_rows(db, sample_table(), {full}), SQLite::Exception);
}

TEST(ResultsTable, AnOlderTableGainsItsNewColumnsAndReadsThemAsNull) {
  SQLite::Database db = memory();
  db.exec(
      "CREATE TABLE samples (id TEXT NOT NULL, count INTEGER NOT NULL DEFAULT 0, ms REAL, "
      "ok INTEGER, note TEXT, PRIMARY KEY (id))");
  db.exec("INSERT INTO samples VALUES ('old', 1, 2.0, 1, 'n')");
  const std::vector<Sample> before = select_rows(db, sample_table());
  ASSERT_EQ(before.size(), 1u);
  EXPECT_TRUE(before[0].extra.is_null());  // the column is missing: NULL
  EXPECT_EQ(existing_columns(db, "samples").size(), 5u);
  create_or_upgrade(db, sample_table().spec);
  EXPECT_EQ(existing_columns(db, "samples").size(), 6u);
  insert_rows(db, sample_table(), {{"new", 2, 3.0, false, "", {1, 2}}});
  const std::vector<Sample> after = select_rows(db, sample_table(), {"", {}, "id"});
  ASSERT_EQ(after.size(), 2u);
  EXPECT_EQ(after[0].id, "new");
  EXPECT_EQ(after[0].extra, (nlohmann::json{1, 2}));
  EXPECT_TRUE(after[1].extra.is_null());
}

TEST(ResultsTable, BadJsonIsAnErrorNamingTheColumn) {
  SQLite::Database db = memory();
  create_or_upgrade(db, sample_table().spec);
  db.exec("INSERT INTO samples (id, extra) VALUES ('x', '{oops')");
  try {
    select_rows(db, sample_table());
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("table samples, column extra, row 1: not JSON"));
  }
}

/// A JSON column declared .json_object(keys) reads only objects holding those keys as objects;
/// any other shape is an error naming table, column and row.
TEST(ResultsTable, JsonOfAnotherShapeIsAnErrorNamingTableColumnAndRow) {
  struct Shaped {
    std::string id;
    nlohmann::json summary;
  };
  TableSpec spec;
  spec.name = "shaped";
  spec.doc = "Shaped.";
  static const Table<Shaped> table(
      spec, {column("id", &Shaped::id, "", "its name").not_null(),
             column("summary", &Shaped::summary, "", "JSON").json_object({"a", "b"})});
  const auto error_of = [](const std::string& json) -> std::string {
    SQLite::Database db = memory();
    create_or_upgrade(db, table.spec);
    SQLite::Statement insert(db, "INSERT INTO shaped (id, summary) VALUES ('x', ?1)");
    insert.bind(1, json);
    insert.exec();
    try {
      const std::vector<Shaped> rows = select_rows(db, table);
      EXPECT_EQ(rows.size(), 1u);
      EXPECT_EQ(rows[0].summary["b"]["n"], 2);
      return "";
    } catch (const std::runtime_error& e) {
      return e.what();
    }
  };
  EXPECT_EQ(error_of(R"({"a": {}, "b": {"n": 2}, "c": 3})"), "");
  const std::string prefix =
      "table shaped, column summary, row 1: expected a JSON object holding "
      "the objects a, b, got ";
  const std::string suffix = " (a corrupted results database)";
  EXPECT_EQ(error_of("[1, 2]"), prefix + "JSON array" + suffix);
  EXPECT_EQ(error_of(R"("text")"), prefix + "JSON string" + suffix);
  EXPECT_EQ(error_of(R"({"a": {}})"), prefix + "no 'b'" + suffix);
  EXPECT_EQ(error_of(R"({"a": {}, "b": 5})"), prefix + "JSON number under 'b'" + suffix);
}

TEST(ResultsTable, ACorruptedCellIsAnErrorNamingTableColumnAndRow) {
  // Cells no writer stores (each in its own row after a good one): text or a blob in a number
  // column, a fraction in an integer column, inf (writers store a non-finite value as NULL).
  const auto error_of = [](const std::string& values) {
    SQLite::Database db = memory();
    create_or_upgrade(db, sample_table().spec);
    db.exec("INSERT INTO samples (id, count, ms) VALUES ('good', 1, 2.5)");
    db.exec("INSERT INTO samples (id, count, ms) VALUES " + values);
    try {
      select_rows(db, sample_table());
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(error_of("('x', 1, 'fast')"),
            "table samples, column ms, row 2: expected a finite number, got text 'fast' (a "
            "corrupted results database)");
  EXPECT_EQ(error_of("('x', 1, 9e999)"),
            "table samples, column ms, row 2: expected a finite number, got inf (a corrupted "
            "results database)");
  EXPECT_EQ(error_of("('x', 1, x'00ff')"),
            "table samples, column ms, row 2: expected a finite number, got a blob of 2 bytes (a "
            "corrupted results database)");
  EXPECT_EQ(error_of("('x', 2.5, 1)"),
            "table samples, column count, row 2: expected an integer, got 2.5 (a corrupted "
            "results database)");
  EXPECT_EQ(error_of("(x'00', 1, 1)"),
            "table samples, column id, row 2: expected text, got a blob of 1 bytes (a corrupted "
            "results database)");
  // What writers store reads: an integer in a real column, NULL anywhere nullable.
  EXPECT_EQ(error_of("('x', 1, 3)"), "no error");
  EXPECT_EQ(error_of("('x', 1, NULL)"), "no error");
}

TEST(ResultsTable, CsvHasTheDeclaredHeaderAndQuotes) {
  const std::vector<ValueRow> rows{{std::string("a,b"), std::int64_t{2}, 0.25, std::int64_t{1},
                                    std::string("say \"hi\""), std::monostate{}},
                                   {std::string("line\nbreak"), std::int64_t{0}, std::monostate{},
                                    std::monostate{}, std::monostate{}, std::string("{}")}};
  EXPECT_EQ(table_csv(sample_table().spec, rows),
            "id,count,ms,ok,note,extra\n"
            "\"a,b\",2,0.25,1,\"say \"\"hi\"\"\",\n"
            "\"line\nbreak\",0,,,,{}\n");
}

TEST(ResultsTable, ValuesRoundTripThroughJsonByColumnType) {
  EXPECT_EQ(value_from_json(value_to_json(Value(2.0)), ColumnType::kReal), Value(2.0));
  EXPECT_EQ(value_from_json(nlohmann::json(3), ColumnType::kReal), Value(3.0));
  EXPECT_EQ(value_from_json(value_to_json(Value(std::int64_t{7})), ColumnType::kInteger),
            Value(std::int64_t{7}));
  EXPECT_EQ(value_from_json(nullptr, ColumnType::kText), Value());
  EXPECT_THROW(value_from_json("x", ColumnType::kInteger), std::runtime_error);
}

TEST(ResultsTable, ReferenceListsEveryColumn) {
  const std::string md = table_reference(sample_table().spec);
  EXPECT_THAT(md, HasSubstr("### `samples`"));
  EXPECT_THAT(md, HasSubstr("Primary key (id)."));
  EXPECT_THAT(md, HasSubstr("| `count` | INTEGER NOT NULL DEFAULT 0 |  | how many |"));
  EXPECT_THAT(md, HasSubstr("| `extra` | TEXT |  | some JSON (since version 2) |"));
}

TEST(ResultsSchema, EveryTableIsDeclaredOnceWithItsKeyColumns) {
  std::set<std::string> names;
  for (const TableSpec* t : all_tables()) {
    EXPECT_TRUE(names.insert(t->name).second) << t->name;
    for (const std::string& k : t->primary_key) EXPECT_NO_THROW(t->index_of(k)) << t->name;
    const std::string key = t->group == TableGroup::kRun ? "run_id" : "sweep_id";
    EXPECT_EQ(t->columns.front().name, key) << t->name;
    // A column added after its table is nullable or has a default (ALTER TABLE ADD COLUMN).
    for (const ColumnSpec& c : t->columns) {
      if (c.since > t->since) {
        EXPECT_TRUE(!c.not_null || !c.default_sql.empty()) << c.name;
      }
    }
  }
  EXPECT_EQ(tables_of(TableGroup::kRun).front()->name, "runs");
  EXPECT_EQ(find_table("offload")->columns.back().name, "spill_bytes");
  EXPECT_EQ(find_table("nope"), nullptr);
}

}  // namespace
}  // namespace edx::results
