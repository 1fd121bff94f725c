-- The results database of schema version 3 (2026-11-26), as edx wrote it before the tables were
-- declared once (arch/results/schema.hpp of that version): the fixture of the upgrade test.
CREATE TABLE IF NOT EXISTS runs (run_id TEXT PRIMARY KEY, config_hash TEXT NOT NULL,
  trace_hash TEXT NOT NULL, platform TEXT NOT NULL, trace TEXT NOT NULL, frames INTEGER NOT NULL,
  policy TEXT NOT NULL, config_json TEXT NOT NULL, summary_json TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS frames (run_id TEXT NOT NULL, variant TEXT NOT NULL,
  frame_id INTEGER NOT NULL, mode TEXT NOT NULL, frontend_ms REAL, backend_ms REAL, e2e_ms REAL,
  host_busy_ms REAL, offloaded INTEGER, energy_j REAL, PRIMARY KEY (run_id, variant, frame_id));
CREATE TABLE IF NOT EXISTS latency (run_id TEXT NOT NULL, variant TEXT NOT NULL,
  mode TEXT NOT NULL, stage TEXT NOT NULL, count INTEGER, mean REAL, sd REAL, rsd REAL, p50 REAL,
  p90 REAL, p99 REAL, max REAL, PRIMARY KEY (run_id, variant, mode, stage));
CREATE TABLE IF NOT EXISTS throughput (run_id TEXT NOT NULL, variant TEXT NOT NULL,
  fps_without_pipelining REAL, fps_with_pipelining REAL, PRIMARY KEY (run_id, variant));
CREATE TABLE IF NOT EXISTS energy (run_id TEXT NOT NULL, variant TEXT NOT NULL,
  mode TEXT NOT NULL, mean_j REAL, sd_j REAL, p99_j REAL, max_j REAL,
  PRIMARY KEY (run_id, variant, mode));
CREATE TABLE IF NOT EXISTS offload (run_id TEXT NOT NULL, frame_id INTEGER NOT NULL,
  kernel_seq INTEGER NOT NULL, kernel TEXT NOT NULL, size REAL, host_ms REAL, accel_ms REAL,
  compute_ms REAL, transfer_ms REAL, fits_spm INTEGER, training INTEGER, offloaded INTEGER,
  PRIMARY KEY (run_id, frame_id, kernel_seq));
CREATE TABLE IF NOT EXISTS schedule (run_id TEXT NOT NULL, kernel TEXT NOT NULL,
  invocations INTEGER, offloaded INTEGER, host_only_s REAL, always_s REAL, policy_s REAL,
  oracle_s REAL, r_squared_train REAL, r_squared_eval REAL, gap_to_oracle REAL,
  PRIMARY KEY (run_id, kernel));
CREATE TABLE IF NOT EXISTS resources (run_id TEXT NOT NULL, entry TEXT NOT NULL,
  grp TEXT NOT NULL, kind TEXT NOT NULL, lut REAL, ff REAL, dsp REAL, bram REAL, ns_lut REAL,
  ns_ff REAL, ns_dsp REAL, ns_bram REAL);
CREATE TABLE IF NOT EXISTS timelines (run_id TEXT PRIMARY KEY, first_frame INTEGER NOT NULL,
  frames INTEGER NOT NULL, json TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS sweeps (sweep_id TEXT PRIMARY KEY, spec TEXT NOT NULL,
  base TEXT NOT NULL, trace TEXT NOT NULL, points INTEGER NOT NULL, spec_json TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS sweep_points (sweep_id TEXT NOT NULL, point INTEGER NOT NULL,
  run_id TEXT NOT NULL, parameters_json TEXT NOT NULL, metrics_json TEXT NOT NULL,
  feasible INTEGER NOT NULL, pareto INTEGER NOT NULL DEFAULT 0, workload TEXT NOT NULL DEFAULT '',
  error TEXT, PRIMARY KEY (sweep_id, point));
CREATE TABLE IF NOT EXISTS sweep_locks (sweep_id TEXT PRIMARY KEY, pid INTEGER NOT NULL,
  host TEXT NOT NULL, started TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS sweep_generations (sweep_id TEXT NOT NULL, generation INTEGER NOT NULL,
  evaluations INTEGER NOT NULL, front_size INTEGER NOT NULL, hypervolume REAL NOT NULL,
  PRIMARY KEY (sweep_id, generation));
CREATE TABLE IF NOT EXISTS sweep_workloads (sweep_id TEXT NOT NULL, workload TEXT NOT NULL,
  workload_json TEXT NOT NULL, trace TEXT NOT NULL, trace_hash TEXT NOT NULL, error TEXT,
  seconds REAL, host TEXT, PRIMARY KEY (sweep_id, workload));
PRAGMA user_version = 3;
