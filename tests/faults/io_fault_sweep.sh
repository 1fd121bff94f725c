#!/usr/bin/env bash
# The I/O-fault sweep (issue 45, point 6; docs/RELIABILITY.md, "I/O faults"), in the manner of
# SQLite's I/O-error tests: each command that writes runs once without faults under the
# io_faults preload library (tests/faults/io_faults.cpp), which counts the bytes, syncs and
# renames of the files under the run's output folder, then again with a write failing after N
# bytes (N spread over that count), with the K-th fsync failing and with the K-th rename or link
# failing, ENOSPC and EIO in turn. Every faulted run must
#   (a) exit non-zero, by exit (no signal, no timeout),
#   (b) print one line on stderr besides warnings and progress, `edx: error: ...`, naming the
#       output,
#       and nothing of a crash or sanitizer,
#   (c) lose nothing committed: an existing results database passes PRAGMA integrity_check and
#       holds its earlier runs, row for row; nothing is left under a new target's name and no
#       temporary file beside it (only SQLite's own -journal/-wal of an existing database,
#       which hold what its next opening needs),
#   (d) be followed by a re-run without faults that exits 0 and gives what a clean run gives.
# A point whose fault never fired (the run wrote less than N) must just succeed.
#
# Usage: tests/faults/io_fault_sweep.sh [--quick | --full] [--edx BIN] [--preload LIB]
#          [--mpiexec MPIRUN] [--only CMD[,CMD...]] [--work DIR] [--keep] [--summary FILE]
#   --quick   a handful of points per command (ctest: IoFaults.QuickSweep, well under a minute)
#   --full    about 40 write points per command plus every fsync and rename (the figures of
#             docs/RELIABILITY.md)
#   Commands: trace simulate_new simulate_existing sweep sweep_mpi report export.
#   Exit 0 when every run passed; 1 when one failed (each failure is printed); 2 on bad usage.
set -u -o pipefail

here=$(cd "$(dirname "$0")" && pwd)
source_dir=$(cd "$here/../.." && pwd)
mode=quick
edx="$source_dir/build/bin/edx"
preload="$source_dir/build/tests/faults/edx_io_faults.so"
mpiexec=""
only=""
work=""
keep=0
summary=""
data="$source_dir/../shared/data"
while [ $# -gt 0 ]; do
  case "$1" in
    --quick) mode=quick ;;
    --full) mode=full ;;
    --edx) edx=$2; shift ;;
    --preload) preload=$2; shift ;;
    --mpiexec) mpiexec=$2; shift ;;
    --only) only=$2; shift ;;
    --work) work=$2; shift ;;
    --keep) keep=1 ;;
    --summary) summary=$2; shift ;;
    --data) data=$2; shift ;;
    *) echo "io_fault_sweep.sh: unknown argument '$1' (see the header of $0)" >&2; exit 2 ;;
  esac
  shift
done
for f in "$edx" "$preload"; do
  [ -f "$f" ] || { echo "io_fault_sweep.sh: $f: not found (build edx and edx_io_faults)" >&2; exit 2; }
done
edx=$(realpath "$edx")  # mpirun and the runs' folders need it absolute
preload=$(realpath "$preload")
command -v sqlite3 >/dev/null || { echo "io_fault_sweep.sh: sqlite3 not found" >&2; exit 2; }
if [ -z "$work" ]; then work=$(mktemp -d /tmp/edx-io-faults.XXXXXX); fi
mkdir -p "$work"
work=$(cd "$work" && pwd)
[ $keep = 1 ] || trap 'rm -rf "$work"' EXIT

golden="$source_dir/tests/data/golden/golden_mix.db"
car="$source_dir/configs/edx_car.yaml"
drone="$source_dir/configs/edx_drone.yaml"
euroc="$data/euroc_v101_micro"
mpirun_prefix=""
if [ -n "$mpiexec" ]; then
  mpirun_prefix="env OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 $mpiexec -np 2 --oversubscribe"
fi

# ---- the commands: set-up of the output folder O, the command, its target, its digest ----------

# Fixtures made once, without the preload: a results database with the golden trace's Edx-Car
# run, and a sweep spec over the golden trace.
fixtures="$work/fixtures"
mkdir -p "$fixtures"
"$edx" simulate --config "$car" --trace "$golden" --out "$fixtures/r.db" >/dev/null 2>"$fixtures/err" ||
  { echo "io_fault_sweep.sh: the fixture simulate failed: $(cat "$fixtures/err")" >&2; exit 1; }
cat >"$fixtures/s.yaml" <<EOF
base: $car
trace: $golden
parameters:
  backend.units.gemm.block: {values: [2, 4, 8]}
