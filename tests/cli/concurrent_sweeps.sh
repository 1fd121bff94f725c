#!/usr/bin/env bash
# Concurrent starts of `edx sweep`, tried many times (issue 45, docs/RELIABILITY.md): what
# SweepCommand.ConcurrentStartsOnANewDatabaseLoseNothing checks ten times in ctest, at a count
# worth a figure.
#
#   concurrent_sweeps.sh --edx BIN [--tries N] [--out DIR]
#
# Each try starts two sweeps at the same moment on a results database that does not exist yet:
#   same:  one spec twice (one process is refused by the other's lock, or runs after it);
#   named: two specs of different names over the same points (they share the runs).
# A try is lost when the database is missing, holds fewer points than the sweep has, or a process
# that exited 0 printed a database that is not there; duplicated runs (named) are the runs
# simulated by both processes. Prints one line per mode with the counts; exit 1 on a loss.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
edx=""
tries=100
out=""
while (($# > 0)); do
  case "$1" in
    --edx) edx="$2"; shift 2 ;;
    --tries) tries="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    *) echo "concurrent_sweeps: unknown argument '$1'" >&2; exit 2 ;;
  esac
done
[[ -x "$edx" ]] || { echo "concurrent_sweeps: --edx BIN is required" >&2; exit 2; }
[[ "$tries" =~ ^[1-9][0-9]*$ ]] || { echo "concurrent_sweeps: --tries needs a positive integer" >&2; exit 2; }
if [[ -z "$out" ]]; then
  out="$(mktemp -d)"
  trap 'rm -rf "$out"' EXIT
fi
mkdir -p "$out"

# A small real trace and the repository's GEMM-block sweep over it (14 points).
"$edx" trace --mix paper --frames 8 --resolution 320x240 --out "$out/t.db" >/dev/null 2>&1
spec="$root/sweeps/gemm_block.yaml"
sed -e 's/^name: .*//' "$spec" | sed -e "s|^base: .*|base: $root/configs/edx_car.yaml|" >"$out/a.yaml"
cp "$out/a.yaml" "$out/b.yaml"
points="$("$edx" sweep "$out/a.yaml" --trace "$out/t.db" --db "$out/probe.db" --json 2>/dev/null |
  python3 -c 'import json,sys; print(len(json.load(sys.stdin)["points"]))')"

lost=0
for mode in same named; do
  mode_lost=0 duplicated=0 refused=0
  for ((i = 0; i < tries; ++i)); do
    db="$out/r-$mode-$i.db"
    second="$out/a.yaml"
    [[ "$mode" == named ]] && second="$out/b.yaml"
    start() {  # $1: the spec, $2: the output name; the exit status into $2.rc
      local rc=0
      "$edx" sweep "$1" --trace "$out/t.db" --db "$db" --json >"$out/$2.json" 2>"$out/$2.err" || rc=$?
      echo "$rc" >"$out/$2.rc"
    }
    start "$out/a.yaml" 1 &
    start "$second" 2 &
    wait
    result="$(python3 - "$db" "$points" "$out" "$mode" <<'EOF'
import json, os, sqlite3, sys
db, points, out, mode = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4]
lost = refused = computed = 0
rcs = [open(f"{out}/{k}.rc").read().strip() for k in "12"]
if not os.path.exists(db):
    lost = 1
else:
    con = sqlite3.connect(db)
    names = ["a"] if mode == "same" else ["a", "b"]
    for name in names:
        n = con.execute("SELECT count(*) FROM sweep_points WHERE sweep_id = ?", (name,)).fetchone()[0]
        if n != points:
            lost = 1
    con.close()
for k, rc in zip("12", rcs):
    if rc == "0":
        computed += json.load(open(f"{out}/{k}.json"))["computed"]
    else:
        refused += 1
        if mode == "named" or "is being run by process" not in open(f"{out}/{k}.err").read():
            lost = 1  # only the lock may refuse, and only a sweep of the same name
if "0" not in rcs:
    lost = 1
print(lost, refused, max(0, computed - points))
EOF
)"
    read -r l r d <<<"$result"
    mode_lost=$((mode_lost + l)) refused=$((refused + r)) duplicated=$((duplicated + d))
    rm -f "$db"
  done
  echo "$mode: $tries tries, $points points each: $mode_lost lost, $refused refused by the lock, $duplicated runs simulated twice"
  lost=$((lost + mode_lost))
done
leftovers="$(find "$out" -name '*.tmp-*' | wc -l)"
echo "temporary files left: $leftovers"
((lost == 0 && leftovers == 0))
