#pragma once
// A results table declared once (gem5's parameters-as-declarations, applied to tables): its
// columns, each with its SQL type, nullability, unit, one-line doc and the row-struct member it
// maps to, and from that one list come the CREATE TABLE and its upgrade (ALTER TABLE ADD COLUMN),
// INSERTs with binds by column, SELECTs that fill row structs, CSV and the reference
// (docs/RESULTS.md). The tables themselves: arch/results/schema.hpp.
//
// Values between a row struct and SQLite (column()):
//   double        REAL     a value that is not finite is NULL; NULL reads as NaN
//   integer, bool INTEGER  NULL reads as 0 (false)
//   std::string   TEXT     in a nullable column "" is NULL; NULL reads as ""
//   json          TEXT     the JSON text (dump()); NULL reads as JSON null, bad JSON is an error,
//                          and so is JSON of another shape than .json_object() declares
// A column a database lacks (written before that column existed) reads as NULL.
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

namespace SQLite {
class Database;
}

namespace edx::results {

enum class ColumnType { kInteger, kReal, kText };
const char* sql_type(ColumnType type);

/// A column's value as the generic code sees it: NULL, INTEGER, REAL or TEXT.
using Value = std::variant<std::monostate, std::int64_t, double, std::string>;
/// One row's values, in the order of its table's columns.
using ValueRow = std::vector<Value>;

/// What a column is, apart from the row-struct member it maps to.
struct ColumnSpec {
  std::string name;
  ColumnType type = ColumnType::kReal;
  bool not_null = false;
  std::string default_sql;  ///< SQL literal of its default ("0", "''"), empty for none
  std::string unit;         ///< "ms", "J", "" for counts, flags and names
  std::string doc;          ///< one line
  std::string label;        ///< the report's heading (the name when empty)
  int since = 0;            ///< the schema version that added it

  /// "name TYPE [NOT NULL] [DEFAULT x]".
  std::string sql() const;
  /// The report's column heading: label (or name), then the unit in parentheses.
  std::string heading() const;
};

/// Tables of runs (edx simulate --out; keyed by run_id) or of sweeps (edx sweep; by sweep_id).
enum class TableGroup { kRun, kSweep };

/// What a table is: the part of a declaration the generic code needs.
struct TableSpec {
  std::string name;
  TableGroup group = TableGroup::kRun;
  std::string doc;
  std::vector<std::string> primary_key;  ///< empty: rows in insertion order (rowid)
  std::vector<ColumnSpec> columns;
  int since = 0;  ///< the schema version that added it

  /// The index of column `name`; throws std::logic_error for an undeclared one.
  std::size_t index_of(std::string_view name) const;
  /// CREATE TABLE IF NOT EXISTS with every column and the primary key.
  std::string create_sql() const;
  /// INSERT [OR REPLACE] INTO name (every column) VALUES (?, ...).
  std::string insert_sql(bool replace) const;
};

/// One column of a table of Row: its spec and how Row holds it.
template <class Row>
struct Column {
  ColumnSpec spec;
  std::function<Value(const Row&)> get;
  std::function<void(Row&, const Value&)> set;
  /// JSON columns: the shape .json_object() declares, shared with `set` (null: any JSON).
  std::shared_ptr<std::optional<std::vector<std::string>>> json_shape;

  /// A JSON column whose every cell is an object holding each of `keys` as an object: a cell of
  /// another shape reads as a corrupted database (a summary a report would otherwise show as
  /// zeros or "not found").
  Column json_object(std::vector<std::string> keys) && {
    *json_shape = std::move(keys);
    return std::move(*this);
  }
  Column not_null() && {
    spec.not_null = true;
    return std::move(*this);
  }
  /// NOT NULL with a default (`sql`: a SQL literal): rows of older writers, added columns.
  Column not_null_default(std::string sql) && {
    spec.not_null = true;
    spec.default_sql = std::move(sql);
    return std::move(*this);
  }
  Column label(std::string text) && {
    spec.label = std::move(text);
    return std::move(*this);
  }
  Column since(int version) && {
    spec.since = version;
    return std::move(*this);
  }
};

namespace detail {
double real_of(const Value& v);
std::int64_t integer_of(const Value& v);
std::string text_of(const Value& v);
nlohmann::json json_of(const Value& v);
/// Throws unless `json` is an object holding each of `keys` as an object.
void check_json_object(const nlohmann::json& json, const std::vector<std::string>& keys);
}  // namespace detail

/// Column `name` stored in `member` of Row (double, an integer type, bool, std::string or
/// nlohmann::json), nullable unless .not_null().
template <class Row, class T>
Column<Row> column(std::string name, T Row::*member, std::string unit, std::string doc) {
  Column<Row> c;
  c.spec.name = std::move(name);
  c.spec.unit = std::move(unit);
  c.spec.doc = std::move(doc);
  if constexpr (std::is_floating_point_v<T>) {
    c.spec.type = ColumnType::kReal;
    c.get = [member](const Row& r) -> Value {
      const double v = r.*member;
      return std::isfinite(v) ? Value(v) : Value();
    };
    c.set = [member](Row& r, const Value& v) { r.*member = detail::real_of(v); };
  } else if constexpr (std::is_integral_v<T>) {
    c.spec.type = ColumnType::kInteger;
    c.get = [member](const Row& r) -> Value { return static_cast<std::int64_t>(r.*member); };
    c.set = [member](Row& r, const Value& v) {
      if constexpr (std::is_same_v<T, bool>) {
        r.*member = detail::integer_of(v) != 0;
      } else {
        r.*member = static_cast<T>(detail::integer_of(v));
      }
    };
  } else if constexpr (std::is_same_v<T, nlohmann::json>) {
    c.spec.type = ColumnType::kText;
    c.get = [member](const Row& r) -> Value { return (r.*member).dump(); };
    c.json_shape = std::make_shared<std::optional<std::vector<std::string>>>();
    c.set = [member, shape = c.json_shape](Row& r, const Value& v) {
      r.*member = detail::json_of(v);
      if (*shape) detail::check_json_object(r.*member, **shape);
    };
  } else {
    static_assert(std::is_same_v<T, std::string>, "a column holds a number, text or JSON");
    c.spec.type = ColumnType::kText;
    c.get = [member](const Row& r) -> Value { return r.*member; };
    c.set = [member](Row& r, const Value& v) { r.*member = detail::text_of(v); };
  }
  return c;
}

/// A table of Row: its spec and its columns' members.
template <class Row>
struct Table {
  TableSpec spec;
  std::vector<Column<Row>> columns;

