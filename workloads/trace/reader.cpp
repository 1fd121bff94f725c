#include "workloads/trace/reader.hpp"

#include <SQLiteCpp/Database.h>
#include <SQLiteCpp/Statement.h>
#include <fmt/core.h>
#include <sqlite3.h>

#include <map>
#include <stdexcept>

#include "workloads/trace/codec.hpp"
#include "workloads/trace/schema.hpp"
#include "workloads/trace/validate.hpp"

namespace edx::trace {
namespace {

constexpr std::array<const char*, 5> kTables{"meta", "frames", "tasks", "kernels", "ops"};

/// Column names and declared types of a table, in order.
std::vector<std::pair<std::string, std::string>> table_layout(SQLite::Database& db,
                                                              const std::string& table) {
  std::vector<std::pair<std::string, std::string>> columns;
  SQLite::Statement query(db, fmt::format("PRAGMA table_info({})", table));
  while (query.executeStep()) {
    columns.emplace_back(query.getColumn(1).getString(), query.getColumn(2).getString());
  }
  return columns;
}

/// A query through SQLite's C API (SQLiteCpp's Column objects share the statement's ownership:
/// a reference count per value read, most of the cost of reading a trace's 70 000 rows).
class Query {
 public:
  Query(SQLite::Database& db, const std::string& sql) : db_(db.getHandle()) {
    const int rc = sqlite3_prepare_v2(db_, sql.c_str(), -1, &statement_, nullptr);
    if (rc != SQLITE_OK) throw SQLite::Exception(db_, rc);
  }
  Query(const Query&) = delete;
  Query& operator=(const Query&) = delete;
  ~Query() { sqlite3_finalize(statement_); }
  /// The next row (false: no more); errors as SQLiteCpp's.
  bool step() {
    const int rc = sqlite3_step(statement_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    throw SQLite::Exception(db_, rc);
  }
  sqlite3_stmt* statement() const { return statement_; }
  std::int64_t int64(int column) const { return sqlite3_column_int64(statement_, column); }
  const char* column_name(int column) const { return sqlite3_column_name(statement_, column); }

 private:
  sqlite3* db_;
  sqlite3_stmt* statement_ = nullptr;
};

/// Typed access to the current row of a query, with error messages naming file, table, row.
/// `where` (a callable giving "file: table row ...") is called only when a check fails: a trace
/// of 70 000 rows formats no text unless it is bad.
template <typename Where>
class Row {
 public:
  Row(const Query& query, Where where)
      : query_(query), statement_(query.statement()), where_(std::move(where)) {}

  // The values are read through SQLite's C API on the statement (SQLiteCpp's Column objects
  // share the statement's ownership: a reference count per value read).
  std::int64_t integer(int column) const {
    if (sqlite3_column_type(statement_, column) != SQLITE_INTEGER) {
      fail(fmt::format("column {} is not an integer", query_.column_name(column)));
    }
    return sqlite3_column_int64(statement_, column);
  }
  std::int64_t count(int column) const {
    const std::int64_t value = integer(column);
    if (value < 0)
      fail(fmt::format("column {} is negative ({})", query_.column_name(column), value));
    return value;
  }
  bool flag(int column) const {
    const std::int64_t value = integer(column);
    if (value != 0 && value != 1) {
      fail(fmt::format("column {} must be 0 or 1, is {}", query_.column_name(column), value));
    }
    return value == 1;
  }
  std::string text(int column) const {
    if (sqlite3_column_type(statement_, column) != SQLITE_TEXT) {
      fail(fmt::format("column {} is not text", query_.column_name(column)));
    }
    const auto* chars = reinterpret_cast<const char*>(sqlite3_column_text(statement_, column));
    return std::string(chars, static_cast<std::size_t>(sqlite3_column_bytes(statement_, column)));
  }
  std::optional<PoseArray> pose(int first) const {
    int nulls = 0;
    PoseArray pose{};
    for (int i = 0; i < 7; ++i) {
      const int type = sqlite3_column_type(statement_, first + i);
      if (type == SQLITE_NULL) {
        ++nulls;
      } else if (type == SQLITE_FLOAT || type == SQLITE_INTEGER) {
        pose[static_cast<std::size_t>(i)] = sqlite3_column_double(statement_, first + i);
      } else {
        fail(fmt::format("column {} is not a number", query_.column_name(first + i)));
      }
    }
    if (nulls == 7) return std::nullopt;
    if (nulls != 0)
      fail(fmt::format("pose starting at column {} is partly NULL", query_.column_name(first)));
    return pose;
  }
  template <typename Parse>
  auto parsed(int column, Parse parse) const {
    const std::string value = text(column);
    try {
      return parse(value);
    } catch (const std::invalid_argument& e) {
      fail(e.what());
    }
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error(fmt::format("{}: {}", where_(), what));
  }