objectives: [{minimize: e2e_latency_mean}]
EOF

setup() {  # setup CMD O: the inputs of CMD in its output folder O
  case "$1" in
    simulate_existing | report | export) cp "$fixtures/r.db" "$2/r.db" ;;
    sweep | sweep_mpi) cp "$fixtures/s.yaml" "$2/s.yaml" ;;
  esac
}

command_of() {  # command_of CMD O: the command line
  local o=$2
  case "$1" in
    trace) echo "$edx trace --dataset $euroc --format euroc --frames 2 --out $o/t.db" ;;
    simulate_new) echo "$edx simulate --config $car --trace $golden --out $o/r.db" ;;
    simulate_existing) echo "$edx simulate --config $drone --trace $golden --out $o/r.db" ;;
    sweep) echo "$edx sweep $o/s.yaml --db $o/s.db -j 1" ;;
    sweep_mpi) echo "$mpirun_prefix $edx sweep $o/s.yaml --db $o/s.db" ;;
    report) echo "$edx report $o/r.db --out $o/report" ;;
    export) echo "$edx export $o/r.db --table latency --out $o/latency.csv" ;;
  esac
}

target_of() {  # target_of CMD O: the output an error must name
  case "$1" in
    trace) echo "$2/t.db" ;;
    simulate_new | simulate_existing) echo "$2/r.db" ;;
    sweep | sweep_mpi) echo "$2/s.db" ;;
    report) echo "$2/report" ;;
    export) echo "$2/latency.csv" ;;
  esac
}

# Entries a failed run may leave changed or new in O (anything else is a finding): an existing
# database being written and SQLite's journal or WAL beside it (hot: needed by its next opening);
# a sweep's database once its first point was stored (it is kept and resumed).
allowed_after_failure() {
  case "$1" in
    simulate_existing) echo '^r\.db(-journal)?$' ;;
    sweep | sweep_mpi) echo '^s\.db(-journal|-wal|-shm)?$' ;;
    *) echo '^$' ;;
  esac
}

# Sorted dump of a database (row order and page layout are not part of the result).
db_dump() { sqlite3 "$1" .dump | sort; }

digest() {  # digest CMD O: what a successful run produced, to compare with the clean run's
  output_of "$1" "$2" | sed "s#$2#O#g"  # the runs' folders differ
}

output_of() {
  local o=$2
  case "$1" in
    trace)  # host times are measured, so they differ from run to run: the rows' counts
      for t in meta frames tasks kernels ops; do
        echo "$t $(sqlite3 "$o/t.db" "SELECT COUNT(*) FROM $t")"
      done ;;
    simulate_new | simulate_existing) db_dump "$o/r.db" ;;
    sweep | sweep_mpi)
      sqlite3 "$o/s.db" "SELECT point, run_id, metrics_json, feasible, pareto, error FROM \
        sweep_points ORDER BY point; SELECT run_id, summary_json FROM runs ORDER BY run_id" ;;
    report) (cd "$o/report" && find . -type f | sort && cat index.html) ;;
    export) cat "$o/latency.csv" ;;
  esac
}

# Rows of the runs `ids` of a results database, table by table (every table with a run_id).
runs_rows() {
  local db=$1 ids=$2 t
  for t in $(sqlite3 "$db" "SELECT m.name FROM sqlite_master m, pragma_table_info(m.name) c \
      WHERE m.type = 'table' AND c.name = 'run_id' ORDER BY m.name"); do
    echo "== $t"
    sqlite3 "$db" "SELECT * FROM $t WHERE run_id IN ($ids) ORDER BY rowid"
  done
}

# Files of a folder: name, size and checksum (directories: name).
snapshot() {
  (cd "$1" && find . -mindepth 1 \( -type f -printf '%P %s ' -exec sh -c 'md5sum <"$1" | cut -c1-32' _ {} \; \) \
    -o \( -printf '%P %y\n' \)) | sort
}

# ---- one run --------------------------------------------------------------------------------

total_runs=0
total_failed=0
declare -A runs fired passed failed nofault
log="$work/log"
: >"$log"

fail() {  # fail RUN_DIR MESSAGE
  echo "FAIL $(basename "$1"): $2" | tee -a "$log" >&2
  failure=1
}

