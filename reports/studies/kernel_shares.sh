#!/usr/bin/env bash
# Backend kernel shares of a trace, per backend mode (the paper's Fig. 7-9 breakdowns and the
# sizes of its Sec. VI-B figure), straight from the trace's SQLite tables (docs/TRACE.md):
#   share(kernel, mode) = sum of the kernel's host_ns / sum of backend_host_ns, over the mode's frames
# and, for each accelerable kernel, its invocations, sizes (m, n) and host ms (min / mean / p50 /
# p99 / max, invocations under 1 ms).
#
#   reports/studies/kernel_shares.sh TRACE.db [--all]    # --all: every kernel, not only the top 6
set -euo pipefail
if (($# < 1)) || [[ ! -f "$1" ]]; then
  echo "usage: $0 TRACE.db [--all]  (TRACE.db: an edx trace; got '${1:-}')" >&2
  exit 2
fi
trace="$1"
limit=6
[[ "${2:-}" == "--all" ]] && limit=1000
command -v sqlite3 >/dev/null || { echo "$0: needs the sqlite3 command (apt-get install sqlite3)" >&2; exit 1; }
if ! sqlite3 -readonly "$trace" "SELECT 1 FROM kernels LIMIT 1" >/dev/null 2>&1; then
  echo "$trace: not an edx trace (no kernels table)" >&2
  exit 1
fi

sqlite3 -readonly -header -column "$trace" <<SQL
.print '== backend time per mode (host ms a frame)'
SELECT backend_mode AS mode, COUNT(*) AS frames,
       ROUND(AVG(backend_host_ns) / 1e6, 3) AS backend_ms,
       ROUND(AVG(frontend_host_ns) / 1e6, 3) AS frontend_ms
FROM frames GROUP BY backend_mode ORDER BY backend_mode;
.print ''
.print '== kernel shares of each mode''s backend time'
WITH mode_total AS (
  SELECT backend_mode, SUM(backend_host_ns) AS ns, COUNT(*) AS frames FROM frames GROUP BY backend_mode),
per_kernel AS (
  SELECT f.backend_mode AS mode, k.kernel, k.accelerable, SUM(k.host_ns) AS ns
  FROM kernels k JOIN frames f ON f.frame_id = k.frame_id GROUP BY f.backend_mode, k.kernel),
ranked AS (
  SELECT p.*, ROW_NUMBER() OVER (PARTITION BY p.mode ORDER BY p.ns DESC) AS rank FROM per_kernel p)
SELECT r.mode, r.kernel, CASE r.accelerable WHEN 1 THEN 'yes' ELSE '' END AS accel,
       ROUND(r.ns / 1e6 / t.frames, 3) AS ms_per_frame,
       ROUND(100.0 * r.ns / t.ns, 1) AS share_pct
FROM ranked r JOIN mode_total t ON t.backend_mode = r.mode
WHERE r.rank <= $limit OR r.accelerable = 1
ORDER BY r.mode, r.ns DESC;
.print ''
.print '== accelerable kernels: sizes and host ms per invocation'
WITH inv AS (
  SELECT f.backend_mode AS mode, k.kernel, k.m, k.n, k.host_ns / 1e6 AS ms,
         ROW_NUMBER() OVER (PARTITION BY f.backend_mode, k.kernel ORDER BY k.host_ns) AS i,
         COUNT(*) OVER (PARTITION BY f.backend_mode, k.kernel) AS c
  FROM kernels k JOIN frames f ON f.frame_id = k.frame_id WHERE k.accelerable = 1)
SELECT mode, kernel, MAX(c) AS calls, MIN(m) || '..' || MAX(m) AS m_range,
       ROUND(AVG(m), 1) AS m_mean, MIN(n) || '..' || MAX(n) AS n_range,
       ROUND(MIN(ms), 3) AS min_ms, ROUND(AVG(ms), 3) AS mean_ms,
       ROUND(MAX(CASE WHEN i = (c + 1) / 2 THEN ms END), 3) AS p50_ms,
       ROUND(MAX(CASE WHEN i = MAX(1, CAST(0.99 * c + 0.999999 AS INTEGER)) THEN ms END), 3) AS p99_ms,
       ROUND(MAX(ms), 3) AS max_ms, SUM(ms < 1.0) AS under_1ms
FROM inv GROUP BY mode, kernel ORDER BY mode, kernel;
SQL
