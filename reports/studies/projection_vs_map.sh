#!/usr/bin/env bash
# The paper's Sec. VI-B projection figure for edx's pipeline: projection latency (and its share
# of the registration backend) against the number of points in the current map, per frame, over
# warehouse maps of several sizes. For each map-run length it runs the real chain:
#   edx gen --scenario indoor_known --frames LOC --map-frames N   (map run N frames, loc run LOC)
#   edx trace --backend slam --save-map  (the map)   ·  edx vocab  ·  edx trace --backend registration
# then writes OUT/projection.tsv (map frames, the run's largest M, frame, M, projection ms,
# backend ms) and
# OUT/projection_vs_map.svg (gnuplot). Host times are the tracing machine's (docs/TRACE.md).
#
#   reports/studies/projection_vs_map.sh [--edx BIN] [--out DIR] [--resolution WxH]
#                                        [--loc-frames N] [--map-frames "N1 N2 ..."] [--seed S]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
edx="$root/build/bin/edx"
out="projection_study"
resolution="640x480"
loc_frames=100
map_frames="50 100 200 400"
seed=1
while (($#)); do
  case "$1" in
    --edx) edx="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --resolution) resolution="$2"; shift 2 ;;
    --loc-frames) loc_frames="$2"; shift 2 ;;
    --map-frames) map_frames="$2"; shift 2 ;;
    --seed) seed="$2"; shift 2 ;;
    *) echo "$0: unknown argument '$1' (see the header of this script)" >&2; exit 2 ;;
  esac
done
[[ -x "$edx" ]] || { echo "$0: no edx binary at $edx (build it: ./edx --version)" >&2; exit 1; }
for tool in sqlite3 gnuplot; do
  command -v "$tool" >/dev/null || { echo "$0: needs $tool (./edx installs it)" >&2; exit 1; }
done
mkdir -p "$out"
tsv="$out/projection.tsv"
printf 'map_frames\tlargest_M\tframe\tM\tprojection_ms\tbackend_ms\n' >"$tsv.tmp"
for n in $map_frames; do
  d="$out/map$n"
  echo "== map run of $n frames ($resolution, loc run $loc_frames frames, seed $seed)" >&2
  "$edx" gen --scenario indoor_known --frames "$loc_frames" --map-frames "$n" \
    --resolution "$resolution" --seed "$seed" --out "$d/data" --force >/dev/null
  "$edx" trace --dataset "$d/data/map" --format euroc --backend slam --save-map "$d/map.json" \
    --out "$d/map.db" --force >/dev/null
  "$edx" vocab --datasets "$d/data/map" --out "$d/vocab.bin" --stride 5 >/dev/null
  "$edx" trace --dataset "$d/data/loc" --format euroc --backend registration --map "$d/map.json" \
    --vocab "$d/vocab.bin" --out "$d/loc.db" --force >"$d/loc.txt"
  sqlite3 -readonly -separator $'\t' "$d/loc.db" "
    SELECT $n, (SELECT MAX(k.k) FROM kernels k WHERE k.kernel = 'local_map'), p.frame_id, p.m,
           p.host_ns / 1e6, f.backend_host_ns / 1e6
    FROM kernels p JOIN frames f ON f.frame_id = p.frame_id
    WHERE p.kernel = 'projection' ORDER BY p.frame_id, p.seq" >>"$tsv.tmp"
  grep -E '^(accuracy|backend  )' "$d/loc.txt" | sed "s/^/  map $n: /" >&2 || true
done
mv "$tsv.tmp" "$tsv"
gnuplot <<GP
set terminal svg size 1100,440 dynamic font "sans,12"
set output "$out/projection_vs_map.svg"
set datafile separator "\t"
set key autotitle columnhead top left
set multiplot layout 1,2 title "Registration: projection vs points in the current map ($resolution, seed $seed)"
set xlabel "points projected (M)"
set ylabel "projection host time (ms)"
set grid
plot for [n in "$map_frames"] "$tsv" using (\$1 == n+0 ? \$4 : 1/0):5 every ::1 with points pt 7 ps 0.4 title sprintf("map run %s frames", n)
set ylabel "projection share of the backend (%)"
plot for [n in "$map_frames"] "$tsv" using (\$1 == n+0 ? \$4 : 1/0):(100*\$5/\$6) every ::1 with points pt 7 ps 0.4 title sprintf("map run %s frames", n)
unset multiplot
GP
echo "wrote $tsv and $out/projection_vs_map.svg" >&2