# run_point CMD CLASS N ERRNO: one faulted run and its re-run.
run_point() {
  local cmd=$1 class=$2 n=$3 err=$4
  local d="$work/runs/$cmd-$class-$n-$err" o
  rm -rf "$d"
  mkdir -p "$d/out"
  o="$d/out"
  setup "$cmd" "$o"
  local before ids="" earlier=""
  before=$(snapshot "$o")
  if [ "$cmd" = simulate_existing ]; then
    ids=$(sqlite3 "$o/r.db" "SELECT group_concat(quote(run_id)) FROM runs")
    earlier=$(runs_rows "$o/r.db" "$ids")
  fi
  local limit_var=EDX_FAULT_CALL
  [ "$class" = write ] && limit_var=EDX_FAULT_BYTES
  local line
  line=$(command_of "$cmd" "$o")
  env EDX_FAULT_PATH="$o" EDX_FAULT_OPS="$class" "$limit_var=$n" EDX_FAULT_ERRNO="$err" \
    EDX_FAULT_REPORT="$d/faults" LD_PRELOAD="$preload" timeout 300 $line >"$d/stdout" 2>"$d/stderr"
  local rc=$?
  failure=0
  total_runs=$((total_runs + 1))
  runs[$cmd]=$((${runs[$cmd]:-0} + 1))
  if ! grep -q '^fault ' "$d/faults" 2>/dev/null; then
    nofault[$cmd]=$((${nofault[$cmd]:-0} + 1))
    [ $rc = 0 ] || fail "$d" "no fault fired, yet exit $rc: $(head -c 300 "$d/stderr")"
  else
    fired[$cmd]=$((${fired[$cmd]:-0} + 1))
    # (a) a non-zero exit, not by a signal or the timeout.
    if [ $rc = 0 ]; then fail "$d" "exit 0 although a fault fired ($(head -1 "$d/faults"))"; fi
    if [ $rc -ge 124 ]; then fail "$d" "exit $rc (signal or timeout)"; fi
    # (b) one line besides warnings (and mpirun's own report), naming the target.
    local lines target
    target=$(target_of "$cmd" "$o")
    if [ -n "$mpirun_prefix" ] && [ "$cmd" = sweep_mpi ]; then
      lines=$(grep '^edx' "$d/stderr" | grep -vE '^edx: warning: |^edx [a-z-]+: ' || true)
    else
      lines=$(grep -vE '^edx: warning: |^edx [a-z-]+: ' "$d/stderr" || true)
    fi
    if [ "$(printf '%s' "$lines" | grep -c '')" != 1 ]; then
      fail "$d" "stderr is not one line: $(head -c 600 "$d/stderr" | tr '\n' '|')"
    elif [[ "$lines" != "edx: error: "* ]] || [[ "$lines" != *"$target"* ]]; then
      fail "$d" "the error does not name $target: $lines"
    fi
    # (MPI_ABORT is how a failed MPI sweep ends its ranks; mpirun names a signal otherwise.)
    if grep -qE 'Sanitizer|Segmentation|terminate called|core dumped|Aborted|on signal' \
      "$d/stderr"; then
      fail "$d" "a crash: $(head -c 300 "$d/stderr")"
    fi
    # (c) nothing changed or left but what may be, and an existing database whole.
    local after changed
    after=$(snapshot "$o")
    changed=$(diff <(echo "$before") <(echo "$after") | grep '^[<>]' | cut -c3- | cut -d' ' -f1 |
      sort -u | grep -vE "$(allowed_after_failure "$cmd")" || true)
    [ -z "$changed" ] || fail "$d" "left or changed: $(echo $changed)"
    for db in "$o/r.db" "$o/s.db"; do
      [ -f "$db" ] || continue
      local check
      check=$(sqlite3 "$db" "PRAGMA integrity_check" 2>&1)
      [ "$check" = ok ] || fail "$d" "$(basename "$db"): integrity_check: $check"
    done
    if [ -n "$ids" ]; then
      [ "$(runs_rows "$o/r.db" "$ids")" = "$earlier" ] || fail "$d" "the earlier run's rows changed"
    fi
  fi
  # (d) the re-run completes and gives the clean run's output.
  if [ $rc != 0 ]; then
    timeout 300 $line >"$d/rerun.stdout" 2>"$d/rerun.stderr"
    local rerun=$?
    if [ $rerun != 0 ]; then
      fail "$d" "the re-run exits $rerun: $(head -c 300 "$d/rerun.stderr")"
    fi
  fi
  if [ $failure = 0 ] && [ "$(digest "$cmd" "$o" 2>&1)" != "$(cat "$work/clean-$cmd.digest")" ]; then
    fail "$d" "the output differs from the clean run's"
  fi
  if [ $failure = 0 ]; then
    passed[$cmd]=$((${passed[$cmd]:-0} + 1))
    echo "pass $(basename "$d") exit=$rc $(grep -m1 '^edx: error: ' "$d/stderr" | cut -c1-400)" >>"$log"
    rm -rf "$d"
  else
    failed[$cmd]=$((${failed[$cmd]:-0} + 1))
    total_failed=$((total_failed + 1))
  fi
}

