#!/usr/bin/env bash
# The example explicit integrator rk4 (examples/rk4) on the stiff four-bar:
# `monohydra compare --integrators trapezoidal,rk4` at the paper's dt = 1 ms,
# then rk4 alone over decreasing steps to find where it stops failing, each
# with its outcome (the failure's time, step and reason) and its CPU time
# (user + system, from /usr/bin/time; noisy on a shared machine). Then the
# free four-bar (no hydraulics), where RK4 is stable at 1 ms.
# docs/results.md quotes this output.
# Usage: studies/rk4-stability.sh MONOHYDRA RK4_PLUGIN_DIR [T_END]
#   e.g. studies/rk4-stability.sh build/bin/monohydra build/examples-installed/build/rk4 1
set -euo pipefail
cd "$(dirname "$0")/.."
mh=$1
export MONOHYDRA_PLUGIN_PATH=$(realpath "$2")
t_end=${3:-1}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "== fourbar, dt = 1 ms, t_end = $t_end s: compare"
"$mh" compare models/fourbar.yaml --integrators trapezoidal,rk4 --t-end "$t_end" 2>&1 |
  grep -Ev '^\s*$' || true
for dt in 1e-3 5e-4 2e-4 1e-4 5e-5 2e-5 1e-5; do
  if /usr/bin/time -f '%U %S' -o "$tmp/cpu" "$mh" run models/fourbar.yaml --integrator rk4 \
    --dt "$dt" --t-end "$t_end" --out "$tmp/rk4.csv" > "$tmp/out" 2>&1; then
    outcome="ran to t_end"
  else
    outcome=$(grep -m1 -E 't = .* s, step' "$tmp/out" || tail -1 "$tmp/out")
  fi
  cpu=$(awk 'END {printf "%.2f", $1 + $2}' "$tmp/cpu")
  echo "rk4 dt = $dt s: cpu $cpu s: $outcome"
done
echo "== fourbar-free (no hydraulics), dt = 1 ms, t_end = $t_end s: compare"
"$mh" compare models/fourbar-free.yaml --integrators trapezoidal,rk4 --t-end "$t_end" 2>&1 |
  grep -Ev '^\s*$' || true
