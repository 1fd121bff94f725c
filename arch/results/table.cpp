#include "arch/results/table.hpp"

#include <SQLiteCpp/SQLiteCpp.h>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <sqlite3.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>

namespace edx::results {

const char* sql_type(ColumnType type) {
  switch (type) {
    case ColumnType::kInteger:
      return "INTEGER";
    case ColumnType::kReal:
      return "REAL";
    case ColumnType::kText:
      return "TEXT";
  }
  return "TEXT";
}

std::string ColumnSpec::sql() const {
  std::string s = name + " " + sql_type(type);
  if (not_null) s += " NOT NULL";
  if (!default_sql.empty()) s += " DEFAULT " + default_sql;
  return s;
}

std::string ColumnSpec::heading() const {
  const std::string& text = label.empty() ? name : label;
  return unit.empty() ? text : fmt::format("{} ({})", text, unit);
}

std::size_t TableSpec::index_of(std::string_view column) const {
  for (std::size_t i = 0; i < columns.size(); ++i) {
    if (columns[i].name == column) return i;
  }
  throw std::logic_error(fmt::format("results table {}: no column '{}'", name, column));
}

std::string TableSpec::create_sql() const {
  std::vector<std::string> parts;
  for (const ColumnSpec& c : columns) parts.push_back(c.sql());
  if (!primary_key.empty()) {
    parts.push_back(fmt::format("PRIMARY KEY ({})", fmt::join(primary_key, ", ")));
  }
  return fmt::format("CREATE TABLE IF NOT EXISTS {} ({})", name, fmt::join(parts, ", "));
}

std::string TableSpec::insert_sql(bool replace) const {
  std::vector<std::string> names;
  for (const ColumnSpec& c : columns) names.push_back(c.name);
  std::string marks;
  for (std::size_t i = 0; i < columns.size(); ++i) marks += i ? ", ?" : "?";
  return fmt::format("INSERT {}INTO {} ({}) VALUES ({})", replace ? "OR REPLACE " : "", name,
                     fmt::join(names, ", "), marks);
}

namespace detail {

double real_of(const Value& v) {
  if (const double* d = std::get_if<double>(&v)) return *d;
  if (const std::int64_t* i = std::get_if<std::int64_t>(&v)) return static_cast<double>(*i);
  return std::numeric_limits<double>::quiet_NaN();
}

std::int64_t integer_of(const Value& v) {
  if (const std::int64_t* i = std::get_if<std::int64_t>(&v)) return *i;
  if (const double* d = std::get_if<double>(&v)) return static_cast<std::int64_t>(*d);
  return 0;
}

std::string text_of(const Value& v) {
  if (const std::string* s = std::get_if<std::string>(&v)) return *s;
  return {};
}

nlohmann::json json_of(const Value& v) {
  const std::string* text = std::get_if<std::string>(&v);
  if (!text) return nullptr;
  try {
    return nlohmann::json::parse(*text);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(fmt::format("not JSON ({})", e.what()));
  }
}

void check_json_object(const nlohmann::json& json, const std::vector<std::string>& keys) {
  const auto expected = [&] {
    return keys.empty()
               ? std::string("a JSON object")
               : fmt::format("a JSON object holding the objects {}", fmt::join(keys, ", "));
  };
  if (!json.is_object()) {
    throw std::runtime_error(fmt::format("expected {}, got JSON {}", expected(), json.type_name()));
  }
  for (const std::string& key : keys) {
    if (!json.contains(key) || !json[key].is_object()) {
      throw std::runtime_error(fmt::format(
          "expected {}, got {} '{}'", expected(),
          json.contains(key) ? fmt::format("JSON {} under", json[key].type_name()) : "no", key));
    }
  }
}

}  // namespace detail

namespace {

/// Binds `value` to parameter `index`; "" in a nullable TEXT column is NULL.
void bind_value(SQLite::Statement& s, int index, const Value& value, const ColumnSpec* column) {
  std::visit(
      [&](const auto& v) {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, std::monostate>) {
          s.bind(index);
        } else if constexpr (std::is_same_v<T, std::string>) {
          if (v.empty() && column && !column->not_null) {
            s.bind(index);
          } else {
            s.bind(index, v);
          }
        } else {
          s.bind(index, v);
        }
      },
      value);
}

/// A stored cell as a Value of its column's type. A cell of another kind than any writer stores
/// (text or a blob in a number column, a fraction in an integer one, a non-finite real: writers
/// store those as NULL) is a corrupted database: an error naming table, column and row.
Value read(const SQLite::Column& c, const ColumnSpec& column, const std::string& table,
           std::int64_t rowid) {
  const int kind = c.getType();
  if (kind == SQLITE_NULL) return {};
  const auto refuse = [&](const char* expected) {
    std::string got;
    if (kind == SQLITE_TEXT) {
      const std::string text = c.getString();
      got = fmt::format("text '{}'", text.size() > 40 ? text.substr(0, 40) + "..." : text);
    } else if (kind == SQLITE_BLOB) {
      got = fmt::format("a blob of {} bytes", c.getBytes());
    } else {
      got = fmt::format("{}", kind == SQLITE_INTEGER ? double(c.getInt64()) : c.getDouble());
    }
    return std::runtime_error(
        fmt::format("table {}, column {}, row {}: expected {}, got {} (a "
                    "corrupted results database)",
                    table, column.name, rowid, expected, got));
  };
  switch (column.type) {
    case ColumnType::kInteger:
      if (kind != SQLITE_INTEGER) throw refuse("an integer");
      return c.getInt64();
    case ColumnType::kReal:
      if (kind == SQLITE_INTEGER) return static_cast<double>(c.getInt64());
      if (kind != SQLITE_FLOAT || !std::isfinite(c.getDouble())) throw refuse("a finite number");
      return c.getDouble();
    case ColumnType::kText:
      if (kind == SQLITE_BLOB) throw refuse("text");
      return c.getString();
  }
  return {};
}

}  // namespace

