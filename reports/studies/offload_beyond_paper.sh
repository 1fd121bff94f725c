#!/usr/bin/env bash
# What offloading kernels beyond the paper's three does on a platform (issue 40): the platform as
# it is, then with SLAM's Schur complement, VIO's covariance update, both, and both with a second
# GEMM array, each simulated on one trace into one results database; prints per variant and mode
# the accelerated backend and end-to-end latency (mean, SD), throughput, the new kernels'
# offloaded invocations, and the resources.
#
#   reports/studies/offload_beyond_paper.sh TRACE.db [--config configs/edx_car.yaml]
#       [--policy regression] --out DIR
#
# DIR gets the variants' platform files (each `extends:` the config) and results.db.
set -euo pipefail
usage() {
  echo "usage: $0 TRACE.db [--config CONFIG.yaml] [--policy POLICY] --out DIR" >&2
  exit 2
}
(($# >= 1)) || usage
trace="$1"
shift
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
config="$root/configs/edx_car.yaml"
policy=regression
out=""
while (($#)); do
  case "$1" in
    --config) config="$2"; shift 2 ;;
    --policy) policy="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    *) usage ;;
  esac
done
[[ -n "$out" && -f "$trace" && -f "$config" ]] || usage
command -v sqlite3 >/dev/null || { echo "$0: needs the sqlite3 command" >&2; exit 1; }
edx="${EDX:-$root/build/bin/edx}"
[[ -x "$edx" ]] || { echo "$0: no edx at $edx (build it: ./edx --version)" >&2; exit 1; }
mkdir -p "$out"
config="$(cd "$(dirname "$config")" && pwd)/$(basename "$config")"
paper="projection, kalman_gain, marginalization"

variant() {  # name, offload list, extra backend YAML
  cat >"$out/$1.yaml" <<YAML
extends: $config
name: $1
scheduler:
  policy: $policy
  offload: [$2]
${3:-}
YAML
  "$edx" simulate --config "$out/$1.yaml" --trace "$trace" --out "$out/results.db" >/dev/null
}
variant paper "$paper"
variant schur "$paper, schur_complement"
variant covariance "$paper, covariance_update"
variant both "$paper, schur_complement, covariance_update"
variant both_2gemm "$paper, schur_complement, covariance_update" \
  "backend:
  units:
    gemm: {count: 2}"

sqlite3 -readonly -header -column "$out/results.db" <<SQL
.print '== accelerated latency per mode (ms): backend mean / SD, end to end mean / SD'
SELECT r.platform AS variant, b.mode,
       ROUND(b.mean, 3) AS be_mean, ROUND(b.sd, 3) AS be_sd,
       ROUND(e.mean, 3) AS e2e_mean, ROUND(e.sd, 3) AS e2e_sd
FROM runs r
JOIN latency b ON b.run_id = r.run_id AND b.variant = 'accelerated' AND b.stage = 'backend'
JOIN latency e ON e.run_id = r.run_id AND e.variant = 'accelerated' AND e.stage = 'e2e'
               AND e.mode = b.mode
ORDER BY b.mode, r.rowid;
.print ''
.print '== throughput (FPS) and energy a frame (J)'
SELECT r.platform AS variant, ROUND(t.fps_without_pipelining, 2) AS fps,
       ROUND(t.fps_with_pipelining, 2) AS fps_pipelined, ROUND(en.mean_j, 4) AS energy_j
FROM runs r
JOIN throughput t ON t.run_id = r.run_id AND t.variant = 'accelerated'
JOIN energy en ON en.run_id = r.run_id AND en.variant = 'accelerated' AND en.mode = 'all'
ORDER BY r.rowid;
.print ''
.print '== offloaded invocations per kernel (evaluation frames), and what they cost on the units'
SELECT r.platform AS variant, o.kernel, COUNT(*) AS invocations, SUM(o.offloaded) AS offloaded,
       ROUND(AVG(o.host_ms), 3) AS host_ms, ROUND(AVG(o.compute_ms), 3) AS units_ms,
       ROUND(AVG(o.transfer_ms), 3) AS transfer_ms, SUM(1 - o.fits_spm) AS spilling
FROM runs r JOIN offload o ON o.run_id = r.run_id
WHERE o.training = 0
GROUP BY r.run_id, o.kernel ORDER BY r.rowid, o.kernel;
.print ''
.print '== resources (total, shared and N.S.)'
SELECT r.platform AS variant, ROUND(x.lut) AS lut, ROUND(x.ff) AS ff, ROUND(x.dsp) AS dsp,
       ROUND(x.bram, 1) AS bram36, ROUND(x.ns_lut) AS ns_lut, ROUND(x.ns_dsp) AS ns_dsp
FROM runs r JOIN resources x ON x.run_id = r.run_id AND x.entry = 'total'
ORDER BY r.rowid;
SQL
