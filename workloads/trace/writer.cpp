#include "workloads/trace/writer.hpp"

#include <fmt/core.h>
#include <unistd.h>

#include <stdexcept>
#include <system_error>

#include "common/atomic_file.hpp"
#include "workloads/trace/codec.hpp"
#include "workloads/trace/schema.hpp"
#include "workloads/trace/validate.hpp"

namespace edx::trace {
namespace {

constexpr const char* kInsertFrame =
    "INSERT INTO frames VALUES (?,?,?,?,?,?,?,?, ?,?,?,?,?,?,?, ?,?,?,?,?,?,?, ?,?)";
constexpr const char* kInsertTask = "INSERT INTO tasks VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)";
constexpr const char* kInsertKernel = "INSERT INTO kernels VALUES (?,?,?,?,?,?,?,?,?)";
constexpr const char* kInsertOp = "INSERT INTO ops VALUES (?,?,?,?,?,?,?,?,?,?)";

void bind_pose(SQLite::Statement& statement, int first, const std::optional<PoseArray>& pose) {
  for (int i = 0; i < 7; ++i) {
    if (pose) {
      statement.bind(first + i, (*pose)[static_cast<std::size_t>(i)]);
    } else {
      statement.bind(first + i);  // NULL
    }
  }
}

}  // namespace

void TraceWriter::check_output(const std::filesystem::path& path, bool overwrite) {
  namespace fs = std::filesystem;
  if (path.empty()) throw std::runtime_error("no output trace file given");
  // A device, FIFO or directory is never replaced by the rename of finish().
  if (fs::exists(path) && !fs::is_regular_file(path)) {
    throw std::runtime_error(fmt::format(
        "{}: not a regular file (a trace is a SQLite file; give a file path)", path.string()));
  }
  if (fs::exists(path) && !overwrite) {
    throw std::runtime_error(
        fmt::format("{}: output exists (refusing to overwrite; use --force)", path.string()));
  }
  if (path.has_parent_path() && !fs::is_directory(path.parent_path())) {
    throw std::runtime_error(fmt::format(
        "{}: directory {} {}", path.string(), path.parent_path().string(),
        fs::exists(path.parent_path()) ? "is a file, not a directory" : "does not exist"));
  }
}

TraceWriter::TraceWriter(std::filesystem::path path, TraceMeta meta, TraceWriterOptions options)
    : path_(std::move(path)), options_(options) {
  namespace fs = std::filesystem;
  check_output(path_, options_.overwrite);
  for (const auto& key : kRequiredMetaKeys) {
    if (!meta.contains(std::string(key))) {
      throw std::runtime_error(
          fmt::format("{}: trace metadata lacks key '{}'", path_.string(), key));
    }
  }
  temp_path_ = path_;
  temp_path_ += fmt::format(".tmp-{}", ::getpid());
  temp_guard_ = std::make_unique<common::TemporaryFileGuard>(temp_path_);
  fs::remove(temp_path_);
  // A constructor that throws runs no destructor: the temporary is removed here.
  try {
    db_ = std::make_unique<SQLite::Database>(temp_path_.string(),
                                             SQLite::OPEN_READWRITE | SQLite::OPEN_CREATE);
    // The temporary file is discarded on failure, so durability per statement is not needed
    // (finish() flushes the whole file to the disk before the rename).
    db_->exec("PRAGMA journal_mode = OFF; PRAGMA synchronous = OFF; PRAGMA foreign_keys = ON;");
    db_->exec(std::string(kSchemaSql));
    SQLite::Statement insert_meta(*db_, "INSERT INTO meta VALUES (?, ?)");
    meta["schema_version"] = std::to_string(kSchemaVersion);
    for (const auto& [key, value] : meta) {
      insert_meta.bind(1, key);
      insert_meta.bind(2, value);
      insert_meta.exec();
      insert_meta.reset();
    }
    insert_frame_ = std::make_unique<SQLite::Statement>(*db_, kInsertFrame);
    insert_task_ = std::make_unique<SQLite::Statement>(*db_, kInsertTask);
    insert_kernel_ = std::make_unique<SQLite::Statement>(*db_, kInsertKernel);
    insert_op_ = std::make_unique<SQLite::Statement>(*db_, kInsertOp);
  } catch (const SQLite::Exception& e) {
    discard();
    throw write_error(e);
  } catch (...) {
    discard();
    throw;
  }
}

std::runtime_error TraceWriter::write_error(const std::exception& e) const {
  return std::runtime_error(
      fmt::format("{}: cannot write the trace: {}", path_.string(), e.what()));
}

void TraceWriter::discard() noexcept {
  insert_frame_.reset();
  insert_task_.reset();
  insert_kernel_.reset();
  insert_op_.reset();
  db_.reset();
  std::error_code ignored;
  std::filesystem::remove(temp_path_, ignored);
}

TraceWriter::~TraceWriter() {
  if (!finished_) discard();
}

void TraceWriter::append(const FrameTrace& frame) {
  if (finished_) throw std::logic_error("TraceWriter::append after finish");
  if (frame.frame.frame_id != static_cast<std::int64_t>(frames_written_)) {
    throw std::runtime_error(fmt::format("{}: frame id {} out of order (expected {})",
                                         path_.string(), frame.frame.frame_id, frames_written_));
  }
  validate_frame(frame, path_.string());
  try {
    if (!in_transaction_) {
      db_->exec("BEGIN");
      in_transaction_ = true;
    }
    insert_frame(frame);
    ++frames_written_;
    if (frames_written_ % static_cast<std::size_t>(options_.frames_per_transaction) == 0) {
      db_->exec("COMMIT");
      in_transaction_ = false;
    }
  } catch (const SQLite::Exception& e) {
    throw write_error(e);
  }
}

void TraceWriter::insert_frame(const FrameTrace& trace) {
  const FrameRecord& f = trace.frame;
  SQLite::Statement& fs = *insert_frame_;
  fs.bind(1, f.frame_id);
  fs.bind(2, f.timestamp_ns);
  fs.bind(3, f.sequence);
  fs.bind(4, to_string(f.scenario));
  fs.bind(5, to_string(f.mode));
  fs.bind(6, f.gps_available ? 1 : 0);
  fs.bind(7, f.map_available ? 1 : 0);
  fs.bind(8, f.backend_status);
  bind_pose(fs, 9, f.estimated_pose);
  bind_pose(fs, 16, f.ground_truth_pose);
  fs.bind(23, f.frontend_host_ns);
  fs.bind(24, f.backend_host_ns);
  fs.exec();
  fs.reset();

  SQLite::Statement& ts = *insert_task_;
  for (std::size_t seq = 0; seq < trace.tasks.size(); ++seq) {
    const TaskRecord& t = trace.tasks[seq];
    int column = 1;
    ts.bind(column++, f.frame_id);
    ts.bind(column++, static_cast<std::int64_t>(seq));
    ts.bind(column++, to_string(t.task));
    ts.bind(column++, to_string(t.image));
    for (const std::int64_t value :
         {t.host_ns, t.pixels, t.levels, t.candidates, t.keypoints, t.descriptors, t.comparisons,
          t.windows, t.window_size, t.search_range, t.points, t.iterations}) {
      ts.bind(column++, value);
    }
    ts.bind(column++, encode_per_level(t.per_level));
    ts.exec();
    ts.reset();
  }

  SQLite::Statement& ks = *insert_kernel_;
  SQLite::Statement& os = *insert_op_;
  for (std::size_t seq = 0; seq < trace.kernels.size(); ++seq) {
    const KernelRecord& k = trace.kernels[seq];
    ks.bind(1, f.frame_id);
    ks.bind(2, static_cast<std::int64_t>(seq));
    ks.bind(3, k.kernel);
    ks.bind(4, k.host_ns);
    ks.bind(5, k.accelerable ? 1 : 0);
    ks.bind(6, k.m);
    ks.bind(7, k.n);
    ks.bind(8, k.k);
    ks.bind(9, k.detail_json);
    ks.exec();
    ks.reset();
    for (std::size_t op_seq = 0; op_seq < k.ops.size(); ++op_seq) {
      const OpRecord& op = k.ops[op_seq];
      os.bind(1, f.frame_id);
      os.bind(2, static_cast<std::int64_t>(seq));
      os.bind(3, static_cast<std::int64_t>(op_seq));
      os.bind(4, to_string(op.op));
      os.bind(5, op.m);
      os.bind(6, op.n);
      os.bind(7, op.k);
      os.bind(8, static_cast<std::int64_t>(op.flags));
      os.bind(9, op.host_ns);
      os.bind(10, op.batch);
      os.exec();
      os.reset();
    }
  }
}

void TraceWriter::set_meta(const std::string& key, const std::string& value) {
  if (finished_) throw std::logic_error("TraceWriter::set_meta after finish");
  try {
    SQLite::Statement update(*db_, "INSERT OR REPLACE INTO meta VALUES (?, ?)");
    update.bind(1, key);
    update.bind(2, value);
    update.exec();
  } catch (const SQLite::Exception& e) {
    throw write_error(e);
  }
}

void TraceWriter::finish() {
  if (finished_) return;
  try {
    if (in_transaction_) {
      db_->exec("COMMIT");
      in_transaction_ = false;
    }
  } catch (const SQLite::Exception& e) {
    throw write_error(e);
  }
  insert_frame_.reset();
  insert_task_.reset();
  insert_kernel_.reset();
  insert_op_.reset();
  db_.reset();
  // On the disk before it has its name: a power cut never leaves a partial trace under it.
  common::sync_file(temp_path_, path_);
  std::error_code error;
  std::filesystem::rename(temp_path_, path_, error);
  if (error) {
    throw std::runtime_error(fmt::format("{}: cannot rename the finished trace into place ({})",
                                         path_.string(), error.message()));
  }
  finished_ = true;
}

}  // namespace edx::trace