# Points spread over 0..total-1: `count` of them (all when there are fewer).
spread() {
  local total=$1 count=$2 i
  [ "$total" -gt 0 ] || return 0
  if [ "$total" -le "$count" ]; then seq 0 $((total - 1)); return; fi
  for ((i = 0; i < count; ++i)); do echo $((i * total / count)); done
}

commands="trace simulate_new simulate_existing sweep sweep_mpi report export"
[ -n "$mpiexec" ] || commands=${commands/ sweep_mpi/}
[ -z "$only" ] || commands=${only//,/ }
start=$(date +%s)
for cmd in $commands; do
  # The clean run under the preload, counting: bytes, syncs and renames under O.
  d="$work/runs/$cmd-clean"
  rm -rf "$d"
  mkdir -p "$d/out"
  setup "$cmd" "$d/out"
  # Bounded like the faulted runs, so that a hang fails naming its run rather than ctest's timeout.
  env EDX_FAULT_PATH="$d/out" EDX_FAULT_REPORT="$d/faults" LD_PRELOAD="$preload" \
    timeout 120 $(command_of "$cmd" "$d/out") >"$d/stdout" 2>"$d/stderr" ||
    { echo "io_fault_sweep.sh: the clean $cmd failed (exit $?; 124: over 120 s):" \
        "$(cat "$d/stderr")" >&2; exit 1; }
  digest "$cmd" "$d/out" >"$work/clean-$cmd.digest"
  bytes=$(awk '/^exit /{for(i=2;i<=NF;++i){split($i,kv,"=");if(kv[1]=="bytes")s+=kv[2]}}END{print s+0}' "$d/faults")
  syncs=$(awk '/^exit /{for(i=2;i<=NF;++i){split($i,kv,"=");if(kv[1]=="fsyncs")s+=kv[2]}}END{print s+0}' "$d/faults")
  renames=$(awk '/^exit /{for(i=2;i<=NF;++i){split($i,kv,"=");if(kv[1]=="renames")s+=kv[2]}}END{print s+0}' "$d/faults")
  echo "clean $cmd: bytes=$bytes fsyncs=$syncs renames=$renames" | tee -a "$log"
  rm -rf "$d"
  if [ $mode = full ]; then
    write_points=$(spread "$bytes" 40)
    sync_points=$(spread "$syncs" 1000)
    rename_points=$(spread "$renames" 1000)
  else
    write_points=$(spread "$bytes" 2 | tail -1)
    sync_points=$(spread "$syncs" 1 | tail -1)
    rename_points=$(spread "$renames" 1 | tail -1)
    [ "$syncs" -gt 0 ] && sync_points=$((syncs - 1))
    [ "$renames" -gt 0 ] && rename_points=$((renames - 1))
  fi
  # ENOSPC and EIO in turn, fsync starting with EIO (a sync fails so on a broken disk).
  i=0
  for n in $write_points; do
    run_point "$cmd" write "$n" "$([ $((i % 2)) = 0 ] && echo ENOSPC || echo EIO)"
    i=$((i + 1))
  done
  i=0
  for k in $sync_points; do
    run_point "$cmd" fsync $((k + 1)) "$([ $((i % 2)) = 0 ] && echo EIO || echo ENOSPC)"
    i=$((i + 1))
  done
  i=0
  for k in $rename_points; do
    run_point "$cmd" rename $((k + 1)) "$([ $((i % 2)) = 0 ] && echo ENOSPC || echo EIO)"
    i=$((i + 1))
  done
done

{
  echo
  echo "I/O-fault sweep ($mode), $(date -u +%Y-%m-%dT%H:%MZ), $(($(date +%s) - start)) s"
  printf '%-18s %5s %7s %9s %6s %6s\n' command runs fired no-fault passed failed
  for cmd in $commands; do
    printf '%-18s %5d %7d %9d %6d %6d\n' "$cmd" "${runs[$cmd]:-0}" "${fired[$cmd]:-0}" \
      "${nofault[$cmd]:-0}" "${passed[$cmd]:-0}" "${failed[$cmd]:-0}"
  done
  echo "total: $total_runs runs, $total_failed failed"
} | tee -a "$log" ${summary:+"$summary"}
[ $keep = 1 ] && echo "runs kept in $work (log: $log)"
[ $total_failed = 0 ]
