#!/usr/bin/env bash
# The edx demo: the whole flow of docs/DEMO.md with the edx command, as an architect would type
# it. `./edx demo` builds edx and runs this script; the end-to-end test runs it with --quick.
#
#   demo.sh --edx BIN [--out DIR] [--shared DIR] [--quick] [--jobs N]
#
# Steps: the paper's scenario mix traced at 1280x720 (Edx-Car) and 640x480 (Edx-Drone), traces of
# the real excerpts in shared/data, both platforms simulated against their CPU-only baselines into
# one results database (Edx-Car and its compared baselines also over the car mix's seeds 1-3),
# one example sweep, the algorithm characterization, the HTML report, and the paper check table
# over the three seeds.
# Everything is written under DIR (default ./demo); generated worlds are kept in DIR/data and
# reused by the next run. Exit status: 0 when every step ran (a paper-check miss is a finding, not
# a failure), 1 when a step failed, 2 on a bad argument.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/.." && pwd)"
edx=""
out="$root/demo"
shared="$root/../shared/data"
quick=0
jobs="$(nproc)"

die_usage() {
  printf 'demo: %s (usage: demo.sh --edx BIN [--out DIR] [--shared DIR] [--quick] [--jobs N])\n' \
    "$1" >&2
  exit 2
}

