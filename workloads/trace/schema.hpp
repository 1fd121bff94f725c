#pragma once
// The trace database schema (docs/TRACE.md). Bump kSchemaVersion on any change of tables or
// column meaning; readers refuse other versions.
#include <array>
#include <string_view>

namespace edx::trace {

// 2 (2026-11-25): host_ns columns are CPU time (host_clock.hpp), no longer wall time.
// 3 (2026-11-25): meta host_speed, the tracing machine's reference-suite times (host_speed.hpp).
// 4 (2026-11-28): ops.batch, identical independent instances of one op; op "qr". Version 3
//   traces are read with batch 1 (TraceReader).
// 5 (2026-11-28): meta precision, the arithmetic of the offloadable backend kernels (fp64|fp32).
//   Version 3 and 4 traces computed in double: read with precision fp64 (TraceReader).
inline constexpr int kSchemaVersion = 5;
/// The oldest version the reader still reads (an upgrade in memory; docs/TRACE.md).
inline constexpr int kOldestReadableSchemaVersion = 3;

/// Metadata keys every trace carries (besides schema_version).
inline constexpr std::array<std::string_view, 12> kRequiredMetaKeys{
    "dataset",         "sequence",    "resolution", "camera_model",
    "pipeline_params", "host_cpu",    "host_cores", "compiler_flags",
    "source_revision", "created_utc", "host_speed", "precision"};

/// Table definitions, executed in order on a new database.
inline constexpr std::string_view kSchemaSql = R"sql(
CREATE TABLE meta (
  key   TEXT PRIMARY KEY NOT NULL,
  value TEXT NOT NULL
);
CREATE TABLE frames (
  frame_id         INTEGER PRIMARY KEY NOT NULL,
  timestamp_ns     INTEGER NOT NULL,
  sequence         TEXT NOT NULL,
  scenario         TEXT NOT NULL,
  backend_mode     TEXT NOT NULL,
  gps_available    INTEGER NOT NULL,
  map_available    INTEGER NOT NULL,
  backend_status   TEXT NOT NULL,
  est_tx REAL, est_ty REAL, est_tz REAL, est_qw REAL, est_qx REAL, est_qy REAL, est_qz REAL,
  gt_tx REAL,  gt_ty REAL,  gt_tz REAL,  gt_qw REAL,  gt_qx REAL,  gt_qy REAL,  gt_qz REAL,
  frontend_host_ns INTEGER NOT NULL,
  backend_host_ns  INTEGER NOT NULL
);
CREATE TABLE tasks (
  frame_id     INTEGER NOT NULL REFERENCES frames(frame_id),
  seq          INTEGER NOT NULL,
  task         TEXT NOT NULL,
  image        TEXT NOT NULL,
  host_ns      INTEGER NOT NULL,
  pixels       INTEGER NOT NULL,
  levels       INTEGER NOT NULL,
  candidates   INTEGER NOT NULL,
  keypoints    INTEGER NOT NULL,
  descriptors  INTEGER NOT NULL,
  comparisons  INTEGER NOT NULL,
  windows      INTEGER NOT NULL,
  window_size  INTEGER NOT NULL,
  search_range INTEGER NOT NULL,
  points       INTEGER NOT NULL,
  iterations   INTEGER NOT NULL,
  per_level    TEXT NOT NULL,
  PRIMARY KEY (frame_id, seq)
);
CREATE TABLE kernels (
  frame_id    INTEGER NOT NULL REFERENCES frames(frame_id),
  seq         INTEGER NOT NULL,
  kernel      TEXT NOT NULL,
  host_ns     INTEGER NOT NULL,
  accelerable INTEGER NOT NULL,
  m INTEGER NOT NULL, n INTEGER NOT NULL, k INTEGER NOT NULL,
  detail      TEXT NOT NULL,
  PRIMARY KEY (frame_id, seq)
);
CREATE TABLE ops (
  frame_id   INTEGER NOT NULL,
  kernel_seq INTEGER NOT NULL,
  seq        INTEGER NOT NULL,
  op         TEXT NOT NULL,
  m INTEGER NOT NULL, n INTEGER NOT NULL, k INTEGER NOT NULL,
  flags      INTEGER NOT NULL,
  host_ns    INTEGER NOT NULL,
  batch      INTEGER NOT NULL,
  PRIMARY KEY (frame_id, kernel_seq, seq),
  FOREIGN KEY (frame_id, kernel_seq) REFERENCES kernels(frame_id, seq)
);
)sql";

}  // namespace edx::trace
