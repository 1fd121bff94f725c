#!/usr/bin/env bash
# Golden results (in the manner of Timeloop's ref_outputs; issue 17): the model's outputs on a
# committed reference trace, compared by tests/cli/golden_test.cpp to 1e-9 relative. A change
# of the model (arch/, configs/, reports/paper_targets.yaml) that moves them regenerates them in
# the same commit, and the commit message says why:
#
#   tests/data/golden/update.sh            # the four expected outputs from golden_mix.db
#   tests/data/golden/update.sh --retrace  # also re-trace golden_mix.db (a workload change;
#                                          # the figures follow its work, not this machine)
#
# golden_mix.db: `edx trace --mix paper --frames 240 --resolution 320x240` (seed 1): all three
# modes and all three accelerable kernels (60 projections, 173 Kalman gains, 3 marginalizations),
# about 1 MB.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../../.." && pwd)"
edx="${EDX:-$root/build/bin/edx}"
[[ -x "$edx" ]] || { echo "$0: no edx at $edx (build it: ./edx --version)" >&2; exit 1; }
cd "$here"
if [[ "${1:-}" == --retrace ]]; then
  data="$(mktemp -d)"
  trap 'rm -rf "$data"' EXIT
  "$edx" trace --mix paper --frames 240 --resolution 320x240 --data "$data" \
    --out golden_mix.db --force >/dev/null
fi
for platform in car drone; do
  config="$root/configs/edx_$platform.yaml"
  "$edx" simulate --config "$config" --trace golden_mix.db --json >"${platform}_simulate.json"
  # edx check exits 1 when a target is missed; the table is the golden output either way.
  "$edx" check --config "$config" --trace golden_mix.db --json >"${platform}_check.json" || true
done
echo "updated $(ls "$here"/*.json | wc -l) golden outputs in $here" >&2
