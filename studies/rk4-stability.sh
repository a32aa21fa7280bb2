#!/usr/bin/env bash
# The example explicit integrator rk4 (examples/rk4) on the stiff four-bar:
# `monohydra compare --integrators trapezoidal,rk4` at the paper's dt = 1 ms,
# then double-step with both integrators over decreasing steps, to find where
# RK4 agrees with the trapezoidal rule (wall times: noisy on a shared
# machine). Then the free four-bar (no hydraulics) at 1 ms.
# docs/results.md quotes this output.
# Usage: studies/rk4-stability.sh MONOHYDRA RK4_PLUGIN_DIR [T_END]
#   e.g. studies/rk4-stability.sh build/bin/monohydra build/examples-installed/build/rk4 10
set -euo pipefail
cd "$(dirname "$0")/.."
mh=$1
export MONOHYDRA_PLUGIN_PATH=$(realpath "$2")
t_end=${3:-1}
echo "== fourbar, dt = 1 ms, t_end = $t_end s: compare"
"$mh" compare models/fourbar.yaml --integrators trapezoidal,rk4 --t-end "$t_end" 2>&1 |
  grep -Ev '^\s*$' || true
# double-step with both integrators as the step shrinks: RK4 "ok" is not
# enough (a bounded instability runs to the end); its drift and distance rows
# say whether it agrees with the trapezoidal rule.
rows='^(status|Newton iterations avg|total wall time|peak \|drift\| \(%|max \|d|explicit step)|FAILED:'
for dt in 1e-3 5e-4 2e-4 1e-4; do
  echo "== fourbar, double-step, dt = $dt s, t_end = $t_end s"
  "$mh" compare models/fourbar.yaml --formulations double-step --integrators trapezoidal,rk4 \
    --dt "$dt" --t-end "$t_end" 2>&1 | grep -E "$rows" || true
done
echo "== fourbar-free (no hydraulics), dt = 1 ms, t_end = $t_end s: compare"
"$mh" compare models/fourbar-free.yaml --integrators trapezoidal,rk4 --t-end "$t_end" 2>&1 |
  grep -Ev '^\s*$' || true
# The host's stability check (docs/integrators.md): the largest stable RK4
# step of each case study under each formulation, and the check's CPU cost,
# from `run`'s summary (a few steps at 1 ms suffice: the check runs first).
for model in fourbar quickreturn; do
  for f in double-step penalty; do
    echo "== $model, $f, rk4, dt = 1 ms: stability check"
    "$mh" run "models/$model.yaml" --formulation "$f" --integrator rk4 --t-end 0.002 2>&1 |
      grep -E '^stability:' || true
  done
done