std::vector<std::string> existing_columns(SQLite::Database& db, std::string_view table) {
  std::vector<std::string> names;
  SQLite::Statement info(db, fmt::format("PRAGMA table_info(\"{}\")", table));
  while (info.executeStep()) names.push_back(info.getColumn(1).getString());
  return names;
}

void create_or_upgrade(SQLite::Database& db, const TableSpec& table) {
  db.exec(table.create_sql());
  const std::vector<std::string> have = existing_columns(db, table.name);
  for (const ColumnSpec& c : table.columns) {
    if (std::find(have.begin(), have.end(), c.name) != have.end()) continue;
    if (c.not_null && c.default_sql.empty()) {
      throw std::logic_error(
          fmt::format("results table {}: column {} was added NOT NULL without "
                      "a default",
                      table.name, c.name));
    }
    db.exec(fmt::format("ALTER TABLE {} ADD COLUMN {}", table.name, c.sql()));
  }
}

void insert_values(SQLite::Database& db, const TableSpec& table, const std::vector<ValueRow>& rows,
                   bool replace) {
  if (rows.empty()) return;
  SQLite::Statement s(db, table.insert_sql(replace));
  for (const ValueRow& row : rows) {
    if (row.size() != table.columns.size()) {
      throw std::runtime_error(fmt::format("{}: a row of {} values, the table has {} columns",
                                           table.name, row.size(), table.columns.size()));
    }
    for (std::size_t i = 0; i < row.size(); ++i) {
      bind_value(s, static_cast<int>(i) + 1, row[i], &table.columns[i]);
    }
    s.exec();
    s.reset();
  }
}