 private:
  const Query& query_;
  sqlite3_stmt* statement_;
  Where where_;
};

}  // namespace

TraceReader::TraceReader(std::filesystem::path path) : path_(std::move(path)) {
  const std::string file = path_.string();
  std::error_code ec;
  if (std::filesystem::is_directory(path_, ec)) {
    throw std::runtime_error(
        fmt::format("{}: is a directory (expected a trace file, written by edx trace)", file));
  }
  if (!std::filesystem::is_regular_file(path_, ec)) {
    throw std::runtime_error(fmt::format("{}: no such trace file", file));
  }
  try {
    SQLite::Database db(file, SQLite::OPEN_READONLY);
    if (!db.tableExists("meta")) {
      throw std::runtime_error(fmt::format("{}: not an edx trace (no meta table)", file));
    }
    SQLite::Statement query(db, "SELECT key, value FROM meta");
    while (query.executeStep()) {
      meta_[query.getColumn(0).getString()] = query.getColumn(1).getString();
    }
    const auto version = meta_.find("schema_version");
    if (version == meta_.end()) {
      throw std::runtime_error(fmt::format("{}: meta lacks schema_version", file));
    }
    for (int v = kOldestReadableSchemaVersion; v <= kSchemaVersion; ++v) {
      if (version->second == std::to_string(v)) schema_version_ = v;
    }
    if (schema_version_ == 0) {
      throw std::runtime_error(
          fmt::format("{}: trace schema version {}, this edx reads versions {} to {}", file,
                      version->second, kOldestReadableSchemaVersion, kSchemaVersion));
    }
    SQLite::Database reference(":memory:", SQLite::OPEN_READWRITE);
    reference.exec(std::string(kSchemaSql));
    // Version 3 had no ops.batch (read as 1).
    if (schema_version_ == 3) reference.exec("ALTER TABLE ops DROP COLUMN batch");
    for (const char* table : kTables) {
      if (table_layout(db, table) != table_layout(reference, table)) {
        throw std::runtime_error(fmt::format("{}: table {} does not match schema version {}", file,
                                             table, schema_version_));
      }
    }
    // Versions 3 and 4 predate meta precision; their backends computed in double.
    if (schema_version_ <= 4) meta_.emplace("precision", to_string(Precision::kFp64));
    for (const auto& key : kRequiredMetaKeys) {
      if (!meta_.contains(std::string(key))) {
        throw std::runtime_error(fmt::format("{}: meta lacks key '{}'", file, key));
      }
    }
    try {
      trace_precision(meta_);
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(fmt::format("{}: meta precision: {}", file, e.what()));
    }
    frame_count_ =
        static_cast<std::size_t>(db.execAndGet("SELECT COUNT(*) FROM frames").getInt64());
    // meta.frames, when the writer recorded it, must match the rows (a truncated trace).
    if (const auto frames = meta_.find("frames"); frames != meta_.end()) {
      if (frames->second != std::to_string(frame_count_)) {
        throw std::runtime_error(
            fmt::format("{}: meta.frames says {} but the trace has {} frame rows", file,
                        frames->second, frame_count_));
      }
    }
  } catch (const SQLite::Exception& e) {
    throw std::runtime_error(fmt::format("{}: cannot read trace: {}", file, e.what()));
  }
}

std::vector<FrameTrace> TraceReader::read_all() const {
  const std::string file = path_.string();
  std::vector<FrameTrace> frames;
  frames.reserve(frame_count_);
  try {
    // A connection of this call alone (no other thread uses it): without SQLite's per-call
    // mutex (OPEN_NOMUTEX), which is most of the cost of reading a value.
    SQLite::Database db(file, SQLite::OPEN_READONLY | SQLite::OPEN_NOMUTEX);
    std::map<std::string, std::int64_t> last_timestamp;  // per sequence

    Query frame_query(db, "SELECT * FROM frames ORDER BY frame_id");
    while (frame_query.step()) {
      const std::int64_t id = frame_query.int64(0);
      const Row row(frame_query, [&] { return fmt::format("{}: frames row {}", file, id); });
      if (id != static_cast<std::int64_t>(frames.size())) {
        row.fail(fmt::format("frame ids must run 0, 1, 2, ...; expected {}", frames.size()));
      }
      FrameTrace trace;
      FrameRecord& f = trace.frame;
      f.frame_id = id;
      f.timestamp_ns = row.integer(1);
      f.sequence = row.text(2);
      f.scenario = row.parsed(3, parse_scenario);
      f.mode = row.parsed(4, parse_backend_mode);
      f.gps_available = row.flag(5);
      f.map_available = row.flag(6);
      f.backend_status = row.text(7);
      f.estimated_pose = row.pose(8);
      f.ground_truth_pose = row.pose(15);
      f.frontend_host_ns = row.count(22);
      f.backend_host_ns = row.count(23);
      auto [previous, inserted] = last_timestamp.try_emplace(f.sequence, f.timestamp_ns);
      if (!inserted) {
        if (f.timestamp_ns <= previous->second) {
          row.fail(fmt::format("timestamp {} not after {} in sequence {}", f.timestamp_ns,
                               previous->second, f.sequence));
        }
        previous->second = f.timestamp_ns;
      }
      frames.push_back(std::move(trace));
    }

    auto frame_of = [&](const auto& row, std::int64_t id) -> FrameTrace& {
      if (id < 0 || id >= static_cast<std::int64_t>(frames.size())) {
        row.fail(fmt::format("refers to missing frame {}", id));
      }
      return frames[static_cast<std::size_t>(id)];
    };

    Query task_query(db, "SELECT * FROM tasks ORDER BY frame_id, seq");
    while (task_query.step()) {
      const std::int64_t id = task_query.int64(0);
      const std::int64_t seq = task_query.int64(1);
      const Row row(task_query,
                    [&] { return fmt::format("{}: tasks row (frame {}, seq {})", file, id, seq); });
      FrameTrace& frame = frame_of(row, id);
      if (seq != static_cast<std::int64_t>(frame.tasks.size())) row.fail("seq not consecutive");
      TaskRecord t;
      t.task = row.parsed(2, parse_task);
      t.image = row.parsed(3, parse_image);
      std::int64_t* counts[] = {&t.host_ns,     &t.pixels,       &t.levels,      &t.candidates,
                                &t.keypoints,   &t.descriptors,  &t.comparisons, &t.windows,
                                &t.window_size, &t.search_range, &t.points,      &t.iterations};
      int column = 4;
      for (std::int64_t* count : counts) *count = row.count(column++);
      t.per_level = row.parsed(column, decode_per_level);
      frame.tasks.push_back(std::move(t));
    }

    Query kernel_query(db, "SELECT * FROM kernels ORDER BY frame_id, seq");
    while (kernel_query.step()) {
      const std::int64_t id = kernel_query.int64(0);
      const std::int64_t seq = kernel_query.int64(1);
      const Row row(kernel_query, [&] {
        return fmt::format("{}: kernels row (frame {}, seq {})", file, id, seq);
      });
      FrameTrace& frame = frame_of(row, id);
      if (seq != static_cast<std::int64_t>(frame.kernels.size())) row.fail("seq not consecutive");
      KernelRecord k;
      k.kernel = row.text(2);
      k.host_ns = row.count(3);
      k.accelerable = row.flag(4);
      k.m = row.count(5);
      k.n = row.count(6);
      k.k = row.count(7);
      k.detail_json = row.text(8);
      frame.kernels.push_back(std::move(k));
    }

    Query op_query(
        db,
        fmt::format("SELECT frame_id, kernel_seq, seq, op, m, n, k, flags, host_ns, {} AS batch "
                    "FROM ops ORDER BY frame_id, kernel_seq, seq",
                    schema_version_ == 3 ? "1" : "batch"));
    while (op_query.step()) {
      const std::int64_t id = op_query.int64(0);
      const std::int64_t kernel_seq = op_query.int64(1);
      const std::int64_t seq = op_query.int64(2);
      const Row row(op_query, [&] {
        return fmt::format("{}: ops row (frame {}, kernel {}, seq {})", file, id, kernel_seq, seq);
      });
      FrameTrace& frame = frame_of(row, id);
      if (kernel_seq < 0 || kernel_seq >= static_cast<std::int64_t>(frame.kernels.size())) {
        row.fail("refers to a missing kernel");
      }
      KernelRecord& kernel = frame.kernels[static_cast<std::size_t>(kernel_seq)];
      if (seq != static_cast<std::int64_t>(kernel.ops.size())) row.fail("seq not consecutive");
      OpRecord op;
      op.op = row.parsed(3, parse_op);
      op.m = row.count(4);
      op.n = row.count(5);
      op.k = row.count(6);
      op.flags = static_cast<std::uint32_t>(row.count(7));
      op.host_ns = row.count(8);
      op.batch = row.count(9);
      kernel.ops.push_back(op);
    }
  } catch (const SQLite::Exception& e) {
    throw std::runtime_error(fmt::format("{}: cannot read trace: {}", file, e.what()));
  }
  const auto resolution = meta_.find("resolution");
  const std::optional<ImageSize> image =
      resolution == meta_.end() ? std::nullopt : parse_image_size(resolution->second);
  for (const FrameTrace& frame : frames) {
    if (image) {
      validate_frame(frame, file, *image);
    } else {
      validate_frame(frame, file);
    }
  }
  return frames;
}

}  // namespace edx::trace
