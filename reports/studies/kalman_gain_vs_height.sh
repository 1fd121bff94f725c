#!/usr/bin/env bash
# The paper's Sec. VI-B Kalman-gain figure for edx's pipeline: per VIO frame, the Kalman gain's
# host time against the height of the frame's stacked H (the rows of all its features after the
# null-space projection; docs/VIO.md "The Kalman gain on the stacked H"), and per call, the
# time against the group's height. Straight from a trace's SQLite tables (docs/TRACE.md):
#   per frame: rows = sum of the frame's kalman_gain m, time = sum of their host_ns
# Writes OUT/kalman_gain_frames.tsv (frame, stacked rows, gains, Kalman-gain ms, backend ms),
# OUT/kalman_gain_calls.tsv (frame, m, n, ms) and OUT/kalman_gain_vs_height.svg (gnuplot), and
# prints the per-frame R² of time against rows. Host times are the tracing machine's.
#
#   reports/studies/kalman_gain_vs_height.sh TRACE.db [--out DIR]
set -euo pipefail
usage="usage: $0 TRACE.db [--out DIR]"
[[ $# -ge 1 ]] || { echo "$usage" >&2; exit 2; }
trace="$1"
shift
out="kalman_gain_study"
while (($#)); do
  case "$1" in
    --out) out="$2"; shift 2 ;;
    *) echo "$0: unknown argument '$1' ($usage)" >&2; exit 2 ;;
  esac
done
[[ -f "$trace" ]] || { echo "$0: $trace: no such trace" >&2; exit 1; }
for tool in sqlite3 gnuplot; do
  command -v "$tool" >/dev/null || { echo "$0: needs $tool (./edx installs it)" >&2; exit 1; }
done
calls=$(sqlite3 -readonly "$trace" "SELECT COUNT(*) FROM kernels WHERE kernel = 'kalman_gain'" \
  2>/dev/null) || { echo "$0: $trace: not an edx trace (no kernels table)" >&2; exit 1; }
[[ "$calls" -gt 0 ]] || { echo "$0: $trace: no kalman_gain kernels (no VIO frames)" >&2; exit 1; }
mkdir -p "$out"
frames="$out/kalman_gain_frames.tsv"
printf 'frame\tstacked_rows\tgains\tkalman_gain_ms\tbackend_ms\n' >"$frames.tmp"
sqlite3 -readonly -separator $'\t' "$trace" "
  SELECT k.frame_id, SUM(k.m), COUNT(*), SUM(k.host_ns) / 1e6, f.backend_host_ns / 1e6
  FROM kernels k JOIN frames f ON f.frame_id = k.frame_id
  WHERE k.kernel = 'kalman_gain' GROUP BY k.frame_id ORDER BY k.frame_id" >>"$frames.tmp"
mv "$frames.tmp" "$frames"
per_call="$out/kalman_gain_calls.tsv"
printf 'frame\tm\tn\tms\n' >"$per_call.tmp"
sqlite3 -readonly -separator $'\t' "$trace" "
  SELECT frame_id, m, n, host_ns / 1e6 FROM kernels WHERE kernel = 'kalman_gain'
  ORDER BY frame_id, seq" >>"$per_call.tmp"
mv "$per_call.tmp" "$per_call"
# R² of the per-frame time against the stacked rows (squared Pearson correlation).
awk -F'\t' 'NR > 1 { n++; x += $2; y += $4; xx += $2 * $2; yy += $4 * $4; xy += $2 * $4 }
  END { sxy = xy - x * y / n; sxx = xx - x * x / n; syy = yy - y * y / n;
        printf "%d frames, %d calls: stacked rows per frame %.0f on average; R^2 of the frame'"'"'s Kalman-gain time against them %.3f\n",
               n, '"$calls"', x / n, (sxx > 0 && syy > 0) ? sxy * sxy / (sxx * syy) : 0 }' "$frames"
gnuplot <<GP
set terminal svg size 1100,440 dynamic font "sans,12"
set output "$out/kalman_gain_vs_height.svg"
set datafile separator "\t"
set multiplot layout 1,2 title "VIO: Kalman gain vs the height of H ($(basename "$trace"))"
set grid
set key off
set xlabel "stacked rows of the frame's H"
set ylabel "Kalman gain host time a frame (ms)"
plot "$frames" using 2:4 every ::1 with points pt 7 ps 0.4
set xlabel "rows of one Kalman gain's H"
set ylabel "host time a call (ms)"
plot "$per_call" using 2:4 every ::1 with points pt 7 ps 0.3
unset multiplot
GP
echo "wrote $frames, $per_call and $out/kalman_gain_vs_height.svg" >&2