while (($# > 0)); do
  case "$1" in
    --edx) [[ $# -ge 2 ]] || die_usage "--edx needs a value"; edx="$2"; shift 2 ;;
    --out) [[ $# -ge 2 ]] || die_usage "--out needs a value"; out="$2"; shift 2 ;;
    --shared) [[ $# -ge 2 ]] || die_usage "--shared needs a value"; shared="$2"; shift 2 ;;
    --jobs) [[ $# -ge 2 && "$2" =~ ^[1-9][0-9]*$ ]] || die_usage "--jobs needs a positive integer"
      jobs="$2"; shift 2 ;;
    --quick) quick=1; shift ;;
    -h | --help) sed -n '2,13p' "${BASH_SOURCE[0]}"; exit 0 ;;
    *) die_usage "unknown argument '$1'" ;;
  esac
done
[[ -n "$edx" ]] || die_usage "--edx is required"
[[ -x "$edx" ]] || die_usage "--edx '$edx' is not an executable"

# Sizes: the paper's (400 mixed frames at each platform's resolution) or a reduced run for CI.
if ((quick)); then
  mix_frames=80
  car_resolution=480x272
  drone_resolution=320x240
  excerpt_frames=(--frames 24)
  characterization=(--seeds 1 --frames 32 --resolution 376x240)
else
  mix_frames=400
  car_resolution=1280x720
  drone_resolution=640x480
  excerpt_frames=()
  # One seed of 200 frames a run at 640x480: minutes, not the hours of the study's defaults
  # (docs/CHARACTERIZATION.md; docs/results/ holds the full-size runs).
  characterization=(--seeds 1 --frames 200 --resolution 640x480)
fi

traces="$out/traces"
results="$out/results.db"
report="$out/report"
mkdir -p "$traces" "$out/data"
start_s=$SECONDS
step_total=8
step_no=0

step() {
  step_no=$((step_no + 1))
  printf '\n== [%d/%d] %s  (%ds elapsed)\n' "$step_no" "$step_total" "$1" $((SECONDS - start_s)) >&2
}

run() {
  printf '$ edx %s\n' "$*" >&2
  if ! "$edx" "$@"; then
    printf 'demo: step failed: edx %s\n' "$*" >&2
    exit 1
  fi
}

step "the paper's scenario mix at ${car_resolution} (Edx-Car input): generate, trace, mode switch"
# Its worlds go where the seeds' trace store of step 4 keeps its data (STORE/data): seed 1 is this
# same mix, whose worlds and vocabulary step 4 then finds made.
run trace --mix paper --resolution "$car_resolution" --frames "$mix_frames" \
  --data "$traces/seeds/data" --out "$traces/car_mix.db" --force

step "the paper's scenario mix at ${drone_resolution} (Edx-Drone input)"
run trace --mix paper --resolution "$drone_resolution" --frames "$mix_frames" \
  --data "$out/data/drone_mix" --out "$traces/drone_mix.db" --force

step "the real excerpts: EuRoC V1_01 (VIO, drone) and KITTI 01 (SLAM, car)"
euroc="$shared/euroc_v101_micro"
kitti="$shared/kitti_odometry_excerpt/sequences/01"
excerpts=()
if [[ -d "$euroc" ]]; then
  run trace --dataset "$euroc" --format euroc --backend vio --resolution "$drone_resolution" \
    "${excerpt_frames[@]}" --out "$traces/euroc_vio.db" --force
  excerpts+=(euroc_vio)
else
  printf 'demo: %s not found: EuRoC excerpt skipped\n' "$euroc" >&2
fi
if [[ -d "$kitti" ]]; then
  run trace --dataset "$kitti" --format kitti --backend slam --resolution "$car_resolution" \
    "${excerpt_frames[@]}" --out "$traces/kitti_slam.db" --force
  excerpts+=(kitti_slam)
else
  printf 'demo: %s not found: KITTI excerpt skipped\n' "$kitti" >&2
fi

step "simulate Edx-Car and Edx-Drone against their CPU-only baselines"
rm -f "$results" "$results-wal" "$results-shm"
run simulate --config "$root/configs/edx_car.yaml" --trace "$traces/car_mix.db" --out "$results" \
  --timeline "$out/car_system_timeline.json"
run simulate --config "$root/configs/edx_drone.yaml" --trace "$traces/drone_mix.db" \
  --out "$results" --timeline "$out/drone_system_timeline.json"
# The paper's other baselines (configs/baselines/): their runs on the car mix let the report's
# paper check compare Edx-Car with them, as `edx check` below does by itself.
for baseline in "$root"/configs/baselines/*.yaml; do
  run simulate --config "$baseline" --trace "$traces/car_mix.db" --out "$results" \
    --timeline "$out/$(basename "$baseline" .yaml)_system_timeline.json"
done
# The car mix over seeds 1-3 (each seed's workload traced once into a store, reused by the
# check below): the report's summary and paper check give each figure's mean and 95 % interval.
printf 'mix: paper\nframes: %s\nresolution: %s\n' "$mix_frames" "$car_resolution" \
  >"$out/car_mix_workload.yaml"
seeds=(--workload "$out/car_mix_workload.yaml" --seeds 1-3 --trace-store "$traces/seeds")
for config in "$root/configs/edx_car.yaml" "$root"/configs/baselines/*.yaml; do
  run simulate --config "$config" "${seeds[@]}" --out "$results" -j "$jobs"
done
for excerpt in "${excerpts[@]}"; do
  config="$root/configs/edx_car.yaml"
  [[ "$excerpt" == euroc_vio ]] && config="$root/configs/edx_drone.yaml"
  run simulate --config "$config" --trace "$traces/$excerpt.db" --out "$results" \
    --timeline "$out/${excerpt}_system_timeline.json"
done

step "sweep: backend GEMM block size vs latency and DSP on the car mix (sweeps/gemm_block.yaml)"
run sweep "$root/sweeps/gemm_block.yaml" --trace "$traces/car_mix.db" --db "$results" -j "$jobs"
run export "$results" --sweep gemm_block --out "$out/gemm_block.csv"

step "characterization: each backend on each scenario, its error and frame rate (paper Sec. III)"
run characterize "${characterization[@]}" --out "$out/characterization" --data "$out/data" \
  -j "$jobs"

step "report: HTML page with plots"
run report "$results" --out "$report" --trace "$traces/car_mix.db" \
  --characterization "$out/characterization/characterization.json"

step "paper check: Edx-Car on the car mix over seeds 1-3 against the paper's figures (reports/paper_targets.yaml)"
# The seeds' traces of the simulate step: every figure as its mean and 95 % interval, each
# verdict inside, across or outside the tolerance.
printf '$ edx check --config configs/edx_car.yaml --workload %s --seeds 1-3 --trace-store %s --characterization %s -j %s\n' \
  "$out/car_mix_workload.yaml" "$traces/seeds" "$out/characterization/characterization.json" \
  "$jobs" >&2
check_status=0
"$edx" check --config "$root/configs/edx_car.yaml" "${seeds[@]}" \
  --characterization "$out/characterization/characterization.json" -j "$jobs" || check_status=$?
if ((check_status > 1)); then
  printf 'demo: step failed: edx check (exit %d)\n' "$check_status" >&2
  exit 1
fi

printf '\ndemo: done in %ds\n' $((SECONDS - start_s)) >&2
printf 'demo: report   %s\n' "$report/index.html"
printf 'demo: results  %s (CSV of the sweep: %s)\n' "$results" "$out/gemm_block.csv"
printf 'demo: traces   %s\n' "$traces"
printf 'demo: timeline %s (open in https://ui.perfetto.dev)\n' "$out/car_system_timeline.json"
if ((check_status == 1)); then
  printf 'demo: the paper check has misses (table above; docs/MODEL.md discusses them)\n'
fi