  Table(TableSpec table, std::vector<Column<Row>> list)
      : spec(std::move(table)), columns(std::move(list)) {
    for (const Column<Row>& c : columns) spec.columns.push_back(c.spec);
  }

  ValueRow values(const Row& row) const {
    ValueRow out;
    out.reserve(columns.size());
    for (const Column<Row>& c : columns) out.push_back(c.get(row));
    return out;
  }
  /// Fills `row` from `values` (the table's column order; `rowid` names the row in errors): a
  /// cell that does not read (bad JSON, JSON of another shape) is a corrupted database, an
  /// error naming table, column and row as the cell checks of select_values do.
  void fill(Row& row, const ValueRow& values, std::int64_t rowid) const {
    for (std::size_t i = 0; i < columns.size(); ++i) {
      try {
        columns[i].set(row, values.at(i));
      } catch (const std::exception& e) {
        throw std::runtime_error("table " + spec.name + ", column " + columns[i].spec.name +
                                 ", row " + std::to_string(rowid) + ": " + e.what() +
                                 " (a corrupted results database)");
      }
    }
  }
};

// ---- SQLite ------------------------------------------------------------------------------

/// Which rows a SELECT reads: `where` a SQL condition on the table's columns with its `binds`
/// (?1, ?2, ...), in `order_by` (SQL; empty: rowid).
struct Query {
  std::string where;
  std::vector<Value> binds;
  std::string order_by;
};

/// The declared columns the database's table has (a table written before a column was added
/// lacks it); empty when the table is missing.
std::vector<std::string> existing_columns(SQLite::Database& db, std::string_view table);
/// Creates the table when missing and adds the declared columns it lacks (ALTER TABLE ADD
/// COLUMN: an added column is nullable or has a default).
void create_or_upgrade(SQLite::Database& db, const TableSpec& table);

/// Opens a database to read it without leaving anything beside it (issue 45): read-write but
/// never creating it when the file and its folder are writable, so that the last connection's
/// close checkpoints a WAL database and removes its -wal and -shm files, which a read-only
/// connection would leave behind; read-only otherwise. Nothing is written by reading.
std::unique_ptr<SQLite::Database> open_for_reading(const std::filesystem::path& path);
/// Inserts rows of values (each in the table's column order); `replace`: INSERT OR REPLACE.
void insert_values(SQLite::Database& db, const TableSpec& table, const std::vector<ValueRow>& rows,
                   bool replace = false);
/// The rows `query` selects, each in the table's column order, NULL for a column the database's
/// table lacks; `rowids`, when given, receives each row's rowid.
std::vector<ValueRow> select_values(SQLite::Database& db, const TableSpec& table,
                                    const Query& query = {},
                                    std::vector<std::int64_t>* rowids = nullptr);

template <class Row>
void insert_rows(SQLite::Database& db, const Table<Row>& table, const std::vector<Row>& rows,
                 bool replace = false) {
  std::vector<ValueRow> values;
  values.reserve(rows.size());
  for (const Row& r : rows) values.push_back(table.values(r));
  insert_values(db, table.spec, values, replace);
}

template <class Row>
std::vector<Row> select_rows(SQLite::Database& db, const Table<Row>& table,
                             const Query& query = {}) {
  std::vector<std::int64_t> rowids;
  const std::vector<ValueRow> values = select_values(db, table.spec, query, &rowids);
  std::vector<Row> rows(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) table.fill(rows[i], values[i], rowids[i]);
  return rows;
}

// ---- text --------------------------------------------------------------------------------

/// `text` as one CSV field (RFC 4180: quoted when it holds a comma, quote or line break).
std::string csv_field(const std::string& text);
/// `value` as one CSV field: NULL empty, numbers as fmt prints them, text quoted as needed.
std::string csv_value(const Value& value);
/// The table as CSV: a header of its declared columns, then one line per row.
std::string table_csv(const TableSpec& table, const std::vector<ValueRow>& rows);

/// `value` as JSON (NULL as null) and back, as the column's type (a whole REAL is a number).
nlohmann::json value_to_json(const Value& value);
Value value_from_json(const nlohmann::json& value, ColumnType type);

/// The Markdown reference of `table`: a heading, its doc, its key and a row per column.
std::string table_reference(const TableSpec& table);

}  // namespace edx::results