std::vector<ValueRow> select_values(SQLite::Database& db, const TableSpec& table,
                                    const Query& query, std::vector<std::int64_t>* rowids) {
  const std::vector<std::string> have = existing_columns(db, table.name);
  std::vector<std::string> selected;  // the declared columns the table has
  std::vector<int> position;          // per declared column: its index in the SELECT, or -1
  for (const ColumnSpec& c : table.columns) {
    const bool present = std::find(have.begin(), have.end(), c.name) != have.end();
    position.push_back(present ? static_cast<int>(selected.size()) : -1);
    if (present) selected.push_back(c.name);
  }
  std::vector<ValueRow> rows;
  if (selected.empty()) return rows;
  SQLite::Statement q(
      db, fmt::format("SELECT {}, rowid FROM {}{}{} ORDER BY {}", fmt::join(selected, ", "),
                      table.name, query.where.empty() ? "" : " WHERE ", query.where,
                      query.order_by.empty() ? "rowid" : query.order_by));
  for (std::size_t i = 0; i < query.binds.size(); ++i) {
    bind_value(q, static_cast<int>(i) + 1, query.binds[i], nullptr);
  }
  while (q.executeStep()) {
    ValueRow row(table.columns.size());
    const std::int64_t rowid = q.getColumn(static_cast<int>(selected.size())).getInt64();
    if (rowids) rowids->push_back(rowid);
    for (std::size_t i = 0; i < table.columns.size(); ++i) {
      if (position[i] >= 0) {
        row[i] = read(q.getColumn(position[i]), table.columns[i], table.name, rowid);
      }
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string q = "\"";
  for (char c : text) {
    q.push_back(c);
    if (c == '"') q.push_back('"');
  }
  q.push_back('"');
  return q;
}

std::string csv_value(const Value& value) {
  return std::visit(
      [](const auto& v) -> std::string {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, std::monostate>) {
          return "";
        } else if constexpr (std::is_same_v<T, std::string>) {
          return csv_field(v);
        } else {
          return fmt::format("{}", v);
        }
      },
      value);
}

std::string table_csv(const TableSpec& table, const std::vector<ValueRow>& rows) {
  std::string csv;
  const auto line = [&csv](const std::vector<std::string>& fields) {
    fmt::format_to(std::back_inserter(csv), "{}\n", fmt::join(fields, ","));
  };
  std::vector<std::string> fields;
  for (const ColumnSpec& c : table.columns) fields.push_back(csv_field(c.name));
  line(fields);
  for (const ValueRow& row : rows) {
    fields.clear();
    for (const Value& v : row) fields.push_back(csv_value(v));
    line(fields);
  }
  return csv;
}

nlohmann::json value_to_json(const Value& value) {
  return std::visit(
      [](const auto& v) -> nlohmann::json {
        if constexpr (std::is_same_v<std::decay_t<decltype(v)>, std::monostate>) {
          return nullptr;
        } else {
          return v;
        }
      },
      value);
}

Value value_from_json(const nlohmann::json& value, ColumnType type) {
  if (value.is_null()) return {};
  if (type == ColumnType::kText && value.is_string()) return value.get<std::string>();
  if (type == ColumnType::kInteger && value.is_number_integer()) return value.get<std::int64_t>();
  if (type == ColumnType::kReal && value.is_number()) return value.get<double>();
  throw std::runtime_error(
      fmt::format("expected {}, got {}", sql_type(type), value.dump().substr(0, 40)));
}

std::string table_reference(const TableSpec& table) {
  std::string md = fmt::format("### `{}`\n\n{}", table.name, table.doc);
  if (table.since > 0) md += fmt::format(" (since version {})", table.since);
  md += table.primary_key.empty()
            ? " No primary key: rows in the order written.\n\n"
            : fmt::format(" Primary key ({}).\n\n", fmt::join(table.primary_key, ", "));
  md += "| column | type | unit | description |\n|---|---|---|---|\n";
  for (const ColumnSpec& c : table.columns) {
    std::string type = sql_type(c.type);
    if (c.not_null) type += " NOT NULL";
    if (!c.default_sql.empty()) type += " DEFAULT " + c.default_sql;
    std::string doc = c.doc;
    if (c.since > table.since) doc += fmt::format(" (since version {})", c.since);
    md += fmt::format("| `{}` | {} | {} | {} |\n", c.name, type, c.unit, doc);
  }
  return md;
}

std::unique_ptr<SQLite::Database> open_for_reading(const std::filesystem::path& path) {
  const std::filesystem::path folder =
      path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
  const bool writable =
      ::access(path.c_str(), W_OK) == 0 && ::access(folder.c_str(), W_OK | X_OK) == 0;
  return std::make_unique<SQLite::Database>(
      path.string(), writable ? SQLite::OPEN_READWRITE : SQLite::OPEN_READONLY);
}

}  // namespace edx::results
